#include "omnisfm/sim/photo_texture.h"

#include <algorithm>
#include <cmath>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "omnisfm/sim/procedural_texture.h"

namespace omnisfm::sim {
namespace {

// Mirrored repetition: ... 2 1 0 0 1 2 ... n-1 n-1 n-2 ...
int mirrored(int i, int n) {
  const int period = 2 * n;
  int k = i % period;
  if (k < 0) k += period;
  return k < n ? k : period - 1 - k;
}

}  // namespace

PhotoTexture::PhotoTexture(const cv::Mat& photo, double metres) {
  if (photo.type() != CV_8UC1 || photo.rows < 2 || photo.cols < 2)
    throw std::invalid_argument("a surface photograph must be 8-bit grey and at least 2 x 2");
  if (!(metres > 0)) throw std::invalid_argument("a surface photograph must cover more than 0 m");
  cv::Mat level;
  photo.convertTo(level, CV_32F);
  levels_.push_back(level);
  while (level.rows >= 2 && level.cols >= 2) {
    cv::Mat half;
    cv::resize(level, half, cv::Size(level.cols / 2, level.rows / 2), 0, 0, cv::INTER_AREA);
    levels_.push_back(half);
    level = half;
  }
  // Each level covers the same metres, so that an odd size keeps every level's repetition in
  // place (its texels slightly larger than twice the finer level's).
  for (const cv::Mat& l : levels_) texels_per_metre_.push_back(l.cols / metres);
}

PhotoTexture PhotoTexture::read(const std::string& path, double metres) {
  const cv::Mat photo = cv::imread(path, cv::IMREAD_GRAYSCALE);
  if (photo.empty()) throw std::runtime_error(path + ": cannot be read as an image");
  return PhotoTexture(photo, metres);
}

double PhotoTexture::bilinear(int level, double x, double y) const {
  const cv::Mat& image = levels_[level];
  const double fx = std::floor(x), fy = std::floor(y);
  const double ax = x - fx, ay = y - fy;
  const int x0 = static_cast<int>(fx), y0 = static_cast<int>(fy);
  const auto at = [&](int xi, int yi) {
    return static_cast<double>(
        image.at<float>(mirrored(yi, image.rows), mirrored(xi, image.cols)));
  };
  return (1 - ay) * ((1 - ax) * at(x0, y0) + ax * at(x0 + 1, y0)) +
         ay * ((1 - ax) * at(x0, y0 + 1) + ax * at(x0 + 1, y0 + 1));
}

double PhotoTexture::value(const Eigen::Vector2d& uv, double footprint) const {
  // The level whose texel is the footprint's size.
  const double texels = std::max(footprint * texels_per_metre_[0], 1.0);
  const double lod = std::min(std::log2(texels), static_cast<double>(levels_.size() - 1));
  const int fine = static_cast<int>(std::floor(lod));
  const int coarse = std::min(fine + 1, static_cast<int>(levels_.size()) - 1);
  const double blend = lod - fine;
  // Texel centres at half-integers, the same place at every level.
  const auto sample = [&](int level) {
    const double across = texels_per_metre_[level];
    const double down = levels_[level].rows * texels_per_metre_[0] / levels_[0].rows;
    return bilinear(level, uv.x() * across - 0.5, uv.y() * down - 0.5);
  };
  const double fine_value = sample(fine);
  return blend > 0 && coarse != fine ? (1 - blend) * fine_value + blend * sample(coarse)
                                     : fine_value;
}

SurfacePhotos::SurfacePhotos(PhotoTexture brick, PhotoTexture gravel, PhotoTexture grass)
    : brick_(std::move(brick)), gravel_(std::move(gravel)), grass_(std::move(grass)) {}

std::shared_ptr<const SurfacePhotos> SurfacePhotos::read(const std::string& folder) {
  // Sizes on the surface, large enough that a pixel of the rig's at 1-5 m still resolves them:
  // bricks about 40 cm long, stones of 4-10 cm (cobbles), tufts of a few centimetres.
  return std::shared_ptr<const SurfacePhotos>(
      new SurfacePhotos(PhotoTexture::read(folder + "/brick.png", 2.5),
                        PhotoTexture::read(folder + "/gravel.png", 2.0),
                        PhotoTexture::read(folder + "/grass.png", 1.2)));
}

bool SurfacePhotos::has_photo(int texture) {
  switch (texture) {
    case kWallTexture:
    case kFloorTexture:
    case kCeilingTexture:
    case kBoxTexture:
    case kGroundTexture:
      return true;
    default:
      return false;
  }
}

double SurfacePhotos::value(int texture, std::uint32_t seed, const Eigen::Vector2d& uv,
                            double footprint) const {
  // Each surface's own quarter turns and shift, from its seed.
  const int turn = static_cast<int>(seed % 4u);
  Eigen::Vector2d p = uv;
  for (int k = 0; k < turn; ++k) p = Eigen::Vector2d(-p.y(), p.x());
  p += Eigen::Vector2d(((seed >> 2) % 997u) * 0.0137, ((seed >> 12) % 991u) * 0.0171);
  switch (texture) {
    case kWallTexture:
      return brick_.value(p, footprint);
    case kCeilingTexture:  // the same bricks, painted light: low contrast
      return 170 + 0.35 * (brick_.value(p, footprint) - 128);
    case kFloorTexture:
      return 0.8 * gravel_.value(p, footprint);
    case kGroundTexture:
      return 0.7 * gravel_.value(p, footprint);
    case kBoxTexture:
      return grass_.value(p, footprint);
    default:
      throw std::invalid_argument("texture " + std::to_string(texture) + " has no photograph");
  }
}

}  // namespace omnisfm::sim
