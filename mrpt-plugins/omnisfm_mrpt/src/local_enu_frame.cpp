#include "omnisfm/mrpt_plugin/local_enu_frame.h"

#include <GeographicLib/LocalCartesian.hpp>

#include <cmath>
#include <stdexcept>

namespace omnisfm::mrpt_plugin {

struct LocalEnuFrame::Conversion {
  GeographicLib::LocalCartesian local;
};

LocalEnuFrame::LocalEnuFrame(const GeodeticPoint& origin) : origin_(origin) {
  if (!std::isfinite(origin.latitude_deg) || !std::isfinite(origin.longitude_deg) ||
      !std::isfinite(origin.height_m) || std::abs(origin.latitude_deg) > 90)
    throw std::invalid_argument("a geodetic origin needs a latitude in [-90, 90] and finite values");
  conversion_ = std::make_unique<Conversion>(Conversion{GeographicLib::LocalCartesian(
      origin.latitude_deg, origin.longitude_deg, origin.height_m)});
}

LocalEnuFrame::~LocalEnuFrame() = default;

LocalEnuFrame::LocalEnuFrame(const LocalEnuFrame& other)
    : origin_(other.origin_), conversion_(std::make_unique<Conversion>(*other.conversion_)) {}

LocalEnuFrame& LocalEnuFrame::operator=(const LocalEnuFrame& other) {
  origin_ = other.origin_;
  conversion_ = std::make_unique<Conversion>(*other.conversion_);
  return *this;
}

Eigen::Vector3d LocalEnuFrame::enu_of(const GeodeticPoint& point) const {
  Eigen::Vector3d enu;
  conversion_->local.Forward(point.latitude_deg, point.longitude_deg, point.height_m, enu.x(),
                             enu.y(), enu.z());
  return enu;
}

GeodeticPoint LocalEnuFrame::geodetic_of(const Eigen::Vector3d& enu) const {
  GeodeticPoint point;
  conversion_->local.Reverse(enu.x(), enu.y(), enu.z(), point.latitude_deg, point.longitude_deg,
                             point.height_m);
  return point;
}

}  // namespace omnisfm::mrpt_plugin
