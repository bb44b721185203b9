#include "omnisfm/sim/procedural_texture.h"

#include <algorithm>
#include <cmath>

namespace omnisfm::sim {
namespace {

// A noise texture: mean + contrast * tanh(gain * n), n the normalised octave sum.
struct NoiseStyle {
  double mean, contrast, gain;
  double longest_wavelength;  // metres; each further octave halves it
  int octaves;
  double persistence;  // amplitude ratio from one octave to the next finer one
};

// Indexed by SurfaceTexture for the noise textures.
constexpr NoiseStyle kWallStyle{140, 90, 1.1, 0.64, 6, 0.8};
constexpr NoiseStyle kFloorStyle{110, 85, 1.3, 0.64, 6, 0.85};
constexpr NoiseStyle kCeilingStyle{185, 45, 1.0, 0.64, 6, 0.8};
constexpr NoiseStyle kBoxStyle{125, 105, 1.4, 0.32, 5, 0.85};
constexpr NoiseStyle kGroundStyle{100, 80, 1.2, 1.28, 7, 0.8};

constexpr double kStripePeriod = 0.30, kStripeWidth = 0.04;
constexpr double kStripeLight = 225, kStripeDark = 25;
constexpr double kPlainValue = 140;

// Standard deviation of one octave of value_noise over the plane, so that the octave sum,
// divided by it and by the root of the summed squared amplitudes, has unit spread.
constexpr double kValueNoiseStd = 0.45;

std::uint64_t mix64(std::uint64_t h) {  // splitmix64's finaliser
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  h ^= h >> 31;
  return h;
}

// A value in [-1, 1] for each lattice point, fixed by the seed.
double lattice_value(std::int64_t ix, std::int64_t iy, std::uint64_t seed) {
  std::uint64_t h = static_cast<std::uint32_t>(ix) |
                    (static_cast<std::uint64_t>(static_cast<std::uint32_t>(iy)) << 32);
  h = mix64(h ^ (seed * 0x9E3779B97F4A7C15ULL));
  return static_cast<double>(h >> 11) * (2.0 / 9007199254740992.0) - 1.0;
}

// Value noise with unit lattice spacing and C2 (quintic) interpolation.
double value_noise(double x, double y, std::uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  const double tx = x - fx, ty = y - fy;
  const double sx = tx * tx * tx * (tx * (6 * tx - 15) + 10);
  const double sy = ty * ty * ty * (ty * (6 * ty - 15) + 10);
  const double v00 = lattice_value(ix, iy, seed), v10 = lattice_value(ix + 1, iy, seed);
  const double v01 = lattice_value(ix, iy + 1, seed), v11 = lattice_value(ix + 1, iy + 1, seed);
  const double bottom = v00 + sx * (v10 - v00), top = v01 + sx * (v11 - v01);
  return bottom + sy * (top - bottom);
}

double noise_texture(const NoiseStyle& style, std::uint32_t seed, const Eigen::Vector2d& uv,
                     double footprint) {
  // Each octave turns by this much more than the last one, hiding the lattice directions.
  constexpr double kOctaveTurn = 1.1;
  const double turn_cos = std::cos(kOctaveTurn), turn_sin = std::sin(kOctaveTurn);
  double sum = 0, squared_amplitudes = 0, amplitude = 1, wavelength = style.longest_wavelength;
  double axis_cos = 1, axis_sin = 0;
  for (int octave = 0; octave < style.octaves; ++octave) {
    squared_amplitudes += amplitude * amplitude;
    // Full weight from two footprints per wavelength, none at one: no aliasing, smooth fade.
    const double weight =
        footprint > 0 ? std::clamp(wavelength / footprint - 1.0, 0.0, 1.0) : 1.0;
    if (weight > 0) {
      const double x = (axis_cos * uv.x() - axis_sin * uv.y()) / wavelength;
      const double y = (axis_sin * uv.x() + axis_cos * uv.y()) / wavelength;
      sum += weight * amplitude * value_noise(x, y, mix64(seed + 0x51ED27ULL * (octave + 1)));
    }
    amplitude *= style.persistence;
    wavelength *= 0.5;
    const double c = axis_cos * turn_cos - axis_sin * turn_sin;
    axis_sin = axis_sin * turn_cos + axis_cos * turn_sin;
    axis_cos = c;
  }
  const double normalised = sum / (kValueNoiseStd * std::sqrt(squared_amplitudes));
  return style.mean + style.contrast * std::tanh(style.gain * normalised);
}

double stripes(const Eigen::Vector2d& uv) {
  const double phase = uv.x() / kStripePeriod - std::floor(uv.x() / kStripePeriod);
  // Stripes centred at half a period, so a wall's edges fall between them.
  const bool dark = std::abs(phase - 0.5) * kStripePeriod < 0.5 * kStripeWidth;
  return dark ? kStripeDark : kStripeLight;
}

}  // namespace

double texture_value(int texture, std::uint32_t seed, const Eigen::Vector2d& uv, double footprint) {
  switch (texture) {
    case kWallTexture: return noise_texture(kWallStyle, seed, uv, footprint);
    case kFloorTexture: return noise_texture(kFloorStyle, seed, uv, footprint);
    case kCeilingTexture: return noise_texture(kCeilingStyle, seed, uv, footprint);
    case kBoxTexture: return noise_texture(kBoxStyle, seed, uv, footprint);
    case kGroundTexture: return noise_texture(kGroundStyle, seed, uv, footprint);
    case kStripedWallTexture: return stripes(uv);
    default: return kPlainValue;
  }
}

std::uint32_t surface_seed(int texture, int index) {
  const std::uint64_t key =
      (static_cast<std::uint64_t>(static_cast<std::uint32_t>(texture)) << 32) |
      static_cast<std::uint32_t>(index);
  return static_cast<std::uint32_t>(mix64(key + 0x243F6A8885A308D3ULL) >> 32);
}

}  // namespace omnisfm::sim
