// TUM trajectories (io::read_tum_trajectory): increasing timestamps, finite positions, rotations.
#include <Eigen/Geometry>

#include "fuzz_contract.h"
#include "omnisfm/io/tum_trajectory.h"

using namespace omnisfm;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string path = fuzz::write_input(data, size, "trajectory.tum");
  fuzz::expect_contract([&] {
    const auto poses = io::read_tum_trajectory(path);
    for (std::size_t i = 0; i < poses.size(); ++i) {
      const Eigen::Matrix3d R = poses[i].world_from_cam.linear();
      fuzz::require(poses[i].world_from_cam.translation().allFinite(), "a position not finite");
      fuzz::require(
          (R.transpose() * R - Eigen::Matrix3d::Identity()).norm() < 1e-6 && R.determinant() > 0,
          "an orientation that is not a rotation");
      if (i > 0) fuzz::require(poses[i].timestamp > poses[i - 1].timestamp, "time going back");
    }
  });
  return 0;
}
