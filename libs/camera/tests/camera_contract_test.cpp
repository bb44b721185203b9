// The contract every catadioptric camera passes: analytic Jacobians equal central differences,
// Jacobian and plain calls agree, projection and unprojection invert each other, and invalid
// geometry is reported, never returned as numbers.

#include <gtest/gtest.h>

#include <random>

#include "test_cameras.h"

namespace omnisfm::camera {
namespace {

using testing::NamedCamera;

class CameraContract : public ::testing::TestWithParam<NamedCamera> {
 protected:
  void SetUp() override { camera_ = std::make_unique<CatadioptricCamera>(GetParam().make()); }

  // Points across the valid field, away from its edges so that perturbing them keeps them valid:
  // rays of random pixels, at random distances.
  std::vector<Eigen::Vector3d> field_points(int wanted, unsigned seed) const {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(0, camera_->image_width() - 1);
    std::uniform_real_distribution<double> v(0, camera_->image_height() - 1);
    std::uniform_real_distribution<double> distance(0.5, 10.0);
    std::vector<Eigen::Vector3d> points;
    for (int tries = 0; tries < 100 * wanted && static_cast<int>(points.size()) < wanted; ++tries) {
      Eigen::Vector3d o, d;
      if (!camera_->unproject({u(rng), v(rng)}, &o, &d)) continue;
      const Eigen::Vector3d X = o + distance(rng) * d;
      Eigen::Vector2d pixel;
      Reflection reflection;
      const auto& mirror = camera_->mirror();
      const double margin = 0.02 * (mirror.s_max() - mirror.s_min());
      if (camera_->project(X, &pixel, nullptr, nullptr, &reflection) &&
          reflection.s > mirror.s_min() + margin && reflection.s < mirror.s_max() - margin)
        points.push_back(X);
    }
    return points;
  }

  std::unique_ptr<CatadioptricCamera> camera_;
};

TEST_P(CameraContract, ValidImageRegionIsLarge) {
  // Sanity of the fixture: a real catadioptric image has a wide valid annulus.
  std::mt19937 rng(1);
  std::uniform_real_distribution<double> u(0, 1023), v(0, 767);
  int valid = 0;
  for (int i = 0; i < 2000; ++i) {
    Eigen::Vector3d o, d;
    valid += camera_->unproject({u(rng), v(rng)}, &o, &d);
  }
  EXPECT_GT(valid, 2000 * 0.1);
}

TEST_P(CameraContract, ProjectUnprojectRoundTripWithin1e6Pixel) {
  std::mt19937 rng(2);
  std::uniform_real_distribution<double> u(0, 1023), v(0, 767), distance(0.2, 50.0);
  int checked = 0;
  for (int i = 0; i < 5000; ++i) {
    const Eigen::Vector2d pixel(u(rng), v(rng));
    Eigen::Vector3d o, d;
    if (!camera_->unproject(pixel, &o, &d)) continue;
    EXPECT_NEAR(d.norm(), 1.0, 1e-12);
    Eigen::Vector2d back;
    ASSERT_TRUE(camera_->project(o + distance(rng) * d, &back)) << pixel.transpose();
    EXPECT_LT((back - pixel).norm(), 1e-6) << pixel.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 500);
}

TEST_P(CameraContract, PointLiesOnTheRayOfItsPixel) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), height(-3, 3), distance(0.3, 20);
  int checked = 0;
  for (int i = 0; i < 5000; ++i) {
    const double a = angle(rng), r = distance(rng);
    // Points all around the rig: the mirror's axis is +z of the camera frame.
    const Eigen::Vector3d X(r * std::cos(a), r * std::sin(a), height(rng));
    Eigen::Vector2d pixel;
    if (!camera_->project(X, &pixel)) continue;
    ASSERT_TRUE(pixel.allFinite());
    Eigen::Vector3d o, d;
    ASSERT_TRUE(camera_->unproject(pixel, &o, &d)) << X.transpose();
    const Eigen::Vector3d offset = X - o;
    const double distance_to_ray = (offset - offset.dot(d) * d).norm();
    EXPECT_LT(distance_to_ray, 1e-9) << X.transpose();
    EXPECT_GT(offset.dot(d), 0);  // in front of the mirror point, not behind it
    ++checked;
  }
  EXPECT_GT(checked, 200);
}

