// The report folder: its text names what happened, its tables hold every residual, and gnuplot
// draws its plots.

#include "omnisfm/calib/calibration_report.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>

#include "omnisfm/io/vnlog.h"
#include "synthetic_boards.h"

namespace omnisfm::calib {
namespace {

namespace fs = std::filesystem;

class CalibrationReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() / ("omnisfm-report-" + std::to_string(::getpid()));
    fs::remove_all(folder_);
    views_ = testing::board_views(testing::true_hyperbolic_rig(), 8, 0.2, 3);
    views_[2].pixels[5] += Eigen::Vector2d(6, -4);  // a corner detected on the wrong spot
    camera_ = std::make_unique<camera::CatadioptricCamera>(testing::nominal_hyperbolic_rig());
    StagedSettings settings;
    settings.groups = {"mirror-pose", "intrinsics"};
    report_ = calibrate_in_stages(camera_.get(), &views_, settings);
    uncertainty_ = projection_uncertainty(*camera_, report_.estimated, views_,
                                          report_.final.joint_covariance, 0.4, 32);
    outcome_.inputs = {"camera nominal", "corners synthetic"};
    outcome_.camera_file = "calibrated.ini";
    outcome_.camera = camera_.get();
    outcome_.report = &report_;
    outcome_.views = &views_;
    outcome_.uncertainty = &uncertainty_;
  }
  void TearDown() override { fs::remove_all(folder_); }

  fs::path folder_;
  std::vector<CalibrationView> views_;
  std::unique_ptr<camera::CatadioptricCamera> camera_;
  StagedReport report_;
  UncertaintyMap uncertainty_;
  CalibrationOutcome outcome_;
};

TEST_F(CalibrationReportTest, TextSaysWhatHappened) {
  ASSERT_TRUE(report_.final.converged);
  ASSERT_EQ(report_.final.num_outliers, 1);
  const std::string text = report_text(outcome_);
  for (const char* expected :
       {"status: converged", "camera file: calibrated.ini", "corners synthetic",
        "estimated (9): fx fy cx cy mirror_rx", "outliers: 1",
        "board 2                     42            1 ",   // per view: observations, outliers
        "board 2                     5     556.39",      // the outlier, by board index
        "conic_kappa         -2              fixed", "mirror_tz           0.", "+- ",
        "fixed relative to the calibration objects"}) {
    EXPECT_NE(text.find(expected), std::string::npos) << "missing '" << expected << "' in\n"
                                                      << text;
  }
}

TEST_F(CalibrationReportTest, FolderHoldsEveryResidualAndThePlots) {
  const std::string note = write_calibration_report(folder_.string(), outcome_);
  EXPECT_TRUE(fs::exists(folder_ / "report.txt"));
  const io::VnlogTable residuals = io::VnlogTable::read((folder_ / "residuals.vnl").string());
  EXPECT_EQ(residuals.column_names(),
            (std::vector<std::string>{"view", "name", "point", "x", "y", "du", "dv", "outlier"}));
  EXPECT_EQ(residuals.num_rows(), 8u * 42u);
  int outliers = 0;
  for (std::size_t row = 0; row < residuals.num_rows(); ++row) {
    if (residuals.text(row, 7) == "1") {
      ++outliers;
      EXPECT_EQ(residuals.text(row, 1), "board_2");
      EXPECT_EQ(residuals.text(row, 2), "5");
    }
  }
  EXPECT_EQ(outliers, 1);
  const io::VnlogTable map = io::VnlogTable::read((folder_ / "uncertainty.vnl").string());
  EXPECT_EQ(map.num_rows(), static_cast<std::size_t>(uncertainty_.columns * uncertainty_.rows));

  if (std::system("gnuplot --version > /dev/null 2>&1") != 0) GTEST_SKIP() << "no gnuplot";
  EXPECT_EQ(note, "");
  for (const char* png : {"residuals.png", "histogram.png", "uncertainty.png"}) {
    ASSERT_TRUE(fs::exists(folder_ / png)) << png;
    EXPECT_GT(fs::file_size(folder_ / png), 10000u) << png;
  }
}

}  // namespace
}  // namespace omnisfm::calib
