#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <memory>
#include <sstream>

#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/tracks_file.h"
#include "omnisfm/io/tum_trajectory.h"
#include "omnisfm/io/vnlog.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sfm/settings_file.h"
#include "omnisfm/sfm/sfm_report.h"
#include "online_outputs.h"
#include "sfm_outputs.h"
#include "terminal_progress.h"
#include "verb_inputs.h"
#include "verbs.h"

namespace omnisfm::app {
namespace {

namespace fs = std::filesystem;

// Frame times from frames.vnl beside the tracks, read in step with the frames (its rows in frame
// order); a frame's index where there is none.
class FrameClock {
 public:
  explicit FrameClock(const std::string& tracks_path) {
    const fs::path frames = fs::path(tracks_path).parent_path() / "frames.vnl";
    if (!fs::exists(frames)) return;
    reader_ = std::make_unique<io::VnlogReader>(frames.string());
    columns_ = reader_->columns({"frame", "timestamp"});
    advance();
  }

  double time(int frame) {
    if (!reader_) return frame;
    while (have_row_ && row_frame_ < frame) advance();
    // A frame without its row would take its index as its time, out of step with the rest.
    if (!(have_row_ && row_frame_ == frame))
      throw io::InputError(reader_->file(), have_row_ ? reader_->line() : 0,
                           "has no row for frame " + std::to_string(frame) +
                               " of the tracks: every frame needs its time");
    return row_time_;
  }

 private:
  void advance() {
    const double previous = row_frame_, previous_time = row_time_;
    const bool first = !have_row_;
    have_row_ = reader_->next();
    if (!have_row_) return;
    row_frame_ = reader_->number(columns_[0]);
    row_time_ = reader_->number(columns_[1]);
    if (!(row_frame_ > previous))
      throw io::InputError(reader_->file(), reader_->line(),
                           "frames must increase from row to row");
    // The times go into the TUM files, which eval and MRPT read in order.
    if (!std::isfinite(row_time_))
      throw io::InputError(reader_->file(), reader_->line(), "the timestamp must be finite");
    if (!first && !(row_time_ > previous_time))
      throw io::InputError(reader_->file(), reader_->line(),
                           "timestamps must increase from row to row");
  }

