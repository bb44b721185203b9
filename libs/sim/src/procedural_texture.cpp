#include "omnisfm/sim/procedural_texture.h"

#include <algorithm>
#include <cmath>

namespace omnisfm::sim {
namespace {

// A noise texture: mean + contrast * soft_clip(gain * n), n the normalised octave sum,
// soft_clip(x) = x / sqrt(1 + x^2).
struct NoiseStyle {
  double mean, contrast, gain;
  double longest_wavelength;  // metres; each further octave halves it
  int octaves;
  double persistence;  // amplitude ratio from one octave to the next finer one
};

// Indexed by SurfaceTexture for the noise textures.
constexpr NoiseStyle kWallStyle{140, 90, 1.2, 0.64, 6, 0.9};
constexpr NoiseStyle kFloorStyle{110, 85, 1.3, 0.64, 6, 0.9};
constexpr NoiseStyle kCeilingStyle{185, 45, 1.2, 0.64, 6, 0.9};
constexpr NoiseStyle kBoxStyle{125, 105, 1.5, 0.32, 5, 0.9};
constexpr NoiseStyle kGroundStyle{100, 80, 1.2, 1.28, 7, 0.9};

constexpr double kStripePeriod = 0.30, kStripeWidth = 0.04;
constexpr double kStripeLight = 225, kStripeDark = 25;
constexpr double kPlainValue = 140;

// Standard deviation of one octave of gradient_noise over the plane, so that the octave sum,
// divided by it and by the root of the summed squared amplitudes, has unit spread.
constexpr double kGradientNoiseStd = 0.216;

std::uint64_t mix64(std::uint64_t h) {  // splitmix64's finaliser
  h ^= h >> 30;
  h *= 0xbf58476d1ce4e5b9ULL;
  h ^= h >> 27;
  h *= 0x94d049bb133111ebULL;
  h ^= h >> 31;
  return h;
}

// 16 unit gradients evenly spread in angle, half a step off the axes.
struct GradientTable {
  double x[16], y[16];
  GradientTable() {
    for (int k = 0; k < 16; ++k) {
      const double angle = (k + 0.5) * 3.14159265358979323846 / 8;
      x[k] = std::cos(angle);
      y[k] = std::sin(angle);
    }
  }
};
const GradientTable kGradients;

// The dot product of the gradient at a lattice point, fixed by the seed, with (dx, dy).
double lattice_ramp(std::int64_t ix, std::int64_t iy, std::uint64_t seed, double dx, double dy) {
  std::uint64_t h = static_cast<std::uint32_t>(ix) |
                    (static_cast<std::uint64_t>(static_cast<std::uint32_t>(iy)) << 32);
  const int k = static_cast<int>(mix64(h ^ (seed * 0x9E3779B97F4A7C15ULL)) >> 60);
  return kGradients.x[k] * dx + kGradients.y[k] * dy;
}

// Perlin's gradient noise with unit lattice spacing and C2 (quintic) blending. Unlike value
// noise it has no flat plateaus at the lattice points, which image as a blocky grid.
double gradient_noise(double x, double y, std::uint64_t seed) {
  const double fx = std::floor(x), fy = std::floor(y);
  const auto ix = static_cast<std::int64_t>(fx), iy = static_cast<std::int64_t>(fy);
  const double tx = x - fx, ty = y - fy;
  const double sx = tx * tx * tx * (tx * (6 * tx - 15) + 10);
  const double sy = ty * ty * ty * (ty * (6 * ty - 15) + 10);
  const double n00 = lattice_ramp(ix, iy, seed, tx, ty);
  const double n10 = lattice_ramp(ix + 1, iy, seed, tx - 1, ty);
  const double n01 = lattice_ramp(ix, iy + 1, seed, tx, ty - 1);
  const double n11 = lattice_ramp(ix + 1, iy + 1, seed, tx - 1, ty - 1);
  const double bottom = n00 + sx * (n10 - n00), top = n01 + sx * (n11 - n01);
  return bottom + sy * (top - bottom);
}

double noise_texture(const NoiseStyle& style, std::uint32_t seed, const Eigen::Vector2d& uv,
                     double footprint) {
  // Each octave turns by 1.1 rad more than the last one, hiding the lattice directions.
  constexpr double turn_cos = 0.4535961214255773, turn_sin = 0.8912073600614354;
  double sum = 0, squared_amplitudes = 0, amplitude = 1, wavelength = style.longest_wavelength;
  double axis_cos = 1, axis_sin = 0;
  for (int octave = 0; octave < style.octaves; ++octave) {
    squared_amplitudes += amplitude * amplitude;
    // Full weight from four footprints per wavelength, none at two (the Nyquist limit), so
    // that octaves fade in and out smoothly as the distance changes instead of aliasing.
    const double weight =
        footprint > 0 ? std::clamp(wavelength / (2 * footprint) - 1.0, 0.0, 1.0) : 1.0;
    if (weight > 0) {
      const double x = (axis_cos * uv.x() - axis_sin * uv.y()) / wavelength;
      const double y = (axis_sin * uv.x() + axis_cos * uv.y()) / wavelength;
      sum += weight * amplitude * gradient_noise(x, y, mix64(seed + 0x51ED27ULL * (octave + 1)));
    }
    amplitude *= style.persistence;
    wavelength *= 0.5;
    const double c = axis_cos * turn_cos - axis_sin * turn_sin;
    axis_sin = axis_sin * turn_cos + axis_cos * turn_sin;
    axis_cos = c;
  }
  const double normalised = sum / (kGradientNoiseStd * std::sqrt(squared_amplitudes));
  // A soft clip like tanh, at a fraction of its cost.
  const double x = style.gain * normalised;
  return style.mean + style.contrast * x / std::sqrt(1 + x * x);
}

// How much of [0, x] the dark stripes cover, stripes centred at half a period so that a wall's
// edges fall between them.
double dark_length(double x) {
  const double periods = std::floor(x / kStripePeriod);
  const double into_period = x - periods * kStripePeriod;
  const double stripe_start = 0.5 * (kStripePeriod - kStripeWidth);
  return periods * kStripeWidth + std::clamp(into_period - stripe_start, 0.0, kStripeWidth);
}

// The stripes averaged over the footprint across them, so that their edges are anti-aliased.
double stripes(const Eigen::Vector2d& uv, double footprint) {
  double dark_fraction = 0;
  if (footprint > 0) {
    const double half = 0.5 * footprint;
    dark_fraction = (dark_length(uv.x() + half) - dark_length(uv.x() - half)) / footprint;
  } else {
    const double into_period = uv.x() - std::floor(uv.x() / kStripePeriod) * kStripePeriod;
    dark_fraction = std::abs(into_period - 0.5 * kStripePeriod) < 0.5 * kStripeWidth ? 1 : 0;
  }
  return kStripeLight + (kStripeDark - kStripeLight) * dark_fraction;
}

}  // namespace

double texture_value(int texture, std::uint32_t seed, const Eigen::Vector2d& uv, double footprint) {
  switch (texture) {
    case kWallTexture: return noise_texture(kWallStyle, seed, uv, footprint);
    case kFloorTexture: return noise_texture(kFloorStyle, seed, uv, footprint);
    case kCeilingTexture: return noise_texture(kCeilingStyle, seed, uv, footprint);
    case kBoxTexture: return noise_texture(kBoxStyle, seed, uv, footprint);
    case kGroundTexture: return noise_texture(kGroundStyle, seed, uv, footprint);
    case kStripedWallTexture: return stripes(uv, footprint);
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
