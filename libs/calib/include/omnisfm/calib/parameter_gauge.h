#pragma once
// Parameters that other estimated parameters make unobservable, so that a solve asked to estimate
// them all would wander along a flat valley and never converge. They are held at their starting
// values; the calibration reports which and why.
//   - conic_z0 duplicates a translation of the mirror along its axis (mirror_tz).
//   - The mirror's size (conic_c, equiangular_r0) trades against its distance from a central
//     camera (an exact trade for a central rig, a faint one otherwise), and against the focal
//     lengths of a telecentric one.
//   - A telecentric (orthographic) camera cannot see the mirror move along its viewing direction
//     (mirror_tz, conic_z0), and sees a sideways move (mirror_tx, mirror_ty) as a move of its
//     centre (cx, cy).

#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"

namespace omnisfm::calib {

struct HeldParameter {
  std::string name;
  std::string reason;
};

// Clears the flags of such parameters in *estimate (CatadioptricCamera::params() order) and
// returns them, in parameter order.
std::vector<HeldParameter> hold_unobservable_parameters(const camera::CatadioptricCamera& camera,
                                                        std::vector<bool>* estimate);

}  // namespace omnisfm::calib
