#include "omnisfm/sim/renderer.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <opencv2/imgproc.hpp>
#include <string>
#include <vector>

#include "omnisfm/camera/equiangular_profile.h"
#include "omnisfm/camera/pinhole_camera.h"
#include "omnisfm/io/camera_file.h"
#include "omnisfm/io/shared_data.h"
#include "omnisfm/sim/procedural_texture.h"
#include "omnisfm/sim/scene.h"

namespace omnisfm::sim {
namespace {

constexpr double kRoomX = 6, kRoomY = 5, kRoomZ = 3;
constexpr double kMarkerRadius = 0.05;
constexpr double kMarkerStandOff = 0.001;  // in front of the wall
constexpr double kPi = 3.14159265358979323846;

camera::CatadioptricCamera default_camera() {
  return io::read_camera_file(io::find_shared_file("cameras/equiangular.ini"));
}

// The rig upright in the room: mirror above the camera, z of C along the world's z (up).
Eigen::Isometry3d rig_pose(const Eigen::Vector3d& position) {
  Eigen::Isometry3d world_from_cam = Eigen::Isometry3d::Identity();
  world_from_cam.translation() = position;
  return world_from_cam;
}

// A textured 6 x 5 x 3 m room, a box in a corner, and five markers on each wall facing inward.
Scene marked_room() {
  Scene scene;
  const Eigen::Vector3d ex(kRoomX, 0, 0), ey(0, kRoomY, 0), ez(0, 0, kRoomZ);
  scene.add_quad({Eigen::Vector3d::Zero(), ex, ey, kFloorTexture});
  scene.add_quad({ez, ex, ey, kCeilingTexture});
  scene.add_quad({Eigen::Vector3d::Zero(), ex, ez, kWallTexture});  // y = 0
  scene.add_quad({ey, ex, ez, kWallTexture});                       // y = kRoomY
  scene.add_quad({Eigen::Vector3d::Zero(), ey, ez, kWallTexture});  // x = 0
  scene.add_quad({ex, ey, ez, kWallTexture});                       // x = kRoomX
  scene.add_box({5.2, 0.2, 0}, {5.8, 0.9, 0.5}, kBoxTexture);

  const double fractions[] = {0.15, 0.32, 0.5, 0.68, 0.85};
  const double heights[] = {0.7, 1.0, 1.3, 0.85, 1.15};
  struct Wall {
    Eigen::Vector3d corner, along, inward;
    double length;
  };
  const Wall walls[] = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, kRoomX},
                        {{0, kRoomY, 0}, {1, 0, 0}, {0, -1, 0}, kRoomX},
                        {{0, 0, 0}, {0, 1, 0}, {1, 0, 0}, kRoomY},
                        {{kRoomX, 0, 0}, {0, 1, 0}, {-1, 0, 0}, kRoomY}};
  int id = 0;
  for (const Wall& wall : walls) {
    for (int k = 0; k < 5; ++k) {
      Marker marker;
      marker.centre = wall.corner + fractions[k] * wall.length * wall.along +
                      heights[k] * Eigen::Vector3d::UnitZ() + kMarkerStandOff * wall.inward;
      marker.normal = wall.inward;
      marker.radius = kMarkerRadius;
      marker.id = id++;
      scene.add_marker(marker);
    }
  }
  return scene;
}

const Eigen::Vector3d kRigPosition(2.8, 2.4, 1.2);

// Renderers are costly to build (one exact unprojection per sample), so each is built once per
// test process, when first needed.
const camera::CatadioptricCamera& full_size_camera() {
  static const camera::CatadioptricCamera camera = default_camera();
  return camera;
}
const Renderer& fine_renderer() {
  static const Renderer renderer(full_size_camera(), 16);
  return renderer;
}
// One sample per pixel reuses the pixel-centre rays the renderer computes anyway: the cheapest.
const Renderer& single_sample_renderer() {
  static const Renderer renderer(full_size_camera(), 1);
  return renderer;
}
// The default camera's mirror on a 320 x 240 pinhole, for tests that do not need resolution.
camera::CatadioptricCamera small_camera() {
  return camera::CatadioptricCamera(
      std::make_unique<camera::PinholeCamera>(camera::PinholeIntrinsics{250, 250, 159.5, 119.5}),
      std::make_unique<camera::EquiangularProfile>(5.0, 0.05, 0.02, 0.35), {}, 320, 240);
}

