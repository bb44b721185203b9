// The tracker on images rendered through the mirror, against the truth: each track's point is
// where the ray of its first observation meets the scene, and its true pixel in a later frame is
// that point's projection (eval/track_accuracy.h). Runs at half the default size (512 x 384) on
// part of each sequence, so that it stays quick; `omnisfm demo` reports the full-size figures.

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <ostream>
#include <string>

#include "omnisfm/eval/track_accuracy.h"
#include "omnisfm/sim/image_file.h"
#include "omnisfm/sim/imaging.h"
#include "omnisfm/sim/renderer.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/track/image_sequence.h"
#include "omnisfm/track/track_images.h"
#include "omnisfm/track/track_lengths.h"

namespace omnisfm::track {
namespace {

namespace fs = std::filesystem;

struct Expected {
  const char* scenario;
  const char* imaging;  // sim::ImagingSettings::named
  int frames;
  double median_px, p95_px;    // at most
  double mistracked_fraction;  // of the tracks, at most
  int wrong_reacquisitions;    // at most
  int median_frames;           // a track's span at the median, at least
};

void PrintTo(const Expected& e, std::ostream* out) { *out << e.scenario << " " << e.imaging; }

eval::TrackAccuracy track_rendered(const Expected& e, TrackedSequence* tracked) {
  sim::SimulationOptions options;
  options.scenario = e.scenario;
  options.image_width = 512;
  options.image_height = 384;
  const sim::Dataset d = sim::simulate(options);
  const fs::path dir =
      fs::temp_directory_path() / ("omnisfm-rendered-" + std::string(e.scenario) + "-" +
                                   e.imaging + "-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  sim::Renderer renderer(d.camera, 4);
  sim::Imaging camera(sim::ImagingSettings::named(e.imaging), &renderer, 1);
  for (int f = 0; f < e.frames; ++f) {
    char name[32];
    std::snprintf(name, sizeof name, "%06d.png", f);
    sim::write_png((dir / name).string(), camera.record(d, f));
  }
  ImageSequence images(dir.string());
  TrackerSettings settings;
  settings.camera_blur_px = sim::ImagingSettings::named(e.imaging).blur_px();
  *tracked = track_images(d.camera, images, settings);
  fs::remove_all(dir);
  return eval::track_accuracy(d, tracked->observations);
}

class RenderedAccuracy : public ::testing::TestWithParam<Expected> {};

TEST_P(RenderedAccuracy, TracksFollowTheirPoints) {
  const Expected& e = GetParam();
  TrackedSequence tracked;
  const eval::TrackAccuracy a = track_rendered(e, &tracked);
  EXPECT_EQ(tracked.statistics.frames, e.frames);
  EXPECT_GE(a.tracks, 112);  // at least those of the first frame
  EXPECT_EQ(a.unanchored_tracks, 0);
  EXPECT_LE(a.median_px, e.median_px);
  EXPECT_LE(a.p95_px, e.p95_px);
  EXPECT_LE(a.mistracked_tracks, e.mistracked_fraction * a.tracks);
  EXPECT_LE(a.wrong_reacquisitions, e.wrong_reacquisitions);
  RecordProperty("median_px", std::to_string(a.median_px));
  RecordProperty("p95_px", std::to_string(a.p95_px));
  RecordProperty("mistracked",
                 std::to_string(a.mistracked_tracks) + "/" + std::to_string(a.tracks));
  const TrackLengths lengths = track_lengths(tracked.observations);
  EXPECT_GE(lengths.median_frames, e.median_frames);
  std::printf(
      "%s %s: %d tracks lasting %d frames at the median, median %.3f px, 95th percentile %.3f "
      "px, max %.3f px, %d mistracked, %d reacquisitions (%d wrong)\n",
      e.scenario, e.imaging, a.tracks, lengths.median_frames, a.median_px, a.p95_px, a.max_px,
      a.mistracked_tracks, a.reacquisitions, a.wrong_reacquisitions);
}

std::string scenario_name(const ::testing::TestParamInfo<Expected>& param) {
  return std::string(param.param.scenario) + "_" + param.param.imaging;
}

// Measured (seed 1), clean images: lab 0.068 / 0.227 px, 0 of 387 tracks mistracked; crane
// 0.039 / 0.150 px, 2 of 234; rover 0.072 / 0.347 px, 9 of 536. The rover's ground, close under
// the rig, changes its look fastest as it drives, and the clean images' procedural textures
// change their look with the scale too. Realistic images (photographs, blur, exposure, noise):
// lab 0.102 / 0.357 px, 4 of 470 mistracked, 13 reacquisitions, all right (15 with 1 wrong
// before a track too young to know its own image motion was looked for where its neighbours'
// motion puts it, for three frames at most); crane 0.064 / 0.209 px, 1 of 244; rover
// 0.062 / 0.178 px, 2 of 510, 1 reacquisition, right. (Before the first frame's motion blur was
// centred on its time, that frame showed the scene shifted by about a ninth of a frame's motion,
// and every track started in it carried the shift.) The bounds hold these; the reacquisitions'
// hold the goal, 1 % wrong (none at these counts). Before reacquisition refused twins
// (TrackerSettings::twin_ncc), 11 of the lab's 24 reacquisitions came back on a neighbouring
// brick. Tracks last (frames at the median): lab 10 clean and 4 realistic, crane 22
// and 3, rover 9 and 6 (before tracks ended on the misfit of their patch's parts rather than on
// a 20 % change of shape: lab 6 and 4, crane 21 and 3, rover 7 and 6; at this half size a patch
// spans twice the angle it does at full size, where the realistic rover's tracks went from 7 to
// 13 frames). The bounds sit just below; tracks.vnl leaves out single sightings, so no bound
// below 3 could fail; the tracker is deterministic, so the crane's realistic bound sits at its
// measured 3. With each track's reference renewed as its look changes steadily
// (TrackerSettings::max_renewals) and no track started on a corner the noise would take below
// min_followable_ncc: lab 11 clean and 4 realistic, crane 29 and 3, rover 9 and 8 frames; the
// realistic rover's 95th percentile 0.249 px (0.178 before), none of its 262 tracks beyond 1 px;
// the clean rover's mistracked 14 of 463 (3.0 %), where renewed references let its procedural
// textures change their look with the scale past max_patch_distortion. With the template
// smoothed as sampling smooths and matched to its patch's scale (told the rendering's blur,
// sim::ImagingSettings::blur_px), each track reporting its reference's best located point
// (ReferencePatch::match_blur, best_located_offset), and the exposure's motion blur about the
// lab's corners centred on the frames' poses: realistic lab 0.087 / 0.206 px (0.104 / 0.331
// before), none of 280 beyond 1 px; crane 0.075 / 0.254 px (0.074 / 0.205), 1 of 190; rover
// 0.075 / 0.236 px, none of 234, 11 frames at the median (8); clean lab 0.080 / 0.277 px, none of
// 279; crane 0.038 / 0.155, 2 of 204; rover 0.080 / 0.385, 13 of 418.
INSTANTIATE_TEST_SUITE_P(Scenarios, RenderedAccuracy,
                         ::testing::Values(Expected{"lab", "clean", 41, 0.1, 0.3, 0.01, 0, 10},
                                           Expected{"crane", "clean", 60, 0.1, 0.3, 0.02, 0, 27},
                                           Expected{"rover", "clean", 60, 0.1, 0.4, 0.035, 0, 8},
                                           Expected{"lab", "realistic", 41, 0.15, 0.25, 0.01, 0, 3},
                                           Expected{"crane", "realistic", 60, 0.1, 0.3, 0.01, 0, 3},
                                           Expected{"rover", "realistic", 60, 0.1, 0.27, 0.01, 0,
                                                    10}),
                         scenario_name);

}  // namespace
}  // namespace omnisfm::track
