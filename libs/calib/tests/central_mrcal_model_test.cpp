#include "omnisfm/calib/central_mrcal_model.h"

#include <gtest/gtest.h>
#include <unistd.h>

extern "C" {
#include <mrcal/mrcal.h>
}

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "omnisfm/io/camera_file.h"
#include "omnisfm/io/shared_data.h"

namespace omnisfm::calib {
namespace {

namespace fs = std::filesystem;
using camera::CatadioptricCamera;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

CatadioptricCamera shipped_camera(const std::string& name) {
  return io::read_camera_file(io::find_shared_file("cameras/" + name));
}

// A hyperbolic mirror with the pinhole at one focus is central: the reflected rays meet at the
// other, so one model fits every distance, and its centre is that focus.
TEST(CentralMrcalModelTest, FitsACentralCameraAtEveryDistance) {
  const CatadioptricCamera camera = shipped_camera("hyperbolic.ini");
  const std::vector<PixelRay> rays = valid_pixel_rays(camera, 8);
  CentralFitSettings settings;
  settings.distance_m = 2;
  const CentralMrcalModel model = fit_central_mrcal_model(camera, rays, settings);

  // The shipped mirror: apex radius of curvature 3 cm, conic constant -2, apex at tz; its inner
  // focus is 0.03 / (1 + sqrt 2) beyond the apex.
  const Eigen::Vector3d focus_C(0, 0, camera.mirror_pose().tz + 0.03 / (1 + std::sqrt(2.0)));
  const Eigen::Vector3d centre_C = -model.R_model_from_C.transpose() * model.t_model_from_C;
  EXPECT_LT((centre_C - focus_C).norm(), 1e-9);
  const ReprojectionError at_fit = reprojection_error(model, rays, 2);
  EXPECT_EQ(at_fit.num_failed, 0);
  EXPECT_EQ(at_fit.num_points, static_cast<int>(rays.size()));
  EXPECT_LT(at_fit.rms_px, 1e-3);
  EXPECT_LT(at_fit.worst_px, 5e-3);
  for (double distance : {20.0, kInfinity}) {
    const ReprojectionError error = reprojection_error(model, rays, distance);
    SCOPED_TRACE(distance);
    EXPECT_EQ(error.num_failed, 0);
    EXPECT_NEAR(error.rms_px, at_fit.rms_px, 1e-6);
    EXPECT_NEAR(error.worst_px, at_fit.worst_px, 1e-6);
  }
}

// A paraboloid seen by a telecentric lens is exactly a stereographic projection from its focus:
// the spline stays flat and the fit is exact.
TEST(CentralMrcalModelTest, ParacatadioptricIsExactlyStereographic) {
  const CatadioptricCamera camera = shipped_camera("parabolic-orthographic.ini");
  const std::vector<PixelRay> rays = valid_pixel_rays(camera, 8);
  const CentralMrcalModel model = fit_central_mrcal_model(camera, rays, CentralFitSettings{});
  EXPECT_LT(model.intrinsics.tail(model.intrinsics.size() - 4).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR(model.intrinsics[0], -model.intrinsics[1], 1e-6);
  for (double distance : {1.0, kInfinity}) {
    const ReprojectionError error = reprojection_error(model, rays, distance);
    SCOPED_TRACE(distance);
    EXPECT_EQ(error.num_failed, 0);
    EXPECT_LT(error.worst_px, 1e-9);
  }
}

// The equiangular rig is noncentral: exact-looking at the fitted distance, off at others.
TEST(CentralMrcalModelTest, FitsTheNoncentralRigAtTheChosenDistance) {
  const CatadioptricCamera camera = shipped_camera("equiangular.ini");
  const std::vector<PixelRay> rays = valid_pixel_rays(camera, 8);
  CentralFitSettings settings;
  settings.distance_m = 1;
  const CentralMrcalModel model = fit_central_mrcal_model(camera, rays, settings);

  // Its field reaches 100.4 degrees from the mirror's -z axis: fov_x_deg is 2 * 100.4 + margin.
  EXPECT_EQ(model.lensmodel, "LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=16_Ny=16_fov_x_deg=203");
  EXPECT_GT(model.intrinsics[0], 0);
  EXPECT_LT(model.intrinsics[1], 0) << "a mirror image needs a negative fy";

  const ReprojectionError at_fit = reprojection_error(model, rays, 1);
  const ReprojectionError far = reprojection_error(model, rays, 10);
  EXPECT_EQ(at_fit.num_failed, 0);
  EXPECT_LT(at_fit.rms_px, 0.005);
  EXPECT_LT(at_fit.worst_px, 0.01);
  // The rays miss the model's centre by up to centimetres: a few tenths of a pixel at 10 m.
  EXPECT_EQ(far.num_failed, 0);
  EXPECT_GT(far.rms_px, 0.1);
  EXPECT_LT(far.rms_px, 0.3);
  EXPECT_LT(far.worst_px, 0.6);
}

TEST(CentralMrcalModelTest, TheWrittenFileReadsBackExactlyInMrcal) {
  const CatadioptricCamera camera = shipped_camera("equiangular.ini");
  const std::vector<PixelRay> rays = valid_pixel_rays(camera, 8);
  const CentralMrcalModel model = fit_central_mrcal_model(camera, rays, CentralFitSettings{});
  const fs::path dir =
      fs::temp_directory_path() / ("omnisfm-central-mrcal-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string path = (dir / "approx.cameramodel").string();
  io::write_cameramodel(path, model, {"a note", "another"});

  mrcal_cameramodel_t* read = mrcal_read_cameramodel_file(path.c_str());
  ASSERT_NE(read, nullptr);
  char name[1024];
  ASSERT_TRUE(mrcal_lensmodel_name(name, sizeof name, &read->lensmodel));
  EXPECT_EQ(std::string(name), model.lensmodel);
  ASSERT_EQ(mrcal_lensmodel_num_params(&read->lensmodel), model.intrinsics.size());
  for (int i = 0; i < model.intrinsics.size(); ++i)
    EXPECT_EQ(read->intrinsics[i], model.intrinsics[i]) << i;
  EXPECT_EQ(read->imagersize[0], 1024u);
  EXPECT_EQ(read->imagersize[1], 768u);
  // rt_cam_ref is the rotation vector and translation of model_from_C.
  const Eigen::Vector3d r(read->rt_cam_ref[0], read->rt_cam_ref[1], read->rt_cam_ref[2]);
  const Eigen::Vector3d t(read->rt_cam_ref[3], read->rt_cam_ref[4], read->rt_cam_ref[5]);
  const Eigen::Matrix3d R = Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix();
  EXPECT_LT((R - model.R_model_from_C).norm(), 1e-15);
  EXPECT_EQ(t, model.t_model_from_C);
  mrcal_free_cameramodel(&read);
  fs::remove_all(dir);
}

TEST(CentralMrcalModelTest, RejectsBadSettings) {
  const CatadioptricCamera camera = shipped_camera("equiangular.ini");
  const std::vector<PixelRay> rays = valid_pixel_rays(camera, 8);
  for (double distance : {0.0, -1.0, kInfinity, std::nan("")}) {
    CentralFitSettings settings;
    settings.distance_m = distance;
    EXPECT_THROW(fit_central_mrcal_model(camera, rays, settings), std::invalid_argument);
  }
  CentralFitSettings settings;
  settings.knots = 3;
  EXPECT_THROW(fit_central_mrcal_model(camera, rays, settings), std::invalid_argument);
  const std::vector<PixelRay> few(rays.begin(), rays.begin() + 100);
  EXPECT_THROW(fit_central_mrcal_model(camera, few, CentralFitSettings{}), std::invalid_argument);
  EXPECT_THROW(valid_pixel_rays(camera, 0), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::calib
