#pragma once
// A calibration's starting camera written from the image alone, as a user would write one from a
// datasheet and one image (share/omnisfm/cameras/*-initial.ini explain the same numbers): the
// mirror's picture (mirror_image.h) gives the image centre and the scale, a generic mirror of the
// chosen kind gives the rest. The staged calibration (staged_calibration.h) frees the parameters
// from there; the start only has to put every corner inside the mirror's picture and each
// parameter within its basin.

#include "omnisfm/calib/mirror_image.h"
#include "omnisfm/camera/catadioptric_camera.h"

namespace omnisfm::calib {

enum class StartingMirror { kConic, kEquiangular };
enum class StartingInner { kPinhole, kOrthographic };

// Throws std::invalid_argument for a combination no generic start exists for (an equiangular
// mirror before a telecentric lens) or circles that are not inside one another.
camera::CatadioptricCamera starting_camera(const MirrorImage& mirror, int image_width,
                                           int image_height, StartingMirror mirror_kind,
                                           StartingInner inner_kind);

}  // namespace omnisfm::calib