  std::unique_ptr<io::VnlogReader> reader_;
  std::vector<std::size_t> columns_;
  bool have_row_ = false;
  double row_frame_ = -1, row_time_ = 0;
};

using Clock = std::chrono::steady_clock;

// `[sfm] batch = false`: the filter alone, the tracks read and the results written frame by frame
// into `dir`, in constant memory. Returns the report.
std::string stream_online_sfm(const camera::CatadioptricCamera& camera,
                              const std::string& tracks_path, const sfm::SfmSettings& settings,
                              const std::string& dir) {
  io::TrackStream stream(tracks_path, camera.image_width(), camera.image_height());
  FrameClock clock(tracks_path);
  sfm::FilterSettings filter_settings = settings.filter;
  filter_settings.kept_history = 0;  // the outputs take what leaves
  sfm::OnlineFilter filter(camera, filter_settings);
  OnlineOutputs out(dir);
  out.attach(&filter);
  TerminalProgress progress("filter", "frames");
  double seconds = 0;
  long observations = 0;
  int next = 0;  // the next frame to process
  const auto process = [&](int f, const std::vector<sfm::TrackPixel>& pixels) {
    const auto started = Clock::now();
    filter.process_frame(f, pixels);
    seconds += std::chrono::duration<double>(Clock::now() - started).count();
    out.frame(filter, f, clock.time(f), settings.filter.smoothed_start_frames);
    progress(f + 1, 0);
  };
  int frame = 0;
  std::vector<core::TrackObservation> rows;
  std::vector<sfm::TrackPixel> pixels;
  while (stream.next_frame(&frame, &rows)) {
    if (next == 0 && (frame != 0 || rows.size() < 6))
      throw io::InputError(
          tracks_path, stream.line(0),
          "frame 0 has " + std::to_string(frame == 0 ? rows.size() : 0) +
              " tracks; at least 6 are needed to start" +
              (frame > 0 ? " (frames count the images from 0; the first with tracks is " +
                               std::to_string(frame) + ")"
                         : ""));
    // Frames without observations: the filter only propagates.
    for (; next < frame; ++next) process(next, {});
    pixels.clear();
    for (const auto& o : rows) pixels.push_back({o.track, o.pixel});
    observations += static_cast<long>(rows.size());
    process(next++, pixels);
  }
  if (next < 2) throw io::InputError(tracks_path, 0, "the tracks span fewer than 2 frames");
  filter.finish_start();
  out.take_what_is_held(filter);
  // Every track seen twice ends as a point or an outlier.
  const std::string most_rejected = sfm::most_rejected_line(
      out.outliers(), out.points() + out.outliers(), filter.pixel_sigma(), settings.filter);
  std::cerr << (most_rejected.empty() ? "" : "omnisfm: " + most_rejected);
  std::ostringstream report;
  report << "frames " << next << ", observations " << observations << ", outlier tracks "
         << out.outliers() << sfm::not_admitted_phrase(filter.not_admitted())
         << sfm::measured_noise_phrase(filter.pixel_sigma(), settings.filter.pixel_sigma) << "\n"
         << most_rejected << "filter: " << seconds << " s (" << 1000 * seconds / next
         << " ms per frame)\n"
         << sfm::considered_camera_line(camera, settings.filter)
         << "online only ([sfm] batch = false): tracks read and results written frame by frame\n";
  out.finish(report.str());
  return report.str();
}

}  // namespace

void add_sfm_verb(CLI::App& app) {
  struct Options {
    std::string camera, tracks, out, config, ground_truth;
  };
  auto o = std::make_shared<Options>();
  CLI::App* verb = app.add_subcommand(
      "sfm",
      "Shape-from-motion from tracks: the online filter then the batch adjustment; writes "
      "online.tum, batch.tum, points.vnl, points.ply, outliers.vnl, report.txt, the batch as an "
      "MRPT pose graph (batch.graph, batch.graphbin) and the residual plots (residuals.png, "
      "residuals_per_frame.png, with their .vnl tables and gnuplot scripts); with "
      "--ground-truth also the paper's figures and trajectory plots (motion.png, path.png, with "
      "motion.dat and the scripts). With [sfm] batch = false, the filter alone: the tracks are "
      "read and the results written frame by frame, in constant memory (no batch.tum, no graph "
      "and no residual plots)");
  verb->add_option("--camera", o->camera, "Camera file (default: the shipped equiangular)");
  verb->add_option("--tracks", o->tracks, "tracks.vnl (# frame track u v)")->required();
  verb->add_option("--out", o->out,
                   "Output folder: made, or replaced whole when an earlier omnisfm run wrote it (a "
                   "folder holding other files, or the inputs, is refused)")
      ->required();
  verb->add_option("--config", o->config,
                   "Settings: an INI file with an [sfm] section (the shipped config/omnisfm.ini "
                   "holds every key at its default)");
  verb->add_option("--ground-truth", o->ground_truth,
                   "A TUM trajectory of the truth: adds the paper's error figures to the report");
  verb->callback([o] {
    // frames.vnl beside the tracks is read too.
    io::check_folder_replaceable(o->out,
                                 {o->camera, o->tracks, o->config, o->ground_truth,
                                  (fs::path(o->tracks).parent_path() / "frames.vnl").string()});
    const camera::CatadioptricCamera camera = load_camera(o->camera);
    sfm::SfmSettings settings =
        o->config.empty() ? sfm::SfmSettings() : sfm::read_sfm_settings(o->config);
    apply_camera_prior(o->config, o->camera, o->camera.empty() ? nullptr : &camera, &settings);
    const std::vector<io::StampedPose> truth = read_ground_truth(o->ground_truth);
    if (!settings.run_batch) {
      std::string report;
      io::write_folder_atomically(o->out, [&](const std::string& dir) {
        report = stream_online_sfm(camera, o->tracks, settings, dir);
        if (!truth.empty())
          report += compare_written_online_with_truth(dir, truth, o->ground_truth, false);
      });
      std::cout << report;
      return;
    }
    const auto tracks = io::read_tracks(o->tracks, camera.image_width(), camera.image_height());
    // frames.vnl's times read, and judged, before the work.
    int last_frame = 0;
    for (const auto& observation : tracks) last_frame = std::max(last_frame, observation.frame);
    FrameClock clock(o->tracks);
    std::vector<double> times;
    for (int f = 0; f <= last_frame; ++f) times.push_back(clock.time(f));

    sfm::SfmResult result;
    try {
      TerminalProgress progress("filter", "frames");
      result = sfm::run_sfm(camera, tracks, settings, progress.callback());
    } catch (const std::invalid_argument& e) {
      throw io::InputError(o->tracks, 0, e.what());
    }
    const std::string most_rejected =
        sfm::most_rejected_line(static_cast<long>(result.outliers.size()), result.num_tracks,
                                result.online_noise_px, settings.filter);
    std::cerr << (most_rejected.empty() ? "" : "omnisfm: " + most_rejected);
    if (settings.run_batch && !result.batch.usable())
      throw std::runtime_error("the batch adjustment failed: " + result.batch.message);

    times.resize(result.num_frames);
    std::ostringstream report;
    report << "frames " << result.num_frames << ", observations " << tracks.size() << ", "
           << sfm::outliers_phrase(result, settings.filter.pixel_sigma) << "\n"
           << most_rejected << "filter: " << result.online_seconds << " s ("
           << 1000 * result.online_seconds / result.num_frames << " ms per frame)\n"
           << sfm::considered_camera_line(camera, settings.filter);
    if (settings.run_batch)
      report << sfm::batch_line(result.batch) << sfm::scale_line(result, settings.batch)
             << sfm::camera_line(camera, result.batch, settings.batch);
    eval::TruthComparison comparison;
    if (!truth.empty()) {
      comparison = eval::compare_with_truth(result, settings.run_batch, truth, o->ground_truth);
      report << comparison.report;
    }

    io::write_folder_atomically(o->out, [&](const std::string& dir) {
      write_sfm_outputs(dir, result, settings.run_batch, times, report.str());
      write_refined_camera(dir, camera, result.batch, settings.batch);
      write_sfm_plots(dir, camera, tracks, result, settings.run_batch, comparison);
    });
    std::cout << report.str();
  });
}

}  // namespace omnisfm::app