// Pixels of the projections of the circle of `radius` about a marker's centre.
std::vector<Eigen::Vector2d> project_circle(const camera::CatadioptricCamera& camera,
                                            const Eigen::Isometry3d& cam_from_world,
                                            const Marker& marker, double radius) {
  const Eigen::Vector3d axis_u = marker.normal.unitOrthogonal();
  const Eigen::Vector3d axis_v = marker.normal.cross(axis_u);
  std::vector<Eigen::Vector2d> pixels;
  for (int k = 0; k < 64; ++k) {
    const double angle = 2 * kPi * k / 64;
    const Eigen::Vector3d point =
        marker.centre + radius * (std::cos(angle) * axis_u + std::sin(angle) * axis_v);
    Eigen::Vector2d pixel;
    if (!camera.project(cam_from_world * point, &pixel)) return {};
    pixels.push_back(pixel);
  }
  return pixels;
}

TEST(RendererTest, MarkerDotCentroidsAgreeWithProjectedCentres) {
  const Scene scene = marked_room();
  const Eigen::Isometry3d world_from_cam = rig_pose(kRigPosition);
  const Eigen::Isometry3d cam_from_world = world_from_cam.inverse();
  const cv::Mat image = fine_renderer().render(scene, world_from_cam);
  ASSERT_EQ(image.type(), CV_8UC1);
  ASSERT_EQ(image.cols, full_size_camera().image_width());
  ASSERT_EQ(image.rows, full_size_camera().image_height());

  int measured = 0;
  double worst = 0;
  for (const Marker& marker : scene.markers()) {
    Eigen::Vector2d centre;
    if (!full_size_camera().project(cam_from_world * marker.centre, &centre)) continue;
    const auto dot_rim = project_circle(full_size_camera(), cam_from_world, marker,
                                        kMarkerDotFraction * marker.radius);
    const auto ring_rim = project_circle(full_size_camera(), cam_from_world, marker, marker.radius);
    if (dot_rim.empty() || ring_rim.empty()) continue;
    double dot_extent = 0, ring_clearance = 1e9;
    for (const auto& p : dot_rim) dot_extent = std::max(dot_extent, (p - centre).norm());
    for (const auto& p : ring_rim) ring_clearance = std::min(ring_clearance, (p - centre).norm());
    // The window takes pixels whose centres lie within `window` of the projected centre. Every
    // pixel with a sample on the dot must be in it, and none with a sample beyond the ring (the
    // wall is darker than the ring). A pixel's 4 x 4 samples lie within 3/8 px of its centre
    // along x and y.
    const double sample_reach = std::sqrt(2.0) * 3.0 / 8.0;
    const double window = 0.5 * (dot_extent + ring_clearance);
    if (!(dot_extent + sample_reach < window && window + sample_reach < ring_clearance)) continue;
    // Stay clear of the rim: every pixel around the marker must have a valid reflection.
    const int reach = static_cast<int>(std::ceil(ring_clearance)) + 3;
    const int cx = static_cast<int>(std::lround(centre.x()));
    const int cy = static_cast<int>(std::lround(centre.y()));
    bool clear_of_rim = true;
    for (int y = cy - reach; y <= cy + reach && clear_of_rim; ++y) {
      for (int x = cx - reach; x <= cx + reach && clear_of_rim; ++x) {
        Eigen::Vector3d origin, direction;
        clear_of_rim = full_size_camera().unproject(Eigen::Vector2d(x, y), &origin, &direction);
      }
    }
    if (!clear_of_rim) continue;

    double weight_sum = 0;
    Eigen::Vector2d weighted_sum = Eigen::Vector2d::Zero();
    for (int y = cy - reach; y <= cy + reach; ++y) {
      for (int x = cx - reach; x <= cx + reach; ++x) {
        if ((Eigen::Vector2d(x, y) - centre).norm() > window) continue;
        const double darkness = std::max(0.0, kMarkerWhite - image.at<std::uint8_t>(y, x));
        weight_sum += darkness;
        weighted_sum += darkness * Eigen::Vector2d(x, y);
      }
    }
    ASSERT_GT(weight_sum, 0) << "marker " << marker.id;
    const double error = (weighted_sum / weight_sum - centre).norm();
    EXPECT_LT(error, 0.2) << "marker " << marker.id << " at pixel " << centre.transpose();
    worst = std::max(worst, error);
    ++measured;
  }
  EXPECT_GE(measured, 16) << "too few markers clear of the rim and resolved";
  RecordProperty("markers_measured", measured);
  RecordProperty("worst_centroid_error_px", std::to_string(worst));
}

