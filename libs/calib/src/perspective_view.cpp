#include "omnisfm/calib/perspective_view.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <opencv2/imgproc.hpp>

namespace omnisfm::calib {

namespace {

// The unit direction of view pixel (u, v) of a square view of `size` pixels.
template <typename Direction>
void for_each_view_pixel(const ViewDirection& d, int size, Direction&& at) {
  const double f = size / 2.0 / std::tan(d.field_of_view / 2);
  const Eigen::Vector3d forward(std::cos(d.elevation) * std::cos(d.azimuth),
                                std::cos(d.elevation) * std::sin(d.azimuth),
                                std::sin(d.elevation));
  const Eigen::Vector3d right(-std::sin(d.azimuth), std::cos(d.azimuth), 0);
  const Eigen::Vector3d up = right.cross(forward);
  for (int v = 0; v < size; ++v)
    for (int u = 0; u < size; ++u) {
      const Eigen::Vector3d ray = ((u + 0.5 - size / 2.0) / f) * right -
                                  ((v + 0.5 - size / 2.0) / f) * up + forward;
      at(u, v, ray.normalized());
    }
}

}  // namespace

GenericViewShape::GenericViewShape(const MirrorImage& mirror, double elevation_span,
                                   double elevation, double field_of_view, int size)
    : centre_(mirror.centre),
      elevation_(elevation),
      field_of_view_(field_of_view),
      size_(size),
      radius_(size, size, CV_64F),
      cosine_(size, size, CV_64F),
      sine_(size, size, CV_64F) {
  for_each_view_pixel(
      {0, elevation, field_of_view}, size, [&](int u, int v, const Eigen::Vector3d& ray) {
        const double azimuth = std::atan2(ray.y(), ray.x());
        const double ray_elevation = std::asin(std::clamp(ray.z(), -1.0, 1.0));
        radius_.at<double>(v, u) =
            mirror.inner_radius +
            (ray_elevation / elevation_span + 0.5) * (mirror.outer_radius - mirror.inner_radius);
        cosine_.at<double>(v, u) = std::cos(azimuth);
        sine_.at<double>(v, u) = std::sin(azimuth);
      });
}

PerspectiveView::PerspectiveView(const GenericViewShape& shape, double azimuth)
    : direction_{azimuth, shape.elevation_, shape.field_of_view_},
      map_x_(shape.size_, shape.size_, CV_32F),
      map_y_(shape.size_, shape.size_, CV_32F) {
  const double turn_cosine = std::cos(azimuth), turn_sine = std::sin(azimuth);
  for (int v = 0; v < shape.size_; ++v)
    for (int u = 0; u < shape.size_; ++u) {
      const double r = shape.radius_.at<double>(v, u);
      const double c = shape.cosine_.at<double>(v, u), s = shape.sine_.at<double>(v, u);
      map_x_.at<float>(v, u) =
          static_cast<float>(shape.centre_.x() + r * (c * turn_cosine - s * turn_sine));
      map_y_.at<float>(v, u) =
          static_cast<float>(shape.centre_.y() + r * (s * turn_cosine + c * turn_sine));
    }
}

PerspectiveView::PerspectiveView(const MirrorImage& mirror, double elevation_span,
                                 const ViewDirection& direction, int size)
    : PerspectiveView(GenericViewShape(mirror, elevation_span, direction.elevation,
                                       direction.field_of_view, size),
                      direction.azimuth) {}

PerspectiveView::PerspectiveView(const camera::CatadioptricCamera& camera,
                                 const ViewDirection& direction, int size)
    : direction_(direction) {
  constexpr double kDistance = 10;  // metres: the mirror's few centimetres of viewpoints blur out
  // Projected on a grid of every kStep-th view pixel and interpolated between: the table is
  // smooth, and projecting every pixel of a hundred views takes seconds.
  constexpr int kStep = 8;
  const int nodes = size / kStep + 1;
  cv::Mat node_x(nodes, nodes, CV_32F), node_y(nodes, nodes, CV_32F);
  ViewDirection coarse = direction;
  const double f = size / 2.0 / std::tan(direction.field_of_view / 2);
  coarse.field_of_view = 2 * std::atan(nodes / 2.0 * kStep / f);
  for_each_view_pixel(coarse, nodes, [&](int u, int v, const Eigen::Vector3d& ray) {
    Eigen::Vector2d pixel;
    if (!camera.project(kDistance * ray, &pixel)) pixel.setConstant(-1e6);
    node_x.at<float>(v, u) = static_cast<float>(pixel.x());
    node_y.at<float>(v, u) = static_cast<float>(pixel.y());
  });
  // With the nodes' focal length f / kStep, node i looks where view pixel
  // x = kStep (i + 0.5 - nodes / 2) + size / 2 - 0.5 does; each view pixel reads the nodes there.
  const double c = (0.5 - size / 2.0) / kStep - 0.5 + nodes / 2.0;
  const cv::Mat to_nodes = (cv::Mat_<double>(2, 3) << 1.0 / kStep, 0, c, 0, 1.0 / kStep, c);
  cv::warpAffine(node_x, map_x_, to_nodes, cv::Size(size, size), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                 cv::BORDER_REPLICATE);
  cv::warpAffine(node_y, map_y_, to_nodes, cv::Size(size, size), cv::INTER_LINEAR | cv::WARP_INVERSE_MAP,
                 cv::BORDER_REPLICATE);
}

cv::Mat PerspectiveView::render(const cv::Mat& raw) const {
  cv::Mat view;
  cv::remap(raw, view, map_x_, map_y_, cv::INTER_CUBIC, cv::BORDER_CONSTANT, cv::Scalar(0));
  return view;
}

cv::Point2f PerspectiveView::raw_pixel(cv::Point2f p) const {
  cv::Mat x, y;
  cv::getRectSubPix(map_x_, cv::Size(1, 1), p, x);
  cv::getRectSubPix(map_y_, cv::Size(1, 1), p, y);
  return {x.at<float>(0, 0), y.at<float>(0, 0)};
}

}  // namespace omnisfm::calib
