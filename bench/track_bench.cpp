// Speed of the feature tracker: time per frame (the per_frame counter) for 112 tracks on the
// simulated rover's rendered 1024 x 768 images (the first 40 of the sequence, rendered once at
// start-up; argument realistic:1 the demo's realistic images, realistic:0 the clean ones), on one
// core (OpenCV's threads off). The peer in the same binary is OpenCV's
// cv::calcOpticalFlowPyrLK alone on the same frames and the same points (where the tracker had its
// live tracks): the part of the work a plain KLT tracker does. The tracker's variants show what
// reacquisition and the refinement against each track's reference cost. The goal is 5 ms per
// frame.

#include <benchmark/benchmark.h>

#include <opencv2/core.hpp>
#include <opencv2/video/tracking.hpp>
#include <vector>

#include "omnisfm/sim/imaging.h"
#include "omnisfm/sim/renderer.h"
#include "omnisfm/sim/scenario.h"
#include "omnisfm/track/feature_tracker.h"
#include "omnisfm/track/valid_region.h"

namespace {

using namespace omnisfm;

constexpr int kFrames = 40;

struct Sequence {
  std::vector<cv::Mat> images;
  cv::Mat region;
  // The tracker's live points in each frame, for the peer.
  std::vector<std::vector<cv::Point2f>> points;
};

Sequence make_rover_sequence(bool realistic) {
  cv::setNumThreads(1);
  Sequence s;
  sim::SimulationOptions options;
  options.scenario = "rover";
  const sim::Dataset dataset = sim::simulate(options);
  sim::Renderer renderer(dataset.camera, 4);
  sim::Imaging camera(sim::ImagingSettings::named(realistic ? "realistic" : "clean"), &renderer,
                      options.seed);
  for (int f = 0; f < kFrames; ++f) s.images.push_back(camera.record(dataset, f));
  const track::TrackerSettings settings;
  s.region = track::valid_region_mask(dataset.camera, settings.rim_margin_px);
  track::FeatureTracker tracker(s.region, settings);
  for (const cv::Mat& image : s.images) {
    s.points.emplace_back();
    for (const auto& p : tracker.track(image))
      s.points.back().emplace_back(static_cast<float>(p.pixel.x()),
                                   static_cast<float>(p.pixel.y()));
  }
  return s;
}

// Rendered on first use only: a filtered run renders what it needs.
const Sequence& rover_sequence(bool realistic) {
  if (realistic) {
    static const Sequence sequence = make_rover_sequence(true);
    return sequence;
  }
  static const Sequence sequence = make_rover_sequence(false);
  return sequence;
}

void run_tracker(benchmark::State& state, const track::TrackerSettings& settings) {
  const Sequence& s = rover_sequence(state.range(0) != 0);
  double tracks = 0;
  for (auto _ : state) {
    track::FeatureTracker tracker(s.region, settings);
    for (const cv::Mat& image : s.images) tracks += tracker.track(image).size();
  }
  state.counters["per_frame"] = benchmark::Counter(
      kFrames, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.counters["tracks"] = tracks / (state.iterations() * kFrames);
}

void BM_FeatureTracker(benchmark::State& state) { run_tracker(state, track::TrackerSettings()); }

void BM_FeatureTrackerNoReacquisition(benchmark::State& state) {
  track::TrackerSettings settings;
  settings.reacquire = false;
  run_tracker(state, settings);
}

void BM_FeatureTrackerNoRefinement(benchmark::State& state) {
  track::TrackerSettings settings;
  settings.reacquire = false;
  settings.refine = false;
  run_tracker(state, settings);
}

// OpenCV's pyramidal Lucas-Kanade from each frame to the next, pyramids built inside the call:
// with the tracker's window and pyramid, and with OpenCV's defaults (21 x 21, 4 levels).
void run_opencv_lk(benchmark::State& state, int window_size, int max_level) {
  const Sequence& s = rover_sequence(state.range(0) != 0);
  const cv::Size window(window_size, window_size);
  std::vector<cv::Point2f> next;
  std::vector<uchar> status;
  std::vector<float> error;
  for (auto _ : state)
    for (int f = 0; f + 1 < kFrames; ++f)
      cv::calcOpticalFlowPyrLK(s.images[f], s.images[f + 1], s.points[f], next, status, error,
                               window, max_level);
  state.counters["per_frame"] = benchmark::Counter(
      kFrames - 1, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

void BM_OpencvPyrLK(benchmark::State& state) {
  const track::TrackerSettings settings;
  run_opencv_lk(state, settings.lk_window, settings.pyramid_levels - 1);
}

void BM_OpencvPyrLKDefaults(benchmark::State& state) { run_opencv_lk(state, 21, 3); }

// Each on the realistic images, then the clean ones.
void on_both_imagings(benchmark::internal::Benchmark* b) {
  b->ArgName("realistic")->Arg(1)->Arg(0)->Unit(benchmark::kMillisecond);
}

BENCHMARK(BM_FeatureTracker)->Apply(on_both_imagings);
BENCHMARK(BM_FeatureTrackerNoReacquisition)->Apply(on_both_imagings);
BENCHMARK(BM_FeatureTrackerNoRefinement)->Apply(on_both_imagings);
BENCHMARK(BM_OpencvPyrLK)->Apply(on_both_imagings);
BENCHMARK(BM_OpencvPyrLKDefaults)->Apply(on_both_imagings);

}  // namespace

BENCHMARK_MAIN();
