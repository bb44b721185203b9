#include "omnisfm/sfm/sfm_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <iomanip>
#include <sstream>

#include "omnisfm/core/mahalanobis.h"
#include "omnisfm/sfm/online_filter.h"

namespace omnisfm::sfm {
namespace {

// A relative standard deviation in per cent, two significant figures.
std::string percent(double relative) {
  char text[32];
  const double p = 100 * relative;
  std::snprintf(text, sizeof text, p >= 10 ? "%.0f %%" : "%.2g %%", p);
  return text;
}

// What the images alone say of the scale: "the images fix it <how> +- X %".
std::string images_fix_it(const BatchResult& batch, const char* how) {
  if (!std::isfinite(batch.scale_sigma_relative))
    return "the images do not fix it at all (its information is singular)";
  return std::string("the images ") + how + " +- " + percent(batch.scale_sigma_relative) +
         " (1 sigma)";
}

// The first ten values, ", "-separated, then ", ..." where there are more.
template <typename T>
std::string first_listed(const std::vector<T>& values) {
  constexpr size_t kListed = 10;
  std::ostringstream text;
  text << std::setprecision(15);
  for (size_t i = 0; i < std::min(values.size(), kListed); ++i)
    text << (i > 0 ? ", " : "") << values[i];
  if (values.size() > kListed) text << ", ...";
  return text.str();
}

}  // namespace

std::string measured_noise_phrase(double taken_px, double stated_px) {
  if (!(taken_px > stated_px)) return "";
  char phrase[160];
  std::snprintf(phrase, sizeof phrase,
                " (judged at the tracks' measured noise, %.3g px per coordinate, where "
                "pixel_sigma says %.3g)",
                taken_px, stated_px);
  return phrase;
}

std::string refused_motion_line(long count, const std::vector<int>& frames, bool batch) {
  if (count <= 0) return "";
  std::ostringstream line;
  line << "motion sensors refused: in " << count << (count == 1 ? " frame" : " frames")
       << " the images showed the motion the vehicle's sensors predicted wrong, grossly or for "
          "good (a jump, a spike, a misdated reading, a sensor stuck)";
  if (!frames.empty())
    line << ": frame" << (frames.size() == 1 ? " " : "s ") << first_listed(frames);
  line << "; the filter took its own prediction there (constant velocity, or where the fault "
          "lasted the random walk)"
       << (batch ? " and the batch left those readings out" : "") << "\n";
  return line.str();
}

std::string refused_fixes_phrase(const MotionSensors& sensors, const std::vector<int>& refused) {
  if (refused.empty()) return "";
  std::vector<double> times;
  for (int i : refused) times.push_back(sensors.gps[i].timestamp);
  std::ostringstream phrase;
  phrase << "; " << refused.size() << (refused.size() == 1 ? " fix" : " fixes")
         << " refused, at odds with the rest as the filter's trajectory places them (at "
         << first_listed(times) << " s)";
  return phrase.str();
}

std::string most_rejected_phrase(long rejected, long tracks, double taken_noise_px,
                                 const FilterSettings& settings) {
  constexpr long kMinTracks = 10;
  if (tracks < kMinTracks || !(2 * rejected > tracks)) return "";
  std::ostringstream phrase;
  phrase << std::setprecision(3) << rejected << " of " << tracks
         << " tracks were rejected as outliers: ";
  const double stated = settings.pixel_sigma;
  if (settings.outlier_test == OutlierTest::kPixels)
    phrase << "[sfm] outlier_threshold_px (" << settings.outlier_threshold_px
           << " px) is too strict for the tracks, or the estimate lost its way";
  else if (!settings.measure_noise)
    phrase << "the tracks may be far noisier than [sfm] pixel_sigma (" << stated
           << " px) says (measure_noise = 1 measures it), outlier_chi2 (" << settings.outlier_chi2
           << ") too strict, or the estimate lost its way";
  else if (taken_noise_px >= 0.999 * OnlineFilter::kMaxNoiseScale * stated)
    phrase << "the tracks are noisier than " << OnlineFilter::kMaxNoiseScale
           << " times [sfm] pixel_sigma (" << stated
           << " px), the most the filter takes (set pixel_sigma nearer their noise), or the "
              "estimate lost its way";
  else
    phrase << "the estimate lost its way (the tracks' noise taken at "
           << (std::isfinite(taken_noise_px) ? std::max(taken_noise_px, stated) : stated)
           << " px), or outlier_chi2 (" << settings.outlier_chi2 << ") is too strict";
  return phrase.str();
}

std::string most_rejected_line(long rejected, long tracks, double taken_noise_px,
                               const FilterSettings& settings) {
  const std::string phrase = most_rejected_phrase(rejected, tracks, taken_noise_px, settings);
  return phrase.empty() ? "" : "warning: " + phrase + "; the results are not to be trusted\n";
}

std::string not_admitted_phrase(long observations) {
  if (observations <= 0) return "";
  return "; " + std::to_string(observations) +
         " observations of new tracks left out for want of room (max_live_points)";
}

std::string outliers_phrase(const SfmResult& result, double stated_noise_px) {
  std::string phrase = "outlier tracks " + std::to_string(result.outliers.size());
  if (result.taken_back > 0)
    phrase += " (the batch took back " + std::to_string(result.taken_back) +
              " that the filter had rejected)";
  if (!result.retest_skipped.empty())
    phrase += " (the filter's; not re-tested by the batch: " + result.retest_skipped + ")";
  if (result.not_in_filter > 0)
    phrase += "; " + std::to_string(result.not_in_filter) +
              " tracks the filter had no room for (max_live_points), of which the batch placed " +
              std::to_string(result.placed_by_triangulation) + " from its poses";
  return phrase + measured_noise_phrase(result.online_noise_px, stated_noise_px);
}

std::string scale_line(const SfmResult& result, const BatchSettings& settings) {
  const BatchResult& batch = result.batch;
  std::ostringstream line;
  line << "scale: ";
  switch (batch.scale_source) {
    case BatchScale::kFromImages:
      line << "from the images, +- " << percent(batch.scale_sigma_relative);
      if (std::isfinite(batch.scale_sigma_relative_camera_held))
        line << " (1 sigma, with the camera refined; kept free as the images fix it to +- "
             << percent(batch.scale_sigma_relative_camera_held)
             << " with the camera as calibrated, within a factor 2 at 3 sigma)";
      else
        line << " (1 sigma; kept free: within a factor 2 at 3 sigma)";
      break;
    case BatchScale::kHeldAtStart:
      line << "held at the filter's: " << images_fix_it(batch, "fix it only to")
           << ", and a free scale is kept only to +- " << percent(settings.max_free_scale_sigma)
           << " (a factor 2 at 3 sigma); lengths are in the filter's units, not metres ([sfm] "
              "known_distance_m holds them at a known distance)";
      break;
    case BatchScale::kHeldAtKnownDistance:
      line << "held at the known distance, " << settings.known_distance_m
           << " m between the first and last cameras ([sfm] known_distance_m); "
           << images_fix_it(batch, "alone would fix it to");
      break;
    case BatchScale::kFromSensors:
      line << "from the motion sensors (" << (result.world_is_enu ? "GPS fixes" : "odometry")
           << ")";
      if (std::isfinite(result.odometry_scale_sigma))
        line << "; the wheel's scale +- "
             << percent(result.odometry_scale_sigma / result.odometry_scale) << " (1 sigma)";
      break;
    case BatchScale::kNoTranslation:
      line << "none: no camera moves away from the first";
      break;
  }
  line << "\n";
  return line.str();
}

std::string batch_line(const BatchResult& batch) {
  std::ostringstream line;
  line << "batch: " << (batch.converged ? "converged" : "did not converge") << " in "
       << batch.iterations << " iterations, " << batch.solve_seconds << " s; RMS "
       << batch.initial_rms_px << " -> " << batch.final_rms_px << " px per coordinate ("
       << batch.message << ")\n";
  return line.str();
}

std::string considered_camera_line(const camera::CatadioptricCamera& camera,
                                   const FilterSettings& settings) {
  const std::vector<int>& considered = settings.camera_uncertainty.parameters;
  if (considered.empty()) return "";
  const std::vector<std::string> names = camera.param_names();
  std::string line = "filter's camera: as calibrated, the calibration's covariance of";
  for (size_t i = 0; i < considered.size(); ++i)
    line += (i ? ", " : " ") + names[static_cast<size_t>(considered[i])];
  return line + " carried in the filter's covariance ([sfm] consider_camera)\n";
}

std::string camera_line(const camera::CatadioptricCamera& camera, const BatchResult& batch,
                        const BatchSettings& settings) {
  const CameraPrior& prior = settings.camera_prior;
  if (prior.parameters.empty()) return "";
  if (!batch.camera_refined) {
    if (batch.scale_source == BatchScale::kHeldAtStart)
      return "camera: held as calibrated: the images do not fix the scale, which the mirror's "
             "size would take up\n";
    if (batch.scale_source == BatchScale::kNoTranslation)
      return "camera: held as calibrated: no camera moves from the first\n";
    return "camera: held as calibrated: the refining solve failed\n";
  }
  const std::vector<std::string> names = camera.param_names();
  const Eigen::VectorXd calibrated = camera.params();
  const int k = static_cast<int>(prior.parameters.size());
  Eigen::VectorXd moved(k);
  std::ostringstream line;
  line << "camera: refined under the calibration's covariance:";
  for (int i = 0; i < k; ++i) {
    const int p = prior.parameters[i];
    moved(i) = batch.camera_params(p) - calibrated(p);
    line << (i ? ", " : " ") << names[p] << " " << std::showpos << std::setprecision(3)
         << moved(i) << std::noshowpos << " (" << std::fixed << std::setprecision(2)
         << moved(i) / std::sqrt(prior.covariance(i, i)) << " sigma)" << std::defaultfloat;
  }
  line << "; " << std::fixed << std::setprecision(2)
       << core::mahalanobis(moved, prior.covariance) << " sigmas from the calibration in all\n";
  return line.str();
}

}  // namespace omnisfm::sfm
