#pragma once
// The Gaussian blur of an 8-bit grey image into floats, for the images patches are aligned on. The
// same as cv::sepFilter2D with cv::getGaussianKernel's taps and the border reflected about the edge
// pixel (cv::BORDER_REFLECT_101 | cv::BORDER_ISOLATED: a region of interest is blurred as a copy of
// it would be, its parent's pixels unread), up to float rounding; written out because OpenCV's
// generic filter engine took a sixth of the tracker's time for a three-tap kernel (on the realistic
// rover 0.25 ms of 1.7 per frame, where this takes 0.12-0.13 ms).

#include <opencv2/core.hpp>

namespace omnisfm::track {

// The kernel reaches three sigma, rounded down, and at least one pixel: a 0.5-pixel blur has 3
// taps (the next would weigh 3e-4). sigma > 0; `grey` CV_8UC1, not empty.
cv::Mat gaussian_blurred_float(const cv::Mat& grey, double sigma);

}  // namespace omnisfm::track