TEST_P(CameraContract, JacobianCallsGiveIdenticalPixels) {
  for (const auto& X : field_points(300, 4)) {
    Eigen::Vector2d plain, with_point, with_all;
    Eigen::Matrix<double, 2, 3> J_X;
    ParamsJacobian J_params;
    ASSERT_TRUE(camera_->project(X, &plain));
    ASSERT_TRUE(camera_->project(X, &with_point, &J_X));
    ASSERT_TRUE(camera_->project(X, &with_all, &J_X, &J_params));
    EXPECT_EQ(J_params.cols(), camera_->num_params());
    EXPECT_EQ(plain, with_point);
    EXPECT_EQ(plain, with_all);
  }
}

// Columns of an analytic Jacobian against central differences, relative to each column's size.
// `noise`: the tolerance's multiple, where the differences themselves are noisier.
void expect_columns_match(const Eigen::MatrixXd& analytic, const Eigen::MatrixXd& numeric,
                          const std::vector<std::string>& names, const std::string& where,
                          double noise = 1) {
  for (int j = 0; j < analytic.cols(); ++j) {
    EXPECT_LT((analytic.col(j) - numeric.col(j)).norm(),
              noise * testing::derivative_tolerance(numeric.col(j).norm()))
        << where << " column " << names[j] << "\nanalytic " << analytic.col(j).transpose()
        << "\nnumeric  " << numeric.col(j).transpose();
  }
}

TEST_P(CameraContract, PointJacobianMatchesCentralDifferences) {
  const auto points = field_points(1000, 5);
  ASSERT_GT(points.size(), 900u);
  for (const auto& X : points) {
    Eigen::Vector2d pixel;
    Eigen::Matrix<double, 2, 3> J_X;
    ASSERT_TRUE(camera_->project(X, &pixel, &J_X));
    Eigen::Matrix<double, 2, 3> numeric;
    for (int j = 0; j < 3; ++j) {
      numeric.col(j) = testing::five_point_derivative(
          [&](double h) {
            Eigen::Vector3d moved = X;
            moved[j] += h;
            Eigen::Vector2d q(NAN, NAN);
            EXPECT_TRUE(camera_->project(moved, &q));
            return q;
          },
          1e-4 * X.norm());
    }
    expect_columns_match(J_X, numeric, {"x", "y", "z"}, "at X = " + std::to_string(X.x()));
  }
}

TEST_P(CameraContract, ParameterJacobianMatchesCentralDifferences) {
  const auto points = field_points(300, 6);
  const int n = camera_->num_params();
  const Eigen::VectorXd params = camera_->params();
  const auto names = camera_->param_names();
  for (const auto& X : points) {
    Eigen::Vector2d pixel;
    ParamsJacobian J;
    ASSERT_TRUE(camera_->project(X, &pixel, nullptr, &J));
    ASSERT_EQ(J.cols(), n);
    Eigen::Matrix<double, 2, Eigen::Dynamic> numeric(2, n);
    CatadioptricCamera perturbed = *camera_;
    for (int j = 0; j < n; ++j) {
      numeric.col(j) = testing::five_point_derivative(
          [&](double h) {
            Eigen::VectorXd moved = params;
            moved[j] += h;
            Eigen::Vector2d q(NAN, NAN);
            EXPECT_TRUE(perturbed.set_params(moved) && perturbed.project(X, &q)) << names[j];
            return q;
          },
          1e-4 * std::max(std::abs(params[j]), 1.0));
    }
    expect_columns_match(J, numeric, names, "params");
  }
}

