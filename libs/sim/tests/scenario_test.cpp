// The simulated experiments match the paper's figures, are deterministic, and their files reproduce
// the noise-free tracks from the ground truth.

#include "omnisfm/sim/scenario.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <map>
#include <set>

#include "omnisfm/io/camera_file.h"
#include "omnisfm/io/tum_trajectory.h"
#include "omnisfm/io/vnlog.h"
#include "omnisfm/sim/dataset_writer.h"
#include "omnisfm/sim/track_simulator.h"
#include "omnisfm/sim/trajectories.h"

namespace omnisfm::sim {
namespace {

namespace fs = std::filesystem;

struct Expected {
  std::string scenario;
  size_t frames;
  double length;
  size_t points;
  size_t outliers;
};

class ScenarioFigures : public ::testing::TestWithParam<Expected> {};

TEST_P(ScenarioFigures, MatchThePaper) {
  const Expected& e = GetParam();
  SimulationOptions options;
  options.scenario = e.scenario;
  const Dataset d = simulate(options);
  EXPECT_EQ(d.world_from_cam.size(), e.frames);
  EXPECT_NEAR(path_length(d.world_from_cam), e.length, 1e-9);
  std::set<std::tuple<double, double, double>> distinct;
  for (const auto& p : d.track_points) distinct.insert({p.x(), p.y(), p.z()});
  EXPECT_EQ(distinct.size(), e.points);
  EXPECT_EQ(d.outliers.size(), e.outliers);
  // Every track has at least two observations and its frames increase.
  std::map<int, std::vector<int>> frames_of;
  for (const auto& o : d.observations) frames_of[o.track].push_back(o.frame);
  EXPECT_EQ(frames_of.size(), d.track_points.size());
  for (const auto& [track, frames] : frames_of) {
    EXPECT_GE(frames.size(), 2u) << track;
    for (size_t i = 1; i < frames.size(); ++i) EXPECT_EQ(frames[i], frames[i - 1] + 1);
  }
}

INSTANTIATE_TEST_SUITE_P(Paper, ScenarioFigures,
                         ::testing::Values(Expected{"lab", 41, 4.08, 44, 0},
                                           Expected{"crane", 140, 3.08, 32, 10},
                                           Expected{"rover", 150, 3.91, 112, 7}),
                         [](const auto& param_info) { return param_info.param.scenario; });

TEST(Scenario, DeterministicForASeed) {
  SimulationOptions options;
  options.scenario = "rover";
  const Dataset a = simulate(options), b = simulate(options);
  ASSERT_EQ(a.observations.size(), b.observations.size());
  for (size_t i = 0; i < a.observations.size(); ++i)
    ASSERT_EQ(a.observations[i].pixel, b.observations[i].pixel);
  options.seed = 2;
  const Dataset c = simulate(options);
  EXPECT_NE(a.track_points.front(), c.track_points.front());
}

TEST(Scenario, NoiseHasTheRequestedSpread) {
  SimulationOptions options;
  options.scenario = "rover";
  options.tracking_noise_px = 0.5;
  const Dataset d = simulate(options);
  std::map<int, int> outlier_frame;
  for (const auto& o : d.outliers) outlier_frame[o.track] = o.frame;
  double sum2 = 0;
  int n = 0;
  for (const auto& o : d.observations) {
    const auto bad = outlier_frame.find(o.track);
    if (bad != outlier_frame.end() && o.frame >= bad->second) continue;
    Eigen::Vector2d truth;
    ASSERT_TRUE(true_pixel(d, o.frame, d.track_points[o.track], &truth));
    sum2 += (o.pixel - truth).squaredNorm();
    n += 2;
  }
  EXPECT_NEAR(std::sqrt(sum2 / n), 0.5, 0.02);
}

// Tracks that never end, on the rover's drive. Lifted 1 km, the rig has the ground patch straight
// below, in the mirror's blind centre: an error rather than an endless search.
TEST(SteadyGroundTracks, SeenInEveryFrameOrRefused) {
  Dataset d{"rover", default_rig(1024, 768), {}, rover_trajectory(0.6), {}, {}, {}, {}, {}, {}};
  std::mt19937_64 rng(3);
  const auto tracks = steady_ground_tracks(d, 20, 0.0, rng);
  ASSERT_EQ(tracks.size(), 20 * d.world_from_cam.size());
  for (const auto& o : tracks) {
    EXPECT_TRUE(o.pixel.allFinite());
    EXPECT_TRUE(o.pixel.x() >= 0 && o.pixel.x() < 1024 && o.pixel.y() >= 0 && o.pixel.y() < 768);
  }
  for (auto& T : d.world_from_cam) T.translation().z() = 1000;
  EXPECT_THROW(steady_ground_tracks(d, 20, 0.0, rng), std::invalid_argument);
}

TEST(Scenario, RejectsNonsense) {
  SimulationOptions options;
  options.scenario = "moon";
  EXPECT_THROW(simulate(options), std::invalid_argument);
  options.scenario = "lab";
  options.tracking_noise_px = -1;
  EXPECT_THROW(simulate(options), std::invalid_argument);
  options.tracking_noise_px = 0.2;
  options.image_width = 0;
  EXPECT_THROW(simulate(options), std::invalid_argument);
}

class WrittenDataset : public ::testing::TestWithParam<std::string> {};

TEST_P(WrittenDataset, GroundTruthFilesReproduceNoiseFreeTracks) {
  SimulationOptions options;
  options.scenario = GetParam();
  options.tracking_noise_px = 0;
  const Dataset d = simulate(options);
  // Its own folder: one left by another run (or build) would be refused as not this run's.
  const std::string dir =
      ::testing::TempDir() + "/dataset-" + GetParam() + "-" + std::to_string(::getpid());
  fs::remove_all(dir);
  write_dataset(d, dir);

  // Read back only from the files, as another program would.
  const auto camera = io::read_camera_file(dir + "/camera.ini");
  const auto truth = io::read_tum_trajectory(dir + "/ground_truth.tum");
  const auto points = io::VnlogTable::read(dir + "/points_gt.vnl");
  const auto tracks = io::VnlogTable::read(dir + "/tracks.vnl");
  const auto outliers = io::VnlogTable::read(dir + "/outliers_gt.vnl");
  ASSERT_EQ(truth.size(), d.world_from_cam.size());
  std::map<int, Eigen::Vector3d> point_of;
  for (size_t r = 0; r < points.num_rows(); ++r)
    point_of[int(points.number(r, 0))] =
        Eigen::Vector3d(points.number(r, 1), points.number(r, 2), points.number(r, 3));
  std::map<int, int> outlier_frame;
  for (size_t r = 0; r < outliers.num_rows(); ++r)
    outlier_frame[int(outliers.number(r, 0))] = int(outliers.number(r, 1));
  EXPECT_EQ(outlier_frame.size(), d.outliers.size());

  int checked = 0;
  const auto cols = tracks.columns({"frame", "track", "u", "v"});
  for (size_t r = 0; r < tracks.num_rows(); ++r) {
    const int frame = int(tracks.number(r, cols[0])), track = int(tracks.number(r, cols[1]));
    const auto bad = outlier_frame.find(track);
    if (bad != outlier_frame.end() && frame >= bad->second) continue;
    const Eigen::Vector3d X_C = truth[frame].world_from_cam.inverse() * point_of.at(track);
    Eigen::Vector2d pixel;
    ASSERT_TRUE(camera.project(X_C, &pixel));
    EXPECT_NEAR(pixel.x(), tracks.number(r, cols[2]), 1e-9);
    EXPECT_NEAR(pixel.y(), tracks.number(r, cols[3]), 1e-9);
    ++checked;
  }
  EXPECT_GT(checked, 500);
  // A mistracked track really leaves its point.
  for (const auto& [track, frame] : outlier_frame) {
    double worst = 0;
    for (size_t r = 0; r < tracks.num_rows(); ++r) {
      if (int(tracks.number(r, cols[1])) != track || int(tracks.number(r, cols[0])) < frame)
        continue;
      const Eigen::Vector3d X_C =
          truth[int(tracks.number(r, cols[0]))].world_from_cam.inverse() * point_of.at(track);
      Eigen::Vector2d pixel;
      if (!camera.project(X_C, &pixel)) continue;
      worst = std::max(worst, (pixel - Eigen::Vector2d(tracks.number(r, cols[2]),
                                                       tracks.number(r, cols[3])))
                                  .norm());
    }
    EXPECT_GT(worst, 2.0) << "track " << track;
  }
  if (GetParam() == "lab") {
    const auto targets = io::VnlogTable::read(dir + "/targets.vnl");
    const auto observations = io::VnlogTable::read(dir + "/observations.vnl");
    EXPECT_EQ(targets.num_rows(), 44u);
    EXPECT_GE(observations.num_rows(), 4 * 40u);
  }
  fs::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(AllScenarios, WrittenDataset, ::testing::Values("lab", "crane", "rover"));

TEST(DatasetWriter, FailureLeavesNothingBehind) {
  const Dataset d = simulate({});
  EXPECT_THROW(write_dataset(d, "/nonexistent-folder/out"), std::runtime_error);
  const std::string dir = ::testing::TempDir() + "/failing";
  fs::remove_all(dir);
  EXPECT_THROW(write_dataset(d, dir,
                             [](int frame, const std::string&) {
                               if (frame == 3) throw std::runtime_error("disk full");
                             }),
               std::runtime_error);
  EXPECT_FALSE(fs::exists(dir));
  for (const auto& entry : fs::directory_iterator(::testing::TempDir()))
    EXPECT_EQ(entry.path().filename().string().find(".failing.partial"), std::string::npos);
  // Replacing a dataset swaps it whole.
  write_dataset(d, dir);
  write_dataset(d, dir);
  EXPECT_TRUE(fs::exists(dir + "/tracks.vnl"));
}

}  // namespace
}  // namespace omnisfm::sim
