#pragma once
// What a real rig's camera does to the light the renderer traces, so that rendered sequences look
// like recorded ones: motion blur over the exposure, the lens's defocus, vignetting toward the
// mirror's rim, an automatic exposure whose gain changes from frame to frame, the sensor's shot
// and read noise, and 8-bit quantisation; with real photographs on the surfaces
// (photo_texture.h). Each effect has its setting; ImagingSettings::clean() has none of them, the
// renderer's own images.

#include <Eigen/Geometry>
#include <cstdint>
#include <memory>
#include <opencv2/core.hpp>
#include <random>
#include <string>

#include "omnisfm/sim/dataset.h"
#include "omnisfm/sim/renderer.h"

namespace omnisfm::sim {

struct ImagingSettings {
  bool photographs = true;  // real photographs on the surfaces, else the procedural textures
  // Motion blur: the image is the mean of this many renderings at poses spread evenly over the
  // exposure (1: none), which lasts exposure_fraction of the interval between frames, centred on
  // the frame's time.
  int motion_blur_samples = 3;
  double exposure_fraction = 0.5;
  double defocus_sigma_px = 0.6;  // Gaussian blur of the focused image
  // Brightness lost toward the rim of the mirror's image: the gain falls as 1 - v (r / r_rim)^2.
  double vignetting = 0.3;
  // Automatic exposure: the first frame's gain brings the mirror's image to a mean grey of 115;
  // each frame after multiplies it by exp(N(0, gain_step_sigma)), held within 1 +- gain_range of
  // the first.
  double gain_step_sigma = 0.04;
  double gain_range = 0.12;
  // Shot noise: a grey level g has variance g / electrons_per_grey (Poisson in electrons); read
  // noise: Gaussian, in grey levels. Then rounded to 8 bits, saturating.
  double electrons_per_grey = 16;
  double read_noise_grey = 1.0;

  // The renderer's images as they are: procedural textures, nothing else.
  static ImagingSettings clean();
  // By name: "clean" or "realistic" (the defaults above). Throws std::invalid_argument naming
  // the name otherwise.
  static ImagingSettings named(const std::string& name);
  bool is_clean() const;
  // The blur of the images these settings make, as a Gaussian's sigma in pixels: the defocus and
  // the pixels' area (a box of a pixel, variance 1/12; motion blur aside). What a tracker is told
  // of the camera (track::TrackerSettings::camera_blur_px).
  double blur_px() const;
};

// The rig's pose at `time` during frame k's exposure: on the parabola through the frame's pose
// and its neighbours' (position, and rotation relative to the frame's), which a rig that turns
// smoothly follows, so that a symmetric exposure's image is centred on the frame's pose. Straight
// legs between poses would make an exposure about a corner an L (the lab's U), whose blurred
// image lies off the frame's pose by a third of the exposure's turn: 0.4 px at the median in the
// realistic lab's corner frames. The first and last frames' exposures run on along their one leg.
Eigen::Isometry3d pose_during_exposure(const Dataset& dataset, int k, double time);

// One sequence's camera: the exposure's gain and the noise go on from frame to frame.
class Imaging {
 public:
  // `renderer` is used for every frame, its photographs set from settings.photographs at each
  // record (so that several Imagings may take turns on one renderer, not at once); seed makes
  // the noise and the gain's walk repeatable.
  Imaging(const ImagingSettings& settings, Renderer* renderer, std::uint64_t seed);

  // Frame `frame` of `dataset` as the camera records it (CV_8UC1). Frames are taken in order.
  cv::Mat record(const Dataset& dataset, int frame);

  // The exposure's gain of the last frame recorded: set on the first frame so that the mirror's
  // image has a mean grey of 115, then walking.
  double gain() const { return exposure_ * gain_; }

 private:
  ImagingSettings settings_;
  Renderer* renderer_;
  std::shared_ptr<const SurfacePhotos> photos_;  // null: procedural textures
  std::mt19937_64 rng_;
  cv::Mat valid_;       // the renderer's valid pixels
  cv::Mat vignetting_;  // CV_32FC1 gain per pixel
  double exposure_ = 1;  // the first frame's
  double gain_ = 1;      // the walk's, relative to it
  bool first_ = true;
};

}  // namespace omnisfm::sim
