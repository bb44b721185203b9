#include "omnisfm/sim/scene.h"

#include <Eigen/Geometry>
#include <cmath>

namespace omnisfm::sim {

void Scene::add_box(const Eigen::Vector3d& lo, const Eigen::Vector3d& hi, int texture) {
  const Eigen::Vector3d size = hi - lo;
  const Eigen::Vector3d ex(size.x(), 0, 0), ey(0, size.y(), 0), ez(0, 0, size.z());
  add_quad({lo, ex, ey, texture});
  add_quad({lo + ez, ex, ey, texture});
  add_quad({lo, ex, ez, texture});
  add_quad({lo + ey, ex, ez, texture});
  add_quad({lo, ey, ez, texture});
  add_quad({lo + ex, ey, ez, texture});
}

bool Scene::intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                      double max_distance, SceneHit* hit) const {
  bool found = false;
  double best = max_distance;
  for (size_t i = 0; i < quads_.size(); ++i) {
    const TexturedQuad& q = quads_[i];
    const Eigen::Vector3d normal = q.edge_u.cross(q.edge_v);
    const double denominator = normal.dot(direction);
    if (std::abs(denominator) < 1e-15 * normal.norm()) continue;
    const double t = normal.dot(q.origin - origin) / denominator;
    if (!(t > 0 && t < best)) continue;
    const Eigen::Vector3d local = origin + t * direction - q.origin;
    const double lu2 = q.edge_u.squaredNorm(), lv2 = q.edge_v.squaredNorm();
    const double a = local.dot(q.edge_u) / lu2, b = local.dot(q.edge_v) / lv2;
    if (a < 0 || a > 1 || b < 0 || b > 1) continue;
    best = t;
    found = true;
    hit->distance = t;
    hit->quad = static_cast<int>(i);
    hit->marker = -1;
    hit->uv << a * std::sqrt(lu2), b * std::sqrt(lv2);
  }
  for (size_t i = 0; i < markers_.size(); ++i) {
    const Marker& m = markers_[i];
    const double denominator = m.normal.dot(direction);
    if (std::abs(denominator) < 1e-15) continue;
    const double t = m.normal.dot(m.centre - origin) / denominator;
    if (!(t > 0 && t < best)) continue;
    const Eigen::Vector3d offset = origin + t * direction - m.centre;
    if (offset.squaredNorm() > m.radius * m.radius) continue;
    // Coordinates in the marker's plane, along any fixed pair of in-plane axes.
    const Eigen::Vector3d axis_u = m.normal.unitOrthogonal(), axis_v = m.normal.cross(axis_u);
    best = t;
    found = true;
    hit->distance = t;
    hit->quad = -1;
    hit->marker = static_cast<int>(i);
    hit->uv << offset.dot(axis_u), offset.dot(axis_v);
  }
  return found;
}

bool Scene::visible(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const {
  const Eigen::Vector3d d = b - a;
  const double length = d.norm();
  if (length <= 0) return true;
  // Points on surfaces must not hide themselves: leave a millimetre at each end.
  constexpr double kEndTolerance = 1e-3;
  if (length <= 2 * kEndTolerance) return true;
  const Eigen::Vector3d direction = d / length;
  SceneHit hit;
  return !intersect(a + kEndTolerance * direction, direction, length - 2 * kEndTolerance, &hit);
}

}  // namespace omnisfm::sim
