// The tracker's tracks against the truth on a rendered simulation (not a benchmark: one run, one
// report): how long tracks last, why they end, how far they stray from their true points and how
// that error grows with a track's age. The images are those `omnisfm simulate --render` wrote
// for the same scenario and seed (rendering them again would take most of the time).
//   omnisfm simulate --scenario rover --render --imaging realistic --out /tmp/rover
//   track_truth rover /tmp/rover/images [SEED=1] [SETTING=VALUE...] [--mistracked] [--size=WxH]
//               [--dump=FILE]
// SETTING is one of the TrackerSettings fields listed in `settable` below. --mistracked lists the
// tracks that strayed beyond 1 px, their errors frame by frame and their last step. --size: the
// images' size when they were rendered at another than the default (simulate --width --height).
// --dump: every observation with its true pixel and what its patch covers (see dump).

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "omnisfm/core/percentile.h"
#include "omnisfm/eval/track_accuracy.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/sim/track_simulator.h"
#include "omnisfm/track/image_sequence.h"
#include "omnisfm/track/track_images.h"
#include "omnisfm/track/track_lengths.h"
#include "setting_assignment.h"

namespace {

using namespace omnisfm;

// Applies "name=value" to *settings; false for a name not listed.
bool set(const std::string& assignment, track::TrackerSettings* settings) {
  const bench::Setters settable = {
      {"min_ncc", [&](double v) { settings->min_ncc = v; }},
      {"quality_level", [&](double v) { settings->quality_level = v; }},
      {"max_renewals", [&](double v) { settings->max_renewals = static_cast<int>(v); }},
      {"min_followable_ncc", [&](double v) { settings->min_followable_ncc = v; }},
      {"max_patch_distortion", [&](double v) { settings->max_patch_distortion = v; }},
      {"max_misfit_px", [&](double v) { settings->max_misfit_px = v; }},
      {"max_refinement_shift_px", [&](double v) { settings->max_refinement_shift_px = v; }},
      {"max_forward_backward_px", [&](double v) { settings->max_forward_backward_px = v; }},
      {"forward_backward_with_refinement",
       [&](double v) { settings->forward_backward_with_refinement = v != 0; }},
      {"patch_half_size", [&](double v) { settings->patch_half_size = static_cast<int>(v); }},
      {"reacquire", [&](double v) { settings->reacquire = v != 0; }},
      {"image_blur_sigma", [&](double v) { settings->image_blur_sigma = v; }},
      {"camera_blur_px", [&](double v) { settings->camera_blur_px = v; }},
      {"max_tracks", [&](double v) { settings->max_tracks = static_cast<int>(v); }},
      {"detect_at_missing", [&](double v) { settings->detect_at_missing = static_cast<int>(v); }},
      {"max_step_deviation_px", [&](double v) { settings->max_step_deviation_px = v; }},
      {"rim_margin_px", [&](double v) { settings->rim_margin_px = v; }},
  };
  return bench::apply_assignment(assignment, settable);
}

// The error's median and 95th percentile per band of track age (frames since the track's
// first observation), over the tracks that follow their points.
void print_errors_by_age(const std::vector<core::TrackObservation>& observations,
                         const std::vector<double>& errors, const eval::TrackAccuracy& accuracy) {
  std::map<int, int> first_frame;
  for (const auto& o : observations)
    if (!first_frame.count(o.track)) first_frame[o.track] = o.frame;
  const std::vector<int> band_starts = {1, 3, 6, 11, 21, 41, 81};
  std::vector<std::vector<double>> bands(band_starts.size());
  for (size_t i = 0; i < observations.size(); ++i) {
    if (!(errors[i] <= 1e9)) continue;
    bool mistracked = false;
    for (const int m : accuracy.mistracked) mistracked |= m == observations[i].track;
    if (mistracked) continue;
    const int age = observations[i].frame - first_frame[observations[i].track];
    size_t band = 0;
    while (band + 1 < band_starts.size() && age >= band_starts[band + 1]) ++band;
    bands[band].push_back(errors[i]);
  }
  std::printf("error by age (frames): ");
  for (size_t b = 0; b < bands.size(); ++b)
    if (!bands[b].empty())
      std::printf("%d+: %.3f/%.3f (%zu)  ", band_starts[b], core::percentile(bands[b], 0.5),
                  core::percentile(bands[b], 0.95), bands[b].size());
  std::printf("\n");
}

// Per mistracked track: where it started, its error in each frame (| where it was reacquired
// after a gap), and its last step against
// the median step of the tracks within 100 px (TrackerSettings::max_step_deviation_px).
void print_mistracked(const std::vector<core::TrackObservation>& observations,
                      const std::vector<double>& errors, const eval::TrackAccuracy& accuracy) {
  std::map<int, std::vector<size_t>> by_track;
  std::map<int, std::map<int, Eigen::Vector2d>> by_frame;  // frame, track: pixel
  for (size_t i = 0; i < observations.size(); ++i) {
    by_track[observations[i].track].push_back(i);
    by_frame[observations[i].frame][observations[i].track] = observations[i].pixel;
  }
  for (const int m : accuracy.mistracked) {
    const std::vector<size_t>& seen = by_track[m];
    const core::TrackObservation& first = observations[seen.front()];
    std::printf("track %d from frame %d at (%.0f, %.0f), error per frame:", m, first.frame,
                first.pixel.x(), first.pixel.y());
    for (size_t k = 0; k < seen.size(); ++k) {
      // A gap: the track was reacquired there.
      if (k > 0 && observations[seen[k]].frame > observations[seen[k - 1]].frame + 1)
        std::printf(" |");
      std::printf(" %.2f", errors[seen[k]]);
    }
    if (seen.size() >= 2) {
      const core::TrackObservation& last = observations[seen.back()];
      const core::TrackObservation& before = observations[seen[seen.size() - 2]];
      std::vector<double> xs, ys;
      for (const auto& [track, pixel] : by_frame[before.frame]) {
        const auto now = by_frame[last.frame].find(track);
        if (track == m || now == by_frame[last.frame].end() ||
            (pixel - before.pixel).norm() > 100)
          continue;
        xs.push_back(now->second.x() - pixel.x());
        ys.push_back(now->second.y() - pixel.y());
      }
      const Eigen::Vector2d step = last.pixel - before.pixel;
      std::printf("; last step (%.1f, %.1f), neighbours' median (%.1f, %.1f) of %zu", step.x(),
                  step.y(), core::percentile(xs, 0.5), core::percentile(ys, 0.5), xs.size());
    }
    std::printf("\n");
  }
}

// Writes a line per observation to `path`: track, frame, age (frames since its first), error
// (px; nan for a first observation), its pixel, its true pixel (-1 -1 where hidden), and what
// its first patch covers: how many of the scene's surfaces (1: one wall; 2 or 3: a crease where
// they meet), plus 10 where a marker is among them (rays through a 5 x 5 grid over the patch).
void dump(const char* path, const sim::Dataset& dataset,
          const std::vector<core::TrackObservation>& observations,
          const std::vector<double>& errors, int half_size) {
  std::map<int, size_t> first;
  for (size_t i = 0; i < observations.size(); ++i)
    if (!first.count(observations[i].track)) first[observations[i].track] = i;
  std::map<int, Eigen::Vector3d> truth;
  std::map<int, int> covers;
  for (const auto& [track, index] : first) {
    const core::TrackObservation& o = observations[index];
    Eigen::Vector3d point;
    sim::SceneHit hit;
    if (sim::scene_point(dataset, o.frame, o.pixel, &point, &hit)) truth[track] = point;
    std::vector<int> quads;
    bool marker = false;
    for (int dy = -2; dy <= 2; ++dy)
      for (int dx = -2; dx <= 2; ++dx)
        if (sim::scene_point(dataset, o.frame,
                             o.pixel + Eigen::Vector2d(dx, dy) * (half_size / 2.0), &point, &hit)) {
          if (hit.marker >= 0) marker = true;
          if (hit.quad >= 0) quads.push_back(hit.quad);
        }
    std::sort(quads.begin(), quads.end());
    covers[track] = static_cast<int>(std::unique(quads.begin(), quads.end()) - quads.begin()) +
                    (marker ? 10 : 0);
  }
  FILE* out = std::fopen(path, "w");
  if (!out) {
    std::fprintf(stderr, "track_truth: cannot write %s\n", path);
    return;
  }
  for (size_t i = 0; i < observations.size(); ++i) {
    const core::TrackObservation& o = observations[i];
    Eigen::Vector2d true_pixel(-1, -1);
    const auto point = truth.find(o.track);
    if (point != truth.end() && !sim::true_pixel(dataset, o.frame, point->second, &true_pixel))
      true_pixel = Eigen::Vector2d(-1, -1);  // hidden: true_pixel still says where it would be
    std::fprintf(out, "%d %d %d %.4f %.3f %.3f %.3f %.3f %d\n", o.track, o.frame,
                 o.frame - observations[first[o.track]].frame, errors[i], o.pixel.x(), o.pixel.y(),
                 true_pixel.x(), true_pixel.y(), covers[o.track]);
  }
  std::fclose(out);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 3) {
    std::fprintf(stderr,
                 "usage: track_truth SCENARIO IMAGES_DIR [SEED=1] [SETTING=VALUE...] "
                 "[--mistracked] [--size=WxH] [--dump=FILE]\n");
    return 2;
  }
  sim::SimulationOptions options;
  options.scenario = argv[1];
  int next = 3;
  if (argc > 3 && std::string(argv[3]).find('=') == std::string::npos)
    options.seed = std::strtoull(argv[next++], nullptr, 10);
  track::TrackerSettings settings;
  bool list_mistracked = false;
  std::string dump_path;
  for (; next < argc; ++next)
    if (std::string(argv[next]) == "--mistracked")
      list_mistracked = true;
    else if (std::string(argv[next]).rfind("--dump=", 0) == 0)
      dump_path = argv[next] + 7;
    else if (std::sscanf(argv[next], "--size=%dx%d", &options.image_width,
                         &options.image_height) == 2)
      continue;
    else if (!set(argv[next], &settings)) {
      std::fprintf(stderr, "track_truth: unknown setting, or not a number: %s\n", argv[next]);
      return 2;
    }
  const sim::Dataset dataset = sim::simulate(options);
  track::ImageSequence images(argv[2]);
  const track::TrackedSequence tracked = track::track_images(dataset.camera, images, settings);
  const eval::TrackAccuracy a = eval::track_accuracy(dataset, tracked.observations);
  const track::TrackLengths lengths = track::track_lengths(tracked.observations);
  const track::TrackerStatistics& s = tracked.statistics;
  std::printf(
      "%s seed %llu: %d tracks, median length %d frames, %d mistracked (%.2f %%), error median "
      "%.3f px, p95 %.3f px, max %.3f px; reacquisitions %d (%d wrong); %.2f ms per frame\n",
      argv[1], static_cast<unsigned long long>(options.seed), a.tracks, lengths.median_frames,
      a.mistracked_tracks, 100.0 * a.mistracked_tracks / std::max(1, a.tracks), a.median_px,
      a.p95_px, a.max_px, a.reacquisitions, a.wrong_reacquisitions,
      1000 * tracked.tracking_seconds / std::max(1, s.frames));
  std::printf(
      "ended: lost %d, forward-backward %d, appearance %d, misfit %d, reshaped %d, jumped %d, "
      "left region %d, duplicate %d; renewed %d, smoothed anew %d, corners too faint %d\n",
      s.lost, s.forward_backward, s.appearance, s.misfit, s.reshaped, s.jumped, s.left_region,
      s.duplicate, s.renewed, s.smoothed_anew, s.too_faint);
  const std::vector<double> errors = eval::track_errors(dataset, tracked.observations);
  print_errors_by_age(tracked.observations, errors, a);
  if (list_mistracked) print_mistracked(tracked.observations, errors, a);
  if (!dump_path.empty())
    dump(dump_path.c_str(), dataset, tracked.observations, errors, settings.patch_half_size);
  return 0;
}
