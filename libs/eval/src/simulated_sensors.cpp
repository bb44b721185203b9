#include "omnisfm/eval/simulated_sensors.h"

namespace omnisfm::eval {

sfm::MotionSensors motion_sensors(const sim::DeadReckoning* dead_reckoning,
                                  const sim::DeadReckoningOptions& options,
                                  const sim::GpsTrack* gps) {
  sfm::MotionSensors sensors;
  if (dead_reckoning) {
    sensors.body_from_cam = dead_reckoning->body_from_cam;
    for (const auto& r : dead_reckoning->odometry) sensors.odometry.push_back({r.timestamp, r.pose});
    for (const auto& r : dead_reckoning->gyro) sensors.gyro.push_back({r.timestamp, r.rate});
    sensors.odometry_noise.position_sigma = options.odometry_position_noise;
    sensors.odometry_noise.heading_sigma = options.odometry_heading_noise;
    sensors.gyro_noise.noise_density = options.gyro_noise_density;
    sensors.gyro_noise.bias_sigma = options.gyro_bias_sigma;
    sensors.gyro_noise.bias_walk = options.gyro_bias_walk;
  }
  if (gps) {
    sensors.body_from_cam = gps->body_from_cam;
    sensors.antenna_in_body = gps->antenna_in_body;
    for (const auto& f : gps->fixes)
      sensors.gps.push_back({f.timestamp, f.enu, gps->horizontal_sigma, gps->vertical_sigma});
  }
  return sensors;
}

}  // namespace omnisfm::eval
