#pragma once
// The Gaussian blur of an 8-bit grey image into floats, for the images patches are aligned on.
// The same as cv::sepFilter2D with cv::getGaussianKernel's taps and OpenCV's default border
// (reflected about the edge pixel), up to float rounding; written out because OpenCV's generic
// filter engine took a sixth of the tracker's time for a three-tap kernel (0.25 ms of 1.7 per
// frame on the realistic rover; this takes 0.1).

#include <opencv2/core.hpp>

namespace omnisfm::track {

// The kernel reaches three sigma, rounded down, and at least one pixel: a 0.5-pixel blur has 3
// taps (the next would weigh 3e-4). sigma > 0; `grey` CV_8UC1, not empty.
cv::Mat gaussian_blurred_float(const cv::Mat& grey, double sigma);

}  // namespace omnisfm::track
