// Checkerboard corners for the Kaidan images of the real-data set, which come without any.
//
// In the raw images the boards are small and strongly bent by the mirror, and the detectors find
// at best partial, irregular grids. So each image is first looked at through virtual perspective
// cameras: the mirror's image is taken as equiangular (elevation linear in the distance from the
// mirror's centre, azimuth the polar angle; the centre and the usable annulus found by a circle
// Hough transform on the mean of all images), and views of 80 and 100 degrees are rendered at 12
// azimuths and 3 elevations. In those the boards are nearly straight, and OpenCV's sector-based
// detector finds them. The corners are mapped back through the same view (exactly: the view is a
// lookup table into the image) and refined on the raw image. No model parameter comes from this
// mapping: it only straightens the boards enough to be found.
//
// The boards are larger than every view shows, so a W x H block of inner corners is searched for
// and used in every image: as a board of its own it is the same in every image, whichever part of
// the physical board it is.
// Writes mrcal's corners.vnl (`# filename x y level`; `filename - - -` where nothing was found).
//   kaidan_corners KAIDAN_DIR W H [IMAGE...] > corners.vnl
// With IMAGE names, only those are searched (the mirror is still found on all images).

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace {

struct Annulus {
  cv::Point2d centre;
  double inner_radius = 0, outer_radius = 0;
};

// The mirror's centre and usable annulus: the strongest circle of the outer rim and of the
// camera's own dark reflection, on the mean image (the scene changes, the mirror does not).
Annulus find_annulus(const std::vector<cv::Mat>& images) {
  cv::Mat sum = cv::Mat::zeros(images.front().size(), CV_64F);
  for (const cv::Mat& image : images) cv::accumulate(image, sum);
  cv::Mat mean;
  sum.convertTo(mean, CV_8U, 1.0 / static_cast<double>(images.size()));
  cv::GaussianBlur(mean, mean, cv::Size(5, 5), 2);
  std::vector<cv::Vec3f> rim, self;
  cv::HoughCircles(mean, rim, cv::HOUGH_GRADIENT, 1, 50, 60, 40, 150, 260);
  cv::HoughCircles(mean, self, cv::HOUGH_GRADIENT, 1, 50, 60, 30, 30, 90);
  if (rim.empty() || self.empty()) {
    std::fprintf(stderr, "kaidan_corners: the mirror's circles were not found\n");
    std::exit(1);
  }
  Annulus a;
  a.centre = cv::Point2d(self[0][0], self[0][1]);
  a.inner_radius = self[0][2];
  // The rim circle is the dark ring's outer edge; the mirror's picture ends ~20 px inside it.
  a.outer_radius = rim[0][2] - 20;
  return a;
}

// Lookup tables (raw-image x and y per view pixel) of a perspective view looking at `azimuth`
// and `elevation` (radians), with elevation spanning +-50 degrees linearly over the annulus.
void view_maps(const Annulus& a, double azimuth, double elevation, double fov_deg, int size,
               cv::Mat* map_x, cv::Mat* map_y) {
  constexpr double kElevationSpan = 100 * M_PI / 180;
  const double f = size / 2.0 / std::tan(fov_deg * M_PI / 360);
  const cv::Vec3d forward(std::cos(elevation) * std::cos(azimuth),
                          std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
  const cv::Vec3d right(-std::sin(azimuth), std::cos(azimuth), 0);
  const cv::Vec3d up = right.cross(forward);
  map_x->create(size, size, CV_32F);
  map_y->create(size, size, CV_32F);
  for (int v = 0; v < size; ++v) {
    for (int u = 0; u < size; ++u) {
      cv::Vec3d d = ((u + 0.5 - size / 2.0) / f) * right - ((v + 0.5 - size / 2.0) / f) * up +
                    forward;
      d /= cv::norm(d);
      const double phi = std::atan2(d[1], d[0]);
      const double eps = std::asin(std::clamp(d[2], -1.0, 1.0));
      const double r = a.inner_radius +
                       (eps / kElevationSpan + 0.5) * (a.outer_radius - a.inner_radius);
      map_x->at<float>(v, u) = static_cast<float>(a.centre.x + r * std::cos(phi));
      map_y->at<float>(v, u) = static_cast<float>(a.centre.y + r * std::sin(phi));
    }
  }
}

// The raw-image position of view position p: the lookup tables interpolated bilinearly.
cv::Point2f through(const cv::Mat& map_x, const cv::Mat& map_y, cv::Point2f p) {
  cv::Mat x, y;
  cv::getRectSubPix(map_x, cv::Size(1, 1), p, x);
  cv::getRectSubPix(map_y, cv::Size(1, 1), p, y);
  return {x.at<float>(0, 0), y.at<float>(0, 0)};
}

// A perspective view's lookup tables; they depend on the annulus only, so every image shares them.
struct View {
  cv::Mat map_x, map_y;
};

// views: one per (field of view, azimuth, elevation) searched, built the first time one is needed.
std::optional<std::vector<cv::Point2f>> find_board(const cv::Mat& image, const Annulus& a,
                                                   cv::Size grid, std::vector<View>* views) {
  size_t index = 0;
  for (double fov : {80.0, 100.0}) {
    for (int az = 0; az < 360; az += 30) {
      for (int el : {0, -20, 20}) {
        if (views->size() <= index) views->resize(index + 1);
        View& v = (*views)[index++];
        if (v.map_x.empty())
          view_maps(a, az * M_PI / 180, el * M_PI / 180, fov, 480, &v.map_x, &v.map_y);
        cv::Mat view;
        cv::remap(image, view, v.map_x, v.map_y, cv::INTER_CUBIC);
        std::vector<cv::Point2f> corners;
        if (!cv::findChessboardCornersSB(view, grid, corners,
                                         cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY))
          continue;
        for (cv::Point2f& c : corners) c = through(v.map_x, v.map_y, c);
        cv::cornerSubPix(image, corners, cv::Size(3, 3), cv::Size(-1, -1),
                         cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50,
                                          1e-3));
        return corners;
      }
    }
  }
  return std::nullopt;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 4) {
    std::fprintf(stderr, "usage: kaidan_corners KAIDAN_DIR W H [IMAGE...] > corners.vnl\n");
    return 2;
  }
  const std::vector<std::string> only(argv + 4, argv + argc);
  const std::filesystem::path folder = argv[1];
  const cv::Size grid(std::atoi(argv[2]), std::atoi(argv[3]));
  std::vector<std::filesystem::path> paths;
  for (const auto& entry : std::filesystem::directory_iterator(folder))
    if (entry.path().extension() == ".jpg") paths.push_back(entry.path());
  std::sort(paths.begin(), paths.end());
  std::vector<cv::Mat> images;
  for (const auto& path : paths) images.push_back(cv::imread(path.string(), cv::IMREAD_GRAYSCALE));
  if (images.empty() || images.front().empty()) {
    std::fprintf(stderr, "kaidan_corners: no readable .jpg in %s\n", folder.c_str());
    return 2;
  }
  const Annulus annulus = find_annulus(images);
  std::fprintf(stderr, "kaidan_corners: mirror centre (%.1f, %.1f), annulus %.0f-%.0f px\n",
               annulus.centre.x, annulus.centre.y, annulus.inner_radius, annulus.outer_radius);

  std::printf("# filename x y level\n");
  int found = 0, searched = 0;
  std::vector<View> views;
  for (size_t i = 0; i < paths.size(); ++i) {
    const std::string name = paths[i].filename().string();
    if (!only.empty() && std::find(only.begin(), only.end(), name) == only.end()) continue;
    ++searched;
    const auto corners = find_board(images[i], annulus, grid, &views);
    if (!corners) {
      std::printf("%s - - -\n", name.c_str());
      continue;
    }
    ++found;
    for (const cv::Point2f& c : *corners) std::printf("%s %.4f %.4f 0\n", name.c_str(), c.x, c.y);
  }
  std::fprintf(stderr, "kaidan_corners: a %dx%d grid in %d of %d images\n", grid.width,
               grid.height, found, searched);
  return 0;
}
