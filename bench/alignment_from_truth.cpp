// Each track's reference aligned again from the truth, to tell the images' part of the tracks'
// errors from the alignment's (not a benchmark: one run, one report). For every later
// observation in a `track_truth --dump` file, the track's first-frame reference patch is aligned
// into that frame starting from the true pixel and the true local affine shape (the scene's flow
// of the patch's pixels, fitted as the window weighs them), four ways:
//   free:          as the tracker aligns, shape and position free;
//   shape held:    the true shape kept, the position searched for the best correlation;
//   blur matched:  free, the reference's template matched to the patch's scale (match_blur);
//   best point:    blur matched, the error of the reference's best located point.
// The errors' medians and 95th percentiles are printed per band of age and per what the patch
// covers (one surface, a crease where surfaces meet, a marker). The images are smoothed as the
// tracker smooths them, and the patches are the tracker's size (TrackerSettings).
//   omnisfm simulate --scenario lab --render --imaging realistic --out /tmp/lab
//   track_truth lab /tmp/lab/images 1 --dump=/tmp/lab.dump
//   alignment_from_truth lab /tmp/lab/images 1 /tmp/lab.dump [CAMERA_BLUR_PX=the tracker's]

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <map>
#include <opencv2/imgcodecs.hpp>
#include <sstream>
#include <string>
#include <vector>

#include "omnisfm/core/percentile.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/sim/track_simulator.h"
#include "omnisfm/track/patch_alignment.h"
#include "omnisfm/track/tracker_settings.h"
// The tracker's own smoothing, which its library keeps to itself.
#include "../libs/track/src/gaussian_blur.h"

namespace {

using namespace omnisfm;

const track::TrackerSettings kTracker;
const int kHalfSize = kTracker.patch_half_size;

// The frame last asked for, smoothed as the tracker smooths it (the dump is in frame order, and a
// reference patch keeps the pixels it needs).
class Frames {
 public:
  explicit Frames(std::string folder) : folder_(std::move(folder)) {}
  const cv::Mat& operator[](int frame) {
    if (frame == frame_) return image_;
    char name[32];
    std::snprintf(name, sizeof name, "/%06d.png", frame);
    const cv::Mat grey = cv::imread(folder_ + name, cv::IMREAD_GRAYSCALE);
    if (grey.empty()) {
      std::fprintf(stderr, "alignment_from_truth: cannot read %s%s\n", folder_.c_str(), name);
      std::exit(2);
    }
    image_ = track::gaussian_blurred_float(grey, kTracker.image_blur_sigma);
    frame_ = frame;
    return image_;
  }

 private:
  std::string folder_;
  int frame_ = -1;
  cv::Mat image_;
};

// The affine map that best carries the patch's pixels about `feature` in frame `from` to where
// the scene puts them in frame `to`, weighted as the patch's window weighs them.
bool true_shape(const sim::Dataset& d, int from, const Eigen::Vector2d& feature, int to,
                track::AffineWarp* warp) {
  std::vector<Eigen::Vector3d> rows;
  std::vector<Eigen::Vector2d> places;
  for (int dy = -kHalfSize; dy <= kHalfSize; dy += 2)
    for (int dx = -kHalfSize; dx <= kHalfSize; dx += 2) {
      Eigen::Vector3d point;
      Eigen::Vector2d pixel;
      if (!sim::scene_point(d, from, feature + Eigen::Vector2d(dx, dy), &point) ||
          !sim::true_pixel(d, to, point, &pixel))
        continue;
      const double w = std::exp(-(dx * dx + dy * dy) / (2.0 * kHalfSize * kHalfSize));
      rows.push_back(w * Eigen::Vector3d(dx, dy, 1));
      places.push_back(w * pixel);
    }
  if (rows.size() < 20) return false;
  Eigen::MatrixXd M(rows.size(), 3), P(rows.size(), 2);
  for (size_t k = 0; k < rows.size(); ++k) {
    M.row(k) = rows[k].transpose();
    P.row(k) = places[k].transpose();
  }
  const Eigen::MatrixXd fit = M.colPivHouseholderQr().solve(P);
  warp->A = fit.topRows(2).transpose();
  warp->b = fit.row(2).transpose();
  return true;
}

// The place near the true one where the patch, its shape held, correlates best: a search at 0.1
// then 0.01 px.
Eigen::Vector2d best_correlated(const track::ReferencePatch& patch, const cv::Mat& image,
                                const track::AffineWarp& shape, const Eigen::Vector2d& truth) {
  Eigen::Vector2d best = truth;
  double best_ncc = -2;
  for (const double step : {0.1, 0.01}) {
    const Eigen::Vector2d centre = best;
    for (int iy = -10; iy <= 10; ++iy)
      for (int ix = -10; ix <= 10; ++ix) {
        track::AffineWarp w = shape;
        w.b = centre + step * Eigen::Vector2d(ix, iy);
        const double ncc = patch.ncc(image, w);
        if (ncc > best_ncc) best_ncc = ncc, best = w.b;
      }
  }
  return best;
}

struct Errors {
  std::vector<double> free, held, matched, best_point;
};

}  // namespace

