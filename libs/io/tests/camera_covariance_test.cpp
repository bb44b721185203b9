#include "omnisfm/io/camera_covariance.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <string>

#include "io_test_folder.h"
#include "omnisfm/io/camera_file.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/shared_data.h"

namespace omnisfm::io {
namespace {

using CameraCovariance = TestFolder;

ParameterCovariance example_covariance() {
  ParameterCovariance covariance;
  covariance.parameters = {"mirror_rx", "mirror_tz", "fx"};
  Eigen::Matrix3d a;
  a << 1e-4, 2e-7, 0.3, 0, 3e-8, 1e-5, 0, 0, 0.7;
  covariance.matrix = a.transpose() * a;  // symmetric, positive definite, awkward digits
  return covariance;
}

TEST_F(CameraCovariance, RoundTripsExactlyBesideTheCamera) {
  const camera::CatadioptricCamera camera = read_camera_file(default_camera_file());
  const ParameterCovariance written = example_covariance();
  const std::string file = path("calibrated.ini");
  write_calibrated_camera_file(file, camera, written);

  // The camera reads back unchanged, and the covariance exactly.
  const camera::CatadioptricCamera back = read_camera_file(file);
  EXPECT_EQ(back.params(), camera.params());
  const auto read = read_camera_covariance(file);
  ASSERT_TRUE(read.has_value());
  EXPECT_EQ(read->parameters, written.parameters);
  EXPECT_EQ(read->matrix, written.matrix);
}

TEST_F(CameraCovariance, AbsentSectionIsNoCovariance) {
  EXPECT_FALSE(read_camera_covariance(default_camera_file()).has_value());
}

TEST_F(CameraCovariance, BadSectionsNameTheKeyAndLine) {
  const camera::CatadioptricCamera camera = read_camera_file(default_camera_file());
  const std::string file = path("good.ini");
  write_camera_file(file, camera);
  std::ifstream in(file);
  const std::string camera_text((std::istreambuf_iterator<char>(in)),
                                std::istreambuf_iterator<char>());
  const int first = 1 + static_cast<int>(std::count(camera_text.begin(), camera_text.end(), '\n'));
  auto error_for = [&](const std::string& section) {
    const std::string bad = write("bad.ini", camera_text + "[omni_camera_covariance]\n" + section);
    return input_error_of([&] { read_camera_covariance(bad); });
  };
  EXPECT_NE(error_for("parameters = mirror_rx nonsense\nrow_0 = 1 0\nrow_1 = 0 1\n")
                .find(":" + std::to_string(first + 1) + ": key 'parameters': the camera has no "
                      "parameter 'nonsense'"),
            std::string::npos);
  EXPECT_NE(error_for("parameters = mirror_rx mirror_ry\nrow_0 = 1 0\nrow_1 = 0\n")
                .find(":" + std::to_string(first + 3) + ": key 'row_1': expected 2 numbers"),
            std::string::npos);
  EXPECT_NE(error_for("parameters = mirror_rx mirror_ry\nrow_0 = 1 0.5\nrow_1 = 0 1\n")
                .find("not symmetric"),
            std::string::npos);
  EXPECT_NE(error_for("parameters = mirror_rx\nrow_0 = -1\n").find("negative"), std::string::npos);
  EXPECT_NE(error_for("parameters = mirror_rx\n").find("missing key 'row_0'"), std::string::npos);
  EXPECT_NE(error_for("parameters = mirror_rx\nrow_0 = 1\nextra = 2\n").find("key 'extra': unknown key"),
            std::string::npos);
}

}  // namespace
}  // namespace omnisfm::io
