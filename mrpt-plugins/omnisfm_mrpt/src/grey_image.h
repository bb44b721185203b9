#pragma once
// An MRPT image as the tracker takes it: one 8-bit grey channel, a copy of its own.

#include <mrpt/img/CImage.h>

#include <opencv2/core.hpp>

namespace omnisfm::mrpt_plugin {

cv::Mat grey_of(const mrpt::img::CImage& image);

}  // namespace omnisfm::mrpt_plugin
