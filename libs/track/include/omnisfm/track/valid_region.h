#pragma once
// Where a tracker may look in a catadioptric image: the pixels that see the scene through the
// mirror (their unprojection is valid: inside the rim, outside the camera's own reflection), kept
// a margin away from every invalid pixel and from the image border, so that a tracking window
// centred there covers the mirror only.

#include <opencv2/core.hpp>

#include "omnisfm/camera/catadioptric_camera.h"

namespace omnisfm::track {

// CV_8UC1 of the camera's image size: 255 where trackable, 0 elsewhere. Validity is evaluated
// on a 4-pixel grid and per pixel only in the grid cells whose corners disagree, so a region
// narrower than 4 pixels may be missed (no real mirror has one).
cv::Mat valid_region_mask(const camera::CatadioptricCamera& camera, double margin_px);

// The centre of the trackable region (its centroid): the image of the mirror's axis, about
// which features are spread.
cv::Point2d region_centre(const cv::Mat& mask);

}  // namespace omnisfm::track
