#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>

#include "geodetic_output.h"
#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/camera_file.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/tum_trajectory.h"
#include "omnisfm/mrpt_plugin/online_replay.h"
#include "omnisfm/mrpt_plugin/rawlog_replay_input.h"
#include "omnisfm/sfm/fused_pipeline.h"
#include "omnisfm/sfm/sfm_report.h"
#include "omnisfm/mrpt_plugin/scene_file.h"
#include "omnisfm/mrpt_plugin/slam_rawlog.h"
#include "online_outputs.h"
#include "run_settings.h"
#include "sfm_outputs.h"
#include "terminal_progress.h"
#include "verb_inputs.h"
#include "verbs.h"

namespace omnisfm::app {
namespace {

std::string sensors_line(const mrpt_plugin::ReplayInput& in) {
  std::ostringstream line;
  line << "motion sensors: " << in.sensors.odometry.size() << " odometry, "
       << in.sensors.gyro.size() << " gyro, " << in.sensors.gps.size() << " GPS readings";
  if (in.gps_origin)
    line << " (ENU origin " << in.gps_origin->latitude_deg << " " << in.gps_origin->longitude_deg
         << " " << in.gps_origin->height_m << ")";
  if (in.out_of_order > 0)
    line << "; " << in.out_of_order
         << " dropped, out of time order (or dated far ahead of their neighbours)";
  line << "\n"
       << "fusion: " << (in.sensors.empty() ? "none: vision alone" : "the sensors with vision")
       << "\n";
  return line.str();
}

// Whether the stated noise models fit the fused batch's residuals.
std::string noise_check_line(const sfm::BatchResult& batch) {
  std::ostringstream line;
  line << std::setprecision(3) << "noise models: chi-square per degree of freedom "
       << batch.variance_factor
       << " (1 when [sfm] pixel_sigma and the [run] sensor noise hold; the covariances take "
          "them as stated)\n";
  return line.str();
}

// What the batch estimated of the sensors themselves: the wheels' scale (for later runs'
// [run] odometry_scale) and the gyro's bias.
std::string motion_estimates_line(const sfm::MotionSensors& sensors, const sfm::SfmResult& result) {
  std::ostringstream line;
  line << std::setprecision(6);
  const auto plus_minus = [&](double sigma) {
    if (std::isfinite(sigma)) line << " +- " << sigma;
  };
  if (!sensors.odometry.empty()) {
    line << "odometry scale " << result.odometry_scale;
    plus_minus(result.odometry_scale_sigma);
    line << " (true distance per distance read; started at " << sensors.odometry_scale;
    if (sensors.odometry_noise.scale_sigma > 0)
      line << " +- " << 100 * sensors.odometry_noise.scale_sigma << " %)\n";
    else
      line << ", held)\n";
  }
  if (!sensors.gyro.empty()) {
    line << "gyro bias " << result.gyro_bias.x() << " " << result.gyro_bias.y() << " "
         << result.gyro_bias.z() << " rad/s";
    if (result.gyro_bias_sigma.allFinite())
      line << " +- " << result.gyro_bias_sigma.x() << " " << result.gyro_bias_sigma.y() << " "
           << result.gyro_bias_sigma.z();
    line << " (body axes)\n";
  }
  return line.str();
}

mrpt_plugin::SceneContents scene_of(const sfm::SfmResult& result, bool batch_ran) {
  mrpt_plugin::SceneContents scene;
  scene.online_world_from_cam = result.online_world_from_cam;
  if (batch_ran) {
    scene.world_from_cam = result.batch.world_from_cam;
    scene.points = result.batch.points;
    scene.point_covariances = result.batch.point_covariances;
  } else {
    scene.world_from_cam = scene.online_world_from_cam;
    scene.online_world_from_cam.clear();
    scene.points = result.online_points;
  }
  return scene;
}

// A damaged rawlog (`problem` not empty) is an error with --strict, else a warning; fewer than two
// camera frames before the damage or the end leave nothing to replay.
void check_replayed(const std::string& rawlog, const std::string& problem, std::size_t frames,
                    bool strict, const std::string& replayed) {
  if (!problem.empty() && strict) throw io::InputError(rawlog, 0, problem);
  if (frames < 2)
    throw io::InputError(rawlog, 0,
                         "holds " + std::to_string(frames) +
                             " camera frames (tracked features or images) before its end: "
                             "nothing to replay" +
                             (problem.empty() ? "" : " (" + problem + ")"));
  if (!problem.empty())
    std::cerr << "omnisfm: warning: " << io::printable_text(rawlog + ": " + problem) << "; "
              << replayed << " the " << frames << " frames before it\n";
}

// `[sfm] batch = false`: the rawlog replayed through the online estimator object by object and
// the results written as they come, in constant memory. Returns the report.
std::string stream_online_run(const std::string& rawlog, const RunSettings& settings, bool strict,
                              const std::string& dir) {
  OnlineOutputs out(dir);
  mrpt_plugin::OnlineReplaySettings replay;
  replay.replay = settings.replay;
  replay.filter = settings.sfm.filter;
  replay.filter.kept_history = 0;  // the outputs take what leaves
  replay.odometry_noise = settings.odometry_noise;
  replay.gyro_noise = settings.gyro_noise;
  replay.odometry_scale = settings.odometry_scale;
  mrpt_plugin::OnlineReplayOutputs outputs;
  outputs.frame = [&](const sfm::OnlineFilter& f, int frame, double time) {
    out.frame(f, frame, time, replay.filter.smoothed_start_frames);
  };
  // The filter lives only as long as the replay: what it holds, and its bias, are taken at its end.
  std::optional<Eigen::Vector3d> bias, bias_sigma;
  long not_admitted = 0, refused_motions = 0;
  outputs.end = [&](const sfm::OnlineFilter& f) {
    out.take_what_is_held(f);
    not_admitted = f.not_admitted();
    refused_motions = f.refused_motions();
    bias = f.gyro_bias();
    bias_sigma = f.gyro_bias_covariance().diagonal().cwiseSqrt();
  };
  outputs.point_ended = [&](int track, const Eigen::Vector3d& p) { out.point(track, p); };
  outputs.track_rejected = [&](const sfm::RejectedTrack& r) { out.outlier(r); };
  TerminalProgress progress("filter", "frames");
  const mrpt_plugin::OnlineReplaySummary summary =
      mrpt_plugin::replay_online(rawlog, replay, outputs, progress.callback());
  check_replayed(rawlog, summary.read.problem, bias ? summary.frames : 0, strict, "replayed");
  if (refused_motions > 0)
    std::cerr << "omnisfm: warning: " << sfm::refused_motion_line(refused_motions, {}, false);
  // Every track seen twice ends as a point or an outlier.
  const std::string most_rejected = sfm::most_rejected_line(
      out.outliers(), out.points() + out.outliers(), summary.noise_px, settings.sfm.filter);
  std::cerr << (most_rejected.empty() ? "" : "omnisfm: " + most_rejected);
  std::ostringstream report;
  if (!summary.read.complete()) report << "rawlog damaged: " << summary.read.problem << "\n";
  report << "rawlog " << rawlog << ": " << summary.read.objects << " objects; vision from "
         << summary.vision << "\n"
         << "frames " << summary.frames << ", outlier tracks " << out.outliers()
         << sfm::not_admitted_phrase(not_admitted)
         << sfm::measured_noise_phrase(summary.noise_px, settings.sfm.filter.pixel_sigma) << "\n"
         << most_rejected << "motion sensors: " << summary.odometry << " odometry, " << summary.gyro
         << " gyro, " << summary.gps
         << " GPS readings (GPS needs the batch: the filter takes odometry and "
            "gyro)\n"
         << sfm::refused_motion_line(refused_motions, {}, false)
         << "online only ([sfm] batch = false): the rawlog read and results written object by "
            "object (no scene.3Dscene, geodetic.vnl or residual plots)\n";
  if (settings.replay.camera)
    report << sfm::considered_camera_line(*settings.replay.camera, settings.sfm.filter);
  if (summary.gyro > 0) {
    const Eigen::Vector3d& b = *bias;
    const Eigen::Vector3d& sigma = *bias_sigma;
    report << "gyro bias (the filter's, at the last frame) " << b.x() << " " << b.y() << " "
           << b.z() << " rad/s +- " << sigma.x() << " " << sigma.y() << " " << sigma.z()
           << " (body axes)\n";
  }
  out.finish(report.str());
  return report.str();
}

// `--slam-rawlog`: the batch's estimate for stock SLAM apps, into `file` (the rawlog `path` once
// renamed). Returns the report's line.
std::string write_slam_rawlog(const std::string& file, const std::string& path,
                              const mrpt_plugin::ReplayInput& in, const sfm::SfmResult& result) {
  if (result.batch.cam_from_world_covariances.empty())
    throw std::runtime_error(path + ": not written: the batch computed no covariances");
  const mrpt_plugin::SlamRawlogSummary summary = mrpt_plugin::write_slam_rawlog(
      file, *in.camera, in.tracks, result.batch, in.frame_times, in.sensors.body_from_cam,
      result.batch.final_rms_px);
  using Summary = mrpt_plugin::SlamRawlogSummary;
  std::ostringstream line;
  line << std::setprecision(3) << "slam rawlog " << path << ": " << summary.frames << " frames, "
       << summary.measurements << " landmark measurements; their sigmas, median and 95 %:";
  const auto quantiles = [&](const std::vector<double>& sigmas, double unit, const char* name) {
    line << " " << name << " " << Summary::quantile(sigmas, 0.5) * unit << ", "
         << Summary::quantile(sigmas, 0.95) * unit;
  };
  quantiles(summary.range_sigmas, 1, "range (m)");
  quantiles(summary.yaw_sigmas, 180 / M_PI, "yaw (deg)");
  quantiles(summary.pitch_sigmas, 180 / M_PI, "pitch (deg)");
  line << " (kf-slam weighs all alike: std_sensor_range, std_sensor_yaw_deg and "
          "std_sensor_pitch_deg at the 95 % values)\n";
  return line.str();
}

struct RunVerbOptions {
  std::string rawlog, out, config, camera, ground_truth, slam_rawlog;
  bool strict = false;
};

void add_run_options(CLI::App* verb, RunVerbOptions* o) {
  verb->add_option("rawlog", o->rawlog, "The rawlog (either format, gzip-compressed or not)")
      ->required();
  verb->add_option("--out", o->out,
                   "Output folder: made, or replaced whole when an earlier omnisfm run wrote it (a "
                   "folder holding other files, or the inputs, is refused)")
      ->required();
  verb->add_option("--config", o->config,
                   "Settings: an INI file with [sfm] (as the sfm verb) and [run] sections (the "
                   "shipped config/omnisfm.ini holds every key at its default)");
  verb->add_option("--camera", o->camera,
                   "Camera file; needed for stock CObservationImage, and replaces the models "
                   "the rawlog carries");
  verb->add_option("--ground-truth", o->ground_truth,
                   "A TUM trajectory of the truth, one pose per frame: adds the error figures "
                   "(after a similarity and a rigid alignment) and plots");
  verb->add_flag("--strict", o->strict,
                 "A damaged rawlog, or GPS fixes too few or on a line to place the estimate, is an "
                 "error (exit 2), not a warning");
  verb->add_option("--slam-rawlog", o->slam_rawlog,
                   "Also write the batch's estimate as a rawlog of stock MRPT classes for stock "
                   "SLAM apps (kf-slam with share/omnisfm/config/kf-slam-6d.ini): per frame the "
                   "robot's increment with its covariance (CActionRobotMovement3D) and the "
                   "tracks' points as range, yaw and pitch from the camera "
                   "(CObservationBearingRange, landmark id = track id); needs the batch");
}

// The settings file with the command line's camera, its calibration's covariance where asked
// for, and what --slam-rawlog needs; refused combinations name the file.
RunSettings run_settings_of(const RunVerbOptions& o) {
  RunSettings settings = read_run_settings(o.config);
  if (!o.slam_rawlog.empty() && io::lies_within(o.slam_rawlog, o.out))
    throw io::InputError(o.slam_rawlog, 0,
                         "is inside the --out folder, which the run replaces whole: put it "
                         "beside it");
  if (!o.slam_rawlog.empty()) {
    require_writable_folder_of(o.slam_rawlog);
    require_not_an_input(o.slam_rawlog, {o.rawlog, o.config, o.camera, o.ground_truth});
  }
  if (!o.camera.empty()) settings.replay.camera = io::read_camera_file(o.camera);
  apply_camera_prior(o.config, o.camera,
                     settings.replay.camera ? &*settings.replay.camera : nullptr, &settings.sfm);
  if (o.slam_rawlog.empty()) return settings;
  if (!settings.sfm.run_batch)
    throw io::InputError(o.config, 0,
                         "--slam-rawlog needs the batch's covariances: [sfm] batch = false "
                         "leaves none");
  if (!settings.sfm.batch.covariances)
    throw io::InputError(o.config, 0,
                         "--slam-rawlog needs the batch's covariances: [sfm] covariances = "
                         "false leaves none");
  // The points' uncertainty as the cameras see them (the measurements' ranges).
  settings.sfm.batch.point_cam_from_world_covariances = true;
  return settings;
}

// The report's lines on the replay, the fusion and the batch.
std::string batch_run_report(const RunVerbOptions& o, const RunSettings& settings,
                             const mrpt_plugin::ReplayInput& in, const sfm::SfmResult& result) {
  std::ostringstream report;
  if (!in.read.complete()) report << "rawlog damaged: " << in.read.problem << "\n";
  report << "rawlog " << o.rawlog << ": " << in.read.objects << " objects; vision from "
         << in.vision << "\n"
         << "frames " << result.num_frames << ", observations " << in.tracks.size() << ", "
         << sfm::outliers_phrase(result, settings.sfm.filter.pixel_sigma) << "\n"
         << sfm::most_rejected_line(static_cast<long>(result.outliers.size()), result.num_tracks,
                                    result.online_noise_px, settings.sfm.filter)
         << sensors_line(in)
         << sfm::refused_motion_line(static_cast<long>(result.refused_motion_frames.size()),
                                     result.refused_motion_frames, settings.sfm.run_batch)
         << sfm::considered_camera_line(*in.camera, settings.sfm.filter)
         << sfm::batch_line(result.batch) << sfm::scale_line(result, settings.sfm.batch)
         << sfm::camera_line(*in.camera, result.batch, settings.sfm.batch)
         << (in.sensors.empty() ? "" : noise_check_line(result.batch))
         << motion_estimates_line(in.sensors, result);
  return report.str();
}

// The rawlog replayed whole, fused by the filter and the batch, and every output written.
void run_with_batch(const RunVerbOptions& o, const RunSettings& settings,
                    const std::vector<io::StampedPose>& truth) {
  mrpt_plugin::ReplayInput in = [&] {
    TerminalProgress progress("tracked", "images");
    return mrpt_plugin::read_replay_input(o.rawlog, settings.replay, progress.callback());
  }();
  check_replayed(o.rawlog, in.read.problem, in.frame_times.size(), o.strict, "replaying");
  if (!in.camera)
    throw io::InputError(o.rawlog, 0,
                         "carries no camera model (stock CObservationImage): give --camera");
  in.sensors.odometry_noise = settings.odometry_noise;
  in.sensors.odometry_scale = settings.odometry_scale;
  in.sensors.gyro_noise = settings.gyro_noise;

  sfm::SfmResult result;
  try {
    TerminalProgress progress("filter", "frames");
    // Fixes that cannot place the estimate in ENU (a straight drive, a rawlog cut short) are
    // left out, as a damaged rawlog's end is: said, and an error with --strict.
    sfm::SfmSettings fused = settings.sfm;
    fused.leave_out_unplaceable_gps = !o.strict;
    result = sfm::run_fused_sfm(*in.camera, in.tracks, in.frame_times, in.sensors, fused,
                                progress.callback());
  } catch (const std::invalid_argument& e) {
    throw io::InputError(o.rawlog, 0, e.what());
  }
  // Camera frames after the last one with tracks have no pose: their times go too.
  in.frame_times.resize(result.num_frames);
  const std::string gps_left_out =
      result.gps_left_out.empty() ? ""
                                  : result.gps_left_out +
                                        ": the fixes are left out, the estimate stays in the first "
                                        "camera's frame";
  if (!gps_left_out.empty())
    std::cerr << "omnisfm: warning: " << io::printable_text(o.rawlog + ": " + gps_left_out) << "\n";
  if (!result.refused_gps_fixes.empty())
    std::cerr << "omnisfm: warning: GPS"
              << sfm::refused_fixes_phrase(in.sensors, result.refused_gps_fixes) << "\n";
  if (!result.refused_motion_frames.empty())
    std::cerr << "omnisfm: warning: "
              << sfm::refused_motion_line(static_cast<long>(result.refused_motion_frames.size()),
                                          result.refused_motion_frames, true);
  const std::string most_rejected =
      sfm::most_rejected_line(static_cast<long>(result.outliers.size()), result.num_tracks,
                              result.online_noise_px, settings.sfm.filter);
  std::cerr << (most_rejected.empty() ? "" : "omnisfm: " + most_rejected);
  if (!result.batch.usable())
    throw std::runtime_error("the batch adjustment failed: " + result.batch.message);

  std::ostringstream report;
  if (!gps_left_out.empty()) report << "warning: " << gps_left_out << "\n";
  report << batch_run_report(o, settings, in, result);
  const std::vector<Eigen::Isometry3d>& trajectory = result.batch.world_from_cam;
  // With fixes the fused estimate is in their ENU frame (run_fused_sfm places it there).
  const bool geodetic = in.gps_origin && result.world_is_enu;
  if (geodetic) {
    const sfm::GpsResiduals gps = sfm::gps_residuals(result.batch.world_from_cam, in.frame_times,
                                                     in.sensors, result.refused_gps_fixes);
    report << "GPS: the estimate is in ENU; " << gps.fixes << " fixes, RMS " << gps.rms_m
           << " m against it" << sfm::refused_fixes_phrase(in.sensors, result.refused_gps_fixes)
           << "\n";
  }
  eval::TruthComparison comparison;
  if (!truth.empty()) {
    comparison = eval::compare_with_truth(result, true, truth, o.ground_truth, true);
    report << comparison.report;
  }

  const auto write_outputs = [&] {
    io::write_folder_atomically(o.out, [&](const std::string& dir) {
      write_sfm_outputs(dir, result, true, in.frame_times, report.str());
      write_refined_camera(dir, *in.camera, result.batch, settings.sfm.batch);
      mrpt_plugin::write_scene_file(dir + "/scene.3Dscene", scene_of(result, true));
      if (geodetic)
        write_geodetic_trajectory(dir + "/geodetic.vnl", trajectory, in.frame_times,
                                  mrpt_plugin::LocalEnuFrame(*in.gps_origin));
      write_sfm_plots(dir, *in.camera, in.tracks, result, true, comparison);
    });
  };
  if (o.slam_rawlog.empty()) {
    write_outputs();
  } else {
    // The rawlog is written first (the report names it) and takes its place only once the
    // folder has: a failure in either leaves both as they were.
    io::write_atomically(o.slam_rawlog, [&](const std::string& temporary) {
      report << write_slam_rawlog(temporary, o.slam_rawlog, in, result);
      write_outputs();
    });
  }
  std::cout << report.str();
}

}  // namespace

void add_run_verb(CLI::App& app) {
  auto o = std::make_shared<RunVerbOptions>();
  CLI::App* verb = app.add_subcommand(
      "run",
      "Replay an MRPT rawlog with fusion: the camera's "
      "tracked features or its images through the tracker, wheel odometry, a gyro and GPS "
      "fixes; writes what the sfm verb writes plus scene.3Dscene (for SceneViewer3D) and, with "
      "GPS, geodetic.vnl. A truncated or corrupt rawlog is replayed up to the damaged object: a "
      "warning names the object's index and what is wrong, and report.txt repeats it "
      "(--strict: exit 2 instead, writing nothing); so are GPS fixes too few or on a line (a "
      "straight drive) to place the estimate, which is then left in the first camera's frame. "
      "With [sfm] batch = false, the online "
      "estimator alone, the rawlog read and the results written object by object in constant "
      "memory (online.tum, points, outliers and the report; GPS fixes are not used)");
  add_run_options(verb, o.get());
  verb->callback([o] {
    // MRPT's own error for a folder is a stack trace.
    if (std::filesystem::is_directory(o->rawlog))
      throw io::InputError(o->rawlog, 0, "is a folder; give the rawlog file");
    io::check_folder_replaceable(o->out, {o->rawlog, o->config, o->camera, o->ground_truth});
    const RunSettings settings = run_settings_of(*o);
    const std::vector<io::StampedPose> truth = read_ground_truth(o->ground_truth);
    if (settings.sfm.run_batch) {
      run_with_batch(*o, settings, truth);
      return;
    }
    std::string report;
    io::write_folder_atomically(o->out, [&](const std::string& dir) {
      report = stream_online_run(o->rawlog, settings, o->strict, dir);
      if (truth.empty()) return;
      report += compare_written_online_with_truth(dir, truth, o->ground_truth, true);
    });
    std::cout << report;
  });
}

}  // namespace omnisfm::app
