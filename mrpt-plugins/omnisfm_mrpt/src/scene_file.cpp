#include "omnisfm/mrpt_plugin/scene_file.h"

#include "omnisfm/mrpt_plugin/scene.h"

#include <mrpt/opengl/CEllipsoid3D.h>
#include <mrpt/opengl/CGridPlaneXY.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloud.h>
#include <mrpt/opengl/CSetOfLines.h>
#include <mrpt/opengl/stock_objects.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "omnisfm/io/atomic_write.h"

#include "eigen_poses.h"

namespace omnisfm::mrpt_plugin {
namespace {

mrpt::opengl::CSetOfLines::Ptr polyline(const std::vector<Eigen::Isometry3d>& poses,
                                        const std::string& name, const mrpt::img::TColor& color) {
  auto lines = mrpt::opengl::CSetOfLines::Create();
  lines->setName(name);
  lines->setColor_u8(color);
  lines->setLineWidth(2);
  for (std::size_t i = 1; i < poses.size(); ++i) {
    const Eigen::Vector3d a = poses[i - 1].translation(), b = poses[i].translation();
    lines->appendLine(a.x(), a.y(), a.z(), b.x(), b.y(), b.z());
  }
  return lines;
}

// A grid under everything, to the next metre beyond the extent of the points and the cameras.
mrpt::opengl::CGridPlaneXY::Ptr ground(const SceneContents& s) {
  Eigen::AlignedBox3d box;
  for (const auto& T : s.world_from_cam) box.extend(T.translation());
  for (const auto& [track, p] : s.points) box.extend(p);
  if (box.isEmpty()) box.extend(Eigen::Vector3d::Zero());
  auto grid = mrpt::opengl::CGridPlaneXY::Create(
      static_cast<float>(std::floor(box.min().x()) - 1), static_cast<float>(std::ceil(box.max().x()) + 1),
      static_cast<float>(std::floor(box.min().y()) - 1), static_cast<float>(std::ceil(box.max().y()) + 1),
      static_cast<float>(box.min().z()), 1.0f);
  grid->setName("ground");
  grid->setColor_u8(mrpt::img::TColor(180, 180, 180, 120));
  return grid;
}

}  // namespace

mrpt::opengl::COpenGLScene::Ptr make_scene(const SceneContents& s) {
  auto scene_pointer = mrpt::opengl::COpenGLScene::Create();
  mrpt::opengl::COpenGLScene& scene = *scene_pointer;
  scene.insert(ground(s));
  scene.insert(polyline(s.world_from_cam, "trajectory", mrpt::img::TColor(30, 60, 230)));
  if (!s.online_world_from_cam.empty())
    scene.insert(
        polyline(s.online_world_from_cam, "online_trajectory", mrpt::img::TColor(128, 128, 128)));

  auto cameras = mrpt::opengl::CSetOfObjects::Create();
  cameras->setName("cameras");
  for (std::size_t i = 0; i < s.world_from_cam.size(); ++i) {
    if (i % 10 != 0 && i + 1 != s.world_from_cam.size()) continue;
    auto triad = mrpt::opengl::stock_objects::CornerXYZSimple(0.1f, 2.0f);
    triad->setPose(pose_of(s.world_from_cam[i]));
    cameras->insert(triad);
  }
  scene.insert(cameras);

  auto points = mrpt::opengl::CPointCloud::Create();
  points->setName("points");
  points->setPointSize(4);
  points->setColor_u8(mrpt::img::TColor(220, 40, 40));
  for (const auto& [track, p] : s.points)
    points->insertPoint(static_cast<float>(p.x()), static_cast<float>(p.y()),
                        static_cast<float>(p.z()));
  scene.insert(points);

  auto ellipsoids = mrpt::opengl::CSetOfObjects::Create();
  ellipsoids->setName("point_uncertainty");
  for (const auto& [track, covariance] : s.point_covariances) {
    const auto point = s.points.find(track);
    if (point == s.points.end() || !covariance.allFinite()) continue;
    auto ellipsoid = mrpt::opengl::CEllipsoid3D::Create();
    ellipsoid->setName("point " + std::to_string(track));
    ellipsoid->setCovMatrix(mrpt::math::CMatrixDouble33(covariance));
    ellipsoid->setQuantiles(static_cast<float>(s.ellipsoid_sigmas));
    ellipsoid->setLocation(point->second.x(), point->second.y(), point->second.z());
    ellipsoid->setColor_u8(mrpt::img::TColor(240, 120, 40, 90));
    ellipsoid->enableDrawSolid3D(false);
    ellipsoids->insert(ellipsoid);
  }
  scene.insert(ellipsoids);
  return scene_pointer;
}

void write_scene_file(const std::string& path, const SceneContents& s) {
  const auto scene = make_scene(s);
  io::write_atomically(path, [&](const std::string& temporary_path) {
    if (!scene->saveToFile(temporary_path)) throw std::runtime_error(path + ": cannot write");
  });
}

}  // namespace omnisfm::mrpt_plugin
