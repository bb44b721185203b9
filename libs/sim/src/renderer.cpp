#include "omnisfm/sim/renderer.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <thread>

namespace omnisfm::sim {
namespace {

constexpr int kTileSize = 16;
constexpr double kPi = 3.14159265358979323846;
// Grazing views blur a texture along one direction only; beyond this obliquity the isotropic
// footprint would wash the other direction out.
constexpr double kMinFootprintCosine = 0.05;

// Runs body(0) ... body(n - 1) on `threads` threads, handing out indices in order.
template <typename Body>
void parallel_for(std::size_t n, int threads, const Body& body) {
  std::atomic<std::size_t> next{0};
  const auto work = [&] {
    for (std::size_t i = next.fetch_add(1); i < n; i = next.fetch_add(1)) body(i);
  };
  std::vector<std::thread> helpers;
  for (int k = 1; k < threads; ++k) helpers.emplace_back(work);
  work();
  for (std::thread& helper : helpers) helper.join();
}

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// A fixed light, so that differently oriented faces differ in brightness.
double light_factor(const Eigen::Vector3d& unit_normal_W) {
  static const Eigen::Vector3d kLight = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();
  return 0.75 + 0.25 * std::abs(unit_normal_W.dot(kLight));
}

double marker_grey(double offset_squared, double radius) {
  const double dot_radius = kMarkerDotFraction * radius;
  return offset_squared < dot_radius * dot_radius ? kMarkerDot : kMarkerWhite;
}

// How a quad looks, whatever frame it is traced in.
struct QuadLook {
  int texture = 0;
  std::uint32_t seed = 0;
  double light = 1;
};

std::vector<QuadLook> quad_looks(const Scene& scene) {
  std::vector<QuadLook> looks;
  looks.reserve(scene.quads().size());
  for (std::size_t i = 0; i < scene.quads().size(); ++i) {
    const TexturedQuad& q = scene.quads()[i];
    looks.push_back({q.texture, surface_seed(q.texture, static_cast<int>(i)),
                     light_factor(q.edge_u.cross(q.edge_v).normalized())});
  }
  return looks;
}

double quad_grey(const QuadLook& look, const Eigen::Vector2d& uv, double distance,
                 double cos_incidence, double angular_size, const SurfacePhotos* photos) {
  const double footprint =
      distance * angular_size / std::max(std::abs(cos_incidence), kMinFootprintCosine);
  if (photos && SurfacePhotos::has_photo(look.texture))
    return look.light * photos->value(look.texture, look.seed, uv, footprint);
  return look.light * texture_value(look.texture, look.seed, uv, footprint);
}

// What one sample's ray meets: a quad (where and how obliquely), or a grey already known (a
// marker, the sky).
struct RayHit {
  int quad = -1;
  Eigen::Vector2d uv{0, 0};
  double distance = 0, cosine = 0;
  double grey = kSkyGrey;  // when quad < 0
};

// A pixel's samples that met the same quad. The texture is filtered to the pixel's footprint
// already, so it is evaluated once per quad and pixel, at the mean of the samples' hits (as
// multisample anti-aliasing does), rather than once per sample: the edges keep the samples'
// anti-aliasing, and the cost no longer grows with the samples per pixel.
struct QuadSamples {
  int quad = -1, count = 0;
  Eigen::Vector2d uv_sum{0, 0};
  double distance_sum = 0, cosine_sum = 0;
};

// A quad in the camera frame, prepared for many ray tests.
struct FrameQuad {
  Eigen::Vector3d origin, normal;  // normal: unit
  double plane_offset = 0;         // normal . origin
  Eigen::Vector3d u_dual, v_dual;  // edge / |edge|^2: local . dual is the fraction along it
  double u_length = 0, v_length = 0;
  Eigen::Vector3d bound_centre;
  double bound_radius = 0;
};

struct FrameMarker {
  Eigen::Vector3d centre, normal;
  double radius = 0;
};

// True when some ray from a ball (centre, radius) with its direction within `cone_angle` of
// `axis` may meet the ball (sphere_centre, sphere_radius). Moving the ray's origin to the centre
// moves the sphere by at most the origin ball's radius, hence the grown sphere.
bool bundle_may_hit(const Eigen::Vector3d& origin_centre, double origin_radius,
                    const Eigen::Vector3d& axis, double cone_angle,
                    const Eigen::Vector3d& sphere_centre, double sphere_radius) {
  const double grown = sphere_radius + origin_radius;
  const Eigen::Vector3d to_sphere = sphere_centre - origin_centre;
  const double distance = to_sphere.norm();
  if (distance <= grown) return true;
  return angle_between(axis, to_sphere) <= cone_angle + std::asin(grown / distance);
}

// The rays of the pixel centres, computed first: they give each pixel's angular size, and a pixel
// with no valid centre in its 3 x 3 neighbourhood has no valid sample (the valid regions of
// catadioptric images are far wider than a pixel).
class PixelCentres {
 public:
  PixelCentres(const camera::CatadioptricCamera& camera, int threads)
      : width_(camera.image_width()), height_(camera.image_height()) {
    const std::size_t num_pixels = static_cast<std::size_t>(width_) * height_;
    origins_.resize(num_pixels);
    directions_.resize(num_pixels);
    valid_.assign(num_pixels, 0);
    parallel_for(height_, threads, [&](std::size_t y) {
      for (int x = 0; x < width_; ++x) {
        const std::size_t i = y * width_ + x;
        valid_[i] = camera.unproject(Eigen::Vector2d(x, static_cast<double>(y)), &origins_[i],
                                     &directions_[i]);
      }
    });
    angular_size_.assign(num_pixels, 0.0);
    parallel_for(height_, threads, [&](std::size_t row) {
      const int y = static_cast<int>(row);
      for (int x = 0; x < width_; ++x) {
        if (!valid(x, y)) continue;
        double size = 0;
        for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}})
          if (valid(x + dx, y + dy))
            size = std::max(size, angle_between(direction(x, y), direction(x + dx, y + dy)));
        angular_size_[index(x, y)] = size;
      }
    });
  }

  bool valid(int x, int y) const {
    return x >= 0 && y >= 0 && x < width_ && y < height_ && valid_[index(x, y)];
  }
  bool valid_near(int x, int y) const {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (valid(x + dx, y + dy)) return true;
    return false;
  }
  const Eigen::Vector3d& origin(int x, int y) const { return origins_[index(x, y)]; }
  const Eigen::Vector3d& direction(int x, int y) const { return directions_[index(x, y)]; }
  // Radians between the rays of neighbouring pixels; a pixel with an invalid centre takes its
  // neighbours' size.
  double angular_size(int x, int y) const {
    if (valid(x, y)) return angular_size_[index(x, y)];
    double size = 0;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (valid(x + dx, y + dy)) size = std::max(size, angular_size_[index(x + dx, y + dy)]);
    return size;
  }

 private:
  std::size_t index(int x, int y) const { return static_cast<std::size_t>(y) * width_ + x; }

  int width_, height_;
  std::vector<Eigen::Vector3d> origins_, directions_;
  std::vector<char> valid_;
  std::vector<double> angular_size_;
};

}  // namespace

