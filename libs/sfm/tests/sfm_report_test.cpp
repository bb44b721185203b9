#include "omnisfm/sfm/sfm_report.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>

#include "omnisfm/sim/scenario.h"

namespace omnisfm::sfm {
namespace {

bool has(const std::string& text, const std::string& part) {
  return text.find(part) != std::string::npos;
}

TEST(SfmReport, ScaleLineSaysHeldWhereverTheBatchHeldIt) {
  SfmResult result;
  BatchSettings settings;
  settings.known_distance_m = 4.2;
  result.batch.scale_sigma_relative = 0.031;
  result.batch.scale_source = BatchScale::kFromImages;
  const std::string free = scale_line(result, settings);
  EXPECT_EQ(free.rfind("scale: from the images, +- 3.1 %", 0), 0u) << free;
  EXPECT_FALSE(has(free, "held")) << free;
  result.batch.scale_sigma_relative_camera_held = 0.084;
  result.batch.scale_sigma_relative = 0.28;
  EXPECT_EQ(scale_line(result, settings),
            "scale: from the images, +- 28 % (1 sigma, with the camera refined; kept free as the "
            "images fix it to +- 8.4 % with the camera as calibrated, within a factor 2 at 3 "
            "sigma)\n");
  result.batch.scale_sigma_relative_camera_held = NAN;
  result.batch.scale_source = BatchScale::kHeldAtStart;
  result.batch.scale_sigma_relative = 0.8;
  const std::string at_start = scale_line(result, settings);
  EXPECT_TRUE(has(at_start, "held at the filter's")) << at_start;
  EXPECT_TRUE(has(at_start, "+- 80 %")) << at_start;
  result.batch.scale_source = BatchScale::kHeldAtKnownDistance;
  result.batch.scale_sigma_relative = INFINITY;
  const std::string known = scale_line(result, settings);
  EXPECT_TRUE(has(known, "held at the known distance, 4.2 m")) << known;
  EXPECT_TRUE(has(known, "do not fix it at all")) << known;
  for (BatchScale source : {BatchScale::kFromImages, BatchScale::kHeldAtStart,
                            BatchScale::kHeldAtKnownDistance, BatchScale::kFromSensors,
                            BatchScale::kNoTranslation}) {
    result.batch.scale_source = source;
    const std::string line = scale_line(result, settings);
    EXPECT_EQ(line.rfind("scale: ", 0), 0u) << line;
    EXPECT_EQ(line.back(), '\n') << line;
  }
}

TEST(SfmReport, OutliersPhraseCountsWhatTheBatchTookBack) {
  SfmResult result;
  result.outliers.resize(3);
  EXPECT_EQ(outliers_phrase(result, 0.3), "outlier tracks 3");
  result.taken_back = 2;
  EXPECT_EQ(outliers_phrase(result, 0.3),
            "outlier tracks 3 (the batch took back 2 that the filter had rejected)");
  result.online_noise_px = 0.3;
  EXPECT_EQ(outliers_phrase(result, 0.3),
            "outlier tracks 3 (the batch took back 2 that the filter had rejected)");
  result.online_noise_px = 0.52;
  EXPECT_EQ(outliers_phrase(result, 0.3),
            "outlier tracks 3 (the batch took back 2 that the filter had rejected) (judged at the "
            "tracks' measured noise, 0.52 px per coordinate, where pixel_sigma says 0.3)");
}

// A run that rejected most of its tracks is said to be one (a pixel_sigma 20 times below the
// tracks' noise rejected 112 of the rover's 116 with exit 0 and a report that only counted them).
TEST(SfmReport, MostRejectedLineWarnsOnlyWhereMostTracksWentAndSaysWhy) {
  FilterSettings settings;
  settings.pixel_sigma = 0.01;
  EXPECT_EQ(most_rejected_line(5, 10, 0.01, settings), "");  // half: no warning
  EXPECT_EQ(most_rejected_line(5, 9, 0.01, settings), "");   // too few to judge
  EXPECT_EQ(most_rejected_line(0, 0, NAN, settings), "");
  // The noise taken at its cap, ten times pixel_sigma: the stated noise is the likeliest cause.
  const std::string capped = most_rejected_line(112, 116, 0.1, settings);
  EXPECT_EQ(capped.rfind("warning: 112 of 116 tracks were rejected as outliers: the tracks are "
                         "noisier than 10 times [sfm] pixel_sigma (0.01 px)",
                         0),
            0u)
      << capped;
  EXPECT_TRUE(has(capped, "the results are not to be trusted\n")) << capped;
  EXPECT_EQ(most_rejected_phrase(112, 116, 0.1, settings) + "; the results are not to be trusted\n",
            capped.substr(std::string("warning: ").size()));
  // The noise measured below the cap: not the noise.
  settings.pixel_sigma = 0.3;
  const std::string lost = most_rejected_line(6, 10, 0.3, settings);
  EXPECT_TRUE(has(lost, "6 of 10 tracks")) << lost;
  EXPECT_TRUE(has(lost,
                  "the estimate lost its way (the tracks' noise taken at 0.3 px), or "
                  "outlier_chi2 (27.6) is too strict"))
      << lost;
  // A replay that ended before the filter measured any noise reports none (NaN): the stated one.
  EXPECT_TRUE(has(most_rejected_line(6, 10, NAN, settings), "noise taken at 0.3 px"));
  settings.measure_noise = false;
  EXPECT_TRUE(has(most_rejected_line(6, 10, 0.3, settings),
                  "may be far noisier than [sfm] "
                  "pixel_sigma (0.3 px) says"));
  // The paper's fixed bound in pixels.
  settings.outlier_test = OutlierTest::kPixels;
  EXPECT_TRUE(has(most_rejected_line(6, 10, 0.3, settings),
                  "[sfm] outlier_threshold_px (2 px) is too strict for the tracks"));
}

TEST(SfmReport, RefusedMotionLineListsTheFramesAndWhatWasDone) {
  EXPECT_EQ(refused_motion_line(0, {}, true), "");
  EXPECT_EQ(refused_motion_line(1, {75}, true),
            "motion sensors refused: in 1 frame the images showed the motion the vehicle's "
            "sensors predicted wrong, grossly or for good (a jump, a spike, a misdated reading, a "
            "sensor stuck): frame 75; the filter took its own prediction there "
            "(constant velocity, or where the fault lasted the random walk) and the batch left "
            "those readings out\n");
  std::vector<int> many;
  for (int f = 1; f <= 12; ++f) many.push_back(10 * f);
  const std::string listed = refused_motion_line(12, many, true);
  EXPECT_NE(listed.find("in 12 frames"), std::string::npos) << listed;
  EXPECT_NE(listed.find("frames 10, 20, 30, 40, 50, 60, 70, 80, 90, 100, ...;"), std::string::npos)
      << listed;
  const std::string streamed = refused_motion_line(3, {}, false);
  EXPECT_NE(streamed.find("in 3 frames"), std::string::npos) << streamed;
  EXPECT_EQ(streamed.find("batch"), std::string::npos) << streamed;
  EXPECT_EQ(streamed.find("frame "), std::string::npos) << streamed;
}

TEST(SfmReport, RefusedFixesPhraseGivesTheirTimes) {
  MotionSensors sensors;
  for (int i = 0; i < 14; ++i) sensors.gps.push_back({1000.5 + i, Eigen::Vector3d::Zero()});
  EXPECT_EQ(refused_fixes_phrase(sensors, {}), "");
  EXPECT_EQ(refused_fixes_phrase(sensors, {3}),
            "; 1 fix refused, at odds with the rest as the filter's trajectory places them (at "
            "1003.5 s)");
  std::vector<int> all(14);
  for (int i = 0; i < 14; ++i) all[i] = i;
  EXPECT_NE(refused_fixes_phrase(sensors, all)
                .find("; 14 fixes refused, at odds with the rest as the filter's trajectory "
                      "places them (at 1000.5, 1001.5, "),
            std::string::npos);
  EXPECT_NE(refused_fixes_phrase(sensors, all).find("1009.5, ... s)"), std::string::npos)
      << refused_fixes_phrase(sensors, all);
}

TEST(SfmReport, BatchLineGivesTheSolveAndItsResiduals) {
  BatchResult batch;
  batch.converged = true;
  batch.iterations = 7;
  batch.solve_seconds = 0.25;
  batch.initial_rms_px = 1.5;
  batch.final_rms_px = 0.2;
  batch.message = "Function tolerance reached.";
  EXPECT_EQ(batch_line(batch), "batch: converged in 7 iterations, 0.25 s; RMS 1.5 -> 0.2 px per "
                               "coordinate (Function tolerance reached.)\n");
  batch.converged = false;
  EXPECT_TRUE(has(batch_line(batch), "batch: did not converge in 7"));
}

TEST(SfmReport, CameraLineGivesEachRefinedParametersMoveInSigmas) {
  const camera::CatadioptricCamera camera = sim::default_rig(1024, 768);
  const std::vector<std::string> names = camera.param_names();
  const int tz = static_cast<int>(std::find(names.begin(), names.end(), "mirror_tz") -
                                  names.begin());
  const int fx = static_cast<int>(std::find(names.begin(), names.end(), "fx") - names.begin());
  BatchSettings settings;
  BatchResult batch;
  EXPECT_EQ(camera_line(camera, batch, settings), "");  // no prior: nothing to say
  settings.camera_prior.parameters = {tz, fx};
  settings.camera_prior.covariance = Eigen::Vector2d(1e-8, 0.25).asDiagonal();
  batch.scale_source = BatchScale::kFromImages;
  batch.camera_refined = true;
  batch.camera_params = camera.params();
  batch.camera_params(tz) += 2e-4;  // 2 sigmas
  batch.camera_params(fx) -= 0.75;  // -1.5 sigmas
  EXPECT_EQ(camera_line(camera, batch, settings),
            "camera: refined under the calibration's covariance: mirror_tz +0.0002 (2.00 sigma), "
            "fx -0.75 (-1.50 sigma); 2.50 sigmas from the calibration in all\n");
  // Not refined, the line says why.
  batch.camera_refined = false;
  EXPECT_EQ(camera_line(camera, batch, settings),
            "camera: held as calibrated: the refining solve failed\n");
  batch.scale_source = BatchScale::kHeldAtStart;
  EXPECT_EQ(camera_line(camera, batch, settings),
            "camera: held as calibrated: the images do not fix the scale, which the mirror's size "
            "would take up\n");
  batch.scale_source = BatchScale::kNoTranslation;
  EXPECT_EQ(camera_line(camera, batch, settings),
            "camera: held as calibrated: no camera moves from the first\n");
}

}  // namespace
}  // namespace omnisfm::sfm
