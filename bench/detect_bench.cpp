// Speed of finding a checkerboard in a raw catadioptric image, on the real vmr set (10 images of a
// 6 x 7 board, 1024 x 768): the mirror's circles on the set's mean image, a detector's first image
// (its 108 views' tables made on the way) and a later one, one view rendered, and OpenCV's quick
// check and full detector on one view as the peers the search is made of. OpenCV runs on one
// thread (cv::setNumThreads, as OMNISFM_THREADS=1 gives the command).
//   detect_bench [--benchmark_filter=...]     (data: ../shared/data/real-catadioptric beside the
//                                              source tree, or $OMNISFM_REAL_DATA)

#include <benchmark/benchmark.h>

#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "omnisfm/calib/board_detection.h"
#include "omnisfm/calib/mirror_image.h"
#include "omnisfm/calib/perspective_view.h"
#include "real_data_folder.h"

namespace {

namespace fs = std::filesystem;
using namespace omnisfm::calib;

const cv::Size kGrid(6, 7);
constexpr double kDegree = M_PI / 180;

const std::vector<cv::Mat>& vmr_images() {
  static const std::vector<cv::Mat> images = [] {
    const fs::path root = omnisfm::test::real_data_folder(OMNISFM_SOURCE_DIR);
    std::vector<cv::Mat> read;
    for (int k = 0; k < 10; ++k) {
      const fs::path path = root / "vmr" / ("VMRImage" + std::to_string(k) + ".jpg");
      read.push_back(cv::imread(path.string(), cv::IMREAD_GRAYSCALE));
      if (read.back().empty()) throw std::runtime_error(path.string() + ": cannot be read");
    }
    return read;
  }();
  return images;
}

const MirrorImage& vmr_mirror() {
  static const MirrorImage mirror = [] {
    MeanImage mean;
    for (const cv::Mat& image : vmr_images()) mean.add(image);
    return find_mirror_image(mean.mean());
  }();
  return mirror;
}

// The view where the board of VMRImage0 is found (detect-corners' summary.vnl: 30 deg, level, 80
// deg wide), rendered.
cv::Mat board_view() {
  const PerspectiveView view(vmr_mirror(), 100 * kDegree, {30 * kDegree, 0, 80 * kDegree}, 480);
  return view.render(vmr_images()[0]);
}

void BM_FindMirrorOnTheMeanImage(benchmark::State& state) {
  MeanImage mean;
  for (const cv::Mat& image : vmr_images()) mean.add(image);
  const cv::Mat grey = mean.mean();
  for (auto _ : state) benchmark::DoNotOptimize(find_mirror_image(grey).centre.x());
}
BENCHMARK(BM_FindMirrorOnTheMeanImage)->Unit(benchmark::kMillisecond);

// A new detector each time: its views' tables are made as the first image is searched.
void BM_DetectFirstImage(benchmark::State& state) {
  const MirrorImage& mirror = vmr_mirror();
  for (auto _ : state) {
    BoardDetector detector(mirror, kGrid);
    if (!detector.detect(vmr_images()[0])) state.SkipWithError("no board in VMRImage0");
  }
}
BENCHMARK(BM_DetectFirstImage)->Unit(benchmark::kMillisecond);

// The images after the first, through one detector: the per-image cost of a folder.
void BM_DetectLaterImage(benchmark::State& state) {
  BoardDetector detector(vmr_mirror(), kGrid);
  detector.detect(vmr_images()[0]);
  int k = 1;
  for (auto _ : state) {
    if (!detector.detect(vmr_images()[k])) state.SkipWithError("no board");
    k = k % 9 + 1;
  }
}
BENCHMARK(BM_DetectLaterImage)->Unit(benchmark::kMillisecond);

void BM_RenderOneView(benchmark::State& state) {
  const PerspectiveView view(vmr_mirror(), 100 * kDegree, {30 * kDegree, 0, 80 * kDegree}, 480);
  for (auto _ : state) benchmark::DoNotOptimize(view.render(vmr_images()[0]).data);
}
BENCHMARK(BM_RenderOneView)->Unit(benchmark::kMillisecond);

// Peers: OpenCV's quick check, which orders the 108 views of every image, and its full detector,
// run on the views in that order until one gives the board.
void BM_OpenCvQuickCheckOneView(benchmark::State& state) {
  const cv::Mat view = board_view();
  for (auto _ : state) benchmark::DoNotOptimize(cv::checkChessboard(view, kGrid));
}
BENCHMARK(BM_OpenCvQuickCheckOneView)->Unit(benchmark::kMillisecond);

// The quick check over all 108 views of VMRImage0 (BoardSearch's defaults), per view: its cost
// depends on what a view shows.
void BM_OpenCvQuickCheckEveryView(benchmark::State& state) {
  const BoardSearch search;
  std::vector<cv::Mat> views;
  for (double fov : search.fields_of_view_deg)
    for (double azimuth = 0; azimuth < 360 - 1e-9; azimuth += search.azimuth_step_deg)
      for (double elevation : search.elevations_deg) {
        const PerspectiveView view(vmr_mirror(), search.elevation_span_deg * kDegree,
                                   {azimuth * kDegree, elevation * kDegree, fov * kDegree},
                                   search.view_size);
        views.push_back(view.render(vmr_images()[0]));
      }
  for (auto _ : state)
    for (const cv::Mat& view : views) benchmark::DoNotOptimize(cv::checkChessboard(view, kGrid));
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(views.size()));
}
BENCHMARK(BM_OpenCvQuickCheckEveryView)->Unit(benchmark::kMillisecond);

void BM_OpenCvFullDetectorOneView(benchmark::State& state) {
  const cv::Mat view = board_view();
  std::vector<cv::Point2f> corners;
  for (auto _ : state) {
    cv::Mat meta;
    if (!cv::findChessboardCornersSB(
            view, kGrid, corners,
            cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY | cv::CALIB_CB_LARGER, meta))
      state.SkipWithError("no board in the view");
  }
}
BENCHMARK(BM_OpenCvFullDetectorOneView)->Unit(benchmark::kMillisecond);

}  // namespace

int main(int argc, char** argv) {
  cv::setNumThreads(1);
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
