#pragma once
// Procedural surface textures for rendered scenes: deterministic grey levels on surface
// coordinates in metres, made for a Lucas-Kanade tracker to lock on to.
//
// The noise textures are multi-octave gradient noise (wavelengths from tens of centimetres down
// to 2 cm, each octave turned and seeded differently so that no lattice direction dominates),
// pushed through a soft clip into blobs with hard-ish edges: corners at every scale a tracker
// window covers from 1 m to 6 m. Octaves shorter than four footprints (the size of one pixel on
// the surface) fade out, gone at two, so that distant surfaces blur (lose contrast) instead of
// aliasing into flicker from frame to frame. The stripes are averaged over the footprint.

#include <Eigen/Core>
#include <cstdint>

namespace omnisfm::sim {

// Values of TexturedQuad::texture.
enum SurfaceTexture : int {
  kWallTexture = 0,         // indoor walls: mid-grey blobs, 2-60 cm
  kFloorTexture = 1,        // indoor floor: darker, blotchier
  kCeilingTexture = 2,      // ceiling: light, low contrast
  kBoxTexture = 3,          // boxes and furniture: high contrast, small scale (2-30 cm)
  kGroundTexture = 4,       // outdoor ground: dark, gravel and patches, 2 cm-1.3 m
  kStripedWallTexture = 5,  // light wall with 4 cm black stripes every 30 cm across edge_u
                            // (vertical lines when edge_u is horizontal), as in the paper's Fig. 2
  kPlainTexture = 6,        // uniform grey, no features
};
inline constexpr int kNumSurfaceTextures = 7;

inline bool is_surface_texture(int texture) {
  return texture >= 0 && texture < kNumSurfaceTextures;
}

// The grey level (0-255, not rounded) of `texture` at surface coordinates uv (metres). `seed`
// decorrelates surfaces sharing a texture; `footprint` is the size of one pixel on the surface in
// metres (0: no filtering). Requires is_surface_texture(texture).
double texture_value(int texture, std::uint32_t seed, const Eigen::Vector2d& uv, double footprint);

// A seed for surface number `index` with `texture`: surfaces sharing a texture still differ.
std::uint32_t surface_seed(int texture, int index);

}  // namespace omnisfm::sim
