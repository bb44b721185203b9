// A result's .3Dscene loads back with MRPT's own deserialisation (COpenGLScene::loadFromFile, as
// SceneViewer3D opens it) with the trajectory, the points and their uncertainty ellipsoids.

#include "omnisfm/mrpt_plugin/scene_file.h"

#include <gtest/gtest.h>
#include <mrpt/opengl/CEllipsoid3D.h>
#include <mrpt/opengl/COpenGLScene.h>
#include <mrpt/opengl/CPointCloud.h>
#include <mrpt/opengl/CSetOfLines.h>

#include "serialization_helpers.h"

namespace omnisfm::mrpt_plugin {
namespace {

TEST(SceneFile, LoadsBackInMrpt) {
  SceneContents contents;
  for (int i = 0; i < 25; ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() = Eigen::Vector3d(0.1 * i, 0.02 * i * i, 0);
    T.linear() = Eigen::AngleAxisd(0.05 * i, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    contents.world_from_cam.push_back(T);
  }
  contents.online_world_from_cam = contents.world_from_cam;
  contents.points = {{3, {1, 2, 0.5}}, {8, {-1, 4, 1.5}}, {11, {0, 0, 3}}};
  Eigen::Matrix3d covariance;
  covariance << 4e-4, 1e-4, 0, 1e-4, 9e-4, 2e-5, 0, 2e-5, 1e-3;
  contents.point_covariances = {{8, covariance}};
  const std::string path = testing::temporary_path("result.3Dscene");
  write_scene_file(path, contents);

  mrpt::opengl::COpenGLScene scene;
  ASSERT_TRUE(scene.loadFromFile(path));
  const auto trajectory =
      std::dynamic_pointer_cast<mrpt::opengl::CSetOfLines>(scene.getByName("trajectory"));
  ASSERT_TRUE(trajectory);
  ASSERT_EQ(trajectory->getLineCount(), 24u);
  double x0, y0, z0, x1, y1, z1;
  trajectory->getLineByIndex(23, x0, y0, z0, x1, y1, z1);
  EXPECT_NEAR(x1, 2.4, 1e-6);
  EXPECT_NEAR(y1, 0.02 * 24 * 24, 1e-5);
  EXPECT_TRUE(scene.getByName("online_trajectory"));

  const auto points = std::dynamic_pointer_cast<mrpt::opengl::CPointCloud>(scene.getByName("points"));
  ASSERT_TRUE(points);
  ASSERT_EQ(points->size(), 3u);
  EXPECT_FLOAT_EQ(points->getPoint3Df(1).z, 1.5f);

  const auto uncertainty =
      std::dynamic_pointer_cast<mrpt::opengl::CSetOfObjects>(scene.getByName("point_uncertainty"));
  ASSERT_TRUE(uncertainty);
  const auto ellipsoid =
      std::dynamic_pointer_cast<mrpt::opengl::CEllipsoid3D>(uncertainty->getByName("point 8"));
  ASSERT_TRUE(ellipsoid);
  EXPECT_LT((ellipsoid->getCovMatrix().asEigen() - covariance).norm(), 1e-12);
  EXPECT_FLOAT_EQ(ellipsoid->getQuantiles(), 3.0f);
  EXPECT_NEAR(ellipsoid->getPoseY(), 4, 1e-6);
  EXPECT_FALSE(uncertainty->getByName("point 3")) << "no covariance, no ellipsoid";

  const auto cameras =
      std::dynamic_pointer_cast<mrpt::opengl::CSetOfObjects>(scene.getByName("cameras"));
  ASSERT_TRUE(cameras);
  EXPECT_EQ(std::distance(cameras->begin(), cameras->end()), 4) << "frames 0, 10, 20 and 24";
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
