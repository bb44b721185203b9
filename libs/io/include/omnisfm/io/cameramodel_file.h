#pragma once
// mrcal's .cameramodel text format: what a file holds, and its writer (the reader is the camera
// module's, camera/mrcal_lensmodel.h).

#include <Eigen/Core>
#include <string>
#include <vector>

namespace omnisfm::io {

// One central camera as a .cameramodel holds it.
struct MrcalCameraModel {
  std::string lensmodel;       // mrcal's name, configuration included
  Eigen::VectorXd intrinsics;  // fx fy cx cy, then the model's own parameters
  int image_width = 0, image_height = 0;
  // The extrinsics: X_model = R X_ref + t.
  Eigen::Matrix3d R_model_from_C = Eigen::Matrix3d::Identity();
  Eigen::Vector3d t_model_from_C = Eigen::Vector3d::Zero();
  // mrcal's valid_intrinsics_region, closed (the first point repeated); empty for none.
  std::vector<Eigen::Vector2d> valid_region;
};

// Writes a .cameramodel that stock mrcal reads, every number with round-trip precision (mrcal's
// own C writer keeps 6 decimals). `notes` become comment lines at the top. The file is replaced
// whole or not at all; throws std::runtime_error when writing fails or the intrinsics do not fit
// the lens model.
void write_cameramodel(const std::string& path, const MrcalCameraModel& model,
                       const std::vector<std::string>& notes);

}  // namespace omnisfm::io