Renderer::Renderer(const camera::CatadioptricCamera& camera, int samples_per_pixel, int threads)
    : width_(camera.image_width()), height_(camera.image_height()), threads_(threads) {
  grid_ = static_cast<int>(std::lround(std::sqrt(std::max(samples_per_pixel, 0))));
  if (samples_per_pixel < 1 || grid_ * grid_ != samples_per_pixel)
    throw std::invalid_argument("samples per pixel must be a square (1, 4, 9, 16, ...), not " +
                                std::to_string(samples_per_pixel));
  if (threads < 1)
    throw std::invalid_argument("renderer threads must be at least 1, not " +
                                std::to_string(threads));

  const PixelCentres centres(camera, threads_);
  const int tiles_x = (width_ + kTileSize - 1) / kTileSize;
  const int tiles_y = (height_ + kTileSize - 1) / kTileSize;
  struct TileRays {
    std::vector<PixelRays> pixels;
    std::vector<Eigen::Vector3f> origins, directions;
  };
  std::vector<TileRays> tile_rays(static_cast<std::size_t>(tiles_x) * tiles_y);
  parallel_for(tile_rays.size(), threads_, [&](std::size_t t) {
    TileRays& rays = tile_rays[t];
    const int x0 = static_cast<int>(t % tiles_x) * kTileSize;
    const int y0 = static_cast<int>(t / tiles_x) * kTileSize;
    for (int y = y0; y < std::min(y0 + kTileSize, height_); ++y) {
      for (int x = x0; x < std::min(x0 + kTileSize, width_); ++x) {
        if (!centres.valid_near(x, y)) continue;
        PixelRays pixel;
        pixel.x = x;
        pixel.y = y;
        pixel.first_ray = static_cast<std::uint32_t>(rays.origins.size());
        pixel.angular_size = static_cast<float>(centres.angular_size(x, y));
        for (int j = 0; j < grid_; ++j) {
          for (int i = 0; i < grid_; ++i) {
            Eigen::Vector3d origin, direction;
            if (2 * i + 1 == grid_ && 2 * j + 1 == grid_) {  // the centre, already unprojected
              if (!centres.valid(x, y)) continue;
              origin = centres.origin(x, y);
              direction = centres.direction(x, y);
            } else {
              const Eigen::Vector2d sample(x + (i + 0.5) / grid_ - 0.5,
                                           y + (j + 0.5) / grid_ - 0.5);
              if (!camera.unproject(sample, &origin, &direction)) continue;
            }
            rays.origins.push_back(origin.cast<float>());
            rays.directions.push_back(direction.cast<float>());
            ++pixel.num_rays;
          }
        }
        if (pixel.num_rays > 0) rays.pixels.push_back(pixel);
      }
    }
  });

  // Concatenate in tile order, and bound each tile's rays.
  for (TileRays& rays : tile_rays) {
    if (rays.pixels.empty()) continue;
    Tile tile;
    tile.first_pixel = pixels_.size();
    const auto ray_offset = static_cast<std::uint32_t>(ray_origins_.size());
    for (PixelRays pixel : rays.pixels) {
      pixel.first_ray += ray_offset;
      pixels_.push_back(pixel);
    }
    tile.end_pixel = pixels_.size();
    bound_rays(rays.origins, rays.directions, &tile);
    tiles_.push_back(tile);
    ray_origins_.insert(ray_origins_.end(), rays.origins.begin(), rays.origins.end());
    ray_directions_.insert(ray_directions_.end(), rays.directions.begin(), rays.directions.end());
    rays = TileRays();
  }
}

