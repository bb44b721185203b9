#include "omnisfm/sfm/pipeline.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>

#include "omnisfm/core/pose_direction.h"
#include "omnisfm/core/pose_vector.h"
#include "omnisfm/io/number_text.h"
#include "omnisfm/sfm/settings_ranges.h"
#include "omnisfm/sfm/sfm_report.h"
#include "omnisfm/sfm/track_consistency.h"
#include "omnisfm/sfm/track_triangulation.h"
#include "pipeline_steps.h"

namespace omnisfm::sfm {
namespace {

// Below this baseline, as a fraction of the scene's median depth, motion counts as rotation only.
constexpr double kMinBaselineRatio = 0.01;

}  // namespace

double SfmSettings::batch_residual_limit_px() const {
  if (!batch_outliers) return 0;
  return filter.outlier_test == OutlierTest::kPixels ? batch_outlier_threshold_px
                                                     : filter.residual_limit_px();
}

std::vector<std::vector<TrackPixel>> observations_by_frame(
    const std::vector<core::TrackObservation>& tracks) {
  int num_frames = 0;
  for (const auto& o : tracks) num_frames = std::max(num_frames, o.frame + 1);
  if (num_frames < 2) throw std::invalid_argument("the tracks span fewer than 2 frames");
  std::vector<std::vector<TrackPixel>> by_frame(num_frames);
  for (const auto& o : tracks) by_frame[o.frame].push_back({o.track, o.pixel});
  if (by_frame[0].size() < 6) {
    // Frames count the images from 0: tracks that start later leave frame 0 empty.
    int first = 0;
    while (by_frame[first].empty()) ++first;
    throw std::invalid_argument(
        "frame 0 has " + std::to_string(by_frame[0].size()) +
        " tracks; at least 6 are needed to start" +
        (first > 0 ? " (frames count the images from 0; the first with tracks is " +
                         std::to_string(first) + ")"
                   : ""));
  }
  return by_frame;
}

std::vector<Eigen::Isometry3d> run_filter(const camera::CatadioptricCamera& camera,
                                          const std::vector<std::vector<TrackPixel>>& by_frame,
                                          const FilterSettings& settings,
                                          const PredictedMotion& predicted_motion,
                                          const Progress& progress, SfmResult* result) {
  const auto started = std::chrono::steady_clock::now();
  FilterSettings collected = settings;
  collected.kept_history = 0;  // every ended point and rejection is collected here instead
  OnlineFilter filter(camera, collected);
  filter.on_point_ended(
      [result](int track, const Eigen::Vector3d& point) { result->online_points[track] = point; });
  filter.on_track_rejected([result](const RejectedTrack& rejected) {
    result->outliers.push_back(rejected);
    result->online_points.erase(rejected.track);
  });
  filter.on_motion_refused([result](int frame) { result->refused_motion_frames.push_back(frame); });
  const int num_frames = static_cast<int>(by_frame.size());
  std::vector<Eigen::Isometry3d> cam_from_world;
  for (int f = 0; f < num_frames; ++f) {
    if (f > 0 && predicted_motion)
      filter.process_frame(f, by_frame[f], predicted_motion(f, filter.sensor_states()));
    else
      filter.process_frame(f, by_frame[f]);
    cam_from_world.push_back(filter.cam_from_world());
    if (progress) progress(f + 1, num_frames);
  }
  filter.finish_start();
  // A lasting fault names the frames that led up to it late.
  std::sort(result->refused_motion_frames.begin(), result->refused_motion_frames.end());
  result->online_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  for (const auto& [frame, T] : filter.smoothed_start()) cam_from_world[frame] = T;
  result->online_world_from_cam = core::inverted(cam_from_world);
  for (const auto& [track, point] : filter.points()) result->online_points[track] = point;
  result->online_gyro_bias = filter.gyro_bias();
  const Eigen::Vector3d bias_variance = filter.gyro_bias_covariance().diagonal();
  if ((bias_variance.array() > 0).all()) result->online_gyro_bias_sigma = bias_variance.cwiseSqrt();
  result->online_wheel_scale = filter.wheel_scale();
  result->online_noise_px = filter.pixel_sigma();
  if (filter.wheel_scale_variance() > 0)
    result->online_wheel_scale_sigma = std::sqrt(filter.wheel_scale_variance());
  return cam_from_world;
}

int tracks_seen_twice(const std::vector<core::TrackObservation>& tracks) {
  std::map<int, int> sightings;
  for (const auto& o : tracks) ++sightings[o.track];
  return static_cast<int>(std::count_if(sightings.begin(), sightings.end(),
                                        [](const auto& s) { return s.second >= 2; }));
}

void refuse_degenerate_motion(const SfmResult& result, const FilterSettings& settings,
                              bool odometry) {
  // Without translation the points' depths are not observable: refuse rather than report a
  // structure made of the initialisation's guesses.
  double baseline = 0, depth = 0;
  const Eigen::Vector3d first = result.online_world_from_cam.front().translation();
  for (const auto& T : result.online_world_from_cam)
    baseline = std::max(baseline, (T.translation() - first).norm());
  std::vector<double> depths;
  for (const auto& [track, X] : result.online_points) depths.push_back((X - first).norm());
  if (!depths.empty()) {
    std::nth_element(depths.begin(), depths.begin() + depths.size() / 2, depths.end());
    depth = depths[depths.size() / 2];
  }
  if (baseline > kMinBaselineRatio * depth) return;
  // A filter held still by its walk sees every track off.
  const std::string held_still = odometry ? ""
                                          : "[sfm] translation_walk_sigma, " +
                                                io::format_double(settings.translation_walk_sigma) +
                                                " per frame, may hold it still";
  // With most tracks rejected the filter's motion is no evidence of the camera's.
  const std::string rejected =
      most_rejected_phrase(static_cast<long>(result.outliers.size()), result.num_tracks,
                           result.online_noise_px, settings);
  if (!rejected.empty())
    throw std::runtime_error("the filter failed: " + rejected + "; its camera moves " +
                             std::to_string(baseline) + " filter units" +
                             (held_still.empty() ? "" : " (" + held_still + ")"));
  throw std::runtime_error(
      "degenerate motion: the camera moves " + std::to_string(baseline) +
      " (filter units) against a median point distance of " + std::to_string(depth) +
      "; with (nearly) pure rotation the structure cannot be recovered" +
      (held_still.empty() ? "" : " (if the camera did move: " + held_still + ")"));
}

namespace {

// The batch's poses as its parameters hold them: what it projected with, bit for bit.
std::vector<Eigen::Isometry3d> cam_from_world_of(const std::vector<core::PoseVector>& parameters) {
  std::vector<Eigen::Isometry3d> poses;
  for (const core::PoseVector& v : parameters) poses.push_back(core::isometry_of(v));
  return poses;
}

// Of the tracks `rejected` (the filter's rejections, or those it never held), those the poses
// explain: triangulated from them, every pixel within `threshold` px. Track -> its point.
std::map<int, Eigen::Vector3d> explained_rejections(
    const camera::CatadioptricCamera& optimised, const std::vector<core::TrackObservation>& tracks,
    const std::set<int>& rejected, const std::vector<Eigen::Isometry3d>& batch_cam_from_world,
    double threshold) {
  std::map<int, std::vector<TrackSighting>> sightings;
  for (const auto& o : tracks)
    if (rejected.count(o.track) && o.frame < static_cast<int>(batch_cam_from_world.size()))
      sightings[o.track].push_back({batch_cam_from_world[o.frame], o.pixel});
  std::map<int, Eigen::Vector3d> explained;
  for (const auto& [track, seen] : sightings) {
    const TriangulatedTrack t = triangulate_track(optimised, seen);
    if (t.valid && t.largest_residual_px <= threshold) explained[track] = t.point;
  }
  return explained;
}

// Why the batch's solution cannot judge the tracks, or empty: a solve that failed, or one whose
// residuals are on average beyond what a single pixel may reach (a start too far off leaves the
// solve in a minimum that explains few tracks, and re-testing against it would reject the rest).
std::string retest_problem(const BatchResult& batch, std::size_t num_frames, double threshold) {
  if (batch.world_from_cam.size() < num_frames) return "the batch failed";
  if (!std::isfinite(batch.final_rms_px))
    return "the batch's solve ended without a usable solution";
  if (batch.final_rms_px > threshold) {
    std::ostringstream why;
    why << "the batch's solution fits the tracks only to " << batch.final_rms_px
        << " px per coordinate, beyond the " << threshold
        << " px a pixel may be off (its start, the filter's, was too far off)";
    return why.str();
  }
  return "";
}

// The batch's re-test: with its solution, the tracks it kept that the whole sequence cannot
// explain, and the tracks the filter rejected that it does.
struct TrackRetest {
  std::map<int, int> failing;                 // kept track -> the frame it fails at
  std::map<int, Eigen::Vector3d> explained;  // left-out track -> its point
};

TrackRetest retest_tracks(const camera::CatadioptricCamera& optimised,
                         const std::vector<core::TrackObservation>& tracks,
                         const std::set<int>& kept, const std::set<int>& left_out,
                         const BatchResult& batch, double threshold, bool threshold_follows_noise,
                         double false_alarm, double stated_noise_px) {
  const std::vector<Eigen::Isometry3d> cam_from_world =
      cam_from_world_of(batch.cam_from_world_parameters);
  // A track's residual and its derivative by the point, at one sighting.
  const auto residual_at = [&](const core::TrackObservation& o, const Eigen::Vector3d& point,
                               Eigen::Vector2d* residual, Eigen::Matrix<double, 2, 3>* by_point) {
    Eigen::Vector2d pixel;
    if (!optimised.project(cam_from_world[o.frame] * point, &pixel, by_point)) return false;
    *residual = pixel - o.pixel;
    *by_point = *by_point * cam_from_world[o.frame].linear();
    return true;
  };
  TrackRetest retest;
  // A kept track fails from the first frame it is found to.
  const auto fail_at = [&retest](int track, int frame) {
    const auto [at, first] = retest.failing.emplace(track, frame);
    if (!first) at->second = std::min(at->second, frame);
  };
  std::map<int, TrackResidualSum> residual_sums;
  for (const auto& o : tracks) {
    if (!kept.count(o.track)) continue;
    const auto point = batch.points.find(o.track);
    Eigen::Vector2d residual;
    Eigen::Matrix<double, 2, 3> by_point;
    if (point != batch.points.end() && residual_at(o, point->second, &residual, &by_point))
      residual_sums[o.track].add(o.frame, residual, by_point);
    else
      fail_at(o.track, o.frame);  // not projected there
  }
  // Those that fit at every frame but not over their length (slow drifts).
  const bool whole_track_test = false_alarm > 0;
  InconsistentTracks drifting;
  if (whole_track_test) drifting = inconsistent_tracks(residual_sums, false_alarm, stated_noise_px);
  // Those beyond the residual limit at a frame. Under the chi-square rule the limit is that many
  // sigmas of the tracks' own noise where it is larger than stated: tracks noisier than
  // pixel_sigma says would otherwise fail wholesale (0.5 px noise at the default 0.3 px rejected
  // 515 good tracks of 1,480 in 20 courtyards).
  const double measured = whole_track_test ? drifting.measured_noise_px
                                           : measured_track_noise_px(residual_sums);
  const double limit = threshold_follows_noise && measured > stated_noise_px
                           ? threshold * measured / stated_noise_px
                           : threshold;
  for (const auto& [track, sum] : residual_sums) {
    if (!(sum.worst_px > limit)) continue;
    for (size_t j = 0; j < sum.frames.size(); ++j)
      if (sum.residuals_px[j].norm() > limit) {
        fail_at(track, sum.frames[j]);
        break;
      }
  }
  for (const auto& [track, frame] : drifting.tracks) retest.failing.emplace(track, frame);
  // The left-out tracks it explains, unless they drift too.
  retest.explained = explained_rejections(optimised, tracks, left_out, cam_from_world, limit);
  if (whole_track_test) {
    std::map<int, TrackResidualSum> explained_sums;
    for (const auto& o : tracks) {
      const auto point = retest.explained.find(o.track);
      Eigen::Vector2d residual;
      Eigen::Matrix<double, 2, 3> by_point;
      if (point != retest.explained.end() && o.frame < static_cast<int>(cam_from_world.size()) &&
          residual_at(o, point->second, &residual, &by_point))
        explained_sums[o.track].add(o.frame, residual, by_point);
    }
    for (const auto& [track, sum] : explained_sums)
      if (exceeds_its_noise(sum, drifting.noise_px, drifting.ramp_noise_px, false_alarm))
        retest.explained.erase(track);
  }
  return retest;
}

}  // namespace

void adjust_on_inliers(const camera::CatadioptricCamera& camera,
                       const std::vector<core::TrackObservation>& tracks, const SfmSettings& settings,
                       const std::vector<Eigen::Isometry3d>& online_cam_from_world,
                       ExtraTerms* extra, SfmResult* result) {
  std::set<int> rejected, kept;
  for (const auto& r : result->outliers) rejected.insert(r.track);
  for (const auto& o : tracks)
    if (!rejected.count(o.track) && result->online_points.count(o.track)) kept.insert(o.track);
  const auto observations_of = [&tracks](const std::set<int>& of) {
    std::vector<core::TrackObservation> chosen;
    for (const auto& o : tracks)
      if (of.count(o.track)) chosen.push_back(o);
    return chosen;
  };
  if (kept.empty()) {
    const std::string why =
        most_rejected_phrase(static_cast<long>(rejected.size()), result->num_tracks,
                             result->online_noise_px, settings.filter);
    throw std::runtime_error(
        "no track is left for the batch adjustment: " +
        (why.empty() ? "the filter rejected all " + std::to_string(rejected.size()) + " as outliers"
                     : why));
  }
  // The tracks' noise, the filter's: the stated one, or what it measured where that is more
  // (FilterSettings::measure_noise). It weighs the pixels against the sensors' terms (alone it is
  // not read: the camera's prior is weighed at the noise the batch measures).
  const double noise_px = result->online_noise_px;
  BatchSettings batch = settings.batch;
  batch.pixel_sigma = noise_px;
  // Tracks the filter had no room for: placed from its poses, as rejected ones are re-tested. A
  // track seen once has no point anywhere (OnlineFilter::points) and nothing to place.
  std::map<int, int> sightings;
  for (const auto& o : tracks) ++sightings[o.track];
  std::set<int> unplaced;
  for (const auto& [track, n] : sightings)
    if (n >= 2 && !rejected.count(track) && !result->online_points.count(track))
      unplaced.insert(track);
  std::map<int, Eigen::Vector3d> online_start = result->online_points;
  result->not_in_filter = static_cast<int>(unplaced.size());
  if (!unplaced.empty()) {
    // Without the batch's outlier test (a limit of 0) every track that triangulates is taken.
    const double limit =
        settings.batch_residual_limit_px() * noise_px / settings.filter.pixel_sigma;
    const std::map<int, Eigen::Vector3d> placed =
        explained_rejections(batch_camera(camera), tracks, unplaced, online_cam_from_world,
                             limit > 0 ? limit : std::numeric_limits<double>::infinity());
    for (const auto& [track, point] : placed) {
      online_start[track] = point;
      kept.insert(track);
    }
    result->placed_by_triangulation = static_cast<int>(placed.size());
    // The rest no pose explains: outliers, named at their first frame.
    for (const auto& o : tracks)
      if (unplaced.count(o.track) && !placed.count(o.track)) {
        result->outliers.push_back({o.track, o.frame});
        rejected.insert(o.track);
        unplaced.erase(o.track);
      }
  }
  result->batch = batch_adjust_with_terms(camera, observations_of(kept), online_cam_from_world,
                                          online_start, batch, extra);
  // Under the chi-square rule the limit is in sigmas of that noise (the filter measures only
  // there; under the pixels rule it is the stated one and the limit stays as set).
  const bool follows_noise = settings.filter.outlier_test == OutlierTest::kChiSquare &&
                             settings.filter.measure_noise;
  const double threshold =
      settings.batch_residual_limit_px() * noise_px / settings.filter.pixel_sigma;
  if (threshold <= 0) return;
  result->retest_skipped =
      retest_problem(result->batch, online_cam_from_world.size(), threshold);
  if (!result->retest_skipped.empty()) return;

  // With the camera as the batch left it.
  camera::CatadioptricCamera optimised = batch_camera(camera);
  if (result->batch.camera_refined && !optimised.set_params(result->batch.camera_params))
    throw std::runtime_error("the batch's refined camera is not a valid camera");
  const TrackRetest retest =
      retest_tracks(optimised, tracks, kept, rejected, result->batch, threshold, follows_noise,
                    settings.batch_track_false_alarm, noise_px);
  if (retest.failing.empty() && retest.explained.empty()) return;
  for (const auto& [track, frame] : retest.failing) kept.erase(track);
  for (const auto& [track, point] : retest.explained) kept.insert(track);
  std::map<int, Eigen::Vector3d> start_points = result->batch.points;
  for (const auto& [track, point] : retest.explained) start_points[track] = point;
  BatchResult rerun = batch_adjust_with_terms(
      camera, observations_of(kept), cam_from_world_of(result->batch.cam_from_world_parameters),
      start_points, batch, extra);
  // A rerun whose solve failed (a track taken back that no longer projects) is no judgement of
  // the tracks: the first solve and the filter's rejections stand.
  if (!rerun.usable()) {
    result->retest_skipped = "the batch with the re-tested tracks failed: " + rerun.message;
    return;
  }
  std::vector<RejectedTrack> outliers;
  for (const auto& r : result->outliers)
    if (!retest.explained.count(r.track)) outliers.push_back(r);
  for (const auto& [track, frame] : retest.failing) outliers.push_back({track, frame});
  result->outliers = std::move(outliers);
  result->taken_back = static_cast<int>(retest.explained.size());
  result->batch = std::move(rerun);
}

void check_settings(const camera::CatadioptricCamera& camera, const SfmSettings& settings) {
  if (const std::string problem = settings_problem(settings); !problem.empty())
    throw std::invalid_argument("SfmSettings: " + problem);
  // A flag asking for a camera prior, the prior it asks for, and their names.
  const auto check = [&camera](bool flag, const char* flag_name, const CameraPrior& prior,
                               const char* prior_name) {
    if (flag && prior.empty())
      throw std::invalid_argument(std::string(flag_name) + ": no " + prior_name +
                                  " (camera_prior_from makes it from the camera file's "
                                  "[omni_camera_covariance])");
    if (const std::string wrong = camera_prior_problem(camera, prior); !wrong.empty())
      throw std::invalid_argument(std::string(prior_name) + ": " + wrong);
  };
  check(settings.refine_camera, "refine_camera", settings.batch.camera_prior, "batch.camera_prior");
  check(settings.consider_camera, "consider_camera", settings.filter.camera_uncertainty,
        "filter.camera_uncertainty");
  if (!(settings.batch_track_false_alarm >= 0 && settings.batch_track_false_alarm < 1))
    throw std::invalid_argument("batch_track_false_alarm: " +
                                std::to_string(settings.batch_track_false_alarm) +
                                " is not a probability below 1 (0 turns the test off)");
}

SfmResult run_sfm(const camera::CatadioptricCamera& camera,
                  const std::vector<core::TrackObservation>& tracks, const SfmSettings& settings,
                  const Progress& progress) {
  check_settings(camera, settings);
  SfmResult result;
  const std::vector<std::vector<TrackPixel>> by_frame = observations_by_frame(tracks);
  result.num_frames = static_cast<int>(by_frame.size());
  result.num_tracks = tracks_seen_twice(tracks);

  const std::vector<Eigen::Isometry3d> online_cam_from_world =
      run_filter(camera, by_frame, settings.filter, nullptr, progress, &result);
  refuse_degenerate_motion(result, settings.filter, false);
  if (settings.run_batch)
    adjust_on_inliers(camera, tracks, settings, online_cam_from_world, nullptr, &result);
  return result;
}

}  // namespace omnisfm::sfm
