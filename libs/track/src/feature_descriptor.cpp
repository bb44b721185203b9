#include "omnisfm/track/feature_descriptor.h"

#include <algorithm>
#include <cmath>
#include <opencv2/features2d.hpp>

namespace omnisfm::track {
namespace {

// ORB's patch and the border it requires around a keypoint.
constexpr int kPatchSize = 31;
constexpr int kEdge = 31;
// ORB smooths the whole image it is given: a small copy keeps that cost per feature.
constexpr int kReach = kEdge + 4;

}  // namespace

FeatureSurroundings surroundings(const cv::Mat& image, const cv::Point2f& at) {
  CV_Assert(image.type() == CV_8UC1);
  FeatureSurroundings around;
  const int x = cvRound(at.x), y = cvRound(at.y);
  const cv::Rect crop(x - kReach, y - kReach, 2 * kReach + 1, 2 * kReach + 1);
  if ((crop & cv::Rect(0, 0, image.cols, image.rows)) != crop) return around;
  around.side = crop.width;
  around.pixels.resize(static_cast<size_t>(crop.width) * crop.height);
  cv::Mat copy(crop.height, crop.width, CV_8UC1, around.pixels.data());
  image(crop).copyTo(copy);
  around.at = cv::Point2f(at.x - crop.x, at.y - crop.y);
  return around;
}

Descriptor describe(const FeatureSurroundings& around, double angle_rad) {
  Descriptor result;
  if (around.pixels.empty()) return result;
  static thread_local const cv::Ptr<cv::ORB> orb =
      cv::ORB::create(1, 1.2f, 1, kEdge, 0, 2, cv::ORB::HARRIS_SCORE, kPatchSize);
  const cv::Mat pixels(around.side, around.side, CV_8UC1,
                       const_cast<std::uint8_t*>(around.pixels.data()));
  std::vector<cv::KeyPoint> keypoints{
      cv::KeyPoint(around.at, kPatchSize, static_cast<float>(angle_rad * 180 / M_PI))};
  cv::Mat descriptors;
  orb->compute(pixels, keypoints, descriptors);
  if (keypoints.size() != 1 || descriptors.rows != 1 ||
      descriptors.cols != static_cast<int>(result.bits.size()))
    return result;
  std::copy(descriptors.ptr<std::uint8_t>(0), descriptors.ptr<std::uint8_t>(0) + descriptors.cols,
            result.bits.begin());
  result.valid = true;
  return result;
}

Descriptor describe(const cv::Mat& image, const cv::Point2f& at, double angle_rad) {
  return describe(surroundings(image, at), angle_rad);
}

int hamming_distance(const Descriptor& a, const Descriptor& b) {
  int bits = 0;
  for (size_t i = 0; i < a.bits.size(); ++i)
    bits += __builtin_popcount(static_cast<unsigned>(a.bits[i] ^ b.bits[i]));
  return bits;
}

}  // namespace omnisfm::track
