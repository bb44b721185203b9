#pragma once
// mrcal's lens model of a name such as "LENSMODEL_OPENCV8", for the code that calls libmrcal.

extern "C" {  // libmrcal's header declares C functions without saying so
#include <mrcal/mrcal.h>
}

#include <string>

namespace omnisfm::camera {

// Throws std::invalid_argument naming `name` when mrcal does not know it.
mrcal_lensmodel_t mrcal_lensmodel_named(const std::string& name);

}  // namespace omnisfm::camera
