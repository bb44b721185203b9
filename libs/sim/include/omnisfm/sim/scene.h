#pragma once
// The world a simulated rig moves through: textured rectangles (walls, floor, ceiling, boxes) and
// flat circular markers (the lab's surveyed targets). Used to decide what the rig can see and to
// render what it sees.

#include <Eigen/Core>
#include <vector>

namespace omnisfm::sim {

// The rectangle origin + a * edge_u + b * edge_v, a and b in [0, 1], seen from both sides.
struct TexturedQuad {
  Eigen::Vector3d origin, edge_u, edge_v;
  int texture = 0;  // which procedural texture covers it
};

// A flat disc: a dark centre dot inside a white ring, as surveyed targets are painted.
struct Marker {
  Eigen::Vector3d centre, normal;  // normal: unit
  double radius = 0.05;            // outer radius of the white ring, metres
  int id = 0;
};

struct SceneHit {
  double distance = 0;    // along the (unit) ray
  int quad = -1;          // index of the quad hit, or -1
  int marker = -1;        // index of the marker hit, or -1
  Eigen::Vector2d uv{0, 0};  // on a quad: metres along its edges; on a marker: offset from the centre
};

class Scene {
 public:
  void add_quad(const TexturedQuad& quad) { quads_.push_back(quad); }
  void add_marker(const Marker& marker) { markers_.push_back(marker); }
  // The six faces of an axis-aligned box.
  void add_box(const Eigen::Vector3d& min, const Eigen::Vector3d& max, int texture);

  // The nearest surface along origin + t * direction (direction unit), 0 < t < max_distance.
  bool intersect(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction,
                 double max_distance, SceneHit* hit) const;
  // True when nothing lies strictly between a and b (ends excluded by a small tolerance).
  bool visible(const Eigen::Vector3d& a, const Eigen::Vector3d& b) const;

  const std::vector<TexturedQuad>& quads() const { return quads_; }
  const std::vector<Marker>& markers() const { return markers_; }

 private:
  std::vector<TexturedQuad> quads_;
  std::vector<Marker> markers_;
};

}  // namespace omnisfm::sim
