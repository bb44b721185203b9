// The mean change one frame's pixel noise makes to the filter's update (a study, not a
// benchmark: one run, a line per frame studied). The filter runs vision alone over
// sim::long_drive to each frame F given; there, copies of it take frame F + 1's exact pixels
// (the reference) and, SAMPLES times, those pixels with fresh Gaussian noise. A linear update is
// unbiased: the noisy updates' mean is the reference's. Printed per frame F + 1: the mean
// rotation error about the camera's axes (z up) and its standard error, the reference's
// rotation relative to the noisy update's as drive_nees axes=1 prints the truth's relative to
// the estimate's; then the mean change of the step since frame F along the reference's step (the
// noisy update's less the reference's, a fraction of that step) and its standard error; the
// reference's step, metres in the filter's units; the tracks frame F + 1 sees.
//   update_bias [SEED=2] [SAMPLES=4000] [F...=1000 2000 3000] [NAME=VALUE...]
// F: from FilterSettings::smoothed_start_frames on (before it, the smoothed start's solve).
// NAME=VALUE: noise (0.2 px, frame F + 1's), state_noise (the tracks' noise up to frame F; 0,
// exact tracks, by default), update_iterations, pixel_sigma.

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <random>
#include <vector>

#include "omnisfm/eval/filter_consistency.h"
#include "omnisfm/sfm/blas_threads.h"
#include "omnisfm/sfm/online_filter.h"
#include "omnisfm/sfm/pipeline.h"
#include "omnisfm/sim/endless_drive.h"
#include "setting_assignment.h"

namespace {

// Sums of samples, for their mean and the mean's standard error.
template <int N>
struct Moments {
  Eigen::Matrix<double, N, 1> sum = Eigen::Matrix<double, N, 1>::Zero();
  Eigen::Matrix<double, N, 1> sum_squares = Eigen::Matrix<double, N, 1>::Zero();
  int count = 0;

  void add(const Eigen::Matrix<double, N, 1>& x) {
    sum += x;
    sum_squares += x.cwiseAbs2();
    ++count;
  }
  Eigen::Matrix<double, N, 1> mean() const { return sum / count; }
  Eigen::Matrix<double, N, 1> standard_error() const {
    const Eigen::Matrix<double, N, 1> variance =
        (sum_squares - count * mean().cwiseAbs2()) / (count - 1);
    return (variance.cwiseMax(0) / count).cwiseSqrt();
  }
};

Eigen::Vector3d camera_centre(const omnisfm::sfm::OnlineFilter& filter) {
  return filter.cam_from_world().inverse().translation();
}

}  // namespace

int main(int argc, char** argv) {
  using namespace omnisfm;
  sfm::use_one_blas_thread();
  double noise = 0.2, state_noise = 0;
  sfm::FilterSettings settings;
  const bench::Setters settable = {
      {"noise", [&](double v) { noise = v; }},
      {"state_noise", [&](double v) { state_noise = v; }},
      {"update_iterations", [&](double v) { settings.update_iterations = static_cast<int>(v); }},
      {"pixel_sigma", [&](double v) { settings.pixel_sigma = v; }},
  };
  std::vector<const char*> positional;
  for (int k = 1; k < argc; ++k) {
    if (!std::strchr(argv[k], '=')) {
      positional.push_back(argv[k]);
    } else if (!bench::apply_assignment(argv[k], settable)) {
      std::fprintf(stderr, "update_bias: unknown setting, or not a number: %s\n", argv[k]);
      return 2;
    }
  }
  // Positional arguments, whole numbers: the seed, the samples, then the frames studied.
  std::vector<int> numbers;
  for (const char* text : positional) {
    double value = 0;
    if (!bench::parse_number(text, &value) || value != std::floor(value)) {
      std::fprintf(stderr, "update_bias: not a whole number: %s\n", text);
      return 2;
    }
    numbers.push_back(static_cast<int>(value));
  }
  const int seed = numbers.size() > 0 ? numbers[0] : 2;
  const int samples = numbers.size() > 1 ? numbers[1] : 4000;
  std::vector<int> studied(numbers.begin() + std::min<size_t>(numbers.size(), 2), numbers.end());
  if (studied.empty()) studied = {1000, 2000, 3000};
  std::sort(studied.begin(), studied.end());
  studied.erase(std::unique(studied.begin(), studied.end()), studied.end());
  if (samples < 2) {
    std::fprintf(stderr, "update_bias: at least 2 samples, for a standard error\n");
    return 2;
  }
  if (studied.front() < settings.smoothed_start_frames) {
    std::fprintf(stderr,
                 "update_bias: the frames studied are %d or later (before, the smoothed "
                 "start's solve)\n",
                 settings.smoothed_start_frames);
    return 2;
  }
  if (!(noise > 0) || !(state_noise >= 0)) {
    std::fprintf(stderr, "update_bias: noise above 0 and state_noise 0 or above, in pixels\n");
    return 2;
  }

  // One frame past the last studied, so that frame F + 1 keeps the tracks that start there.
  const int frames = studied.back() + 3;
  const sim::Dataset exact = sim::long_drive(frames, 0.0, seed);
  const auto exact_frames = sfm::observations_by_frame(exact.observations);
  const auto state_frames =
      state_noise > 0
          ? sfm::observations_by_frame(sim::long_drive(frames, state_noise, seed).observations)
          : exact_frames;
  sfm::OnlineFilter filter(exact.camera, settings);
  std::mt19937_64 random(static_cast<std::uint64_t>(seed) * 7919 + 1);
  std::normal_distribution<double> pixel_noise(0, noise);
  constexpr double kDeg = 180 / M_PI;
  std::printf(
      "# frame rotation_x_deg rotation_y_deg rotation_z_deg standard_error_x standard_error_y "
      "standard_error_z step_change step_change_standard_error step tracks\n");
  size_t next = 0;
  for (int f = 0; next < studied.size(); ++f) {
    filter.process_frame(f, state_frames[f]);
    if (f != studied[next]) continue;
    ++next;
    const Eigen::Vector3d centre = camera_centre(filter);
    sfm::OnlineFilter reference = filter;
    reference.process_frame(f + 1, exact_frames[f + 1]);
    const Eigen::Vector3d reference_step = camera_centre(reference) - centre;
    Moments<4> bias;  // rotation about x, y, z (deg), then the step's change along its direction
    for (int s = 0; s < samples; ++s) {
      sfm::OnlineFilter noisy = filter;
      std::vector<core::TrackPixel> pixels = exact_frames[f + 1];
      for (core::TrackPixel& p : pixels)
        p.pixel += Eigen::Vector2d(pixel_noise(random), pixel_noise(random));
      noisy.process_frame(f + 1, pixels);
      Eigen::Vector4d sample;
      sample.head<3>() =
          eval::filter_pose_error(reference.cam_from_world(), noisy.cam_from_world()).head<3>() *
          kDeg;
      sample[3] = (camera_centre(noisy) - centre - reference_step).dot(reference_step) /
                  reference_step.squaredNorm();
      bias.add(sample);
    }
    const Eigen::Vector4d mean = bias.mean(), standard_error = bias.standard_error();
    std::printf("%d %.2e %.2e %.2e %.1e %.1e %.1e %.2e %.1e %.4f %zu\n", f + 1, mean[0], mean[1],
                mean[2], standard_error[0], standard_error[1], standard_error[2], mean[3],
                standard_error[3], reference_step.norm(), exact_frames[f + 1].size());
    std::fflush(stdout);
  }
}