void Renderer::bound_rays(const std::vector<Eigen::Vector3f>& origins,
                          const std::vector<Eigen::Vector3f>& directions, Tile* tile) {
  Eigen::Vector3d origin_sum = Eigen::Vector3d::Zero(), direction_sum = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < origins.size(); ++k) {
    origin_sum += origins[k].cast<double>();
    direction_sum += directions[k].cast<double>();
  }
  tile->origin_centre = origin_sum / static_cast<double>(origins.size());
  tile->origin_radius = 0;
  for (const Eigen::Vector3f& origin : origins)
    tile->origin_radius =
        std::max(tile->origin_radius, (origin.cast<double>() - tile->origin_centre).norm());
  const double axis_norm = direction_sum.norm();
  if (axis_norm > 1e-9) {
    tile->cone_axis = direction_sum / axis_norm;
    tile->cone_angle = 0;
    for (const Eigen::Vector3f& direction : directions)
      tile->cone_angle =
          std::max(tile->cone_angle, angle_between(tile->cone_axis, direction.cast<double>()));
  } else {  // directions all around: no cone to speak of
    tile->cone_axis = Eigen::Vector3d::UnitZ();
    tile->cone_angle = kPi;
  }
  // Rounding in the bounds must not cull a surface that a ray at the edge of the bundle meets.
  tile->origin_radius += 1e-9;
  tile->cone_angle += 1e-6;
}

void Renderer::check_textures(const Scene& scene) const {
  for (std::size_t i = 0; i < scene.quads().size(); ++i)
    if (!is_surface_texture(scene.quads()[i].texture))
      throw std::invalid_argument("quad " + std::to_string(i) + " has texture " +
                                  std::to_string(scene.quads()[i].texture) +
                                  ", which is not a SurfaceTexture");
}

