#pragma once
// A binary descriptor of a feature's appearance, for recognising it when it is seen again: ORB's
// rotated BRIEF (256 intensity comparisons on a smoothed 31 x 31 patch) at a given orientation.
// The tracker keeps the pixels around a feature where its reference patch is taken, describes
// them at angle 0 only if the track is lost, and describes a candidate at the rotation the
// reference underwent to align there, so that both sample the same points of the feature however
// the image turned.

#include <array>
#include <cstdint>
#include <opencv2/core.hpp>
#include <vector>

namespace omnisfm::track {

struct Descriptor {
  std::array<std::uint8_t, 32> bits{};  // 256 comparisons
  bool valid = false;
};

// A copy of the pixels a descriptor of a feature reads, to describe it later.
struct FeatureSurroundings {
  std::vector<std::uint8_t> pixels;  // side x side, row-major; empty when they did not fit
  int side = 0;
  cv::Point2f at;  // the feature, in the copy's pixels
};

FeatureSurroundings surroundings(const cv::Mat& image, const cv::Point2f& at);

// The descriptor of the feature, its pattern turned by `angle_rad` (image axes, y down: from x
// toward y). Invalid when the surroundings are empty.
Descriptor describe(const FeatureSurroundings& around, double angle_rad);

// The same for the feature at `at` in `image` (CV_8UC1).
Descriptor describe(const cv::Mat& image, const cv::Point2f& at, double angle_rad);

// How many of the 256 comparisons differ.
int hamming_distance(const Descriptor& a, const Descriptor& b);

}  // namespace omnisfm::track
