#include "omnisfm/mrpt_plugin/geodetic_table.h"

#include <stdexcept>

#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/vnlog.h"

namespace omnisfm::mrpt_plugin {

void write_geodetic_table(const std::string& path, const std::vector<double>& timestamps,
                          const std::vector<Eigen::Vector3d>& enu_positions,
                          const LocalEnuFrame& enu, const std::string& what) {
  if (timestamps.size() != enu_positions.size())
    throw std::invalid_argument("a geodetic table needs one timestamp per position");
  io::write_text_atomically(path, [&](std::ostream& out) {
    io::VnlogWriter table(out, {"timestamp", "latitude", "longitude", "height"});
    table.comment(what + ": degrees, metres above the WGS84 ellipsoid");
    for (std::size_t i = 0; i < timestamps.size(); ++i) {
      const GeodeticPoint p = enu.geodetic_of(enu_positions[i]);
      table.row({timestamps[i], p.latitude_deg, p.longitude_deg, p.height_m});
    }
  });
}

}  // namespace omnisfm::mrpt_plugin
