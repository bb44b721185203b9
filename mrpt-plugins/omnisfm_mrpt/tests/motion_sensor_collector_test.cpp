// MotionSensorCollector keeps each sensor's readings in time order: a reading that comes back in
// time is dropped, and a single one dated ahead of its neighbours gives way to them.

#include "omnisfm/mrpt_plugin/motion_sensor_collector.h"

#include <gtest/gtest.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>

namespace omnisfm::mrpt_plugin {
namespace {

mrpt::obs::CObservationIMU gyro_at(double t, double rate_z) {
  mrpt::obs::CObservationIMU imu;
  imu.timestamp = mrpt::Clock::fromDouble(t);
  imu.set(mrpt::obs::IMU_WX, 0);
  imu.set(mrpt::obs::IMU_WY, 0);
  imu.set(mrpt::obs::IMU_WZ, rate_z);
  return imu;
}

mrpt::obs::CObservationOdometry odometry_at(double t, double x) {
  mrpt::obs::CObservationOdometry odometry;
  odometry.timestamp = mrpt::Clock::fromDouble(t);
  odometry.odometry = mrpt::poses::CPose2D(x, 0, 0);
  return odometry;
}

template <typename Sample>
std::vector<double> times_of(const std::vector<Sample>& samples) {
  std::vector<double> times;
  for (const auto& s : samples) times.push_back(s.timestamp);
  return times;
}

// One gyro reading dated 1,000 s ahead used to hold its predecessor's rate over the rest of the
// drive and to refuse every later reading: the rover's batch ended 0.6-3.2 % off with 44-57 of
// its 110 tracks rejected (sensor_glitch_test.cpp's misdating, without this).
TEST(MotionSensorCollector, AReadingDatedAheadOfItsNeighboursGivesWay) {
  MotionSensorCollector collector({}, std::nullopt);
  for (double t : {100.00, 100.01, 100.02}) EXPECT_TRUE(collector.add(gyro_at(t, 0.1)));
  EXPECT_TRUE(collector.add(gyro_at(1100.03, 5.0)));  // misdated: not yet known as such
  EXPECT_TRUE(collector.add(gyro_at(100.03, 0.1)));
  EXPECT_TRUE(collector.add(gyro_at(100.04, 0.1)));
  EXPECT_EQ(times_of(collector.sensors().gyro),
            (std::vector<double>{100.00, 100.01, 100.02, 100.03, 100.04}));
  for (const auto& s : collector.sensors().gyro) EXPECT_DOUBLE_EQ(s.rate.z(), 0.1);
  EXPECT_EQ(collector.out_of_order(), 1u);

  // A reading from the past is the one dropped.
  EXPECT_FALSE(collector.add(gyro_at(100.015, 0.1)));
  EXPECT_EQ(collector.sensors().gyro.size(), 5u);
  EXPECT_EQ(collector.out_of_order(), 2u);
}

// A reading merely late (or two swapped) is the one dropped: the last is not far ahead.
TEST(MotionSensorCollector, ALateReadingIsTheOneDropped) {
  MotionSensorCollector collector({}, std::nullopt);
  for (double t : {1.0, 1.1, 1.2}) EXPECT_TRUE(collector.add(odometry_at(t, t)));
  EXPECT_FALSE(collector.add(odometry_at(1.15, 1.3)));
  EXPECT_TRUE(collector.add(odometry_at(1.4, 1.4)));
  EXPECT_EQ(times_of(collector.sensors().odometry), (std::vector<double>{1.0, 1.1, 1.2, 1.4}));
  EXPECT_EQ(collector.out_of_order(), 1u);
}

TEST(MotionSensorCollector, OdometryDatedAheadGivesWayToo) {
  MotionSensorCollector collector({}, std::nullopt);
  EXPECT_TRUE(collector.add(odometry_at(10.0, 0.0)));
  EXPECT_TRUE(collector.add(odometry_at(10.1, 0.1)));
  EXPECT_TRUE(collector.add(odometry_at(99.0, 0.2)));
  EXPECT_TRUE(collector.add(odometry_at(10.2, 0.2)));
  EXPECT_EQ(times_of(collector.sensors().odometry), (std::vector<double>{10.0, 10.1, 10.2}));
  EXPECT_EQ(collector.out_of_order(), 1u);
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