int main(int argc, char** argv) {
  if (argc < 5) {
    std::fprintf(stderr,
                 "usage: alignment_from_truth SCENARIO IMAGES_DIR SEED DUMP [CAMERA_BLUR_PX]\n");
    return 2;
  }
  sim::SimulationOptions options;
  options.scenario = argv[1];
  options.seed = std::strtoull(argv[3], nullptr, 10);
  const sim::Dataset dataset = sim::simulate(options);
  Frames frames(argv[2]);
  track::TrackerSettings settings = kTracker;
  if (argc > 5) settings.camera_blur_px = std::atof(argv[5]);
  const double image_blur = settings.blur_variance();
  std::ifstream dump(argv[4]);
  if (!dump) {
    std::fprintf(stderr, "alignment_from_truth: cannot read %s\n", argv[4]);
    return 2;
  }
  struct Reference {
    int frame;
    Eigen::Vector2d pixel;
    track::ReferencePatch patch;
  };
  std::map<int, Reference> references;
  std::map<std::string, Errors> by_kind;
  std::string line;
  while (std::getline(dump, line)) {
    std::istringstream in(line);
    int track = 0, frame = 0, age = 0, covers = 0;
    std::string error;
    Eigen::Vector2d pixel, true_pixel;
    in >> track >> frame >> age >> error >> pixel.x() >> pixel.y() >> true_pixel.x() >>
        true_pixel.y() >> covers;
    if (!in) continue;
    if (age == 0) {
      Reference r{frame, pixel, {}};
      if (track::ReferencePatch::extract(frames[frame], pixel, kHalfSize, &r.patch))
        references[track] = r;
      continue;
    }
    const auto reference = references.find(track);
    if (reference == references.end() || !(std::atof(error.c_str()) < 1) || true_pixel.x() < 0)
      continue;
    const Reference& r = reference->second;
    track::AffineWarp truth;
    if (!true_shape(dataset, r.frame, r.pixel, frame, &truth)) continue;
    const cv::Mat& image = frames[frame];
    track::AffineWarp free = truth, matched_warp = truth;
    track::ReferencePatch matched = r.patch;
    matched.match_blur(truth.A, image_blur, 0);
    if (!r.patch.align(image, &free, 50, 1e-3).converged ||
        !matched.align(image, &matched_warp, 50, 1e-3).converged)
      continue;
    // The best located point's true place, and where the matched alignment puts it.
    const Eigen::Vector2d offset = r.patch.best_located_offset();
    Eigen::Vector3d point;
    Eigen::Vector2d point_pixel;
    if (!sim::scene_point(dataset, r.frame, r.pixel + offset, &point) ||
        !sim::true_pixel(dataset, frame, point, &point_pixel))
      continue;
    const std::string band = age <= 2 ? "1-2" : age <= 8 ? "3-8" : "9+";
    const std::string kind = covers >= 10 ? "marker" : covers > 1 ? "crease" : "one surface";
    const double free_error = (free.b - true_pixel).norm();
    const double held_error =
        (best_correlated(r.patch, image, truth, true_pixel) - true_pixel).norm();
    const double matched_error = (matched_warp.b - true_pixel).norm();
    const double best_point_error = (matched_warp.A * offset + matched_warp.b - point_pixel).norm();
    for (const std::string& key : {std::string("all"), band + " " + kind}) {
      Errors& e = by_kind[key];
      e.free.push_back(free_error);
      e.held.push_back(held_error);
      e.matched.push_back(matched_error);
      e.best_point.push_back(best_point_error);
    }
  }
  std::printf(
      "errors (px), median / 95th percentile: free, shape held, blur matched, best point\n");
  for (const auto& [key, e] : by_kind)
    std::printf("%-16s %5zu: %.3f / %.3f  %.3f / %.3f  %.3f / %.3f  %.3f / %.3f\n", key.c_str(),
                e.free.size(), core::percentile(e.free, 0.5), core::percentile(e.free, 0.95),
                core::percentile(e.held, 0.5), core::percentile(e.held, 0.95),
                core::percentile(e.matched, 0.5), core::percentile(e.matched, 0.95),
                core::percentile(e.best_point, 0.5), core::percentile(e.best_point, 0.95));
  return 0;
}