// Unprojection's Jacobian against central differences of unproject: the direction's whole
// change, the origin's across the ray (the stencil's origin slides along the mirror, which moves
// the ray nothing). Pixels of the field's points, away from the rim. Two cameras unproject by an
// iteration that agrees with their projection to about 1e-6 pixel only, which the stencil
// divides by its step: mrcal's unprojection of its lens model (errors up to 1e-5 of the column,
// tolerance 20 times the others'), and the tabulated profile's intersection, whose interpolated
// surface turns the direction differently from the projection's by up to 6e-4 (1000 times; the
// next test holds it to the projection's own consistency).
TEST_P(CameraContract, RayJacobianMatchesCentralDifferences) {
  const auto points = field_points(100, 7);
  const int n = camera_->num_params();
  const Eigen::VectorXd params = camera_->params();
  std::vector<std::string> names = camera_->param_names();
  const std::string& name = GetParam().name;
  const double noise = name == "EquiangularMrcalOpencv8" ? 20 : name == "TablePinhole" ? 1000 : 1;
  for (const auto& X : points) {
    Eigen::Vector2d pixel;
    ASSERT_TRUE(camera_->project(X, &pixel));
    Eigen::Vector3d o, d, o_plain, d_plain;
    RayJacobian J;
    ASSERT_TRUE(camera_->unproject(pixel, &o, &d, &J, true));
    ASSERT_TRUE(camera_->unproject(pixel, &o_plain, &d_plain));
    EXPECT_EQ(o, o_plain);
    EXPECT_EQ(d, d_plain);
    ASSERT_EQ(J.direction_params.cols(), n);
    const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - d * d.transpose();
    // The ray at `camera` for `at`, as (direction, origin across the ray) in one vector.
    const auto ray = [&](const CatadioptricCamera& camera, const Eigen::Vector2d& at) {
      Eigen::Vector3d origin(NAN, NAN, NAN), direction(NAN, NAN, NAN);
      EXPECT_TRUE(camera.unproject(at, &origin, &direction));
      Eigen::Matrix<double, 6, 1> v;
      v << direction, across * (origin - o);
      return v;
    };
    Eigen::Matrix<double, 6, 2> numeric_pixel;
    for (int j = 0; j < 2; ++j)
      numeric_pixel.col(j) = testing::five_point_derivative(
          [&](double h) {
            Eigen::Vector2d moved = pixel;
            moved[j] += h;
            return ray(*camera_, moved);
          },
          1e-2);
    Eigen::Matrix<double, 6, 2> analytic_pixel;
    analytic_pixel << J.direction_pixel, J.origin_pixel;
    expect_columns_match(analytic_pixel, numeric_pixel, {"u", "v"}, "pixel", noise);

    Eigen::MatrixXd numeric_params(6, n), analytic_params(6, n);
    analytic_params << J.direction_params, J.origin_params;
    CatadioptricCamera perturbed = *camera_;
    for (int j = 0; j < n; ++j)
      numeric_params.col(j) = testing::five_point_derivative(
          [&](double h) {
            Eigen::VectorXd moved = params;
            moved[j] += h;
            EXPECT_TRUE(perturbed.set_params(moved)) << names[j];
            return ray(perturbed, pixel);
          },
          1e-4 * std::max(std::abs(params[j]), 1.0));
    expect_columns_match(analytic_params, numeric_params, names, "params", noise);
  }
}

