#include "omnisfm/eval/similarity_alignment.h"

#include <Eigen/Eigenvalues>
#include <stdexcept>

namespace omnisfm::eval {

Similarity align(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b,
                 bool with_scale) {
  const size_t n = a.size();
  if (n != b.size() || n < 3) throw std::invalid_argument("align: need 3 or more pairs");
  Eigen::Vector3d mean_a = Eigen::Vector3d::Zero(), mean_b = Eigen::Vector3d::Zero();
  for (size_t i = 0; i < n; ++i) {
    mean_a += a[i];
    mean_b += b[i];
  }
  mean_a /= n;
  mean_b /= n;
  Eigen::Matrix3d M = Eigen::Matrix3d::Zero();
  double spread_a = 0;
  for (size_t i = 0; i < n; ++i) {
    const Eigen::Vector3d da = a[i] - mean_a, db = b[i] - mean_b;
    M += da * db.transpose();
    spread_a += da.squaredNorm();
  }
  // Horn (1987): the rotation is the unit quaternion of the largest eigenvalue of N.
  const double Sxx = M(0, 0), Sxy = M(0, 1), Sxz = M(0, 2), Syx = M(1, 0), Syy = M(1, 1),
               Syz = M(1, 2), Szx = M(2, 0), Szy = M(2, 1), Szz = M(2, 2);
  Eigen::Matrix4d N;
  N << Sxx + Syy + Szz, Syz - Szy, Szx - Sxz, Sxy - Syx,  //
      Syz - Szy, Sxx - Syy - Szz, Sxy + Syx, Szx + Sxz,   //
      Szx - Sxz, Sxy + Syx, -Sxx + Syy - Szz, Syz + Szy,  //
      Sxy - Syx, Szx + Sxz, Syz + Szy, -Sxx - Syy + Szz;
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> eig(N);
  const Eigen::Vector4d q = eig.eigenvectors().col(3);
  // A degenerate (collinear) configuration leaves the top two eigenvalues equal.
  const Eigen::Vector4d values = eig.eigenvalues();
  if (spread_a <= 0 || values[3] - values[2] <= 1e-12 * std::max(1.0, std::abs(values[3])))
    throw std::invalid_argument("align: the points are degenerate (coincident or collinear)");
  Similarity s;
  s.rotation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
  // The least-squares scale for this rotation.
  double correlation = 0;
  for (size_t i = 0; i < n; ++i) correlation += (b[i] - mean_b).dot(s.rotation * (a[i] - mean_a));
  s.scale = with_scale ? correlation / spread_a : 1.0;
  s.translation = mean_b - s.scale * s.rotation * mean_a;
  return s;
}

}  // namespace omnisfm::eval
