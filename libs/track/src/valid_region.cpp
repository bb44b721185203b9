#include "omnisfm/track/valid_region.h"

#include <opencv2/imgproc.hpp>

namespace omnisfm::track {
namespace {

constexpr int kGridStep = 4;

bool sees_mirror(const camera::CatadioptricCamera& camera, double x, double y) {
  Eigen::Vector3d origin, direction;
  return camera.unproject(Eigen::Vector2d(x, y), &origin, &direction);
}

}  // namespace

cv::Mat valid_region_mask(const camera::CatadioptricCamera& camera, double margin_px) {
  const int width = camera.image_width(), height = camera.image_height();
  const int nodes_x = (width - 1) / kGridStep + 2, nodes_y = (height - 1) / kGridStep + 2;
  cv::Mat node_valid(nodes_y, nodes_x, CV_8UC1);
  for (int j = 0; j < nodes_y; ++j)
    for (int i = 0; i < nodes_x; ++i)
      node_valid.at<uchar>(j, i) = sees_mirror(camera, i * kGridStep, j * kGridStep);

  // A one-pixel invalid frame makes the distance transform keep away from the image border.
  cv::Mat valid = cv::Mat::zeros(height + 2, width + 2, CV_8UC1);
  for (int j = 0; j + 1 < nodes_y; ++j)
    for (int i = 0; i + 1 < nodes_x; ++i) {
      const int corners = node_valid.at<uchar>(j, i) + node_valid.at<uchar>(j, i + 1) +
                          node_valid.at<uchar>(j + 1, i) + node_valid.at<uchar>(j + 1, i + 1);
      for (int y = j * kGridStep; y < std::min((j + 1) * kGridStep, height); ++y)
        for (int x = i * kGridStep; x < std::min((i + 1) * kGridStep, width); ++x) {
          const bool inside = corners == 4   ? true
                              : corners == 0 ? false
                                             : sees_mirror(camera, x, y);
          valid.at<uchar>(y + 1, x + 1) = inside ? 255 : 0;
        }
    }

  cv::Mat distance;
  cv::distanceTransform(valid, distance, cv::DIST_L2, cv::DIST_MASK_PRECISE);
  cv::Mat mask;
  cv::compare(distance(cv::Rect(1, 1, width, height)), margin_px, mask, cv::CMP_GT);
  return mask;
}

cv::Point2d region_centre(const cv::Mat& mask) {
  const cv::Moments m = cv::moments(mask, true);
  if (m.m00 <= 0) return {(mask.cols - 1) / 2.0, (mask.rows - 1) / 2.0};
  return {m.m10 / m.m00, m.m01 / m.m00};
}

}  // namespace omnisfm::track