// The ray Jacobian by its definition, through projection alone: a point of the ray moved as the
// Jacobian says, projected with the parameter (or the pixel) moved, stays at the (moved) pixel,
// at a distance other than the two the Jacobian was built from. The tabulated profile's curvature
// is piecewise (its interpolation's), which the stencil's steps of the mirror's shift cross: there
// the points stay to 2e-4 of the pixel's move only, and its tolerance is 1000 times the others'.
TEST_P(CameraContract, RayJacobianKeepsTheRaysPointsOnTheirPixel) {
  const double noise = GetParam().name == "TablePinhole" ? 1000 : 1;
  const auto points = field_points(100, 8);
  const int n = camera_->num_params();
  const Eigen::VectorXd params = camera_->params();
  const std::vector<std::string> names = camera_->param_names();
  for (const auto& X : points) {
    Eigen::Vector2d pixel;
    ParamsJacobian J_params;
    ASSERT_TRUE(camera_->project(X, &pixel, nullptr, &J_params));
    Eigen::Vector3d o, d;
    RayJacobian J;
    ASSERT_TRUE(camera_->unproject(pixel, &o, &d, &J, true));
    const double distance = 3.0;
    Eigen::Matrix2d pixel_moves;
    for (int j = 0; j < 2; ++j)
      pixel_moves.col(j) = testing::five_point_derivative(
          [&](double h) {
            const Eigen::Vector3d moved =
                o + h * J.origin_pixel.col(j) + distance * (d + h * J.direction_pixel.col(j));
            Eigen::Vector2d q(NAN, NAN);
            EXPECT_TRUE(camera_->project(moved, &q));
            return q;
          },
          1e-2);
    expect_columns_match(pixel_moves, Eigen::Matrix2d::Identity(), {"u", "v"}, "pixel");
    CatadioptricCamera perturbed = *camera_;
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector2d stays = testing::five_point_derivative(
          [&](double h) {
            Eigen::VectorXd moved_params = params;
            moved_params[j] += h;
            const Eigen::Vector3d moved =
                o + h * J.origin_params.col(j) + distance * (d + h * J.direction_params.col(j));
            Eigen::Vector2d q(NAN, NAN);
            EXPECT_TRUE(perturbed.set_params(moved_params) && perturbed.project(moved, &q))
                << names[j];
            return q;
          },
          1e-4 * std::max(std::abs(params[j]), 1.0));
      // Against how far the parameter alone moves the point's pixel.
      EXPECT_LT(stays.norm(), noise * testing::derivative_tolerance(J_params.col(j).norm()))
          << names[j];
    }
  }
}

// A copy with a wider patch (for estimators, whose iterates cross the rim) projects as the camera
// does inside the patch, and beyond the rim where the camera reports invalid.
TEST_P(CameraContract, AWiderPatchProjectsTheSameWithinAndBeyondTheRim) {
  const CatadioptricCamera wider = camera_->with_wider_patch(0.05);
  const MirrorProfile& mirror = camera_->mirror();
  EXPECT_GT(wider.mirror().s_max(), mirror.s_max());
  if (mirror.s_min() > 0) {
    EXPECT_LT(wider.mirror().s_min(), mirror.s_min());
  }
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> u(0, 1023), v(0, 767);
  // Points seen anywhere in the patch, up to the rim, project the same.
  int within = 0, near_rim = 0;
  for (int i = 0; i < 4000 && within < 200; ++i) {
    Eigen::Vector3d o, d;
    if (!camera_->unproject({u(rng), v(rng)}, &o, &d)) continue;
    const Eigen::Vector3d X = o + 3 * d;
    Eigen::Vector2d pixel, wider_pixel;
    Reflection reflection;
    if (!camera_->project(X, &pixel, nullptr, nullptr, &reflection)) continue;
    ++within;
    near_rim += reflection.s > mirror.s_max() - 0.05 * (mirror.s_max() - mirror.s_min());
    ASSERT_TRUE(wider.project(X, &wider_pixel));
    EXPECT_LT((pixel - wider_pixel).norm(), 1e-9);
  }
  EXPECT_GT(near_rim, 0);
  // Beyond the rim only the wider one does.
  int beyond = 0;
  for (int i = 0; i < 20000 && beyond < 20; ++i) {
    Eigen::Vector3d o, d;
    if (!wider.unproject({u(rng), v(rng)}, &o, &d)) continue;
    const Eigen::Vector3d X = o + 3 * d;
    Eigen::Vector2d pixel;
    Reflection reflection;
    if (!wider.project(X, &pixel, nullptr, nullptr, &reflection) ||
        reflection.s <= mirror.s_max())
      continue;
    ++beyond;
    EXPECT_FALSE(camera_->project(X, &pixel)) << reflection.s;
  }
  EXPECT_GT(beyond, 0);
}