cv::Mat Renderer::valid_pixels() const {
  cv::Mat mask(height_, width_, CV_8UC1, cv::Scalar(0));
  for (const PixelRays& pixel : pixels_) mask.at<std::uint8_t>(pixel.y, pixel.x) = 255;
  return mask;
}

template <typename TracerOfTile>
cv::Mat Renderer::shade_pixels(const Scene& scene, const TracerOfTile& tracer_of_tile,
                               int type) const {
  const std::vector<QuadLook> looks = quad_looks(scene);
  cv::Mat image(height_, width_, type, cv::Scalar(kInvalidGrey));
  const bool rounded = type == CV_8UC1;
  const SurfacePhotos* photos = photos_.get();
  const int samples = grid_ * grid_;
  parallel_for(tiles_.size(), threads_, [&](std::size_t t) {
    const Tile& tile = tiles_[t];
    const auto trace = tracer_of_tile(tile);
    std::vector<QuadSamples> groups;
    groups.reserve(samples);
    for (std::size_t p = tile.first_pixel; p < tile.end_pixel; ++p) {
      const PixelRays& pixel = pixels_[p];
      const double angular_size = pixel.angular_size;
      double sum = (samples - pixel.num_rays) * kInvalidGrey;
      groups.clear();
      for (std::uint32_t r = pixel.first_ray; r < pixel.first_ray + pixel.num_rays; ++r) {
        const RayHit hit = trace(ray_origins_[r].cast<double>(), ray_directions_[r].cast<double>());
        if (hit.quad < 0) {
          sum += hit.grey;
          continue;
        }
        auto group = std::find_if(groups.begin(), groups.end(),
                                  [&](const QuadSamples& g) { return g.quad == hit.quad; });
        if (group == groups.end()) group = groups.insert(groups.end(), QuadSamples{hit.quad});
        ++group->count;
        group->uv_sum += hit.uv;
        group->distance_sum += hit.distance;
        group->cosine_sum += std::abs(hit.cosine);
      }
      for (const QuadSamples& g : groups)
        sum += g.count * quad_grey(looks[g.quad], g.uv_sum / g.count, g.distance_sum / g.count,
                                   g.cosine_sum / g.count, angular_size, photos);
      if (rounded)
        image.at<std::uint8_t>(pixel.y, pixel.x) = cv::saturate_cast<std::uint8_t>(sum / samples);
      else
        image.at<float>(pixel.y, pixel.x) = static_cast<float>(sum / samples);
    }
  });
  return image;
}

cv::Mat Renderer::render(const Scene& scene, const Eigen::Isometry3d& world_from_cam) const {
  return trace_scene(scene, world_from_cam, CV_8UC1);
}

cv::Mat Renderer::render_radiance(const Scene& scene,
                                  const Eigen::Isometry3d& world_from_cam) const {
  return trace_scene(scene, world_from_cam, CV_32FC1);
}

