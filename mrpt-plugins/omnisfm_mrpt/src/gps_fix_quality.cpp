#include "omnisfm/mrpt_plugin/gps_fix_quality.h"

#include <algorithm>
#include <cmath>

namespace omnisfm::mrpt_plugin {
namespace {

constexpr double kSmallestDop = 0.5;

}  // namespace

double user_equivalent_range_error(int fix_quality) {
  switch (fix_quality) {
    case 0:
      return 0;
    case 2:
      return 0.7;  // differential (SBAS, DGPS)
    case 4:
      return 0.02;  // RTK fixed
    case 5:
      return 0.2;  // RTK float
    default:
      return 3.0;  // autonomous, and anything else that claims a position
  }
}

GpsFixQuality gps_fix_quality_of(double horizontal_sigma, double vertical_sigma) {
  GpsFixQuality fix;
  for (const int quality : {4, 5, 2, 1}) {
    fix.fix_quality = quality;
    if (horizontal_sigma <= 2 * user_equivalent_range_error(quality)) break;
  }
  const double uere = user_equivalent_range_error(fix.fix_quality);
  fix.hdop = std::max(kSmallestDop, std::sqrt(2.0) * horizontal_sigma / uere);
  fix.vdop = std::max(kSmallestDop, vertical_sigma / uere);
  return fix;
}

GpsSigma gps_sigma_of(int fix_quality, double hdop, double vdop_or_zero) {
  const double uere = user_equivalent_range_error(fix_quality);
  GpsSigma sigma;
  sigma.horizontal = hdop * uere / std::sqrt(2.0);
  sigma.vertical = vdop_or_zero > 0 ? vdop_or_zero * uere : 2 * sigma.horizontal;
  return sigma;
}

}  // namespace omnisfm::mrpt_plugin
