#include "omnisfm/sim/imaging.h"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <opencv2/imgproc.hpp>
#include <stdexcept>

#include "omnisfm/io/shared_data.h"
#include "omnisfm/sim/dead_reckoning.h"

namespace omnisfm::sim {
namespace {

// Where an automatic exposure puts a scene's mean: a little below mid-grey, as cameras do to keep
// highlights.
constexpr double kExposureTarget = 115;

}  // namespace

Eigen::Isometry3d pose_during_exposure(const Dataset& dataset, int k, double t) {
  const std::vector<double>& times = dataset.timestamps;
  if (k == 0 || k + 1 >= static_cast<int>(times.size())) return extrapolate_pose(dataset, t);
  const double t0 = times[k - 1], t1 = times[k], t2 = times[k + 1];
  if (!(t0 < t1 && t1 < t2)) return extrapolate_pose(dataset, t);
  // Lagrange's weights of the three poses at t.
  const double w0 = (t - t1) * (t - t2) / ((t0 - t1) * (t0 - t2));
  const double w1 = (t - t0) * (t - t2) / ((t1 - t0) * (t1 - t2));
  const double w2 = (t - t0) * (t - t1) / ((t2 - t0) * (t2 - t1));
  const Eigen::Isometry3d& before = dataset.world_from_cam[k - 1];
  const Eigen::Isometry3d& at = dataset.world_from_cam[k];
  const Eigen::Isometry3d& after = dataset.world_from_cam[k + 1];
  const auto turn_to = [&](const Eigen::Isometry3d& pose) {
    const Eigen::AngleAxisd turn(at.linear().transpose() * pose.linear());
    return Eigen::Vector3d(turn.angle() * turn.axis());
  };
  const Eigen::Vector3d turn = w0 * turn_to(before) + w2 * turn_to(after);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = w0 * before.translation() + w1 * at.translation() + w2 * after.translation();
  pose.linear() =
      turn.norm() > 0
          ? Eigen::Matrix3d(at.linear() * Eigen::AngleAxisd(turn.norm(), turn.normalized()))
          : at.linear();
  return pose;
}

ImagingSettings ImagingSettings::clean() {
  ImagingSettings s;
  s.photographs = false;
  s.motion_blur_samples = 1;
  s.exposure_fraction = 0;
  s.defocus_sigma_px = 0;
  s.vignetting = 0;
  s.gain_step_sigma = 0;
  s.gain_range = 0;
  s.electrons_per_grey = 0;  // no shot noise
  s.read_noise_grey = 0;
  return s;
}

ImagingSettings ImagingSettings::named(const std::string& name) {
  if (name == "clean") return clean();
  if (name == "realistic") return {};
  throw std::invalid_argument("unknown imaging \"" + name + "\" (clean or realistic)");
}

double ImagingSettings::blur_px() const {
  return std::sqrt(defocus_sigma_px * defocus_sigma_px + 1.0 / 12);
}

bool ImagingSettings::is_clean() const {
  return !photographs && motion_blur_samples <= 1 && defocus_sigma_px <= 0 && vignetting <= 0 &&
         gain_step_sigma <= 0 && electrons_per_grey <= 0 && read_noise_grey <= 0;
}

Imaging::Imaging(const ImagingSettings& settings, Renderer* renderer, std::uint64_t seed)
    : settings_(settings), renderer_(renderer), rng_(seed) {
  if (settings_.photographs)
    photos_ = SurfacePhotos::read(
        std::filesystem::path(io::find_shared_file("textures/brick.png")).parent_path().string());
  // Vignetting about the centre of the mirror's image, to its rim: the valid pixels' centroid and
  // farthest extent.
  valid_ = renderer_->valid_pixels();
  const cv::Mat& valid = valid_;
  const cv::Moments m = cv::moments(valid, true);
  const double cx = m.m00 > 0 ? m.m10 / m.m00 : valid.cols / 2.0;
  const double cy = m.m00 > 0 ? m.m01 / m.m00 : valid.rows / 2.0;
  double rim = 1;
  for (int y = 0; y < valid.rows; ++y)
    for (int x = 0; x < valid.cols; ++x)
      if (valid.at<std::uint8_t>(y, x)) rim = std::max(rim, std::hypot(x - cx, y - cy));
  vignetting_.create(valid.size(), CV_32FC1);
  for (int y = 0; y < valid.rows; ++y)
    for (int x = 0; x < valid.cols; ++x) {
      const double r = std::min(std::hypot(x - cx, y - cy) / rim, 1.0);
      vignetting_.at<float>(y, x) = static_cast<float>(1 - settings_.vignetting * r * r);
    }
}

cv::Mat Imaging::record(const Dataset& dataset, int frame) {
  const int frames = static_cast<int>(dataset.world_from_cam.size());
  if (frame < 0 || frame >= frames) throw std::invalid_argument("no frame " + std::to_string(frame));
  renderer_->use_photos(photos_);
  if (settings_.is_clean()) return renderer_->render(dataset.scene, dataset.world_from_cam[frame]);

  // Motion blur: renderings over the exposure, centred on the frame's time (also about the first
  // and last frames: a clamped exposure there would shift those frames' image of the scene).
  const int samples = std::max(settings_.motion_blur_samples, 1);
  cv::Mat light;
  if (samples == 1 || frames < 2) {
    light = renderer_->render_radiance(dataset.scene, dataset.world_from_cam[frame]);
  } else {
    const double t = dataset.timestamps[frame];
    const double interval = frame + 1 < frames ? dataset.timestamps[frame + 1] - t
                                               : t - dataset.timestamps[frame - 1];
    const double exposure = settings_.exposure_fraction * interval;
    light = cv::Mat::zeros(renderer_->height(), renderer_->width(), CV_32FC1);
    for (int k = 0; k < samples; ++k) {
      const double at = t + exposure * ((k + 0.5) / samples - 0.5);
      light += renderer_->render_radiance(dataset.scene, pose_during_exposure(dataset, frame, at));
    }
    light /= samples;
  }
  if (settings_.defocus_sigma_px > 0)
    cv::GaussianBlur(light, light, cv::Size(), settings_.defocus_sigma_px);
  if (first_) {
    // The automatic exposure's start: the mirror's image at a mean grey of kExposureTarget.
    first_ = false;
    const double mean = cv::mean(light.mul(vignetting_), valid_)[0];
    exposure_ = mean > 1 ? kExposureTarget / mean : 1;
  } else if (settings_.gain_step_sigma > 0) {
    std::normal_distribution<double> step(0, settings_.gain_step_sigma);
    gain_ = std::clamp(gain_ * std::exp(step(rng_)), 1 - settings_.gain_range,
                       1 + settings_.gain_range);
  }
  light = light.mul(vignetting_, exposure_ * gain_);

  // Shot and read noise: a standard normal per pixel, scaled by that pixel's sigma.
  const cv::Mat variance =
      cv::max(light, 0.0) *
          (settings_.electrons_per_grey > 0 ? 1 / settings_.electrons_per_grey : 0.0) +
      settings_.read_noise_grey * settings_.read_noise_grey;
  cv::Mat sigma;
  cv::sqrt(variance, sigma);
  cv::Mat noise(light.size(), CV_32FC1);
  cv::RNG normal(rng_());
  normal.fill(noise, cv::RNG::NORMAL, 0, 1);
  cv::Mat image;
  const cv::Mat noisy = light + noise.mul(sigma);
  noisy.convertTo(image, CV_8U);
  return image;
}

}  // namespace omnisfm::sim
