// Each inner camera's Jacobians against central differences, and its projection and
// unprojection inverting each other.

#include <gtest/gtest.h>

#include <fstream>

#include <random>

#include "test_cameras.h"

namespace omnisfm::camera {
namespace {

struct NamedInner {
  std::string name;
  std::function<std::unique_ptr<InnerCamera>()> make;
};

class InnerContract : public ::testing::TestWithParam<NamedInner> {
 protected:
  void SetUp() override { camera_ = GetParam().make(); }
  std::vector<Eigen::Vector3d> points() const {
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> xy(-0.3, 0.3), z(0.5, 2.0);
    std::vector<Eigen::Vector3d> p;
    for (int i = 0; i < 500; ++i) p.emplace_back(xy(rng), xy(rng), z(rng));
    return p;
  }
  std::unique_ptr<InnerCamera> camera_;
};

TEST_P(InnerContract, JacobiansMatchCentralDifferences) {
  const int n = camera_->num_params();
  const Eigen::VectorXd params = camera_->params();
  for (const auto& p : points()) {
    Eigen::Vector2d q;
    Eigen::Matrix<double, 2, 3> J_p;
    ParamsJacobian J;
    ASSERT_TRUE(camera_->project(p, &q, &J_p, &J));
    ASSERT_EQ(J.cols(), n);
    for (int j = 0; j < 3; ++j) {
      const Eigen::Vector2d numeric = testing::five_point_derivative(
          [&](double h) {
            Eigen::Vector3d moved = p;
            moved[j] += h;
            Eigen::Vector2d moved_pixel(NAN, NAN);
            EXPECT_TRUE(camera_->project(moved, &moved_pixel, nullptr, nullptr));
            return moved_pixel;
          },
          1e-4);
      EXPECT_LT((J_p.col(j) - numeric).norm(), testing::derivative_tolerance(numeric.norm()));
    }
    auto perturbed = camera_->clone();
    for (int j = 0; j < n; ++j) {
      const Eigen::Vector2d numeric = testing::five_point_derivative(
          [&](double h) {
            Eigen::VectorXd moved = params;
            moved[j] += h;
            Eigen::Vector2d moved_pixel(NAN, NAN);
            EXPECT_TRUE(perturbed->set_params(moved) &&
                        perturbed->project(p, &moved_pixel, nullptr, nullptr));
            return moved_pixel;
          },
          1e-4 * std::max(std::abs(params[j]), 1.0));
      EXPECT_LT((J.col(j) - numeric).norm(), testing::derivative_tolerance(numeric.norm()))
          << camera_->param_names()[j];
    }
  }
}

TEST_P(InnerContract, UnprojectInvertsProject) {
  for (const auto& p : points()) {
    Eigen::Vector2d q, back;
    ASSERT_TRUE(camera_->project(p, &q, nullptr, nullptr));
    Eigen::Vector3d o, d;
    ASSERT_TRUE(camera_->unproject(q, &o, &d));
    EXPECT_NEAR(d.norm(), 1, 1e-12);
    EXPECT_GT(d.z(), 0);
    const Eigen::Vector3d offset = p - o;
    EXPECT_LT((offset - offset.dot(d) * d).norm(), 1e-9);
  }
}

TEST_P(InnerContract, RejectsBadParameters) {
  Eigen::VectorXd bad = camera_->params();
  bad[0] = NAN;
  EXPECT_FALSE(camera_->set_params(bad));
  EXPECT_FALSE(camera_->set_params(Eigen::VectorXd::Ones(camera_->num_params() + 1)));
}

INSTANTIATE_TEST_SUITE_P(
    AllInnerCameras, InnerContract,
    ::testing::Values(
        NamedInner{"Pinhole", [] { return testing::default_pinhole(false); }},
        NamedInner{"PinholeDistorted", [] { return testing::default_pinhole(true); }},
        NamedInner{"Orthographic",
                   [] {
                     return std::make_unique<OrthographicCamera>(
                         OrthographicIntrinsics{12000, 11900, 511.5, 383.5});
                   }},
        NamedInner{"MrcalOpencv8",
                   [] {
                     return std::make_unique<MrcalCamera>(
                         MrcalCamera::from_file(testing::write_opencv8_cameramodel()));
                   }}),
    [](const auto& param_info) { return param_info.param.name; });

TEST(PinholeCamera, PointsBehindTheCameraAreInvalid) {
  const auto camera = testing::default_pinhole(true);
  Eigen::Vector2d q;
  EXPECT_FALSE(camera->project({0.1, 0.2, -1}, &q, nullptr, nullptr));
  EXPECT_FALSE(camera->project({0.1, 0.2, 0}, &q, nullptr, nullptr));
}

TEST(MrcalCamera, ReadsWritesAndMatchesMrcalConventions) {
  const auto original = MrcalCamera::from_file(testing::write_opencv8_cameramodel());
  EXPECT_EQ(original.lensmodel_name(), "LENSMODEL_OPENCV8");
  EXPECT_EQ(original.num_params(), 12);
  EXPECT_EQ(original.image_width(), 1024);
  const std::string copy = ::testing::TempDir() + "/copy.cameramodel";
  original.write(copy);
  const auto reread = MrcalCamera::from_file(copy);
  EXPECT_EQ(reread.params(), original.params());
  // OPENCV8 without distortion is a plain pinhole.
  Eigen::VectorXd k = Eigen::VectorXd::Zero(12);
  k.head<4>() << 700, 710, 500, 400;
  const MrcalCamera plain("LENSMODEL_OPENCV8", k, 1000, 800);
  Eigen::Vector2d q;
  ASSERT_TRUE(plain.project({0.1, -0.2, 2.0}, &q, nullptr, nullptr));
  EXPECT_NEAR(q.x(), 700 * 0.05 + 500, 1e-12);
  EXPECT_NEAR(q.y(), 710 * -0.1 + 400, 1e-12);
  EXPECT_THROW(MrcalCamera::from_file("/nonexistent.cameramodel"), std::runtime_error);
  EXPECT_THROW(MrcalCamera("LENSMODEL_NOPE", k, 10, 10), std::invalid_argument);
}

// What libmrcal 2.2's parser reads past its buffer on is refused first, naming the file and line;
// a model whose last line has no newline still reads.
TEST(MrcalCamera, TextThatMrcalsParserWouldOverrunIsRefused) {
  const std::string path = ::testing::TempDir() + "/damaged.cameramodel";
  const auto error_for = [&](const std::string& text) {
    std::ofstream(path, std::ios::binary) << text;
    try {
      MrcalCamera::from_file(path);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_EQ(error_for("{'lensmodel': 'LENSMODEL_OP\n 'imagersize': [1, 2]}\n"),
            path + ":1: a string that does not end on its line");
  EXPECT_EQ(error_for("# a pinhole\x01{"), path + ":1: a control character");
  EXPECT_EQ(error_for("{'lensmodel\": 'LENSMODEL_PINHOLE"),
            path + ":1: a string that does not end");
  EXPECT_EQ(error_for("{\n'lensmodel': 'LENSMODEL_\xc3\xa9'}"),
            path + ":2: a byte that is not ASCII text");
  std::ofstream(path) << "# a comment may hold \xc2\xb1\n"
                         "{'lensmodel': 'LENSMODEL_PINHOLE', 'intrinsics': [700, 700, 50, 40],"
                         " 'extrinsics': [0, 0, 0, 0, 0, 0], 'imagersize': [100, 80]}"
                         " # a last line without its newline";
  EXPECT_EQ(MrcalCamera::from_file(path).image_width(), 100);
}

}  // namespace
}  // namespace omnisfm::camera
