#include "omnisfm/sfm/sensor_ranges.h"

#include "omnisfm/io/ini_file.h"
#include "omnisfm/io/number_text.h"

namespace omnisfm::sfm {

// Beyond these bounds a noise is numerically zero or the sensor says nothing, and the estimators
// failed, or ran far off. The gyro's low ends lie below a navigation-grade gyro's (an HG9900's
// bias is about 1.5e-8 rad/s).
const std::vector<SensorRange>& sensor_ranges() {
  static const std::vector<SensorRange> ranges = {
      {"odometry_position_sigma", 1e-6, 1,
       "metres per sqrt(metre travelled) (a wheel a metre off per metre is no odometry)",
       [](MotionSensors& s) -> double& { return s.odometry_noise.position_sigma; }},
      {"odometry_heading_sigma", 1e-6, 1, "radians per sqrt(metre travelled)",
       [](MotionSensors& s) -> double& { return s.odometry_noise.heading_sigma; }},
      {"odometry_scale", 0.1, 10,
       "true distance per distance read (a factor of ten off is another unit than MRPT's metres)",
       [](MotionSensors& s) -> double& { return s.odometry_scale; }},
      {"odometry_scale_sigma", 0, 0.5,
       "the scale's relative uncertainty (0 holds it; beyond 0.5 the scale would be negative "
       "within two sigmas)",
       [](MotionSensors& s) -> double& { return s.odometry_noise.scale_sigma; }},
      {"gyro_noise_density", 1e-10, 1, "rad/s per sqrt(Hz)",
       [](MotionSensors& s) -> double& { return s.gyro_noise.noise_density; }},
      {"gyro_bias_sigma", 1e-10, 1, "rad/s (a bias of a radian a second is no gyro)",
       [](MotionSensors& s) -> double& { return s.gyro_noise.bias_sigma; }},
      {"gyro_bias_walk", 1e-12, 1, "rad/s^2 per sqrt(Hz)",
       [](MotionSensors& s) -> double& { return s.gyro_noise.bias_walk; }},
  };
  return ranges;
}

std::string sensors_problem(const MotionSensors& sensors) {
  MotionSensors copy;  // the numbers are reached through the table's references
  copy.odometry_noise = sensors.odometry_noise;
  copy.odometry_scale = sensors.odometry_scale;
  copy.gyro_noise = sensors.gyro_noise;
  for (const SensorRange& r : sensor_ranges()) {
    const double value = r.field(copy);
    if (const std::string problem = io::range_problem(value, r.low, r.high, false, r.meaning);
        !problem.empty())
      return std::string(r.key) + " = " + io::format_double(value) + " " + problem;
  }
  return "";
}

}  // namespace omnisfm::sfm
