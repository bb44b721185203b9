// The rover's outdoor variant as a rawlog, read back into the estimators' inputs: GPS fixes
// through NMEA and geodetic coordinates return to the simulated ENU positions, the receiver's
// noise to its sigmas, the odometry, gyro and tracks to what was simulated; a damaged rawlog gives
// its valid part and names the damaged object.

#include <gtest/gtest.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationImage.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <opencv2/imgcodecs.hpp>

#include "omnisfm/io/input_error.h"
#include "omnisfm/io/tum_trajectory.h"
#include "omnisfm/io/vnlog.h"
#include "omnisfm/mrpt_plugin/gps_fix_quality.h"
#include "omnisfm/mrpt_plugin/gps_ground_truth.h"
#include "omnisfm/mrpt_plugin/local_enu_frame.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/mrpt_plugin/rawlog_reader.h"
#include "omnisfm/mrpt_plugin/rawlog_replay_input.h"
#include "omnisfm/mrpt_plugin/simulated_rawlog.h"
#include "omnisfm/sim/scenario.h"
#include "serialization_helpers.h"

namespace omnisfm::mrpt_plugin {
namespace {

struct OutdoorRover {
  sim::Dataset dataset;
  SimulatedRawlogOptions options;
  std::string path;
};

const OutdoorRover& outdoor_rover() {
  static const OutdoorRover rover = [] {
    sim::SimulationOptions simulation;
    simulation.scenario = "rover";
    OutdoorRover r{sim::simulate(simulation), {}, {}};
    r.options.gps = sim::GpsOptions();
    r.path = testing::temporary_path("outdoor_rover.rawlog");
    write_simulated_rawlog(r.dataset, r.path, r.options);
    return r;
  }();
  return rover;
}

TEST(LocalEnuFrame, NorthIsTheMeridianArc) {
  // 0.001 degree of latitude is the WGS84 meridian's radius of curvature times the angle.
  const GeodeticPoint origin{40.4435, -79.9455, 280};
  const LocalEnuFrame enu(origin);
  const double a = 6378137.0, f = 1 / 298.257223563, e2 = f * (2 - f);
  const double s = std::sin(origin.latitude_deg * M_PI / 180);
  const double meridian_radius = a * (1 - e2) / std::pow(1 - e2 * s * s, 1.5);
  const Eigen::Vector3d north =
      enu.enu_of({origin.latitude_deg + 0.001, origin.longitude_deg, origin.height_m});
  EXPECT_NEAR(north.y(), (meridian_radius + origin.height_m) * 0.001 * M_PI / 180, 1e-3);
  EXPECT_NEAR(north.x(), 0, 1e-9);
  // The earth curves away below the tangent plane by d^2 / 2R.
  EXPECT_NEAR(north.z(), -north.y() * north.y() / (2 * meridian_radius), 1e-5);

  const Eigen::Vector3d somewhere(123.4, -56.7, 8.9);
  EXPECT_LT((enu.enu_of(enu.geodetic_of(somewhere)) - somewhere).norm(), 1e-8);
}

TEST(GpsFixQuality, StatesTheNoiseItWasGiven) {
  for (const double sigma : {0.02, 0.1, 0.3, 1.0, 4.0}) {
    const GpsFixQuality fix = gps_fix_quality_of(sigma, 2 * sigma);
    const GpsSigma back = gps_sigma_of(fix.fix_quality, fix.hdop, fix.vdop);
    EXPECT_NEAR(back.horizontal, sigma, 1e-12 * sigma) << sigma;
    EXPECT_NEAR(back.vertical, 2 * sigma, 1e-12 * sigma) << sigma;
    EXPECT_GE(fix.hdop, 0.5);
    EXPECT_LE(fix.hdop, 2 * std::sqrt(2.0)) << "a dilution a receiver would report";
  }
  EXPECT_EQ(gps_fix_quality_of(0.02, 0.04).fix_quality, 4) << "RTK fixed";
  EXPECT_EQ(gps_fix_quality_of(0.3, 0.6).fix_quality, 5) << "RTK float";
  EXPECT_EQ(gps_fix_quality_of(1.0, 2.0).fix_quality, 2) << "differential";
  EXPECT_EQ(gps_fix_quality_of(4.0, 8.0).fix_quality, 1) << "autonomous";
}

TEST(OutdoorRawlog, GgaMessagesHoldTheFixes) {
  const OutdoorRover& rover = outdoor_rover();
  const sim::GpsTrack truth = sim::simulate_gps(rover.dataset, *rover.options.gps);
  const LocalEnuFrame enu({truth.latitude_deg, truth.longitude_deg, truth.height_m});
  RawlogReader reader(rover.path);
  std::size_t fixes = 0;
  double previous = 0;
  while (const auto object = reader.next()) {
    const auto observation = std::dynamic_pointer_cast<mrpt::obs::CObservation>(object);
    ASSERT_TRUE(observation);
    const double t = mrpt::Clock::toDouble(observation->timestamp);
    EXPECT_GE(t, previous) << "time-ordered with the other sensors";
    previous = t;
    const auto gps = std::dynamic_pointer_cast<mrpt::obs::CObservationGPS>(object);
    if (!gps) continue;
    ASSERT_LT(fixes, truth.fixes.size());
    const auto& gga = gps->getMsgByClass<mrpt::obs::gnss::Message_NMEA_GGA>().fields;
    // Copies: MRPT packs the message's fields, and gtest binds references to what it compares.
    const int fix_quality = gga.fix_quality;
    const uint32_t satellites = gga.satellitesUsed;
    const double hdop = gga.HDOP;
    EXPECT_EQ(fix_quality, 4);
    EXPECT_EQ(satellites, 12u);
    EXPECT_NEAR(hdop, std::sqrt(2.0), 1e-6);
    const Eigen::Vector3d back =
        enu.enu_of({gga.latitude_degrees, gga.longitude_degrees, gga.altitude_meters});
    EXPECT_LT((back - truth.fixes[fixes].enu).norm(), 1e-6);
    EXPECT_DOUBLE_EQ(t, rover.options.start_time + truth.fixes[fixes].timestamp);
    ++fixes;
  }
  EXPECT_TRUE(reader.problem().empty()) << reader.problem();
  EXPECT_EQ(fixes, truth.fixes.size());
  EXPECT_EQ(fixes, 75u) << "1 Hz over 74.5 s";
}

TEST(OutdoorRawlog, ReplayInputIsWhatWasSimulated) {
  const OutdoorRover& rover = outdoor_rover();
  const sim::GpsTrack gps = sim::simulate_gps(rover.dataset, *rover.options.gps);
  const sim::DeadReckoning dead_reckoning =
      sim::simulate_dead_reckoning(rover.dataset, rover.options.sensors);
  ReplayOptions options;
  options.gps_origin = GeodeticPoint{gps.latitude_deg, gps.longitude_deg, gps.height_m};
  const ReplayInput in = read_replay_input(rover.path, options);
  EXPECT_TRUE(in.read.complete()) << in.read.problem;
  EXPECT_EQ(in.vision, "tracked features");

  ASSERT_EQ(in.tracks.size(), rover.dataset.observations.size());
  EXPECT_EQ(in.tracks[500].pixel, rover.dataset.observations[500].pixel);
  ASSERT_EQ(in.frame_times.size(), 150u);
  EXPECT_DOUBLE_EQ(in.frame_times[149], rover.options.start_time + rover.dataset.timestamps[149]);
  ASSERT_TRUE(in.camera);
  EXPECT_EQ(in.camera->params(), rover.dataset.camera.params());
  EXPECT_LT((in.sensors.body_from_cam.matrix() - dead_reckoning.body_from_cam.matrix()).norm(),
            1e-12);

  ASSERT_EQ(in.sensors.odometry.size(), dead_reckoning.odometry.size());
  for (std::size_t i = 0; i < in.sensors.odometry.size(); i += 50) {
    EXPECT_LT((in.sensors.odometry[i].pose - dead_reckoning.odometry[i].pose).norm(), 1e-12) << i;
    EXPECT_DOUBLE_EQ(in.sensors.odometry[i].timestamp,
                     rover.options.start_time + dead_reckoning.odometry[i].timestamp);
  }
  ASSERT_EQ(in.sensors.gyro.size(), dead_reckoning.gyro.size());
  EXPECT_LT((in.sensors.gyro[1234].rate - dead_reckoning.gyro[1234].rate).norm(), 1e-15);

  // About the simulation's own origin, the fixes come back where they were simulated.
  ASSERT_EQ(in.sensors.gps.size(), gps.fixes.size());
  for (std::size_t i = 0; i < gps.fixes.size(); ++i)
    EXPECT_LT((in.sensors.gps[i].enu - gps.fixes[i].enu).norm(), 1e-6) << i;
  EXPECT_NEAR(in.sensors.gps[0].horizontal_sigma, 0.02, 1e-8);
  EXPECT_NEAR(in.sensors.gps[0].vertical_sigma, 0.04, 1e-8);
  EXPECT_LT((in.sensors.antenna_in_body - gps.antenna_in_body).norm(), 1e-15);
  ASSERT_TRUE(in.gps_origin);
  EXPECT_EQ(in.gps_origin->latitude_deg, gps.latitude_deg);
}

TEST(OutdoorRawlog, WithoutAnOriginTheFirstFixIsIt) {
  const OutdoorRover& rover = outdoor_rover();
  const sim::GpsTrack gps = sim::simulate_gps(rover.dataset, *rover.options.gps);
  const ReplayInput in = read_replay_input(rover.path, ReplayOptions{});
  ASSERT_EQ(in.sensors.gps.size(), gps.fixes.size());
  EXPECT_LT(in.sensors.gps[0].enu.norm(), 1e-9);
  // Two tangent planes 4 m apart differ by 4 m / 6400 km in attitude: a few micrometres here.
  for (std::size_t i = 0; i < gps.fixes.size(); ++i)
    EXPECT_LT((in.sensors.gps[i].enu - (gps.fixes[i].enu - gps.fixes[0].enu)).norm(), 2e-5) << i;
}

TEST(OutdoorRawlog, GroundTruthInEnuAndGeodetic) {
  const OutdoorRover& rover = outdoor_rover();
  const sim::GpsTrack gps = sim::simulate_gps(rover.dataset, *rover.options.gps);
  const std::string dir = testing::temporary_path("outdoor_truth");
  std::filesystem::create_directories(dir);
  write_gps_ground_truth(rover.dataset, gps, rover.options.start_time, dir);
  const auto enu_truth = io::read_tum_trajectory(dir + "/ground_truth_enu.tum");
  const io::VnlogTable geodetic = io::VnlogTable::read(dir + "/ground_truth_geodetic.vnl");
  ASSERT_EQ(enu_truth.size(), 150u);
  ASSERT_EQ(geodetic.num_rows(), 150u);
  const LocalEnuFrame enu({gps.latitude_deg, gps.longitude_deg, gps.height_m});
  const auto cols = geodetic.columns({"timestamp", "latitude", "longitude", "height"});
  for (std::size_t f = 0; f < 150; f += 7) {
    const Eigen::Vector3d centre = gps.enu_from_world * rover.dataset.world_from_cam[f].translation();
    EXPECT_LT((enu_truth[f].world_from_cam.translation() - centre).norm(), 1e-9);
    const Eigen::Vector3d back = enu.enu_of(
        {geodetic.number(f, cols[1]), geodetic.number(f, cols[2]), geodetic.number(f, cols[3])});
    EXPECT_LT((back - centre).norm(), 1e-6) << f;
    EXPECT_DOUBLE_EQ(geodetic.number(f, cols[0]), enu_truth[f].timestamp);
  }
}

// A rawlog with both the images and the tracked features of every frame, read in one pass: kAuto
// takes the tracks (the images it may have started on are dropped), kImages tracks the images.
TEST(ReplayVision, AutoTakesTheTracksAndImagesModeTracksTheImages) {
  sim::SimulationOptions simulation;
  simulation.scenario = "lab";
  const sim::Dataset lab = sim::simulate(simulation);
  cv::Mat picture(lab.camera.image_height(), lab.camera.image_width(), CV_8UC1);
  for (int y = 0; y < picture.rows; ++y)
    for (int x = 0; x < picture.cols; ++x)
      picture.at<uint8_t>(y, x) = static_cast<uint8_t>((x * 7) ^ (y * 13));
  const std::string png = testing::temporary_path("replay_frame.png");
  ASSERT_TRUE(cv::imwrite(png, picture));
  SimulatedRawlogOptions rawlog;
  rawlog.image_file = [&](int) { return png; };
  const std::string path = testing::temporary_path("lab_images_and_tracks.rawlog");
  write_simulated_rawlog(lab, path, rawlog);

  const ReplayInput automatic = read_replay_input(path, ReplayOptions{});
  EXPECT_TRUE(automatic.read.complete()) << automatic.read.problem;
  EXPECT_EQ(automatic.vision, "tracked features");
  EXPECT_EQ(automatic.tracks.size(), lab.observations.size());
  EXPECT_EQ(automatic.frame_times.size(), 41u);
  EXPECT_EQ(automatic.frames_with_images, 0);

  ReplayOptions images;
  images.vision = ReplayVision::kImages;
  images.tracker.max_tracks = 20;
  std::vector<int> progress;
  const ReplayInput tracked = read_replay_input(path, images, [&](int done, int all) {
    EXPECT_EQ(all, 0);
    progress.push_back(done);
  });
  EXPECT_TRUE(tracked.read.complete()) << tracked.read.problem;
  EXPECT_EQ(tracked.vision, "images");
  EXPECT_EQ(tracked.frames_with_images, 41);
  ASSERT_EQ(tracked.frame_times.size(), 41u);
  EXPECT_EQ(tracked.frame_times, automatic.frame_times);
  ASSERT_EQ(progress.size(), 41u);
  EXPECT_EQ(progress.back(), 41);
  // The picture stands still: every track stays where it started, in every frame (within
  // 0.03 px: a template is smoothed as sampling between pixels smooths, and a still picture is
  // sampled at whole pixels, where it is not; measured 0.027 px at most).
  EXPECT_GE(tracked.tracks.size(), 41u * 15);
  EXPECT_EQ(tracked.tracks.back().frame, 40);
  std::map<int, Eigen::Vector2d> first;
  for (const auto& o : tracked.tracks)
    EXPECT_LT((o.pixel - first.try_emplace(o.track, o.pixel).first->second).norm(), 0.03)
        << "track " << o.track << " frame " << o.frame;
  // The motion sensors come with either.
  EXPECT_EQ(tracked.sensors.odometry.size(), automatic.sensors.odometry.size());
  EXPECT_GT(tracked.sensors.odometry.size(), 0u);
}

// An image that cannot be loaded, before the tracked features: with kAuto the images were not the
// vision, so the replay goes on to the tracks; with kImages it is damage at that object.
TEST(ReplayVision, AnUnloadableImageIsDamageOnlyWhenImagesAreTheVision) {
  mrpt::obs::CObservationImage image;
  image.image.setExternalStorage("no_such_image.png");
  CObservationTrackedFeatures features;
  for (int track = 0; track < 8; ++track) features.features.push_back({track, 100.0 + track, 200.0});
  const std::string path = testing::temporary_path("unloadable_image_then_tracks.rawlog");
  testing::write_plain_rawlog(path, {&image, &features});
  ReplayOptions options;
  options.camera = sim::default_rig(1024, 768);

  const ReplayInput automatic = read_replay_input(path, options);
  EXPECT_TRUE(automatic.read.complete()) << automatic.read.problem;
  EXPECT_EQ(automatic.vision, "tracked features");
  EXPECT_EQ(automatic.tracks.size(), 8u);

  options.vision = ReplayVision::kImages;
  const ReplayInput images = read_replay_input(path, options);
  EXPECT_EQ(images.read.objects, 0u);
  EXPECT_NE(images.read.problem.find("object 0"), std::string::npos) << images.read.problem;
  EXPECT_TRUE(images.tracks.empty());

  // With kAuto and no tracks after it, the images are the vision: the same damage.
  testing::write_plain_rawlog(path, {&image});
  options.vision = ReplayVision::kAuto;
  const ReplayInput only_image = read_replay_input(path, options);
  EXPECT_EQ(only_image.vision, "images");
  EXPECT_EQ(only_image.read.objects, 0u);
  EXPECT_NE(only_image.read.problem.find("object 0"), std::string::npos) << only_image.read.problem;
}

TEST(DamagedReplay, TheValidPartIsReplayedAndTheObjectNamed) {
  const OutdoorRover& rover = outdoor_rover();
  // The same objects, uncompressed, cut in the middle of object 3000.
  std::vector<mrpt::serialization::CSerializable::Ptr> objects;
  RawlogReader reader(rover.path);
  while (auto object = reader.next()) objects.push_back(object);
  std::vector<const mrpt::serialization::CSerializable*> raw;
  for (const auto& object : objects) raw.push_back(object.get());
  const std::string path = testing::temporary_path("damaged_rover.rawlog");
  const auto offsets = testing::write_plain_rawlog(path, raw);
  std::filesystem::resize_file(path, (offsets[3000] + offsets[3001]) / 2);
  std::size_t frames_before = 0;
  for (std::size_t i = 0; i < 3000; ++i)
    frames_before += std::dynamic_pointer_cast<CObservationTrackedFeatures>(objects[i]) ? 1 : 0;

  const ReplayInput in = read_replay_input(path, ReplayOptions{});
  EXPECT_FALSE(in.read.complete());
  EXPECT_NE(in.read.problem.find("object 3000"), std::string::npos) << in.read.problem;
  EXPECT_NE(in.read.problem.find("truncated"), std::string::npos) << in.read.problem;
  EXPECT_EQ(in.read.objects, 3000u);
  EXPECT_EQ(in.frame_times.size(), frames_before);
  EXPECT_GT(frames_before, 40u);
  EXPECT_LT(in.sensors.gyro.back().timestamp, rover.options.start_time + rover.dataset.timestamps.back());
}

// Camera frames that go back in time or share one time, or come from another pose on the robot
// under the same label, are refused with the file and the object (MRPT stamps an observation when
// it is made, so even a rig without a clock of its own gives each frame its time).
TEST(BadReplay, FramesOutOfTimeOrderOrFromAnotherCameraPoseAreRefused) {
  const auto frame = [](double time, double camera_height) {
    auto features = std::make_shared<CObservationTrackedFeatures>();
    features->timestamp = mrpt::Clock::fromDouble(time);
    features->sensorPose = mrpt::poses::CPose3D(0, 0, camera_height, 0, 0, 0);
    for (int track = 0; track < 8; ++track)
      features->features.push_back({track, 10.0 + track, 20.0});  // inside the small camera too
    return features;
  };
  ReplayOptions options;
  options.camera = sim::default_rig(1024, 768);
  const std::string path = testing::temporary_path("bad_frames.rawlog");
  const auto refusal = [&](const std::vector<std::shared_ptr<CObservationTrackedFeatures>>& frames) {
    std::vector<const mrpt::serialization::CSerializable*> raw;
    for (const auto& f : frames) raw.push_back(f.get());
    testing::write_plain_rawlog(path, raw);
    try {
      read_replay_input(path, options);
    } catch (const io::InputError& e) {
      return std::string(e.what());
    }
    return std::string();
  };

  EXPECT_EQ(refusal({frame(10, 1), frame(10.5, 1), frame(11, 1)}), "");
  // Two frames at one time: streamed, they were one time twice in online.tum, which eval refused.
  const std::string twice = refusal({frame(10, 1), frame(10, 1), frame(11, 1)});
  EXPECT_NE(twice.find("object 1: a camera frame at 10 s, the time of the one before: two frames "
                       "cannot share a time"),
            std::string::npos)
      << twice;
  const std::string backwards = refusal({frame(10, 1), frame(11, 1), frame(10.5, 1)});
  EXPECT_NE(backwards.find(path), std::string::npos) << backwards;
  EXPECT_NE(backwards.find("object 2: a camera frame at 10.5 s after one at 11 s: the observations "
                           "are out of time order"),
            std::string::npos)
      << backwards;
  const std::string moved = refusal({frame(10, 1), frame(11, 1.2)});
  EXPECT_NE(moved.find(path), std::string::npos) << moved;
  EXPECT_NE(moved.find("object 1: the camera's pose on the robot"), std::string::npos) << moved;
  EXPECT_NE(moved.find("is not the first frame's"), std::string::npos) << moved;

  // Images out of order, then tracked features: with kAuto the features are the vision and the
  // images' order does not matter; with kImages it is refused.
  const auto image = [](double time) {
    auto observation = std::make_shared<mrpt::obs::CObservationImage>();
    observation->timestamp = mrpt::Clock::fromDouble(time);
    observation->image = mrpt::img::CImage(64, 48, mrpt::img::CH_GRAY);
    return observation;
  };
  // A camera given for the rawlog's of other images: refused, naming the sizes.
  auto modelled = frame(10, 1);
  modelled->model.set_camera(sim::default_rig(320, 240));
  testing::write_plain_rawlog(path, {modelled.get()});
  try {
    read_replay_input(path, options);
    ADD_FAILURE() << "a 1024x768 camera was taken for 320x240 features";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("its camera is 320x240 pixels but the one given "
                                         "(--camera) is 1024x768"),
              std::string::npos)
        << e.what();
  }

  const auto late = image(11), early = image(10);
  const auto first = frame(12, 0), second = frame(13, 0);
  testing::write_plain_rawlog(path, {late.get(), early.get(), first.get(), second.get()});
  ReplayOptions small;
  small.camera = sim::default_rig(64, 48);
  const ReplayInput automatic = read_replay_input(path, small);
  EXPECT_EQ(automatic.vision, "tracked features");
  EXPECT_TRUE(automatic.read.complete()) << automatic.read.problem;
  small.vision = ReplayVision::kImages;
  try {
    read_replay_input(path, small);
    ADD_FAILURE() << "images out of time order were taken";
  } catch (const io::InputError& e) {
    EXPECT_NE(std::string(e.what()).find("object 1: a camera frame at 10 s after one at 11 s"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