TEST(RendererTest, NoReflectionIsDark) {
  // The default camera is aligned: its valid region is the annulus between the images of the
  // camera's own reflection and of the rim, centred on the principal point.
  const double inner = 800 * std::tan(0.02), rim = 800 * std::tan(0.35);
  const cv::Mat image = single_sample_renderer().render(marked_room(), rig_pose(kRigPosition));
  int outside = 0, inside = 0, lit_inside = 0;
  for (int y = 0; y < image.rows; ++y) {
    for (int x = 0; x < image.cols; ++x) {
      const double r = std::hypot(x - 511.5, y - 383.5);
      const int grey = image.at<std::uint8_t>(y, x);
      if (r > rim + 2 || r < inner - 2) {
        ASSERT_EQ(grey, kInvalidGrey) << "pixel " << x << " " << y;
        ++outside;
      } else if (r > inner + 2 && r < rim - 2) {
        ++inside;
        lit_inside += grey > kInvalidGrey;
      }
    }
  }
  EXPECT_GT(outside, 400000);
  EXPECT_GT(lit_inside, 0.999 * inside);
}

TEST(RendererTest, Deterministic) {
  const Scene scene = marked_room();
  const Eigen::Isometry3d pose = rig_pose(kRigPosition);
  const Renderer two_threads(small_camera(), 4, 2), one_thread(small_camera(), 4, 1);
  const cv::Mat first = two_threads.render(scene, pose);
  const cv::Mat second = two_threads.render(scene, pose);
  EXPECT_EQ(cv::countNonZero(first != second), 0);
  EXPECT_EQ(cv::countNonZero(first != one_thread.render(scene, pose)), 0);
}

TEST(RendererTest, CullingChangesNothing) {
  const Scene scene = marked_room();
  const Renderer& renderer = single_sample_renderer();
  // Rotated and off-centre, so that no tile bundle is aligned with the room.
  Eigen::Isometry3d pose = rig_pose({1.3, 3.9, 0.8});
  pose.linear() = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) *
                   Eigen::AngleAxisd(0.2, Eigen::Vector3d::UnitX()))
                      .toRotationMatrix();
  const cv::Mat fast = renderer.render(scene, pose);
  const cv::Mat reference = renderer.render_unaccelerated(scene, pose);
  cv::Mat difference;
  cv::absdiff(fast, reference, difference);
  // Only rays grazing an edge may fall differently after the change of frame.
  EXPECT_LE(cv::countNonZero(difference > 1), 2);
  EXPECT_LT(cv::mean(difference)[0], 0.01);
}

