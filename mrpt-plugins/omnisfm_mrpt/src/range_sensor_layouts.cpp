// The stored layouts of the range sensors' observations a real MRPT rawlog holds beside what
// omnisfm takes: 2D laser scans and sonar-like range arrays, as MRPT 2.5's serializeFrom reads
// them. omnisfm skips them, but MRPT sizes their readings from a stored count.
#include <mrpt/math/CMatrixF.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationRange.h>
#include <mrpt/poses/CPose3D.h>

#include "class_layouts.h"

namespace omnisfm::mrpt_plugin {
namespace {

constexpr std::size_t kTimestamp = 8, kFloat = 4, kDouble = 8, kBool = 1;

void scan_2d(BoundedObjectCopy& in, int version) {
  if (version > 7) in.layout_unknown();
  in.skip(kFloat + kBool + kFloat);  // aperture, direction, maximum range
  in.object<mrpt::poses::CPose3D>();  // the sensor pose
  if (version < 6) in.object<mrpt::math::CMatrixF>();  // its covariance, dropped in version 6
  const auto beams = in.value<std::uint32_t>();
  in.counted(beams, kFloat);                // ranges
  if (version >= 1) in.counted(beams, 1);  // which are valid
  if (version <= 3) {
    if (version >= 2) in.skip(kFloat);  // the error's standard deviation
    if (version >= 3) in.skip(kTimestamp);
    return;
  }
  in.skip(kFloat + kTimestamp + kFloat);  // the error, the time, the beams' aperture
  if (version >= 5) {
    in.string();  // the sensor label
    in.skip(kDouble);  // the pitch between beams
  }
  if (version >= 7 && in.flag()) in.counted(beams, sizeof(std::int32_t));  // intensities
}

void range(BoundedObjectCopy& in, int version) {
  if (version > 3) in.layout_unknown();
  in.skip(3 * kFloat);  // the distances' range and the cone's aperture
  const auto measurements = in.value<std::uint32_t>();
  const std::size_t id_bytes = version >= 3 ? sizeof(std::uint16_t) : 0;
  in.elements(measurements, id_bytes + BoundedObjectCopy::kLeastObjectBytes + kFloat, [&] {
    in.skip(id_bytes);  // the sensor's ID
    in.object<mrpt::poses::CPose3D>();
    in.skip(kFloat);  // the distance
  });
  if (version >= 1) in.string();  // the sensor label
  if (version >= 2) in.skip(kTimestamp);
}

}  // namespace

std::vector<ClassLayoutEntry> range_sensor_layouts() {
  using namespace mrpt::obs;
  return {{CLASS_ID(CObservation2DRangeScan), scan_2d}, {CLASS_ID(CObservationRange), range}};
}

}  // namespace omnisfm::mrpt_plugin
