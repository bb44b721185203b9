#pragma once
// Grey photographs laid on the scenes' surfaces, in place of the procedural textures
// (procedural_texture.h): the look of a real scene, with its repetitions, shading and flat
// patches, that a tracker must live with.
//
// A photograph covers a square of `metres` on the surface and repeats mirrored, so that its
// edges meet without seams. It is filtered to a pixel's footprint through a pyramid of halved
// copies, sampled bilinearly in the two levels around the footprint and blended between them
// (trilinear filtering): distant surfaces blur instead of aliasing from frame to frame.

#include <Eigen/Core>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace omnisfm::sim {

class PhotoTexture {
 public:
  // An 8-bit grey photograph (CV_8UC1, at least 2 x 2) covering `metres` (> 0) of the surface.
  // Throws std::invalid_argument otherwise.
  PhotoTexture(const cv::Mat& photo, double metres);
  // Reads a PNG (or any image OpenCV reads, turned grey). Throws std::runtime_error naming the
  // file when it cannot be read.
  static PhotoTexture read(const std::string& path, double metres);

  // The grey level (0-255) at surface coordinates uv (metres), filtered to `footprint` metres.
  double value(const Eigen::Vector2d& uv, double footprint) const;

 private:
  double bilinear(int level, double x, double y) const;

  std::vector<cv::Mat> levels_;  // CV_32FC1, each half the size of the one before (rounded down)
  std::vector<double> texels_per_metre_;  // per level: its own width over the photograph's
};

// The photographs the procedural textures stand for, and where on each surface they lie.
class SurfacePhotos {
 public:
  // Reads brick.png, gravel.png and grass.png from `folder` (share/omnisfm/textures). Throws
  // std::runtime_error naming the file that cannot be read.
  static std::shared_ptr<const SurfacePhotos> read(const std::string& folder);

  // Whether `texture` (a SurfaceTexture) has a photograph; the striped wall (the paper's Fig. 2)
  // and the plain texture keep their procedural look.
  static bool has_photo(int texture);
  // The grey level of `texture` on surface `seed` (surface_seed) at uv, filtered to `footprint`:
  // each surface sees its photograph turned and shifted by its seed, so that surfaces sharing a
  // photograph differ. Requires has_photo(texture).
  double value(int texture, std::uint32_t seed, const Eigen::Vector2d& uv, double footprint) const;

 private:
  SurfacePhotos(PhotoTexture brick, PhotoTexture gravel, PhotoTexture grass);
  PhotoTexture brick_, gravel_, grass_;
};

}  // namespace omnisfm::sim
