#pragma once
// Sub-pixel alignment of a track's reference patch into a later image, so that a track's position
// is measured against how the feature looked when its reference was taken rather than chained
// from frame to frame (a chain of frame-to-frame matches drifts as a random walk).
//
// The patch is an affine image of the reference: template offset x (pixels from the feature)
// lands at A x + b in the image. Alignment is inverse-compositional Lucas-Kanade (Baker and
// Matthews) on the six affine parameters, with the warped image normalised to the template's mean
// and contrast at every step, so that it minimises a weighted zero-mean normalised SSD; the
// Gaussian window weight (sigma: the half size) lets the patch's rim matter less.
//
// The template is the image's own pixels around the feature, smoothed by (1/12, 5/6, 1/12) along
// each axis as bilinear sampling smooths on average (no resampling: an interpolated template is
// smoothed by an amount that depends on its sub-pixel phase, which would bias every later
// alignment); template coordinates are offsets from the feature itself. Images are
// CV_32FC1, sampled bilinearly; a warp whose patch comes within a pixel of the border fails.

#include <Eigen/Core>
#include <memory>
#include <opencv2/core.hpp>
#include <vector>

namespace omnisfm::track {

struct AffineWarp {
  Eigen::Matrix2d A = Eigen::Matrix2d::Identity();
  Eigen::Vector2d b{0, 0};  // where the feature lands
};

// How far the warp's linear part A stretches or shrinks the patch along any direction: its
// singular values' largest departure from 1.
double patch_distortion(const Eigen::Matrix2d& A);

struct AlignmentResult {
  bool converged = false;
  int iterations = 0;
  // Weighted zero-mean normalised cross-correlation where the last step started (converged: a
  // step below the tolerance before the end).
  double ncc = 0;
  // Converged: the largest shift of the feature that one part of the patch (its left, right, top
  // or bottom half, or its centre) would take on its own from the warp found. Where one warp fits
  // the whole patch, each part stays; where the look has changed in a way an affine warp cannot
  // follow (a patch of ground foreshortened unevenly as it comes closer, a feature on a crease),
  // the parts pull apart, and the feature's position is off by about as much (measured against
  // the truth on the rendered sets). The centre catches the even part of such a change (the same
  // for opposite halves), which shifts the whole patch's best fit but not the centre's.
  double misfit_px = 0;
  // Converged: the weighted RMS of what is left of the template after the alignment (grey levels
  // of the template): the noise of both images, and whatever the warp does not follow.
  double residual_rms = 0;
};

class ReferencePatch {
 public:
  ReferencePatch() = default;

  // The (2 half_size + 1)^2 pixels of `image` around the pixel nearest `feature`, smoothed as
  // above. False when the patch does not fit in the image or is flat (no texture to align on).
  static bool extract(const cv::Mat& image, const Eigen::Vector2d& feature, int half_size,
                      ReferencePatch* patch);
  // What contrast() of that patch would be, at a fraction of extract's work; 0 where it does not
  // fit.
  static double contrast_at(const cv::Mat& image, const Eigen::Vector2d& feature, int half_size);

  // Asks the caches for the pixels a patch of this half size about `at` reads (a patch that
  // moves little reads about them): a hint, which changes nothing else.
  static void prefetch(const cv::Mat& image, const Eigen::Vector2d& at, int half_size);

  // Moves *warp to the best alignment, starting from it. Not converged when the patch leaves the
  // image, the warp degenerates, or max_iterations pass before a step of the feature is
  // below step_tolerance_px.
  AlignmentResult align(const cv::Mat& image, AffineWarp* warp, int max_iterations,
                        double step_tolerance_px) const;

  // The weighted zero-mean NCC of the patch against `image` at `warp`, or -1 when it leaves
  // the image.
  double ncc(const cv::Mat& image, const AffineWarp& warp) const;

  // An image blurs what it shows by the same amount at any scale, so a patch that the image
  // shrinks (the warp's A below 1 along some direction) shows its texture more blurred than the
  // template does, and one it magnifies sharper: (image_blur_variance + s) A^-1 A^-T in template
  // coordinates, s the smoothing of bilinear sampling (1/6 px^2 along each axis on average),
  // against the template's image_blur_variance + s. An alignment then trades the patch's shape
  // for the difference, and the feature moves with it (on the realistic lab, patches shrunk
  // below 0.8 were 0.63 px off at the 95th percentile, 0.27 with the template blurred to match).
  // Takes the template anew from the reference image's pixels, smoothed by what makes up the
  // difference (less than s where the patch grows, none from about 1.1 times; a Gaussian beyond
  // s where it shrinks), once the Gaussian differs from the template's by more than `tolerance`
  // (px^2, the largest change along a direction) or the smoothing below s by 0.05 px^2. The
  // template stays where it was, so the track's position inherits no error, as it would from a
  // new reference.
  // image_blur_variance: the reference image's own blur (px^2 along each axis: the camera's and
  // the tracker's smoothing). False when nothing changed (within tolerance; the reference kept
  // no pixels for it, taken too near the image's border; or the template would be flat).
  bool match_blur(const Eigen::Matrix2d& A, double image_blur_variance, double tolerance);
  // What the template's pixels are smoothed by (covariance, px^2, template coordinates): s
  // along each axis as extracted, then what match_blur set.
  Eigen::Matrix2d smoothing() const;