TEST_P(CameraContract, InvalidGeometryIsReportedNotReturned) {
  Eigen::Vector2d pixel;
  // The camera centre, and points on the mirror axis: behind the mirror, inside its body, and
  // between camera and mirror (their reflection is the apex, hidden by the camera itself).
  if (!camera_->inner().is_orthographic()) {
    EXPECT_FALSE(camera_->project(Eigen::Vector3d::Zero(), &pixel));
  }
  const auto& pose = camera_->mirror_pose();
  const Eigen::Matrix3d R = pose.rotation();
  MeridianPoint apex;
  camera_->mirror().evaluate(0.0, &apex, nullptr);
  auto on_axis = [&](double z_M) { return Eigen::Vector3d(R.col(2) * z_M + pose.translation()); };
  EXPECT_FALSE(camera_->project(on_axis(apex.z + 5.0), &pixel));
  EXPECT_FALSE(camera_->project(on_axis(apex.z + 0.005), &pixel));
  const bool aligned = pose.rx == 0 && pose.ry == 0 && pose.tx == 0 && pose.ty == 0;
  if (aligned) {
    EXPECT_FALSE(camera_->project(on_axis(apex.z - 0.01), &pixel));
  }
  EXPECT_FALSE(camera_->project(Eigen::Vector3d(NAN, 0, 1), &pixel));
  // Anything reported valid is finite.
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> c(-5, 5);
  for (int i = 0; i < 20000; ++i) {
    const Eigen::Vector3d X(c(rng), c(rng), c(rng));
    Eigen::Matrix<double, 2, 3> J_X;
    if (camera_->project(X, &pixel, &J_X)) {
      EXPECT_TRUE(pixel.allFinite() && J_X.allFinite()) << X.transpose();
    }
  }
  // The apex's pixel lies in the camera's own reflection; the image corners beyond the rim.
  Eigen::Vector2d apex_pixel;
  ASSERT_TRUE(camera_->inner().project(on_axis(apex.z), &apex_pixel, nullptr, nullptr));
  Eigen::Vector3d o, d;
  EXPECT_FALSE(camera_->unproject(apex_pixel, &o, &d));
  EXPECT_FALSE(camera_->unproject({0, 0}, &o, &d));
  EXPECT_FALSE(camera_->unproject({1023, 767}, &o, &d));
  EXPECT_FALSE(camera_->unproject({NAN, 3}, &o, &d));
}

// A table's patch that reaches its last sample cannot widen at the rim: it widens at the other
// end alone, and projects as before.
TEST(WiderPatch, StopsWhereATablesSamplesEnd) {
  std::vector<double> rho, z;
  for (int i = 0; i < 40; ++i) {
    rho.push_back(0.03 * i / 39);
    z.push_back(0.05 - std::sqrt(0.05 * 0.05 - rho.back() * rho.back()));
  }
  const CatadioptricCamera camera(testing::default_pinhole(),
                                  std::make_unique<TableProfile>(rho, z, 0.004, 0.03),
                                  MirrorPose{0.01, -0.01, 0.002, 0.001, 0.12}, 1024, 768);
  const CatadioptricCamera wider = camera.with_wider_patch(0.05);
  EXPECT_EQ(wider.mirror().s_max(), 0.03);
  EXPECT_NEAR(wider.mirror().s_min(), 0.004 - 0.05 * 0.026, 1e-12);
  int seen = 0;
  for (int v = 0; v < 768; v += 16)
    for (int u = 0; u < 1024; u += 16) {
      Eigen::Vector3d o, d;
      Eigen::Vector2d pixel, wider_pixel;
      if (!camera.unproject({u, v}, &o, &d) || !camera.project(o + 2 * d, &pixel)) continue;
      ++seen;
      ASSERT_TRUE(wider.project(o + 2 * d, &wider_pixel));
      EXPECT_LT((pixel - wider_pixel).norm(), 1e-9);
    }
  EXPECT_GT(seen, 100);
}

INSTANTIATE_TEST_SUITE_P(AllCameras, CameraContract,
                         ::testing::ValuesIn(testing::contract_cameras()),
                         [](const auto& param_info) { return param_info.param.name; });

}  // namespace
}  // namespace omnisfm::camera
