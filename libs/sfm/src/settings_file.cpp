#include "omnisfm/sfm/settings_file.h"

#include "omnisfm/io/ini_file.h"

namespace omnisfm::sfm {
namespace {

double positive(const io::IniSection& s, const std::string& key, double fallback, bool zero_ok) {
  const double v = s.get_double(key, fallback);
  if (!(zero_ok ? v >= 0 : v > 0)) s.fail(key, zero_ok ? "must be >= 0" : "must be > 0");
  return v;
}

bool flag(const io::IniSection& s, const std::string& key, bool fallback) {
  const double v = s.get_double(key, fallback ? 1 : 0);
  if (v != 0 && v != 1) s.fail(key, "must be 0 or 1");
  return v == 1;
}

}  // namespace

SfmSettings read_sfm_settings(const std::string& path) {
  const io::IniFile ini = io::IniFile::read(path);
  SfmSettings settings;
  if (!ini.has_section("sfm")) return settings;
  const io::IniSection& s = ini.section("sfm");
  FilterSettings& f = settings.filter;
  f.pixel_sigma = positive(s, "pixel_sigma", f.pixel_sigma, false);
  f.rotation_walk_sigma = positive(s, "rotation_walk_sigma", f.rotation_walk_sigma, true);
  f.translation_walk_sigma = positive(s, "translation_walk_sigma", f.translation_walk_sigma, true);
  f.initial_depth = positive(s, "initial_depth", f.initial_depth, false);
  f.inverse_depth_sigma = positive(s, "inverse_depth_sigma", f.inverse_depth_sigma, false);
  f.outlier_threshold_px = positive(s, "outlier_threshold_px", f.outlier_threshold_px, false);
  f.innovation_gate_chi2 = positive(s, "innovation_gate_chi2", f.innovation_gate_chi2, true);
  f.update_iterations = static_cast<int>(positive(s, "update_iterations", f.update_iterations, false));
  settings.run_batch = flag(s, "batch", settings.run_batch);
  settings.batch_outlier_threshold_px =
      positive(s, "batch_outlier_threshold_px", settings.batch_outlier_threshold_px, true);
  settings.batch.huber_px = positive(s, "huber_px", settings.batch.huber_px, true);
  settings.batch.covariances = flag(s, "covariances", settings.batch.covariances);
  settings.batch.max_iterations =
      static_cast<int>(positive(s, "max_iterations", settings.batch.max_iterations, false));
  for (const auto& entry : s.unread()) s.fail(entry.key, "unknown key in [sfm]");
  return settings;
}

}  // namespace omnisfm::sfm
