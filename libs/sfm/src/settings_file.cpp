#include "omnisfm/sfm/settings_file.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "omnisfm/io/ini_file.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/sfm/settings_ranges.h"

namespace omnisfm::sfm {
SfmSettings read_sfm_settings(const std::string& path) {
  const io::IniFile ini = io::IniFile::read(path);
  SfmSettings settings;
  for (const io::IniSection& section : ini.sections()) {
    if (section.name() == "sfm") {
      settings = read_sfm_settings(section);
    } else if (section.name().empty()) {
      // A key before any section would otherwise be silently ignored.
      if (!section.entries().empty())
        section.fail(section.entries().front().key, "belongs in the [sfm] section");
    } else if (section.name() != "run") {  // the run verb's, as in the shipped omnisfm.ini
      throw io::InputError(path, section.line(),
                           "unknown section [" + section.name() + "]: expected [sfm] (or [run])");
    }
  }
  return settings;
}

SfmSettings read_sfm_settings(const io::IniSection& s) {
  SfmSettings settings;
  FilterSettings& f = settings.filter;
  // The bounds hold what the settings can mean (settings_ranges.h): beyond them a noise or walk
  // is numerically zero or says nothing, and the filter failed far from the file.
  for (const SettingRange& r : setting_ranges()) {
    if (std::string(r.key) == "known_distance_m") continue;  // below: empty when not known
    double& field = r.field(settings);
    field = s.get_within(r.key, field, r.low, r.high, r.meaning, r.zero_off);
  }
  const std::string test = s.get_string("outlier_test", "chi2");
  if (test == "pixels")
    f.outlier_test = OutlierTest::kPixels;
  else if (test != "chi2")
    s.fail("outlier_test",
           "must be chi2 (the residual against its covariance) or pixels (the "
           "paper's fixed outlier_threshold_px)");
  f.measure_noise = s.get_flag("measure_noise", f.measure_noise);
  f.linearise_at_constant_velocity =
      s.get_flag("linearise_at_constant_velocity", f.linearise_at_constant_velocity);
  for (const CountRange& r : count_ranges()) {
    int& field = r.field(settings);
    field = s.get_positive_int(r.key, field, r.zero_off || r.low == 0);
    if (!(r.zero_off && field == 0) && (field < r.low || field > r.high))
      s.fail(r.key, r.requirement());
  }
  settings.run_batch = s.get_flag("batch", settings.run_batch);
  settings.batch_outliers = s.get_flag("batch_outliers", settings.batch_outliers);
  settings.batch_track_false_alarm =
      s.get_positive("batch_track_false_alarm", settings.batch_track_false_alarm, true);
  if (!(settings.batch_track_false_alarm < 1))
    s.fail("batch_track_false_alarm",
           "must be a probability below 1 (the chance a good track fails), or 0 (off)");
  settings.batch.covariances = s.get_flag("covariances", settings.batch.covariances);
  settings.batch.scale_start = s.get_flag("batch_scale_start", settings.batch.scale_start);
  settings.refine_camera = s.get_flag("refine_camera", settings.refine_camera);
  if (settings.refine_camera && !settings.run_batch)
    s.fail("refine_camera", "the batch refines the camera, and batch = false leaves none");
  settings.consider_camera = s.get_flag("consider_camera", settings.consider_camera);
  // Empty, the default, when not known: 0 would say the first and last cameras coincide.
  if (!s.get_string("known_distance_m", "").empty()) {
    // Below a millimetre or beyond 1e8 m (a thousand times the Earth) no rig's positions are.
    settings.batch.known_distance_m = s.get_within(
        "known_distance_m", 1, 1e-3, 1e8,
        "the distance between the first and last camera positions in metres (empty when not "
        "known)");
  }
  for (const auto& entry : s.unread()) s.fail(entry.key, "unknown key in [sfm]");
  return settings;
}

CameraPrior camera_prior_from(const camera::CatadioptricCamera& camera,
                                             const io::ParameterCovariance& covariance) {
  const std::vector<std::string> names = camera.param_names();
  CameraPrior prior;
  for (const std::string& name : covariance.parameters) {
    const auto at = std::find(names.begin(), names.end(), name);
    if (at == names.end())
      throw std::invalid_argument("the covariance names " + name +
                                  ", which the camera does not have");
    prior.parameters.push_back(static_cast<int>(at - names.begin()));
  }
  prior.covariance = covariance.matrix;
  if (const std::string wrong = camera_prior_problem(camera, prior); !wrong.empty())
    throw std::invalid_argument(wrong);
  return prior;
}

}  // namespace omnisfm::sfm
