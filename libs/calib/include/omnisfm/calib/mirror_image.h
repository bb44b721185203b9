#pragma once
// Where a catadioptric camera's image shows its mirror: the circle of its rim and the disc of the
// camera's own reflection at its centre. Found on the mean of many images, where the scene, which
// changes from image to image, blurs away and the mirror, which does not, stays sharp.

#include <Eigen/Core>
#include <opencv2/core.hpp>

namespace omnisfm::calib {

struct MirrorImage {
  Eigen::Vector2d centre{0, 0};  // pixels, 0-based, (0,0) the centre of the top-left pixel
  double inner_radius = 0;       // the camera's own reflection ends here
  double outer_radius = 0;       // the mirror's picture ends here, inside its rim
};

// The mean of 8-bit grey images of one size, taken one at a time (a video need not be held).
class MeanImage {
 public:
  void add(const cv::Mat& grey);
  int count() const { return count_; }
  cv::Mat mean() const;  // 8-bit grey; empty before the first image

 private:
  cv::Mat sum_;  // CV_64F
  int count_ = 0;
};

// The mirror's circles on a mean image (8-bit grey): the rim, a circle of radius 0.25-0.7 of the
// image's smaller side that may run past the image's edges, and within it the camera's
// reflection, a circle of 0.05-0.45 of the rim's radius about nearly the same centre, whose
// centre is the better estimate of the mirror's. Throws std::runtime_error saying which circle
// was not found, or that the edges found do not stand out of the image as a mirror's do.
MirrorImage find_mirror_image(const cv::Mat& mean_grey);

}  // namespace omnisfm::calib
