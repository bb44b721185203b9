#pragma once
// Any central lens model that mrcal can project (LENSMODEL_OPENCV8, LENSMODEL_SPLINED_...), with
// its gradients from libmrcal. The camera's extrinsics in the .cameramodel are ignored: the
// mirror-to-camera transform places the mirror. Parameters: mrcal's intrinsics vector.

#include "omnisfm/camera/inner_camera.h"

namespace omnisfm::camera {

class MrcalCamera final : public InnerCamera {
 public:
  // Reads a .cameramodel file; throws std::runtime_error naming the file when it cannot.
  static MrcalCamera from_file(const std::string& path);
  // lensmodel: mrcal's name, e.g. "LENSMODEL_OPENCV8"; intrinsics: core then distortion.
  // Throws std::invalid_argument when the model is unknown or the vector has the wrong size.
  MrcalCamera(const std::string& lensmodel, const Eigen::VectorXd& intrinsics, int image_width,
              int image_height);
  ~MrcalCamera() override;
  MrcalCamera(const MrcalCamera& other);
  MrcalCamera& operator=(const MrcalCamera& other);

  std::unique_ptr<InnerCamera> clone() const override;
  InnerKind kind() const override { return InnerKind::kMrcal; }
  bool is_orthographic() const override { return false; }
  int num_params() const override;
  std::vector<std::string> param_names() const override;
  Eigen::VectorXd params() const override { return intrinsics_; }
  bool set_params(const Eigen::VectorXd& params) override;

  bool project(const Eigen::Vector3d& p, Eigen::Vector2d* pixel, Eigen::Matrix<double, 2, 3>* J_p,
               ParamsJacobian* J_params) const override;
  bool unproject(const Eigen::Vector2d& pixel, Eigen::Vector3d* origin,
                 Eigen::Vector3d* direction) const override;

  const std::string& lensmodel_name() const { return lensmodel_name_; }
  int image_width() const { return width_; }
  int image_height() const { return height_; }
  // Writes a .cameramodel file (identity extrinsics); throws std::runtime_error on failure.
  void write(const std::string& path) const;

 private:
  struct Lensmodel;  // mrcal_lensmodel_t, kept out of this header
  std::unique_ptr<Lensmodel> lensmodel_;
  std::string lensmodel_name_;
  Eigen::VectorXd intrinsics_;
  int width_ = 0, height_ = 0;
};

}  // namespace omnisfm::camera
