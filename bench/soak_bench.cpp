// Soak: the estimators over an endless drive (sim::EndlessDrive, 0.2 px; 100,000 frames, 3 km, by
// default), recording every 1,000 frames the resident memory, the time per frame and the errors.
// Memory or time per frame that grows with the frames shows here first.
//   BM_FilterSoak:    sfm::OnlineFilter on the tracks alone.
//   BM_EstimatorSoak: the MRPT front end (mrpt_plugin::OmniSfmEstimator) fed MRPT observations
//                     as a live robot would: wheel odometry (reading 1.5 % long) and a biased
//                     gyro (sim::DeadReckoningStream), then each frame's tracked features.
//   soak_bench [--benchmark_filter=...] [--soak_frames=N] [--soak_out=PREFIX]
// With --soak_out, each benchmark writes PREFIX<name>.vnl (bench/plot_soak.sh plots them):
//   frame distance_m rss_mb ms_per_frame block_error_percent block_scale drift_percent
//   rotation_error_deg nees live_points rejected
// block_error_percent: the mean position error over the last 1,000 frames after aligning them
// onto the truth (a similarity for the filter alone, whose scale is free; rigid with the wheels),
// in percent of their distance, and block_scale that alignment's scale; drift_percent: the
// current position error in the first frame's gauge, no alignment, in percent of the distance so
// far; rotation_error_deg: the current orientation's; nees: the current pose error's squared
// Mahalanobis distance under the published covariance (6 degrees of freedom: 6 on average when
// the covariance is honest).

#include <benchmark/benchmark.h>
#include <mrpt/math/wrap2pi.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>

#include "omnisfm/eval/filter_consistency.h"
#include "omnisfm/eval/trajectory_errors.h"
#include "omnisfm/io/vnlog.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/mrpt_plugin/omni_sfm_estimator.h"
#include "omnisfm/sfm/online_filter.h"
#include "omnisfm/sim/dead_reckoning.h"
#include "omnisfm/sim/endless_drive.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/sfm/blas_threads.h"

namespace {

using namespace omnisfm;

std::string soak_out;  // --soak_out=PREFIX
int soak_frames = 100000;

double resident_mb() {
  std::ifstream statm("/proc/self/statm");
  long pages = 0, resident = 0;
  statm >> pages >> resident;
  return static_cast<double>(resident) * static_cast<double>(sysconf(_SC_PAGESIZE)) / 1048576.0;
}

// The series and the counters of one soak.
class SoakRecord {
 public:
  static constexpr int kBlock = 1000;

  SoakRecord(const std::string& name, bool with_scale) : with_scale_(with_scale) {
    if (soak_out.empty()) return;
    file_ = std::make_unique<std::ofstream>(soak_out + name + ".vnl");
    series_ = std::make_unique<io::VnlogWriter>(
        *file_, std::vector<std::string>{"frame", "distance_m", "rss_mb", "ms_per_frame",
                                         "block_error_percent", "block_scale", "drift_percent",
                                         "rotation_error_deg", "nees", "live_points",
                                         "rejected"});
  }

  // One frame: its time in the estimator, and the estimated and true poses, world_from_cam in the
  // first frame's gauge.
  void frame(double seconds, const Eigen::Isometry3d& estimate, const Eigen::Isometry3d& truth,
             double nees, int live_points, long rejected) {
    ++frames_;
    if (frames_ > 1) distance_ += (truth.translation() - previous_.translation()).norm();
    previous_ = truth;
    block_seconds_ += seconds;
    block_estimate_.push_back(estimate);
    block_truth_.push_back(truth);
    if (frames_ % kBlock != 0) return;
    const eval::TrajectoryErrors e =
        eval::trajectory_errors(block_estimate_, block_truth_, with_scale_);
    const double drift = 100 * (estimate.translation() - truth.translation()).norm() / distance_;
    const double rotation =
        Eigen::AngleAxisd(estimate.linear().transpose() * truth.linear()).angle() * 180 / M_PI;
    const double ms = 1000 * block_seconds_ / kBlock, rss = resident_mb();
    if (frames_ == kBlock) rss_first_ = rss;
    if (frames_ > kBlock) block_ms_.push_back(ms);
    rss_last_ = rss;
    worst_rotation_ = std::max(worst_rotation_, rotation);
    worst_block_ = std::max(worst_block_, e.translation_error_percent);
    last_drift_ = drift;
    if (series_)
      series_->row({double(frames_), distance_, rss, ms, e.translation_error_percent,
                    e.alignment.scale, drift, rotation, nees, double(live_points),
                    double(rejected)});
    block_estimate_.clear();
    block_truth_.clear();
    block_seconds_ = 0;
  }