cv::Mat Renderer::trace_scene(const Scene& scene, const Eigen::Isometry3d& world_from_cam,
                              int type) const {
  check_textures(scene);
  const Eigen::Isometry3d cam_from_world = world_from_cam.inverse();
  const Eigen::Matrix3d rotation = cam_from_world.linear();

  std::vector<FrameQuad> quads;
  quads.reserve(scene.quads().size());
  for (const TexturedQuad& q : scene.quads()) {
    FrameQuad f;
    f.origin = cam_from_world * q.origin;
    const Eigen::Vector3d edge_u = rotation * q.edge_u, edge_v = rotation * q.edge_v;
    f.normal = edge_u.cross(edge_v).normalized();
    f.plane_offset = f.normal.dot(f.origin);
    f.u_dual = edge_u / edge_u.squaredNorm();
    f.v_dual = edge_v / edge_v.squaredNorm();
    f.u_length = edge_u.norm();
    f.v_length = edge_v.norm();
    f.bound_centre = f.origin + 0.5 * (edge_u + edge_v);
    f.bound_radius = 0.5 * std::max((edge_u + edge_v).norm(), (edge_u - edge_v).norm());
    quads.push_back(f);
  }
  std::vector<FrameMarker> markers;
  markers.reserve(scene.markers().size());
  for (const Marker& m : scene.markers())
    markers.push_back({cam_from_world * m.centre, rotation * m.normal, m.radius});

  const auto tracer_of_tile = [&](const Tile& tile) {
    std::vector<int> tile_quads, tile_markers;
    for (std::size_t i = 0; i < quads.size(); ++i)
      if (bundle_may_hit(tile.origin_centre, tile.origin_radius, tile.cone_axis, tile.cone_angle,
                         quads[i].bound_centre, quads[i].bound_radius))
        tile_quads.push_back(static_cast<int>(i));
    for (std::size_t i = 0; i < markers.size(); ++i)
      if (bundle_may_hit(tile.origin_centre, tile.origin_radius, tile.cone_axis, tile.cone_angle,
                         markers[i].centre, markers[i].radius))
        tile_markers.push_back(static_cast<int>(i));

    // The same tests, in the same order, as Scene::intersect.
    return [&, tile_quads = std::move(tile_quads), tile_markers = std::move(tile_markers)](
               const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
      double best = std::numeric_limits<double>::infinity();
      int hit_quad = -1, hit_marker = -1;
      double hit_a = 0, hit_b = 0, hit_cosine = 0, hit_offset_squared = 0;
      for (const int i : tile_quads) {
        const FrameQuad& q = quads[i];
        const double cosine = q.normal.dot(direction);
        if (std::abs(cosine) < 1e-15) continue;
        const double t = (q.plane_offset - q.normal.dot(origin)) / cosine;
        if (!(t > 0 && t < best)) continue;
        const Eigen::Vector3d local = origin + t * direction - q.origin;
        const double a = local.dot(q.u_dual);
        if (a < 0 || a > 1) continue;
        const double b = local.dot(q.v_dual);
        if (b < 0 || b > 1) continue;
        best = t;
        hit_quad = i;
        hit_a = a;
        hit_b = b;
        hit_cosine = cosine;
      }
      for (const int i : tile_markers) {
        const FrameMarker& m = markers[i];
        const double cosine = m.normal.dot(direction);
        if (std::abs(cosine) < 1e-15) continue;
        const double t = m.normal.dot(m.centre - origin) / cosine;
        if (!(t > 0 && t < best)) continue;
        const double offset_squared = (origin + t * direction - m.centre).squaredNorm();
        if (offset_squared > m.radius * m.radius) continue;
        best = t;
        hit_marker = i;
        hit_offset_squared = offset_squared;
      }
      RayHit hit;
      if (hit_marker >= 0) {
        hit.grey = marker_grey(hit_offset_squared, markers[hit_marker].radius);
      } else if (hit_quad >= 0) {
        const FrameQuad& q = quads[hit_quad];
        hit.quad = hit_quad;
        hit.uv << hit_a * q.u_length, hit_b * q.v_length;
        hit.distance = best;
        hit.cosine = hit_cosine;
      }
      return hit;
    };
  };
  return shade_pixels(scene, tracer_of_tile, type);
}

cv::Mat Renderer::render_unaccelerated(const Scene& scene,
                                       const Eigen::Isometry3d& world_from_cam) const {
  check_textures(scene);
  const auto tracer_of_tile = [&](const Tile&) {
    return [&](const Eigen::Vector3d& origin_C, const Eigen::Vector3d& direction_C) {
      const Eigen::Vector3d direction_W = world_from_cam.linear() * direction_C;
      SceneHit scene_hit;
      RayHit hit;
      if (!scene.intersect(world_from_cam * origin_C, direction_W,
                           std::numeric_limits<double>::infinity(), &scene_hit))
        return hit;
      if (scene_hit.marker >= 0) {
        hit.grey = marker_grey(scene_hit.uv.squaredNorm(),
                               scene.markers()[scene_hit.marker].radius);
        return hit;
      }
      const TexturedQuad& q = scene.quads()[scene_hit.quad];
      hit.quad = scene_hit.quad;
      hit.uv = scene_hit.uv;
      hit.distance = scene_hit.distance;
      hit.cosine = q.edge_u.cross(q.edge_v).normalized().dot(direction_W);
      return hit;
    };
  };
  return shade_pixels(scene, tracer_of_tile, CV_8UC1);
}

}  // namespace omnisfm::sim
