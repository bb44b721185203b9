#pragma once
// A virtual perspective camera looking out of the mirror: a square view rendered from the raw
// image through a lookup table (raw pixel per view pixel), in which a board that the mirror bends
// is nearly straight again. The table comes from the camera model when there is one, else from a
// generic approximation of any mirror of revolution: elevation linear in the distance from the
// mirror's centre across its picture (equiangular), azimuth the polar angle. Either only has to
// straighten a board enough for a detector to find it; the corners are refined on the raw image.

#include <opencv2/core.hpp>

#include "omnisfm/calib/mirror_image.h"
#include "omnisfm/camera/catadioptric_camera.h"

namespace omnisfm::calib {

struct ViewDirection {
  double azimuth = 0;    // radians, about the mirror's axis
  double elevation = 0;  // radians above the plane across the axis
  double field_of_view = 0;  // radians, across the square view
};

// The generic table's costly part, shared by views that differ in azimuth alone (a view at
// azimuth a is the one at azimuth 0 turned by a about the mirror's centre): each view pixel's
// distance from the centre and the cosine and sine of its azimuth, looking at azimuth 0.
// Elevations run from -elevation_span/2 at the inner radius to +elevation_span/2 at the outer one.
class GenericViewShape {
 public:
  GenericViewShape(const MirrorImage& mirror, double elevation_span, double elevation,
                   double field_of_view, int size);
  double elevation() const { return elevation_; }
  double field_of_view() const { return field_of_view_; }

 private:
  friend class PerspectiveView;
  Eigen::Vector2d centre_;
  double elevation_, field_of_view_;
  int size_;
  cv::Mat radius_, cosine_, sine_;  // CV_64F, per view pixel
};

class PerspectiveView {
 public:
  // The generic table, looking at `azimuth`.
  PerspectiveView(const GenericViewShape& shape, double azimuth);
  PerspectiveView(const MirrorImage& mirror, double elevation_span, const ViewDirection& direction,
                  int size);
  // Through the model: each view pixel's direction (frame C, z the mirror's axis) projected at
  // 10 m. A pixel whose direction does not project maps outside the image.
  PerspectiveView(const camera::CatadioptricCamera& camera, const ViewDirection& direction,
                  int size);

  // The view rendered from a raw image (bicubic; black outside it).
  cv::Mat render(const cv::Mat& raw) const;
  // The raw image's pixel at a view pixel, the table interpolated bilinearly.
  cv::Point2f raw_pixel(cv::Point2f view_pixel) const;
  const ViewDirection& direction() const { return direction_; }

 private:
  ViewDirection direction_;
  cv::Mat map_x_, map_y_;  // CV_32F, the raw pixel per view pixel
};

}  // namespace omnisfm::calib