  // time_trend: the time per frame of the last ten blocks over that of the first ten after the
  // first (1 when flat).
  void counters(benchmark::State& state, long rejected) const {
    state.counters["rss_growth_mb"] = rss_last_ - rss_first_;
    const std::size_t n = std::min<std::size_t>(10, block_ms_.size());
    double first = 0, last = 0;
    for (std::size_t k = 0; k < n; ++k) {
      first += block_ms_[k] / n;
      last += block_ms_[block_ms_.size() - n + k] / n;
    }
    state.counters["ms_per_frame"] = first;
    state.counters["time_trend"] = n > 0 ? last / first : 0;
    state.counters["worst_block_error_pct"] = worst_block_;
    state.counters["final_drift_pct"] = last_drift_;
    state.counters["worst_rotation_deg"] = worst_rotation_;
    state.counters["rejected"] = static_cast<double>(rejected);
  }

 private:
  bool with_scale_;
  std::unique_ptr<std::ofstream> file_;
  std::unique_ptr<io::VnlogWriter> series_;
  long frames_ = 0;
  double distance_ = 0, block_seconds_ = 0;
  Eigen::Isometry3d previous_ = Eigen::Isometry3d::Identity();
  std::vector<Eigen::Isometry3d> block_estimate_, block_truth_;
  double rss_first_ = 0, rss_last_ = 0;
  std::vector<double> block_ms_;  // after the first block
  double worst_rotation_ = 0, worst_block_ = 0, last_drift_ = 0;
};

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

// The filter's pose error as its covariance states it: rotation as a left perturbation, then
// translation, of cam_from_world.
double filter_nees(const sfm::OnlineFilter& filter, const Eigen::Isometry3d& true_cam_from_world) {
  const Eigen::Matrix<double, 6, 1> e =
      eval::filter_pose_error(true_cam_from_world, filter.cam_from_world());
  return e.dot(filter.pose_covariance().ldlt().solve(e));
}

void BM_FilterSoak(benchmark::State& state) {
  const int frames = soak_frames;
  SoakRecord record("filter_soak", true);
  long rejected = 0;
  for (auto _ : state) {
    sim::EndlessDrive drive(sim::default_rig(1024, 768), 0.2, 1);
    sfm::OnlineFilter filter(drive.camera(), sfm::FilterSettings{});
    filter.on_track_rejected([&](const sfm::RejectedTrack&) { ++rejected; });
    Eigen::Isometry3d first_from_world = Eigen::Isometry3d::Identity();
    std::vector<sfm::TrackPixel> pixels;
    for (int f = 0; f < frames; ++f) {
      const sim::DriveFrame frame = drive.next();
      pixels.clear();
      for (const auto& o : frame.observations) pixels.push_back({o.track, o.pixel});
      const auto started = std::chrono::steady_clock::now();
      filter.process_frame(f, pixels);
      const double seconds = seconds_since(started);
      if (f == 0) first_from_world = frame.world_from_cam.inverse();
      const Eigen::Isometry3d truth = first_from_world * frame.world_from_cam;
      record.frame(seconds, filter.cam_from_world().inverse(), truth,
                   filter_nees(filter, truth.inverse()), filter.num_live_points(), rejected);
    }
  }
  record.counters(state, rejected);
}
BENCHMARK(BM_FilterSoak)->Iterations(1)->Unit(benchmark::kSecond);

mrpt::Clock::time_point clock_of(double t) { return mrpt::Clock::fromDouble(1e9 + t); }

void BM_EstimatorSoak(benchmark::State& state) {
  const int frames = soak_frames;
  SoakRecord record("estimator_soak", false);
  for (auto _ : state) {
    sim::EndlessDrive drive(sim::default_rig(1024, 768), 0.2, 1);
    // The drive's camera looks up: the body is the camera's frame.
    sim::DeadReckoningOptions sensors;
    sim::DeadReckoningStream dead_reckoning(Eigen::Isometry3d::Identity(), sensors, true);
    mrpt_plugin::OmniSfmEstimatorOptions options;
    options.camera = drive.camera();
    options.odometry_noise.position_sigma = sensors.odometry_position_noise;
    mrpt_plugin::OmniSfmEstimator estimator(options);
    estimator.enableMapUpdating(false);  // keyframes grow with distance: the soak measures the rest
    Eigen::Isometry3d first_from_world = Eigen::Isometry3d::Identity();
    std::vector<sim::OdometryReading> odometry;
    std::vector<sim::GyroReading> gyro;
    // A frame's features go in once the readings up to its time have: the stream gives those at
    // the frame's own time with the next frame, so each frame waits for the next one.
    sim::DriveFrame frame = drive.next(), coming;
    dead_reckoning.add_frame(frame.timestamp, frame.world_from_cam, &odometry, &gyro);
    for (int f = 0; f < frames; ++f) {
      coming = drive.next();
      dead_reckoning.add_frame(coming.timestamp, coming.world_from_cam, &odometry, &gyro);
      // MRPT's observations, as a sensor loop would deliver them; their making is not timed.
      std::vector<mrpt::obs::CObservation::Ptr> observations;
      const auto due = [&](double t) { return t <= frame.timestamp + 1e-9; };
      size_t used = 0;
      for (; used < odometry.size() && due(odometry[used].timestamp); ++used) {
        const sim::OdometryReading& r = odometry[used];
        auto o = std::make_shared<mrpt::obs::CObservationOdometry>();
        o->timestamp = clock_of(r.timestamp);
        o->odometry = mrpt::poses::CPose2D(r.pose.x(), r.pose.y(), r.pose.z());
        observations.push_back(o);
      }
      odometry.erase(odometry.begin(), odometry.begin() + static_cast<long>(used));
      for (used = 0; used < gyro.size() && due(gyro[used].timestamp); ++used) {
        const sim::GyroReading& r = gyro[used];
        auto o = std::make_shared<mrpt::obs::CObservationIMU>();
        o->timestamp = clock_of(r.timestamp);
        o->set(mrpt::obs::IMU_WX, r.rate.x());
        o->set(mrpt::obs::IMU_WY, r.rate.y());
        o->set(mrpt::obs::IMU_WZ, r.rate.z());
        observations.push_back(o);
      }
      gyro.erase(gyro.begin(), gyro.begin() + static_cast<long>(used));
      auto features = std::make_shared<mrpt_plugin::CObservationTrackedFeatures>();
      features->timestamp = clock_of(frame.timestamp);
      features->frame = f;
      for (const auto& o : frame.observations)
        features->features.push_back({o.track, o.pixel.x(), o.pixel.y()});
      observations.push_back(features);
      const auto started = std::chrono::steady_clock::now();
      for (const auto& o : observations) estimator.processObservation(o);
      mrpt::poses::CPose3DPDFGaussian pose;
      estimator.getCurrentPoseEstimation(pose);
      const double seconds = seconds_since(started);

      if (f == 0) first_from_world = frame.world_from_cam.inverse();
      const Eigen::Isometry3d truth = first_from_world * frame.world_from_cam;
      const Eigen::Isometry3d estimate(
          pose.mean.getHomogeneousMatrixVal<mrpt::math::CMatrixDouble44>().asEigen());
      const mrpt::poses::CPose3D true_pose(
          mrpt::math::CMatrixDouble44(Eigen::Matrix4d(truth.matrix())));
      Eigen::Matrix<double, 6, 1> e;
      e << true_pose.x() - pose.mean.x(), true_pose.y() - pose.mean.y(),
          true_pose.z() - pose.mean.z(), mrpt::math::wrapToPi(true_pose.yaw() - pose.mean.yaw()),
          mrpt::math::wrapToPi(true_pose.pitch() - pose.mean.pitch()),
          mrpt::math::wrapToPi(true_pose.roll() - pose.mean.roll());
      const Eigen::Matrix<double, 6, 6> cov = pose.cov.asEigen();
      const double nees = f == 0 ? 0 : e.dot(cov.ldlt().solve(e));
      record.frame(seconds, estimate, truth, nees, 0, 0);
      frame = std::move(coming);
    }
  }
  record.counters(state, 0);
}
BENCHMARK(BM_EstimatorSoak)->Iterations(1)->Unit(benchmark::kSecond);

}  // namespace

int main(int argc, char** argv) {
  omnisfm::sfm::use_one_blas_thread();  // as the omnisfm command runs the filter
  std::vector<char*> args;
  for (int i = 0; i < argc; ++i) {
    const auto value = [&](const char* prefix) -> const char* {
      return std::strncmp(argv[i], prefix, std::strlen(prefix)) == 0 ? argv[i] + std::strlen(prefix)
                                                                      : nullptr;
    };
    if (const char* out = value("--soak_out="))
      soak_out = out;
    else if (const char* frames = value("--soak_frames="))
      soak_frames = std::max(SoakRecord::kBlock, std::atoi(frames));
    else
      args.push_back(argv[i]);
  }
  int count = static_cast<int>(args.size());
  benchmark::Initialize(&count, args.data());
  if (benchmark::ReportUnrecognizedArguments(count, args.data())) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
