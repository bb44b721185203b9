#include "grey_image.h"

namespace omnisfm::mrpt_plugin {

cv::Mat grey_of(const mrpt::img::CImage& image) {
  const mrpt::img::CImage grey(image, mrpt::img::FAST_REF_OR_CONVERT_TO_GRAY);
  cv::Mat mat;
  grey.asCvMat(mat, mrpt::img::DEEP_COPY);
  if (mat.type() != CV_8UC1) {
    cv::Mat converted;
    mat.convertTo(converted, CV_8U);
    return converted;
  }
  return mat;
}

}  // namespace omnisfm::mrpt_plugin
