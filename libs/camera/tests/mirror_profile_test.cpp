// Each mirror profile's derivatives against central differences, and the consistency of its
// parametric and implicit forms.

#include <gtest/gtest.h>

#include "test_cameras.h"

namespace omnisfm::camera {
namespace {

struct NamedProfile {
  std::string name;
  std::function<std::unique_ptr<MirrorProfile>()> make;
};

class ProfileContract : public ::testing::TestWithParam<NamedProfile> {
 protected:
  void SetUp() override { profile_ = GetParam().make(); }
  std::vector<double> samples() const {
    std::vector<double> s;
    for (int i = 0; i <= 200; ++i)
      s.push_back(profile_->s_min() + (profile_->s_max() - profile_->s_min()) * i / 200.0);
    return s;
  }
  std::unique_ptr<MirrorProfile> profile_;
};

TEST_P(ProfileContract, MeridianDerivativesMatchCentralDifferences) {
  for (double s : samples()) {
    MeridianPoint p, pp, pm;
    profile_->evaluate(s, &p, nullptr);
    const double h = 1e-6 * (profile_->s_max() - profile_->s_min());
    profile_->evaluate(s + h, &pp, nullptr);
    profile_->evaluate(s - h, &pm, nullptr);
    const double scale = std::hypot(p.drho, p.dz);
    EXPECT_NEAR(p.drho, (pp.rho - pm.rho) / (2 * h), 1e-7 * scale) << s;
    EXPECT_NEAR(p.dz, (pp.z - pm.z) / (2 * h), 1e-7 * scale) << s;
    const double scale2 = std::max(std::hypot(p.d2rho, p.d2z), scale);
    EXPECT_NEAR(p.d2rho, (pp.drho - pm.drho) / (2 * h), 1e-6 * scale2) << s;
    EXPECT_NEAR(p.d2z, (pp.dz - pm.dz) / (2 * h), 1e-6 * scale2) << s;
  }
}

TEST_P(ProfileContract, ShapeJacobianMatchesCentralDifferences) {
  const Eigen::VectorXd params = profile_->shape_params();
  for (double s : samples()) {
    MeridianPoint p;
    MeridianShapeJacobian J;
    profile_->evaluate(s, &p, &J);
    for (int j = 0; j < profile_->num_shape_params(); ++j) {
      auto plus = profile_->clone(), minus = profile_->clone();
      const double h = 1e-6 * std::max(std::abs(params[j]), 1.0);
      Eigen::VectorXd a = params, b = params;
      a[j] += h;
      b[j] -= h;
      ASSERT_TRUE(plus->set_shape_params(a) && minus->set_shape_params(b));
      MeridianPoint pp, pm;
      plus->evaluate(s, &pp, nullptr);
      minus->evaluate(s, &pm, nullptr);
      const Eigen::Vector4d numeric((pp.rho - pm.rho) / (2 * h), (pp.z - pm.z) / (2 * h),
                                    (pp.drho - pm.drho) / (2 * h), (pp.dz - pm.dz) / (2 * h));
      EXPECT_LT((J.col(j) - numeric).norm(), 1e-6 * std::max(numeric.norm(), 1e-6))
          << profile_->shape_param_names()[j] << " at s = " << s << "\n"
          << J.col(j).transpose() << "\n"
          << numeric.transpose();
    }
  }
}

TEST_P(ProfileContract, ImplicitFormVanishesOnTheSurfaceWithCorrectGradient) {
  for (double s : samples()) {
    MeridianPoint p;
    profile_->evaluate(s, &p, nullptr);
    double g_rho, g_z;
    EXPECT_NEAR(profile_->implicit(p.rho, p.z, &g_rho, &g_z), 0, 1e-14);
    EXPECT_NEAR(profile_->parameter_at(p.rho, p.z), s, 1e-12);
    // The gradient is normal to the meridian tangent and points away from the camera's side.
    EXPECT_NEAR(g_rho * p.drho + g_z * p.dz, 0, 1e-9 * std::hypot(g_rho, g_z) * std::hypot(p.drho, p.dz));
    EXPECT_GT(g_z, 0);
    const double h = 1e-7;
    double unused0, unused1;
    const double numeric_rho = (profile_->implicit(p.rho + h, p.z, &unused0, &unused1) -
                                profile_->implicit(p.rho - h, p.z, &unused0, &unused1)) /
                               (2 * h);
    const double numeric_z = (profile_->implicit(p.rho, p.z + h, &unused0, &unused1) -
                              profile_->implicit(p.rho, p.z - h, &unused0, &unused1)) /
                             (2 * h);
    EXPECT_NEAR(g_rho, numeric_rho, 1e-6 * std::hypot(g_rho, g_z));
    EXPECT_NEAR(g_z, numeric_z, 1e-6 * std::hypot(g_rho, g_z));
    // Negative in front of the reflective face.
    EXPECT_LT(profile_->implicit(p.rho, p.z - 1e-4, &unused0, &unused1), 0);
  }
}

TEST_P(ProfileContract, RejectsInvalidRangesAndShapes) {
  EXPECT_FALSE(profile_->set_valid_range(profile_->s_max(), profile_->s_min()));
  EXPECT_FALSE(profile_->set_valid_range(-1, profile_->s_max()));
  if (profile_->num_shape_params() > 0) {
    Eigen::VectorXd bad = profile_->shape_params();
    bad[0] = NAN;
    EXPECT_FALSE(profile_->set_shape_params(bad));
    EXPECT_FALSE(profile_->set_shape_params(Eigen::VectorXd(profile_->num_shape_params() + 1)));
  }
}

INSTANTIATE_TEST_SUITE_P(
    AllProfiles, ProfileContract,
    ::testing::Values(
        NamedProfile{"Equiangular", [] { return testing::default_equiangular(); }},
        NamedProfile{"EquiangularAlpha3",
                     [] { return std::make_unique<EquiangularProfile>(3.0, 0.08, 0.01, 0.6); }},
        NamedProfile{"Hyperboloid",
                     [] { return std::make_unique<ConicProfile>(0.01, 30.0, -2.2, 0.001, 0.03); }},
        NamedProfile{"Paraboloid",
                     [] { return std::make_unique<ConicProfile>(0.0, 50.0, -1.0, 0.0, 0.03); }},
        NamedProfile{"Ellipsoid",
                     [] { return std::make_unique<ConicProfile>(0.0, 25.0, -0.5, 0.0, 0.03); }},
        NamedProfile{"Sphere",
                     [] { return std::make_unique<ConicProfile>(0.0, 20.0, 0.0, 0.0, 0.045); }},
        NamedProfile{"Table", [] { return testing::sampled_sphere_profile(0.05, 40); }}),
    [](const auto& param_info) { return param_info.param.name; });

TEST(EquiangularProfile, RayLeavesAtAlphaTimesTheta) {
  // Aligned, a camera ray at angle theta from +z leaves the mirror at alpha * theta from -z.
  const double alpha = 5.0;
  CatadioptricCamera camera(testing::default_pinhole(), testing::default_equiangular(), {}, 1024,
                            768);
  for (double theta = 0.03; theta < 0.35; theta += 0.01) {
    for (double azimuth : {0.0, 1.0, 2.5, -2.0}) {
      const Eigen::Vector3d ray(std::sin(theta) * std::cos(azimuth),
                                std::sin(theta) * std::sin(azimuth), std::cos(theta));
      Eigen::Vector2d pixel;
      ASSERT_TRUE(camera.inner().project(ray, &pixel, nullptr, nullptr));
      Eigen::Vector3d o, d;
      ASSERT_TRUE(camera.unproject(pixel, &o, &d));
      EXPECT_NEAR(std::acos(-d.z()), alpha * theta, 1e-9) << theta;
      EXPECT_NEAR(std::atan2(d.y(), d.x()), azimuth, 1e-9);  // stays in the plane of the axis
    }
  }
}

TEST(ConicProfile, FocusedMirrorsAreCentralAndMisalignedOnesAreNot) {
  auto max_ray_distance_to = [](const CatadioptricCamera& camera, const Eigen::Vector3d& point) {
    double worst = 0;
    int rays = 0;
    for (double u = 0; u < 1024; u += 13)
      for (double v = 0; v < 768; v += 11) {
        Eigen::Vector3d o, d;
        if (!camera.unproject({u, v}, &o, &d)) continue;
        const Eigen::Vector3d offset = point - o;
        worst = std::max(worst, (offset - offset.dot(d) * d).norm());
        ++rays;
      }
    EXPECT_GT(rays, 300);
    return worst;
  };
  const auto hyperbolic = testing::hyperbolic_camera();
  const auto& conic = dynamic_cast<const ConicProfile&>(hyperbolic.mirror());
  const Eigen::Vector3d focus_C(0, 0, conic.inner_focus_z() + hyperbolic.mirror_pose().tz);
  EXPECT_LT(max_ray_distance_to(hyperbolic, focus_C), 1e-12);
  const auto shifted = testing::hyperbolic_camera({0, 0, 0.005, 0, 0});
  EXPECT_GT(max_ray_distance_to(shifted, focus_C + Eigen::Vector3d(0.005, 0, 0)), 1e-4);

  const auto parabolic = testing::parabolic_camera();
  const auto& paraboloid = dynamic_cast<const ConicProfile&>(parabolic.mirror());
  const Eigen::Vector3d parabolic_focus(0, 0, paraboloid.inner_focus_z() + parabolic.mirror_pose().tz);
  EXPECT_LT(max_ray_distance_to(parabolic, parabolic_focus), 1e-12);
  const auto tilted = testing::parabolic_camera({0.02, 0, 0, 0, 0});
  EXPECT_GT(max_ray_distance_to(tilted, parabolic_focus), 1e-4);
}

TEST(TableProfile, SplineReproducesTheSampledSurface) {
  // Dense samples of a sphere: the spline's heights and slopes match the sphere's closely.
  const double R = 0.05;
  const auto table = testing::sampled_sphere_profile(R, 200);
  for (double rho = 0.002; rho < 0.028; rho += 0.0001) {
    MeridianPoint p;
    table->evaluate(rho, &p, nullptr);
    const double z = R - std::sqrt(R * R - rho * rho), dz = rho / std::sqrt(R * R - rho * rho);
    EXPECT_NEAR(p.z, z, 1e-10);
    EXPECT_NEAR(p.dz, dz, 1e-7);
  }
  // C2 at the knots: second derivatives from both sides agree.
  for (double knot : {0.03 * 10 / 199, 0.03 * 100 / 199}) {
    MeridianPoint left, right;
    table->evaluate(knot - 1e-12, &left, nullptr);
    table->evaluate(knot + 1e-12, &right, nullptr);
    EXPECT_NEAR(left.d2z, right.d2z, 1e-6 * std::abs(left.d2z));
  }
}

TEST(TableProfile, RejectsBadTables) {
  EXPECT_THROW(TableProfile({0, 0.01, 0.02}, {0, 0, 0}, 0, 0.02), std::invalid_argument);
  EXPECT_THROW(TableProfile({0, 0.02, 0.01, 0.03}, {0, 0, 0, 0}, 0, 0.02), std::invalid_argument);
  EXPECT_THROW(TableProfile({0, 0.01, 0.02, 0.03}, {0, 0, 0, 0}, 0, 0.05), std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::camera
