#pragma once
// A calibration of the simulated rig: its mirror pose's covariance as `omnisfm calibrate`
// reported it from the simulated lab's surveyed targets (seed 1, survey error 1 mm: sigmas 0.57
// and 0.57 mrad, 0.055, 0.054 and 0.044 mm), which eval::calibrated_with_error draws errors from.

#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/sfm/settings_file.h"

namespace omnisfm::sfm {

inline const std::vector<std::string> kMirrorPoseNames = {"mirror_rx", "mirror_ry", "mirror_tx",
                                                          "mirror_ty", "mirror_tz"};

inline Eigen::MatrixXd lab_target_calibration_covariance() {
  Eigen::MatrixXd c(5, 5);
  c << 3.2248611024091e-07, -5.786951927710481e-09, 5.487638620218244e-10,
      2.9479709969065556e-08, -3.630972804548073e-10,  //
      -5.786951927710481e-09, 3.204393963826476e-07, -2.9903366990453066e-08,
      -6.945530861522817e-10, 2.3306048817398037e-10,  //
      5.487638620218244e-10, -2.9903366990453066e-08, 3.006520521282828e-09,
      5.883352239819051e-11, 1.205513228280538e-10,  //
      2.9479709969065556e-08, -6.945530861522817e-10, 5.883352239819051e-11,
      2.874808952741325e-09, -1.2569831647908706e-10,  //
      -3.630972804548073e-10, 2.3306048817398037e-10, 1.205513228280538e-10,
      -1.2569831647908706e-10, 1.9162867931779855e-09;
  return c;
}

// The batch's prior for `camera` from that calibration.
inline CameraPrior lab_target_calibration_prior(
    const camera::CatadioptricCamera& camera) {
  return camera_prior_from(camera, {kMirrorPoseNames, lab_target_calibration_covariance()});
}

}  // namespace omnisfm::sfm
