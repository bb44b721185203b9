#pragma once
// The plain zero-mean normalised correlation of one square of an image with squares of the same
// image elsewhere (OpenCV's TM_CCOEFF_NORMED), computed only where asked: the twin search asks
// at a few thousand places about a lost track, where cv::matchTemplate's transform over the whole
// search square cost an eighth of the tracker's instructions on the realistic rover.

#include <opencv2/core.hpp>
#include <vector>

namespace omnisfm::track {

class SquareCorrelation {
 public:
  // The square of side 2 half + 1 about `centre` of `image` (CV_32FC1), which must lie inside it.
  SquareCorrelation(const cv::Mat& image, const cv::Point& centre, int half);

  // Its correlation with the square about `centre`, in [-1, 1]; 0 where either square is flat.
  // That square must lie inside the image.
  double at(const cv::Point& centre) const;

  // Whether the square about `centre` lies inside the image.
  bool fits(const cv::Point& centre) const { return fits(image_, centre, half_); }
  // Whether the square of side 2 half + 1 about `centre` lies inside `image`.
  static bool fits(const cv::Mat& image, const cv::Point& centre, int half);

 private:
  cv::Mat image_;
  int half_;
  // Its rows padded with zeros to whole registers, and which of a padded row's pixels count.
  int padded_side_ = 0;
  std::vector<float> zero_mean_;  // the first square less its mean, row-major, padded rows
  std::vector<float> mask_;
  double norm_squared_ = 0;  // the sum of zero_mean_'s squares
};

}  // namespace omnisfm::track