  int half_size() const { return half_size_; }
  // The inverse of the alignment's Hessian: the Gram matrix of the six steepest-descent images
  // (w gx u, w gx v, w gy u, w gy v, w gx, w gy against gx u, ..., gy; u, v the offsets from the
  // feature, w the Gaussian window summing to 1, g the central differences).
  const Eigen::Matrix<double, 6, 6>& hessian_inverse() const { return solves_->hessian_inverse; }
  // The point of the template (offset from the feature) whose place an alignment measures best:
  // where the variance of A x + b is least, over the six parameters' covariance taken as the
  // inverse Hessian (the Gaussian window's weights make the true one H^-1 (sum w^2 s s^T) H^-1,
  // which that stands for up to their spread). Errors in the patch's shape A move a point by A's
  // error times its offset from that point, so a track reports it rather than the feature: on the
  // realistic lab, aligned from the truth, the features were 0.26 px off at the 95th percentile and
  // these points 0.23 (1.1 px from the features at the median, 2.7 at the 95th percentile). Within
  // half_size of the feature.
  Eigen::Vector2d best_located_offset() const;
  // The template's weighted standard deviation, grey levels.
  double contrast() const { return norm_; }

  // Template pixels sampled at once.
  static constexpr int kLanes = 4;
  bool empty() const { return values_.size() == 0; }

 private:
  // extract, with the template's pixels smoothed by (w, 1 - 2 w, w) along each axis.
  static bool extract_smoothed(const cv::Mat& image, const Eigen::Vector2d& feature, int half_size,
                               float side_weight, ReferencePatch* patch);
  // The template's values and weighted gradients anew from `pixels` (the reference image's kept
  // pixels, or those blurred; the feature's nearest pixel at (centre, centre)), smoothed with
  // (w, 1 - 2 w, w); the Hessian stays. False, and unchanged, where they would be flat.
  bool retake_values(const cv::Mat& pixels, int centre, float side_weight);
  // Samples `image` at warp * offset for every offset into `values` (one entry per padded
  // template pixel), and returns the weighted zero-mean NCC of the template against them,
  // their weighted mean and the gain that maps their contrast onto the template's. -1 when
  // the patch leaves the image.
  double sample(const cv::Mat& image, const AffineWarp& warp, float* values, double* mean,
                double* gain) const;

  int half_size_ = 0;
  // The reference image's pixels about the feature's nearest pixel, as they were, wide enough
  // for the added blur's kernel (empty where they did not fit: KeptPixels in the source tells
  // their square); the feature in that image; the Gaussian added to the template; and the share
  // of sampling's smoothing it has.
  std::vector<float> pixels_;
  Eigen::Vector2d feature_{0, 0};
  Eigen::Matrix2d added_ = Eigen::Matrix2d::Zero();
  double sampled_share_ = 1;
  // Per template pixel, row-major, padded with zeros to a multiple of kLanes pixels. From the
  // feature to the pixel:
  Eigen::ArrayXf offsets_x_, offsets_y_;
  Eigen::ArrayXf weights_;  // Gaussian window about the feature, sums to 1
  Eigen::ArrayXf values_;   // the template, weighted mean removed
  double norm_ = 0;         // sqrt(sum w * values^2)
  // The template's gradient times the window weight, per pixel: with the offsets they give the
  // six steepest-descent images (w gx u, w gx v, w gy u, w gy v, w gx, w gy), which are not
  // stored. A patch's data is read at every step of every track, and kept this small it stays in
  // the cache from one step to the next.
  Eigen::ArrayXf weighted_gx_, weighted_gy_;
  // The solves' matrices, 0.9 kB, held apart and shared (never changed once made): a tracker
  // moves its tracks, references and all, several times a frame.
  static constexpr int kParts = 5;
  struct Solves {
    Eigen::Matrix<double, 6, 6> hessian_inverse;
    // Each part of the patch's (left, right, top, bottom, centre) rows of the translation in the
    // Hessian of its own pixels, and the inverse of their translation block (zero for a part too
    // flat to place on its own).
    Eigen::Matrix<double, 2, 6> part_coupling[kParts];
    Eigen::Matrix2d part_hessian_inverse[kParts];
  };
  std::shared_ptr<const Solves> solves_;

  // Turns sampled *values into the residuals (normalised by the sample's mean and gain, less
  // the template) in place, and returns the alignment cost's gradient over the six affine
  // parameters: the residuals' sums against each steepest-descent image, in the same pass.
  Eigen::Matrix<double, 6, 1> residuals_and_gradient(float mean, float gain,
                                                     Eigen::ArrayXf* values) const;
  // The largest shift one part of the patch would take alone after the whole patch's last step
  // (of the six parameters), from the residuals before it: the step is below the tolerance but
  // not nothing, and an affine step left untaken pulls the halves apart.
  double misfit(const Eigen::ArrayXf& residuals, const AffineWarp& warp,
                const Eigen::Matrix<double, 6, 1>& last_step) const;
};

}  // namespace omnisfm::track
