// The stored layout of mrpt::obs::CObservationGPS at each of MRPT 2.5's versions: since version
// 10 a list of GNSS messages, each its type and a block of its fields; before, the NMEA GGA and
// RMC and the Topcon PZS fields one by one, with the sizes of the fields MRPT reads them into.
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/poses/CPose3D.h>

#include "class_layouts.h"

namespace omnisfm::mrpt_plugin {
namespace {

using mrpt::obs::gnss::Message_NMEA_GGA;
using mrpt::obs::gnss::Message_NMEA_RMC;
using mrpt::obs::gnss::Message_TOPCON_PZS;

constexpr std::size_t kTimestamp = 8;

// The NMEA messages, stored as their type, a 32-bit byte count and their fields. The others
// (Topcon's and Novatel's) have layouts of their own.
bool is_nmea(std::int32_t type) {
  return type >= mrpt::obs::gnss::NMEA_GGA && type <= mrpt::obs::gnss::NMEA_ZDA;
}

void gnss_messages(BoundedObjectCopy& in) {
  const auto messages = in.value<std::uint32_t>();
  for (std::uint32_t i = 0; i < messages; ++i) {
    if (!is_nmea(in.value<std::int32_t>())) in.layout_unknown();
    in.array(1);
  }
}

template <typename Matrix>
constexpr std::size_t matrix_bytes() {
  return sizeof(typename Matrix::Scalar) * Matrix::RowsAtCompileTime * Matrix::ColsAtCompileTime;
}

std::size_t gga_bytes(int version) {
  const Message_NMEA_GGA::content_t f;
  std::size_t bytes = sizeof f.UTCTime.hour + sizeof f.UTCTime.minute + sizeof f.UTCTime.sec +
                      sizeof f.latitude_degrees + sizeof f.longitude_degrees +
                      sizeof f.fix_quality + sizeof f.altitude_meters + sizeof f.satellitesUsed +
                      sizeof f.thereis_HDOP + sizeof f.HDOP;
  if (version >= 9)
    bytes += sizeof f.geoidal_distance + sizeof f.orthometric_altitude +
             sizeof f.corrected_orthometric_altitude;
  return bytes;
}

std::size_t rmc_bytes() {
  const Message_NMEA_RMC::content_t f;
  return sizeof f.UTCTime.hour + sizeof f.UTCTime.minute + sizeof f.UTCTime.sec +
         sizeof f.validity_char + sizeof f.latitude_degrees + sizeof f.longitude_degrees +
         sizeof f.speed_knots + sizeof f.direction_degrees;
}

std::size_t pzs_bytes(int version) {
  const Message_TOPCON_PZS f;
  std::size_t bytes = sizeof f.latitude_degrees + sizeof f.longitude_degrees +
                      sizeof f.height_meters + sizeof f.RTK_height_meters + sizeof f.PSigma +
                      sizeof f.angle_transmitter + sizeof f.nId + sizeof f.Fix +
                      sizeof f.TXBattery + sizeof f.RXBattery + sizeof f.error;
  if (version >= 6)
    bytes += sizeof f.hasCartesianPosVel + sizeof f.cartesian_x + sizeof f.cartesian_y +
             sizeof f.cartesian_z + sizeof f.cartesian_vx + sizeof f.cartesian_vy +
             sizeof f.cartesian_vz + sizeof f.hasPosCov +
             matrix_bytes<decltype(f.pos_covariance)>() + sizeof f.hasVelCov +
             matrix_bytes<decltype(f.vel_covariance)>() + sizeof f.hasStats +
             sizeof f.stats_GPS_sats_used + sizeof f.stats_GLONASS_sats_used;
  if (version >= 8) bytes += sizeof f.stats_rtk_fix_progress;
  return bytes;
}

// Versions 1 to 9: the messages' fields one by one, each message after a flag saying it is there.
void gps_fields(BoundedObjectCopy& in, int version) {
  if (version >= 3) in.skip(kTimestamp);
  if (in.flag()) in.skip(gga_bytes(version));
  if (in.flag()) in.skip(rmc_bytes());
  if (version > 1) in.string();  // the sensor label
  if (version >= 4) in.object<mrpt::poses::CPose3D>();  // the sensor pose
  if (version >= 5 && in.flag()) in.skip(pzs_bytes(version));
  if (version >= 7 && in.flag()) in.layout_unknown();  // satellites, which MRPT refuses to read
}

}  // namespace

void gps_layout(BoundedObjectCopy& in, int version) {
  if (version > 11) in.layout_unknown();
  if (version >= 10) {
    in.skip(2 * kTimestamp);
    in.string();  // the sensor label
    in.object<mrpt::poses::CPose3D>();  // the sensor pose
    if (version >= 11) in.skip(1);  // whether it has the satellites' time
    gnss_messages(in);
  } else if (version == 0) {
    if (in.flag()) in.skip(sizeof(Message_NMEA_GGA::content_t));
    if (in.flag()) in.skip(sizeof(Message_NMEA_RMC::content_t));
  } else {
    gps_fields(in, version);
  }
}

}  // namespace omnisfm::mrpt_plugin