TEST(RendererTest, TexturesHaveTrackableCorners) {
  cv::Mat image = single_sample_renderer().render(marked_room(), rig_pose(kRigPosition));
  std::vector<cv::Point2f> corners;
  cv::goodFeaturesToTrack(image, corners, 2000, 0.01, 8.0);
  int in_view = 0;
  for (const cv::Point2f& c : corners) {
    const double r = std::hypot(c.x - 511.5, c.y - 383.5);
    in_view += r > 30 && r < 280;  // not the edges of the valid annulus
  }
  EXPECT_GT(in_view, 500);
}

TEST(ProceduralTextureTest, ContrastAtTrackingScalesBlurredWhenFar) {
  for (const int texture : {kWallTexture, kFloorTexture, kCeilingTexture, kBoxTexture,
                            kGroundTexture}) {
    double sum = 0, squares = 0, far_sum = 0, far_squares = 0;
    double lo = 255, hi = 0;
    const int n = 200;
    for (int i = 0; i < n; ++i) {
      for (int j = 0; j < n; ++j) {
        const Eigen::Vector2d uv(0.01 * i, 0.01 * j);  // 2 m x 2 m at 1 cm
        const double near = texture_value(texture, 7, uv, 0.0);
        const double far = texture_value(texture, 7, uv, 1.0);
        lo = std::min(lo, near);
        hi = std::max(hi, near);
        sum += near;
        squares += near * near;
        far_sum += far;
        far_squares += far * far;
      }
    }
    const double count = n * n;
    const double spread = std::sqrt(squares / count - std::pow(sum / count, 2));
    const double far_spread = std::sqrt(far_squares / count - std::pow(far_sum / count, 2));
    EXPECT_GE(lo, 0) << texture;
    EXPECT_LE(hi, 255) << texture;
    EXPECT_GT(spread, texture == kCeilingTexture ? 15 : 30) << texture;
    EXPECT_LT(far_spread, 0.7 * spread) << texture;
    EXPECT_EQ(texture_value(texture, 7, {0.123, 4.56}, 0.01),
              texture_value(texture, 7, {0.123, 4.56}, 0.01));
    EXPECT_NE(texture_value(texture, 7, {0.123, 4.56}, 0.0),
              texture_value(texture, 8, {0.123, 4.56}, 0.0));
  }
}

TEST(ProceduralTextureTest, StripesAveragedOverTheFootprint) {
  // 4 cm stripes every 30 cm, centred at 15 cm: dark there, light between, and their share of
  // the period over a footprint of whole periods.
  const double dark = texture_value(kStripedWallTexture, 0, {0.15, 1.0}, 0.0);
  const double light = texture_value(kStripedWallTexture, 0, {0.0, 1.0}, 0.0);
  EXPECT_LT(dark, 40);
  EXPECT_GT(light, 200);
  EXPECT_NEAR(texture_value(kStripedWallTexture, 0, {0.37, 1.0}, 0.6),
              light + (dark - light) * 0.04 / 0.30, 1e-9);
  // Half a stripe's edge under a footprint of one stripe width: halfway.
  EXPECT_NEAR(texture_value(kStripedWallTexture, 0, {0.13, 1.0}, 0.04), 0.5 * (dark + light),
              1e-9);
}

TEST(RendererConstruction, RejectsBadSettings) {
  const camera::CatadioptricCamera camera = default_camera();
  EXPECT_THROW(Renderer(camera, 3), std::invalid_argument);
  EXPECT_THROW(Renderer(camera, 0), std::invalid_argument);
  EXPECT_THROW(Renderer(camera, 1, 0), std::invalid_argument);
}

TEST(RendererTest, RejectsUnknownTexture) {
  const Renderer renderer(small_camera(), 1);
  Scene scene;
  scene.add_quad({Eigen::Vector3d(-5, -5, -1), Eigen::Vector3d(10, 0, 0),
                  Eigen::Vector3d(0, 10, 0), kNumSurfaceTextures});
  EXPECT_THROW(renderer.render(scene, Eigen::Isometry3d::Identity()), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::sim
