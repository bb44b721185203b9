#pragma once
// Projecting and unprojecting whole vnlog tables through a camera, as `omnisfm project` and
// `omnisfm unproject` do. Rows keep their order; columns other than the ones used are ignored.
// A row with a missing input value, or with no valid reflection, gives '-' in every output column.

#include <iosfwd>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/io/vnlog.h"

namespace omnisfm::io {

// `# x y z` (frame C) -> `# u v`. Throws InputError for a missing column or a non-number.
void write_projected_points(const camera::CatadioptricCamera& camera, const VnlogTable& points,
                            std::ostream& out);

// `# u v` -> `# ox oy oz dx dy dz`: the reflected ray's origin on the mirror and unit direction.
void write_unprojected_pixels(const camera::CatadioptricCamera& camera, const VnlogTable& pixels,
                              std::ostream& out);

}  // namespace omnisfm::io
