#pragma once
// Shi-Tomasi corners, as cv::goodFeaturesToTrack finds them with its defaults (3 x 3 Sobel
// gradients summed over 3 x 3 blocks, the smaller eigenvalue of their second-moment matrix; the
// local maxima of it above quality_level times the strongest in the mask, strongest first, each
// at least min_distance from every stronger one kept), in fewer passes over the image: the
// tracker detects on every frame that it has tracks to replace, and OpenCV's box filter of the
// moments (double sums over three channels) and its full sort of every candidate cost more than
// the rest of the detection.

#include <opencv2/core.hpp>
#include <vector>

namespace omnisfm::track {

// image: CV_8UC1; mask: CV_8UC1 of the image's size (non-zero where corners may be). At most
// max_corners corners, strongest first, at whole pixels; none on the image's outermost pixels.
std::vector<cv::Point2f> shi_tomasi_corners(const cv::Mat& image, int max_corners,
                                            double quality_level, double min_distance,
                                            const cv::Mat& mask);

}  // namespace omnisfm::track
