#pragma once
// Renders what a catadioptric rig sees of a Scene: an 8-bit grey image of the camera's size.
//
// Each pixel holds an n x n grid of samples (samples_per_pixel = n^2) at offsets (i + 0.5)/n - 0.5
// from its centre. Each sample's reflected ray (camera.unproject) is traced to the nearest
// surface, and the pixel is the mean of its samples' greys, rounded (render_radiance: not
// rounded, for a camera's response to act on; imaging.h). Samples with no valid
// reflection (beyond the rim, in the camera's own reflection) are kInvalidGrey, as a real rig's
// unlit surround is; rays that hit nothing are kSkyGrey.
//
// Shading:
//   quads:   texture_value(quad.texture, ...) (procedural_texture.h lists the ids: 0 wall,
//            1 floor, 2 ceiling, 3 box, 4 outdoor ground, 5 striped wall, 6 plain) on SceneHit::uv,
//            or with use_photos() the photograph standing for that id (photo_texture.h),
//            filtered to the pixel's footprint on the surface, times a fixed diffuse light factor
//            of the quad's orientation (0.75-1) so that box faces differ. Being filtered already,
//            the texture is evaluated once per pixel and quad, at the mean of the hits of the
//            samples that met the quad: the samples anti-alias the edges between surfaces.
//   markers: per sample, kMarkerWhite on the disc of Marker::radius, kMarkerDot on the centre dot
//            of radius kMarkerDotFraction * radius; the target is the disc's centre. Not lit.
//
// The rays are computed once, at construction; render() transforms the scene into the camera
// frame, culls surfaces per 16 x 16 pixel tile against the tile's bundle of rays, and shades
// tiles on `threads` threads. The result depends neither on the thread count nor on timing.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/sim/photo_texture.h"
#include "omnisfm/sim/procedural_texture.h"
#include "omnisfm/sim/scene.h"

namespace omnisfm::sim {

inline constexpr double kInvalidGrey = 10;
inline constexpr double kSkyGrey = 200;
inline constexpr double kMarkerWhite = 250;
inline constexpr double kMarkerDot = 20;
inline constexpr double kMarkerDotFraction = 0.4;

class Renderer {
 public:
  // samples_per_pixel must be a square (1, 4, 9, 16, ...) and threads >= 1; throws
  // std::invalid_argument otherwise.
  Renderer(const camera::CatadioptricCamera& camera, int samples_per_pixel, int threads = 2);

  // From now on the surfaces whose texture has a photograph (SurfacePhotos::has_photo) show it
  // instead of their procedural texture; null: procedural again.
  void use_photos(std::shared_ptr<const SurfacePhotos> photos) { photos_ = std::move(photos); }

  // CV_8UC1, image_height x image_width. Throws std::invalid_argument when a quad's texture is
  // not a SurfaceTexture.
  cv::Mat render(const Scene& scene, const Eigen::Isometry3d& world_from_cam) const;
  // The same before rounding: CV_32FC1 grey levels, for a camera's response (imaging.h) to act on.
  cv::Mat render_radiance(const Scene& scene, const Eigen::Isometry3d& world_from_cam) const;
  // CV_8UC1, 255 where a pixel has at least one sample with a valid reflection, else 0.
  cv::Mat valid_pixels() const;

  // The same image with every ray traced by Scene::intersect in the world frame, without culling:
  // slow, the reference that render() is tested against.
  cv::Mat render_unaccelerated(const Scene& scene, const Eigen::Isometry3d& world_from_cam) const;

  int width() const { return width_; }
  int height() const { return height_; }
  int samples_per_pixel() const { return grid_ * grid_; }
  // How many samples have a valid ray.
  std::size_t num_rays() const { return ray_origins_.size(); }

 private:
  // The pixels of an image tile that have at least one valid sample, and what bounds their rays:
  // every origin lies within origin_radius of origin_centre, every direction within cone_angle
  // of cone_axis.
  struct Tile {
    std::size_t first_pixel = 0, end_pixel = 0;
    Eigen::Vector3d origin_centre{0, 0, 0};
    double origin_radius = 0;
    Eigen::Vector3d cone_axis{0, 0, 1};
    double cone_angle = 0;
  };
  // A pixel with valid samples: rays [first_ray, first_ray + num_rays).
  struct PixelRays {
    std::int32_t x = 0, y = 0;
    std::uint32_t first_ray = 0;
    std::uint16_t num_rays = 0;
    float angular_size = 0;  // radians between neighbouring pixels' rays
  };

  // Sets the tile's bounds to those of the rays (not empty).
  static void bound_rays(const std::vector<Eigen::Vector3f>& origins,
                         const std::vector<Eigen::Vector3f>& directions, Tile* tile);
  // tracer_of_tile(tile) returns the function that traces one of the tile's rays.
  // Into an image of `type`, CV_8UC1 (rounded) or CV_32FC1.
  template <typename TracerOfTile>
  cv::Mat shade_pixels(const Scene& scene, const TracerOfTile& tracer_of_tile, int type) const;
  cv::Mat trace_scene(const Scene& scene, const Eigen::Isometry3d& world_from_cam, int type) const;
  void check_textures(const Scene& scene) const;

  int width_ = 0, height_ = 0, grid_ = 1, threads_ = 1;
  std::shared_ptr<const SurfacePhotos> photos_;
  std::vector<Tile> tiles_;
  std::vector<PixelRays> pixels_;
  // Frame C; single precision halves the memory of 16 samples per pixel, and costs at most a
  // micrometre at the scenes' distances.
  std::vector<Eigen::Vector3f> ray_origins_, ray_directions_;
};

}  // namespace omnisfm::sim
