#include <cstdio>
#include <filesystem>
#include <opencv2/imgcodecs.hpp>
#include <iostream>
#include <memory>
#include <string>

#include "omnisfm/io/input_error.h"
#include "omnisfm/io/tracks_file.h"
#include "omnisfm/track/frames_file.h"
#include "omnisfm/track/image_sequence.h"
#include "omnisfm/track/track_images.h"
#include "omnisfm/track/track_lengths.h"
#include "tracks_drawing.h"
#include "verb_inputs.h"
#include "terminal_progress.h"
#include "verbs.h"
#ifdef OMNISFM_WITH_MRPT_PLUGIN
#include "omnisfm/mrpt_plugin/rawlog_replay_input.h"
#endif

namespace omnisfm::app {
namespace {

namespace fs = std::filesystem;

bool is_rawlog(const std::string& path) {
  const std::string name = fs::path(path).filename().string();
  for (const std::string ending : {".rawlog", ".rawlog.gz"})
    if (name.size() > ending.size() && name.compare(name.size() - ending.size(), ending.size(), ending) == 0)
      return true;
  return false;
}

// The images of an MRPT rawlog through the tracker (the plugin reads them): the rawlog's own camera
// model unless a camera file is given; a damaged rawlog is tracked up to the damaged object.
track::TrackedSequence track_rawlog(const std::string& path, const std::string& camera_file,
                                    const track::TrackerSettings& settings) {
#ifdef OMNISFM_WITH_MRPT_PLUGIN
  mrpt_plugin::ReplayOptions options;
  options.vision = mrpt_plugin::ReplayVision::kImages;
  if (!camera_file.empty()) options.camera = load_camera(camera_file);
  options.tracker = settings;
  const mrpt_plugin::ReplayInput in = [&] {
    TerminalProgress progress("tracked", "frames");
    return mrpt_plugin::read_replay_input(path, options, progress.callback());
  }();
  if (!in.read.complete())
    std::cerr << "omnisfm: warning: " << path << ": " << in.read.problem << "; tracked the "
              << in.frame_times.size() << " images before it\n";
  track::TrackedSequence sequence;
  sequence.observations = in.tracks;
  for (size_t i = 0; i < in.frame_times.size(); ++i)
    sequence.frames.push_back({static_cast<int>(i), "", in.frame_times[i]});
  sequence.statistics.frames = static_cast<int>(in.frame_times.size());
  return sequence;
#else
  (void)camera_file, (void)settings;
  throw io::InputError(path, 0, "is a rawlog: this omnisfm was built without the MRPT plugin");
#endif
}

// Frame `frame` of the images, as the tracker read it (the frames before it not decoded).
cv::Mat read_frame(const std::string& images, int frame) {
  track::ImageSequence sequence(images);
  track::SequenceFrame f;
  if (sequence.skip(frame) < frame || !sequence.next(&f))
    throw io::InputError(images, 0, "has no frame " + std::to_string(frame));
  return f.image;
}

// frames.vnl first (and the drawing, when asked): a complete tracks.vnl is the sign that all are
// written. A folder made for them goes again when writing fails.
void write_tracks_and_frames(const fs::path& out, const track::TrackedSequence& result,
                             const cv::Mat& drawing, int drawn_frame) {
  const fs::path folder = out.parent_path();
  in_folder_made_if_missing(folder, [&] {
    track::write_frames_file((folder / "frames.vnl").string(), result.frames);
    if (!drawing.empty()) {
      const fs::path png = folder / ("tracks_" + std::to_string(drawn_frame) + ".png");
      if (!cv::imwrite(png.string(), drawing))
        throw io::InputError(png.string(), 0, "cannot be written");
    }
    io::write_tracks(out.string(), result.observations);
  });
}

}  // namespace

void add_track_verb(CLI::App& app) {
  struct Options {
    std::string camera, images, out, timestamps;
    track::TrackerSettings settings;
    bool no_reacquisition = false;
    int draw = -1;
  };
  auto o = std::make_shared<Options>();
  CLI::App* verb = app.add_subcommand(
      "track",
      "Track features through images seen through the mirror (pyramidal Lucas-Kanade, refined "
      "against each track's first appearance); writes tracks.vnl and frames.vnl beside it");
  verb->add_option("--camera", o->camera, "Camera file (default: the shipped equiangular)");
  verb->add_option("--images", o->images,
                   "A folder of PNG or JPG images (taken in file-name order), a video file, or "
                   "an MRPT rawlog (X.rawlog: its camera images, with the model they carry unless "
                   "--camera is given; a damaged rawlog is tracked up to the damaged object)")
      ->required();
  verb->add_option(
          "--out", o->out,
          "The tracks file to write (# frame track u v); its folder is made when missing (not its "
          "parent)")
      ->required();
  verb->add_option("--timestamps", o->timestamps,
                   "A table with image and timestamp columns (such as a simulated dataset's "
                   "frames.vnl) giving each image's time; default: a video's own times, else "
                   "the frame index");
  verb->add_option("--max-tracks", o->settings.max_tracks,
                   "Tracks kept alive: new ones start once 8 (or an eighth, if fewer) are missing")
      ->capture_default_str()
      ->check(whole_number_between(6, 100000));
  verb->add_option("--min-ncc", o->settings.min_ncc,
                   "End a track whose patch correlates less than this with its first appearance")
      ->capture_default_str()
      ->check(number_between(0, 1));
  verb->add_option("--camera-blur", o->settings.camera_blur_px,
                   "The camera's own blur, pixels (a Gaussian's sigma: its optics and its "
                   "pixels' area); references are smoothed to match as their patches change "
                   "scale")
      ->capture_default_str()
      ->check(number_between(0, 5));
  verb->add_flag("--no-reacquisition", o->no_reacquisition, "Do not look for lost features again");
  verb->add_option("--draw", o->draw,
                   "Also write tracks_FRAME.png beside the tracks: that frame (counted from 0) "
                   "with the path of each track seen in it over its last 10 frames, blue for a "
                   "track started there to red for one that has lasted 10 frames or more")
      ->check(whole_number_between(0, 1000000000));
  verb->callback([o] {
    o->settings.reacquire = !o->no_reacquisition;
    const bool rawlog = is_rawlog(o->images);
    if (rawlog && !o->timestamps.empty())
      throw io::InputError(o->timestamps, 0,
                           "a rawlog's images carry their own times: leave out --timestamps");
    if (rawlog && o->draw >= 0)
      throw io::InputError(o->images, 0, "is a rawlog: --draw takes a folder of images or a video");
    const auto no_frame_to_draw = [&](int frames) {
      return io::InputError(o->images, 0,
                            "has " + std::to_string(frames) + " frames: there is no frame " +
                                std::to_string(o->draw) + " to draw");
    };
    if (!rawlog && o->draw >= 0) {
      const int expected = track::ImageSequence(o->images).expected_frames();
      if (expected > 0 && o->draw >= expected) throw no_frame_to_draw(expected);  // before tracking
    }
    const fs::path out = fs::absolute(o->out).lexically_normal();
    check_output_file(o->out, out);
    // frames.vnl is written beside the tracks.
    const std::string frames_file = (out.parent_path() / "frames.vnl").string();
    for (const std::string& written : {o->out, frames_file})
      require_not_an_input(written, {o->camera, o->images, o->timestamps});
    const auto timestamps = o->timestamps.empty() ? std::map<std::string, track::ImageTimestamp>()
                                                  : track::read_image_timestamps(o->timestamps);

    track::TrackedSequence result;
    if (rawlog) {
      result = track_rawlog(o->images, o->camera, o->settings);
    } else {
      const camera::CatadioptricCamera camera = load_camera(o->camera);
      track::ImageSequence images(o->images);
      TerminalProgress progress("tracked", "frames");
      result = track::track_images(camera, images, o->settings, progress.callback());
      if (const std::string lost = images.shortfall(); !lost.empty())
        std::cerr << "omnisfm: warning: " << io::printable_text(o->images + ": " + lost) << "\n";
    }
    if (result.frames.size() < 2)
      throw io::InputError(o->images, 0,
                           "holds " + std::to_string(result.frames.size()) +
                               (rawlog ? " camera images (CObservationImage or "
                                         "CObservationOmniImage)"
                                       : " image") +
                               ": tracking needs at least 2");
    if (!o->timestamps.empty()) track::apply_timestamps(timestamps, o->timestamps, &result.frames);

    constexpr int kTrail = 10;
    cv::Mat drawing;
    if (o->draw >= 0) {
      if (o->draw >= static_cast<int>(result.frames.size()))
        throw no_frame_to_draw(static_cast<int>(result.frames.size()));
      drawing = draw_tracks(read_frame(o->images, o->draw), result.observations, o->draw, kTrail);
    }
    write_tracks_and_frames(out, result, drawing, o->draw);

    if (rawlog) {
      std::printf("frames %zu, observations %zu, from the images of %s\n", result.frames.size(),
                  result.observations.size(), o->images.c_str());
      finish_stdout();
      return;
    }
    // Counts of what tracks.vnl holds, and how the tracker's own counts come to them.
    const auto& s = result.statistics;
    const track::TrackLengths lengths = track::track_lengths(result.observations);
    std::printf(
        "frames %zu, tracks %d (%d started, %d seen in one frame only and left out), lasting %d "
        "frames at the median (longest %d), observations %zu, reacquired %d (%d after a gap in "
        "their track, %d in the frame that lost them; %d lost ones forgotten where their look "
        "repeats nearby); ended: %d lost by Lucas-Kanade, %d failed the appearance check, %d no "
        "longer fitted one warp, %d changed shape too much, %d jumped away from their "
        "neighbours, %d left the mirror, %d duplicates; %d references renewed; %d corners too "
        "faint to follow in the images' noise; %.1f ms per frame\n",
        result.frames.size(), lengths.tracks, s.started, result.single_frame_tracks,
        lengths.median_frames, lengths.longest_frames, result.observations.size(), s.reacquired,
        s.reacquired - s.reacquired_at_once, s.reacquired_at_once, s.forgotten_among_twins,
        s.forward_backward + s.lost, s.appearance, s.misfit, s.reshaped, s.jumped, s.left_region,
        s.duplicate, s.renewed, s.too_faint, 1000 * result.tracking_seconds / result.frames.size());
    finish_stdout();
  });
}

}  // namespace omnisfm::app
