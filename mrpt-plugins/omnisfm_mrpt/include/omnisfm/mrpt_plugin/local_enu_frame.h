#pragma once
// A local east-north-up (ENU) frame about a geodetic origin on the WGS84 ellipsoid, as GPS fixes
// are turned into positions the estimators use (GeographicLib's LocalCartesian, an exact
// conversion through earth-centred coordinates, not a flat-earth approximation).
//
// MRPT-free and GeographicLib-free for its users: the omnisfm command writes geodetic
// trajectories through it.

#include <Eigen/Core>
#include <memory>

namespace omnisfm::mrpt_plugin {

struct GeodeticPoint {
  double latitude_deg = 0;   // north positive
  double longitude_deg = 0;  // east positive
  double height_m = 0;       // above the WGS84 ellipsoid
};

class LocalEnuFrame {
 public:
  // Throws std::invalid_argument for a latitude outside [-90, 90] or a value that is not finite.
  explicit LocalEnuFrame(const GeodeticPoint& origin);
  ~LocalEnuFrame();
  LocalEnuFrame(const LocalEnuFrame& other);
  LocalEnuFrame& operator=(const LocalEnuFrame& other);

  const GeodeticPoint& origin() const { return origin_; }
  Eigen::Vector3d enu_of(const GeodeticPoint& point) const;
  GeodeticPoint geodetic_of(const Eigen::Vector3d& enu) const;

 private:
  struct Conversion;
  GeodeticPoint origin_;
  std::unique_ptr<Conversion> conversion_;
};

}  // namespace omnisfm::mrpt_plugin
