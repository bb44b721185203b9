// The real checkerboard sets (../shared/data/real-catadioptric beside the source tree, or
// $OMNISFM_REAL_DATA): calibrated from the shipped starting guesses, they converge to the RMS the
// README reports. Skipped when the data is absent.

#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>

#include "omnisfm/calib/calibration_views.h"
#include "omnisfm/calib/staged_calibration.h"
#include "omnisfm/io/camera_file.h"
#include "omnisfm/io/checkerboard_files.h"
#include "real_data_folder.h"

namespace omnisfm::calib {
namespace {

namespace fs = std::filesystem;

std::string real_data_folder() { return test::real_data_folder(std::getenv("OMNISFM_SOURCE_DIR")); }

struct RealCalibration {
  camera::CatadioptricCamera camera;
  StagedReport report;
};

RealCalibration calibrate_set(const std::string& set, const std::string& initial_camera) {
  const fs::path folder = fs::path(real_data_folder()) / set;
  std::vector<CalibrationView> views = board_views(
      io::read_corners((folder / "corners.vnl").string()),
      io::read_board((folder / "board.vnl").string()), "corners.vnl", "board.vnl");
  RealCalibration result{io::read_camera_file(std::string(std::getenv("OMNISFM_SOURCE_DIR")) +
                                              "/share/omnisfm/cameras/" + initial_camera),
                         {}};
  StagedSettings settings;
  settings.groups = {"mirror-pose", "intrinsics", "mirror-shape"};
  result.report = calibrate_in_stages(&result.camera, &views, settings);
  return result;
}

class RealData : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::getenv("OMNISFM_SOURCE_DIR") || !fs::is_directory(real_data_folder()))
      GTEST_SKIP() << "no real data at '" << real_data_folder() << "'";
  }
};

TEST_F(RealData, VmrConvergesFromTheDatasheetGuess) {
  const RealCalibration c = calibrate_set("vmr", "vmr-initial.ini");
  ASSERT_TRUE(c.report.final.converged) << c.report.final.message;
  // OpenCV's omnidir reaches 0.2352 px per coordinate on these corners.
  EXPECT_LT(c.report.final.rms_px, 0.2360);
  EXPECT_EQ(c.report.final.num_outliers, 0);
  EXPECT_EQ(c.report.final.num_observations, 420);
  EXPECT_NEAR(c.camera.params()[0], 900, 100);  // fx: far from the guess's 771
}

TEST_F(RealData, ParacatadioptricConvergesFromTheDatasheetGuess) {
  const RealCalibration c = calibrate_set("paracatadioptric", "paracatadioptric-initial.ini");
  ASSERT_TRUE(c.report.final.converged) << c.report.final.message;
  EXPECT_LT(c.report.final.rms_px, 0.48);
  EXPECT_LT(c.report.final.num_outliers, 30);  // mostly the outer corners of two views
  EXPECT_EQ(c.report.final.num_observations, 480);
}

}  // namespace
}  // namespace omnisfm::calib
