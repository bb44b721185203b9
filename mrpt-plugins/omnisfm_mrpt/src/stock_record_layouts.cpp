// The stored layouts of the stock MRPT records omnisfm takes: sensory frames and action
// collections, 2D and 3D robot movements, odometry, IMU, image and comment observations (GPS in
// gps_layout.cpp), as MRPT 2.5's serializeFrom reads them.
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationGPS.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/img/CImage.h>
#include <mrpt/img/TCamera.h>
#include <mrpt/math/CMatrixF.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDF.h>

#include "class_layouts.h"

namespace omnisfm::mrpt_plugin {
namespace {

using Movement2D = mrpt::obs::CActionRobotMovement2D;

// MRPT draws this many samples from a stored motion model; its default is 300.
constexpr std::uint32_t kMaxMotionModelParticles = 1000000;

constexpr std::size_t kTimestamp = 8, kFloat = 4, kDouble = 8, kInt32 = 4, kBool = 1;

void sensory_frame(BoundedObjectCopy& in, int version) {
  if (version > 2) in.layout_unknown();
  if (version < 2) in.skip(kInt32);  // an ID, dropped in version 2
  if (version == 0) in.skip(kTimestamp);
  const auto observations = in.value<std::uint32_t>();
  in.elements(observations, BoundedObjectCopy::kLeastObjectBytes,
              [&] { in.object<mrpt::obs::CObservation>(); });
}

void action_collection(BoundedObjectCopy& in, int version) {
  if (version != 0) in.layout_unknown();
  const auto actions = in.value<std::uint32_t>();
  in.elements(actions, BoundedObjectCopy::kLeastObjectBytes,
              [&] { in.object<mrpt::obs::CAction>(); });
}

// The motion model stored with an odometry increment (versions 3 to 7), from which MRPT draws
// the movement's PDF: Thrun's model draws as many particles as it says.
void motion_model(BoundedObjectCopy& in, int version) {
  const auto model = in.value<std::int32_t>();
  if (version == 3) {
    in.skip(3 * kFloat + 2 * kDouble);
  } else {
    in.skip(6 * kFloat);
  }
  const auto particles = in.value<std::uint32_t>();
  if (model == Movement2D::mmThrun && particles > kMaxMotionModelParticles)
    in.out_of_range("its motion model draws " + std::to_string(particles) + " particles");
  in.skip(4 * kFloat);
  if (version >= 5) in.skip(2 * kFloat);
}

void robot_movement_2d(BoundedObjectCopy& in, int version) {
  if (version > 7) in.layout_unknown();
  if (version <= 1) {
    in.object<mrpt::poses::CPosePDF>();  // the pose PDF
    in.skip(kInt32);
    if (version == 1) in.skip(kBool + 2 * kFloat + kBool + 2 * kInt32);
    return;
  }
  if (in.value<std::int32_t>() == Movement2D::emOdometry) {
    in.object<mrpt::poses::CPose2D>();  // the odometry increment
    if (version == 2) {
      in.skip(44);  // the motion model's options as they were
    } else {
      motion_model(in, version);
    }
  } else {
    in.object<mrpt::poses::CPosePDF>();  // the pose PDF
  }
  if (version >= 7) {
    if (in.flag()) in.skip(3 * kDouble);  // velocities
    if (in.flag()) in.skip(2 * kInt32);   // encoders
  } else {
    in.skip(kBool + 2 * kFloat + kBool + 2 * kInt32);
  }
  if (version >= 6) in.skip(kTimestamp);
}

void robot_movement_3d(BoundedObjectCopy& in, int version) {
  if (version > 1) in.layout_unknown();
  in.skip(kInt32);  // the estimation method
  in.object<mrpt::poses::CPose3DPDFGaussian>();      // the pose change
  in.array(1);      // which velocities it has, a vector of bools
  in.array(kFloat);  // the velocities
  if (version >= 1) in.skip(kTimestamp);
}

void odometry(BoundedObjectCopy& in, int version) {
  if (version > 2) in.layout_unknown();
  in.object<mrpt::poses::CPose2D>();  // the pose
  in.string();  // the sensor label
  in.skip(kTimestamp);
  if (version == 0) return;
  if (version == 1) {
    in.skip(kBool + 2 * kInt32 + kBool + 2 * kFloat);
    return;
  }
  if (in.flag()) in.skip(2 * kInt32);    // encoders
  if (in.flag()) in.skip(3 * kDouble);  // velocities
}

void imu(BoundedObjectCopy& in, int version) {
  if (version > 4) in.layout_unknown();
  constexpr std::size_t fields = mrpt::obs::COUNT_IMU_DATA_FIELDS;
  in.object<mrpt::poses::CPose3D>();  // the sensor pose
  if (version == 4) {
    in.skip(fields * kBool + kTimestamp + fields * kDouble);
  } else {
    in.array(1);  // presence flags
    in.skip(kTimestamp);
    in.array(version == 0 ? kFloat : kDouble);
  }
  in.string();  // the sensor label
}

void comment(BoundedObjectCopy& in, int version) {
  if (version != 0) in.layout_unknown();
  in.string();
  in.skip(kTimestamp);
}

}  // namespace

void observation_image_layout(BoundedObjectCopy& in, int version) {
  if (version < 0 || version > 4) in.layout_unknown();
  in.object<mrpt::poses::CPose3D>();  // the camera pose
  if (version >= 4) {
    in.object<mrpt::img::TCamera>();  // the camera parameters
  } else {
    in.object<mrpt::math::CMatrixF>();  // distortion
    in.object<mrpt::math::CMatrixF>();  // intrinsic parameters
  }
  in.object<mrpt::img::CImage>();  // the image
  if (version >= 1) in.skip(kTimestamp);
  if (version == 2 || version == 3) in.skip(kDouble);  // the focal length
  if (version >= 3) in.string();                       // the sensor label
}

std::vector<ClassLayoutEntry> stock_record_layouts() {
  using namespace mrpt::obs;
  return {{CLASS_ID(CSensoryFrame), sensory_frame},
          {CLASS_ID(CActionCollection), action_collection},
          {CLASS_ID(CActionRobotMovement2D), robot_movement_2d},
          {CLASS_ID(CActionRobotMovement3D), robot_movement_3d},
          {CLASS_ID(CObservationOdometry), odometry},
          {CLASS_ID(CObservationIMU), imu},
          {CLASS_ID(CObservationGPS), gps_layout},
          {CLASS_ID(CObservationImage), observation_image_layout},
          {CLASS_ID(CObservationComment), comment}};
}

}  // namespace omnisfm::mrpt_plugin
