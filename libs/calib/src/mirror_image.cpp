#include "omnisfm/calib/mirror_image.h"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <opencv2/imgproc.hpp>
#include <stdexcept>
#include <vector>

namespace omnisfm::calib {

void MeanImage::add(const cv::Mat& grey) {
  if (sum_.empty()) sum_ = cv::Mat::zeros(grey.size(), CV_64F);
  cv::accumulate(grey, sum_);
  ++count_;
}

cv::Mat MeanImage::mean() const {
  cv::Mat mean;
  if (count_ > 0) sum_.convertTo(mean, CV_8U, 1.0 / count_);
  return mean;
}

namespace {

// A blurred image as the circles are searched on: at most kSearchWidth wide (the Hough
// transform's cost grows with the radii), and how much smaller than the image.
struct SearchImage {
  cv::Mat small;
  double scale = 1;
};
SearchImage search_image(const cv::Mat& blurred) {
  constexpr double kSearchWidth = 640;
  SearchImage search{blurred, std::min(1.0, kSearchWidth / blurred.cols)};
  if (search.scale < 1)
    cv::resize(blurred, search.small, cv::Size(), search.scale, search.scale, cv::INTER_AREA);
  return search;
}

// The Hough transform's edges: Canny's, at the thresholds it takes (the upper, and half of it).
constexpr double kCannyThreshold = 60;

// Circles of radius [min_radius, max_radius], strongest first, in the coordinates of the full
// image.
std::vector<cv::Vec3f> circles(const SearchImage& search, double min_radius, double max_radius,
                               double accumulator_threshold) {
  const double scale = search.scale;
  std::vector<cv::Vec3f> found;
  cv::HoughCircles(search.small, found, cv::HOUGH_GRADIENT, 1,
                   std::max(1.0, min_radius * scale / 4), kCannyThreshold, accumulator_threshold,
                   static_cast<int>(min_radius * scale),
                   static_cast<int>(std::ceil(max_radius * scale)));
  for (cv::Vec3f& c : found) c /= scale;
  return found;
}

// The fraction of the search image's pixels on an edge.
double edge_fraction(const SearchImage& search) {
  cv::Mat edges;
  cv::Canny(search.small, edges, kCannyThreshold / 2, kCannyThreshold);
  return cv::countNonZero(edges) / static_cast<double>(edges.total());
}

// The grey at angle `a` on the circle of radius r about `centre` (the nearest pixel), or false
// outside the image.
bool grey_on_circle(const cv::Mat& blurred, const Eigen::Vector2d& centre, double r, double a,
                    double* grey) {
  const int x = static_cast<int>(std::lround(centre.x() + r * std::cos(a)));
  const int y = static_cast<int>(std::lround(centre.y() + r * std::sin(a)));
  if (x < 0 || y < 0 || x >= blurred.cols || y >= blurred.rows) return false;
  *grey = blurred.at<std::uint8_t>(y, x);
  return true;
}

// Circles are sampled at this many angles, and an edge's step is taken this many pixels either
// side of it (the edge is blurred).
constexpr int kCircleAngles = 360;
constexpr int kStepHalfWidth = 3;

// The radius in [from, to] about `centre` where the mean grey along circles rises fastest
// (rising = true: the edge of a dark disc, the camera's reflection, against the scene around it)
// or falls fastest (the mirror's picture against the dark ring of its rim). Circles are sampled
// inside the image only.
struct Edge {
  double radius = 0;
  double step = 0;  // grey levels across it, over 6 px
};
Edge steepest_edge(const cv::Mat& blurred, const Eigen::Vector2d& centre, double from, double to,
                   bool rising) {
  std::vector<double> profile;
  for (int r = static_cast<int>(from); r <= static_cast<int>(to); ++r) {
    double sum = 0, grey;
    int n = 0;
    for (int k = 0; k < kCircleAngles; ++k)
      if (grey_on_circle(blurred, centre, r, 2 * M_PI * k / kCircleAngles, &grey)) {
        sum += grey;
        ++n;
      }
    profile.push_back(n > 0 ? sum / n : 0);
  }
  constexpr int kStep = kStepHalfWidth;
  double best = 0, radius = from;  // a range too short to hold an edge has none
  for (int i = kStep; i + kStep < static_cast<int>(profile.size()); ++i)
    if (const double rise = (rising ? 1 : -1) * (profile[i + kStep] - profile[i - kStep]);
        rise > best) {
      best = rise;
      radius = from + i;
    }
  return {radius, best};
}

// The radius in [from, to] about `centre` where the grey steps most across the circle, either way
// (a mirror whose picture ends against a mount as bright as the scene it shows): at each radius
// the median over angles of the step's size; and the median of those more than 10 px from it, how
// much the scene alone steps. A mirror's edge is one sharp circle, a texture's steps are
// everywhere. Radii with less than a quarter of their circle in the image are not counted; with
// fewer than 10 radii left to tell the scene by, the background is infinite (nothing stands out).
struct UnsignedEdge {
  double radius = 0;
  double step = 0;        // the median step's size across the circle, grey levels over 6 px
  double background = 0;  // the scene's, at the other radii
};
UnsignedEdge strongest_unsigned_edge(const cv::Mat& blurred, const Eigen::Vector2d& centre,
                                     double from, double to) {
  constexpr double kEdgeWidth = 10;
  constexpr std::size_t kMinBackgroundRadii = 10;
  UnsignedEdge edge{from, 0, INFINITY};
  std::vector<std::pair<double, double>> profile;  // radius, median step
  std::vector<double> steps;
  for (int r = static_cast<int>(from); r <= static_cast<int>(to); ++r) {
    steps.clear();
    for (int k = 0; k < kCircleAngles; ++k) {
      const double a = 2 * M_PI * k / kCircleAngles;
      double inside, outside;
      if (grey_on_circle(blurred, centre, r - kStepHalfWidth, a, &inside) &&
          grey_on_circle(blurred, centre, r + kStepHalfWidth, a, &outside))
        steps.push_back(std::abs(outside - inside));
    }
    if (steps.size() < kCircleAngles / 4) continue;
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    profile.emplace_back(r, steps[steps.size() / 2]);
    if (profile.back().second > edge.step) edge.step = profile.back().second, edge.radius = r;
  }
  steps.clear();
  for (const auto& [r, step] : profile)
    if (std::abs(r - edge.radius) > kEdgeWidth) steps.push_back(step);
  if (steps.size() >= kMinBackgroundRadii) {
    std::nth_element(steps.begin(), steps.begin() + steps.size() / 2, steps.end());
    edge.background = steps[steps.size() / 2];
  }
  return edge;
}

// The circle through the edge of the dark disc about `centre` of radius near `radius`: along each
// of many rays, the steepest rise within 20 % of it, and a least-squares circle through those
// (Kasa's algebraic fit: x^2 + y^2 + D x + E y + F = 0, linear in D, E, F). The Hough transform's
// centre is only as fine as its grid.
bool fit_disc_edge(const cv::Mat& blurred, Eigen::Vector2d* centre, double* radius) {
  constexpr int kRays = 180;
  Eigen::MatrixXd A(kRays, 3);
  Eigen::VectorXd b(kRays);
  int n = 0;
  for (int k = 0; k < kRays; ++k) {
    const Eigen::Vector2d ray(std::cos(2 * M_PI * k / kRays), std::sin(2 * M_PI * k / kRays));
    double best = 0, at = -1;
    for (double r = 0.8 * *radius; r <= 1.2 * *radius; r += 0.25) {
      const Eigen::Vector2d inside = *centre + (r - 2) * ray, outside = *centre + (r + 2) * ray;
      if (inside.minCoeff() < 0 || outside.minCoeff() < 0 || outside.x() > blurred.cols - 2 ||
          outside.y() > blurred.rows - 2 || inside.x() > blurred.cols - 2 ||
          inside.y() > blurred.rows - 2)
        continue;
      cv::Mat grey_in, grey_out;
      cv::getRectSubPix(blurred, cv::Size(1, 1), cv::Point2f(inside.x(), inside.y()), grey_in, CV_32F);
      cv::getRectSubPix(blurred, cv::Size(1, 1), cv::Point2f(outside.x(), outside.y()), grey_out, CV_32F);
      if (const double rise = grey_out.at<float>(0, 0) - grey_in.at<float>(0, 0); rise > best) {
        best = rise;
        at = r;
      }
    }
    if (at < 0) continue;
    const Eigen::Vector2d p = *centre + at * ray;
    A.row(n) << p.x(), p.y(), 1;
    b[n++] = -p.squaredNorm();
  }
  if (n < kRays / 2) return false;
  const Eigen::Vector3d DEF = A.topRows(n).colPivHouseholderQr().solve(b.head(n));
  *centre = -0.5 * DEF.head<2>();
  *radius = std::sqrt(std::max(0.0, centre->squaredNorm() - DEF[2]));
  return true;
}

// The mirror's circles about a candidate rim (a Hough circle): the camera's reflection found
// within it and the picture's end about the reflection's centre, with how far each steps.
struct MirrorCandidate {
  MirrorImage mirror;
  double reflection_rise = 0;  // grey levels
  double picture_step = 0;     // grey levels, falling (or either way where either_way)
  bool either_way = false;
};
// Hough finds some circle in anything; a mirror's edges stand out of the grey about them (the
// shared sets': 35-62 grey levels for the camera's reflection, 43-101 for the picture's end, on
// their mean or on one image).
constexpr double kMinEdgeStep = 10;

MirrorCandidate mirror_about(const cv::Vec3f& rim, const cv::Mat& blurred,
                             const SearchImage& search) {
  MirrorImage mirror;
  mirror.centre = Eigen::Vector2d(rim[0], rim[1]);
  // The reflection's radius from the radial profile, where Hough's votes favour big circles;
  // then its centre from a circle of about that radius.
  Edge self_edge = steepest_edge(blurred, mirror.centre, 0.05 * rim[2], 0.45 * rim[2], true);
  const double self_radius = self_edge.radius;
  mirror.inner_radius = self_radius;
  for (const cv::Vec3f& self : circles(search, 0.9 * self_radius, 1.1 * self_radius, 20)) {
    if (std::hypot(self[0] - rim[0], self[1] - rim[1]) > 0.1 * rim[2]) continue;
    mirror.centre = Eigen::Vector2d(self[0], self[1]);
    mirror.inner_radius = self[2];
    break;
  }
  Eigen::Vector2d centre = mirror.centre;
  double radius = mirror.inner_radius;
  if (fit_disc_edge(blurred, &centre, &radius) && (centre - mirror.centre).norm() < 0.1 * radius) {
    mirror.centre = centre;
    mirror.inner_radius = radius;
  }
  // How far the reflection's edge rises, measured about its own centre: about the rim's, which
  // may be off by several pixels where the rim runs past the image's edges, the circles cross
  // the edge and blur its rise (the omnidir tutorial's mean, 5 px off: 9.2 grey levels, about
  // the reflection's centre 12.3). The range holds the step's width either side of a small
  // reflection's edge too.
  const double reach = std::max(0.2 * mirror.inner_radius, 2.0 * kStepHalfWidth + 2);
  self_edge = steepest_edge(blurred, mirror.centre, std::max(0.0, mirror.inner_radius - reach),
                            mirror.inner_radius + reach, true);
  // About that centre: the strongest circle may be the mount's rather than the mirror's own edge,
  // and the picture ends where the grey falls most steeply, a little inside that (the edge is
  // blurred).
  Edge picture_edge = steepest_edge(blurred, mirror.centre, 0.5 * rim[2], 1.05 * rim[2], false);
  bool either_way = false;
  if (picture_edge.step < kMinEdgeStep) {
    // A mount as bright as the scene: the picture's end steps either way around the circle and
    // its mean cancels (opencv_contrib's omnidir sample: 5.3 grey levels on average, a median of
    // 18 either way, where the scene steps 3 at other radii). A texture steps as much at every
    // radius: a photograph of gravel, 30 against 23.
    constexpr double kMinAboveScene = 4;
    if (const UnsignedEdge unsigned_edge =
            strongest_unsigned_edge(blurred, mirror.centre, 0.5 * rim[2], 1.05 * rim[2]);
        unsigned_edge.step >= kMinEdgeStep &&
        unsigned_edge.step >= kMinAboveScene * unsigned_edge.background) {
      picture_edge = {unsigned_edge.radius, unsigned_edge.step};
      either_way = true;
    }
  }
  mirror.outer_radius = 0.98 * picture_edge.radius;
  return {mirror, self_edge.step, picture_edge.step, either_way};
}

}  // namespace

MirrorImage find_mirror_image(const cv::Mat& mean_grey) {
  CV_Assert(mean_grey.type() == CV_8UC1);
  cv::Mat blurred;
  cv::GaussianBlur(mean_grey, blurred, cv::Size(5, 5), 2);
  const double side = std::min(mean_grey.cols, mean_grey.rows);
  const SearchImage search = search_image(blurred);
  // Edges everywhere (noise: 38 % of the pixels, where the shared sets' images and means have
  // 5-12 %) hide any circle, and the transform would take a minute to say so.
  constexpr double kMaxEdgeFraction = 0.25;
  if (const double edges = edge_fraction(search); edges > kMaxEdgeFraction) {
    char why[160];
    std::snprintf(why, sizeof why,
                  "the mirror was not found: the image is edges nearly everywhere (%.0f %% of its "
                  "pixels, as noise or a close texture gives; a mirror's images, 5-12 %%)",
                  100 * edges);
    throw std::runtime_error(why);
  }
  // The strongest circle on the reduced image may be another than the mirror's where few images
  // were averaged and the scene's edges stay (boards' arcs on the mean of three vmr images: its
  // reflection rises 10.9 grey levels and its picture falls 4.6), where the full image's is the
  // mirror's (50.5 and 107): that one is tried next (slower: the transform's cost grows with the
  // radii). Only the strongest of each: more circles tried, more of a texture's pass (of a
  // photograph of bricks' five strongest, one does).
  const auto stands_out = [](const MirrorCandidate& c) {
    return std::min(c.reflection_rise, c.picture_step);
  };
  std::vector<SearchImage> images{search};
  if (search.scale < 1) images.push_back({blurred, 1});
  MirrorCandidate best;
  bool any_rim = false;
  for (const SearchImage& image : images) {
    if (any_rim && stands_out(best) >= kMinEdgeStep) break;
    const std::vector<cv::Vec3f> rims = circles(image, 0.25 * side, 0.7 * side, 40);
    if (rims.empty()) continue;
    const MirrorCandidate candidate = mirror_about(rims.front(), blurred, search);
    if (!any_rim || stands_out(candidate) > stands_out(best)) best = candidate;
    any_rim = true;
  }
  if (!any_rim) throw std::runtime_error("the mirror's rim (a circle) was not found");
  if (best.reflection_rise < kMinEdgeStep || best.picture_step < kMinEdgeStep) {
    char why[200];
    std::snprintf(why, sizeof why,
                  "the mirror was not found: no circle stands out (the camera's reflection would "
                  "end in a rise of %.1f grey levels, the mirror's picture in a %s of %.1f; a "
                  "mirror's are %.0f or more)",
                  best.reflection_rise, best.either_way ? "step either way" : "fall",
                  best.picture_step, kMinEdgeStep);
    throw std::runtime_error(why);
  }
  return best.mirror;
}

}  // namespace omnisfm::calib
