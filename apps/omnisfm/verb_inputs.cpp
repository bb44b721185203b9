#include "verb_inputs.h"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <iostream>
#include <stdexcept>

#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/camera_covariance.h"
#include "omnisfm/io/camera_file.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/number_text.h"
#include "omnisfm/io/shared_data.h"
#include "omnisfm/sfm/settings_file.h"

namespace omnisfm::app {

camera::CatadioptricCamera load_camera(const std::string& path) {
  return io::read_camera_file(path.empty() ? io::default_camera_file() : path);
}

void apply_camera_prior(const std::string& config_file, const std::string& camera_file,
                        const camera::CatadioptricCamera* camera, sfm::SfmSettings* settings) {
  if (!settings->refine_camera && !settings->consider_camera) return;
  const std::string flag = settings->refine_camera ? "refine_camera" : "consider_camera";
  const std::string use = settings->refine_camera ? "refines the camera under"
                                                  : "carries in the filter's covariance";
  if (camera_file.empty() || !camera)
    throw io::InputError(config_file, 0,
                         "[sfm] " + flag + " needs a calibrated camera file (--camera) holding "
                         "its [omni_camera_covariance]");
  const auto covariance = io::read_camera_covariance(camera_file);
  if (!covariance)
    throw io::InputError(camera_file, 0,
                         "[sfm] " + flag + " " + use + " its calibration's covariance, and this "
                         "file holds no [omni_camera_covariance] (omnisfm calibrate writes it)");
  sfm::CameraPrior prior;
  try {
    prior = sfm::camera_prior_from(*camera, *covariance);
  } catch (const std::invalid_argument& e) {
    throw io::InputError(camera_file, 0, std::string("[omni_camera_covariance]: ") + e.what());
  }
  if (settings->refine_camera) settings->batch.camera_prior = prior;
  if (settings->consider_camera) settings->filter.camera_uncertainty = prior;
}

io::VnlogTable read_table_or_stdin(const std::string& path) {
  if (path.empty() || path == "-") return io::VnlogTable::read(std::cin, "<stdin>");
  return io::VnlogTable::read(path);
}

std::vector<io::StampedPose> read_ground_truth(const std::string& path) {
  if (path.empty()) return {};
  std::vector<io::StampedPose> truth = io::read_tum_trajectory(path);
  if (truth.size() < 3)
    throw io::InputError(path, 0,
                         "holds " + std::to_string(truth.size()) +
                             " poses: comparing with the truth needs at least 3");
  // Before any work: the alignment with the estimate turns about the truth's positions, and
  // about a line of them it cannot.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const auto& pose : truth)
    mean += pose.world_from_cam.translation() / static_cast<double>(truth.size());
  Eigen::Matrix3d scatter = Eigen::Matrix3d::Zero();
  for (const auto& pose : truth) {
    const Eigen::Vector3d d = pose.world_from_cam.translation() - mean;
    scatter += d * d.transpose();
  }
  const Eigen::Vector3d spread =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(scatter).eigenvalues();
  if (!(spread[1] > 1e-18 * spread[2]) || !(spread[2] > 0))
    throw io::InputError(path, 0,
                         "its positions lie on one line: the alignment with the estimate cannot "
                         "fix the rotation about it");
  return truth;
}

void finish_stdout() {
  std::cout.flush();
  if (!std::cout) throw std::runtime_error("cannot write to standard output");
}

namespace {

CLI::Validator text_check(const std::string& name, const std::string& wanted,
                          const std::function<bool(const std::string&)>& accepts) {
  return CLI::Validator(
      [wanted, accepts](const std::string& text) {
        return accepts(text) ? std::string() : "must be " + wanted + ", not '" + text + "'";
      },
      name);
}

CLI::Validator number_check(const std::string& wanted, const std::function<bool(double)>& accepts) {
  return text_check("NUMBER", wanted, [accepts](const std::string& text) {
    double value = 0;
    return io::parse_double(text, &value) && std::isfinite(value) && accepts(value);
  });
}

}  // namespace

CLI::Validator number_between(double min, double max) {
  return number_check("a number from " + io::format_double(min) + " to " + io::format_double(max),
                      [min, max](double value) { return value >= min && value <= max; });
}

CLI::Validator positive_number() {
  return number_check("a positive number", [](double value) { return value > 0; });
}

CLI::Validator whole_number_between(int min, int max) {
  const std::string wanted =
      max == INT_MAX ? "a whole number, at least " + std::to_string(min)
                     : "a whole number from " + std::to_string(min) + " to " + std::to_string(max);
  return text_check("WHOLE NUMBER", wanted, [min, max](const std::string& text) {
    int value = 0;
    return io::parse_int(text, &value) && value >= min && value <= max;
  });
}

CLI::Validator seed_number() {
  return text_check("SEED", "a whole number from 0 to 18446744073709551615",
                    [](const std::string& text) {
                      if (text.empty() || text.size() > 20 ||
                          text.find_first_not_of("0123456789") != std::string::npos)
                        return false;
                      // 20 digits may still pass 2^64 - 1: compare as text of equal length.
                      return text.size() < 20 || text <= "18446744073709551615";
                    });
}

void require_writable_folder_of(const std::string& path) {
  io::require_writable_folder(path,
                              std::filesystem::absolute(path).lexically_normal().parent_path());
}

}  // namespace omnisfm::app

namespace omnisfm::app {

void check_output_file(const std::string& given, const std::filesystem::path& out) {
  if (std::filesystem::is_directory(out) || out.filename().empty() || out.filename() == "." ||
      out.filename() == "..")
    throw io::InputError(given, 0, "is a folder; give the file's name");
  const std::filesystem::path folder = out.parent_path();
  io::require_writable_folder(given,
                              std::filesystem::exists(folder) ? folder : folder.parent_path());
}

void require_not_an_input(const std::string& output, const std::vector<std::string>& inputs) {
  std::error_code ignored;
  const std::filesystem::path out =
      std::filesystem::weakly_canonical(std::filesystem::absolute(output), ignored);
  for (const std::string& input : inputs)
    if (!input.empty() &&
        std::filesystem::weakly_canonical(std::filesystem::absolute(input), ignored) == out)
      throw io::InputError(
          output, 0,
          "is also an input (" + input + "), which writing it would destroy: give another name");
}

void in_folder_made_if_missing(const std::filesystem::path& folder,
                               const std::function<void()>& write) {
  const bool made = std::filesystem::create_directory(folder);
  try {
    write();
  } catch (...) {
    std::error_code ignored;
    if (made) std::filesystem::remove_all(folder, ignored);
    throw;
  }
}

}  // namespace omnisfm::app
