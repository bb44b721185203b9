#pragma once
// The conventional ("inner") camera that looks at the mirror, in OpenCV's frame C (x right, y down,
// z forward). Central cameras (pinhole, mrcal) have their centre at the origin of C; an
// orthographic (telecentric) camera looks along +z from every point.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

namespace omnisfm::camera {

// d pixel / d parameters: two rows, a column per parameter of the model that fills it (its
// num_params()); the model sizes it.
using ParamsJacobian = Eigen::Matrix<double, 2, Eigen::Dynamic>;

// Named, and made from numbers, in camera_kinds.h.
enum class InnerKind { kPinhole, kOrthographic, kMrcal };

class InnerCamera {
 public:
  virtual ~InnerCamera() = default;
  virtual std::unique_ptr<InnerCamera> clone() const = 0;

  virtual InnerKind kind() const = 0;
  // True when every pixel looks along +z (a telecentric lens); false for central cameras.
  virtual bool is_orthographic() const = 0;

  virtual int num_params() const = 0;
  virtual std::vector<std::string> param_names() const = 0;
  virtual Eigen::VectorXd params() const = 0;
  // Returns false, changing nothing, when the vector has the wrong size or invalid values.
  virtual bool set_params(const Eigen::VectorXd& params) = 0;

  // Pixel of a point p in frame C. J_p: d pixel / d p. J_params: d pixel / d params (resized to
  // 2 x num_params()). Returns false where the camera cannot see p.
  virtual bool project(const Eigen::Vector3d& p, Eigen::Vector2d* pixel,
                       Eigen::Matrix<double, 2, 3>* J_p, ParamsJacobian* J_params) const = 0;

  // The ray of a pixel in frame C: a point on it (the centre, for central cameras) and a unit
  // direction with positive z.
  virtual bool unproject(const Eigen::Vector2d& pixel, Eigen::Vector3d* origin,
                         Eigen::Vector3d* direction) const = 0;
};

}  // namespace omnisfm::camera
