#include "omnisfm/track/patch_alignment.h"

#include <Eigen/Cholesky>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <cstring>
#include <type_traits>
#include <utility>
#include <vector>

#include "float_lanes.h"

namespace omnisfm::track {
namespace {

// Contrast below this (grey levels, weighted standard deviation) is no texture.
constexpr double kMinContrast = 1.0;

using LaneIndices = int __attribute__((vector_size(16)));
static_assert(ReferencePatch::kLanes == kLanes);

using Pair = float __attribute__((vector_size(8)));

Pair load_pair(const float* p) {
  Pair pair;
  std::memcpy(&pair, p, sizeof pair);
  return pair;
}

Lanes join(const Pair& low, const Pair& high) {
  return __builtin_shufflevector(low, high, 0, 1, 2, 3);
}

// The parts of a patch of half size h: its left half (template offset x < 0), its right half
// (the rest), its top and bottom halves (y < 0, the rest), and its centre (within h / 2 of the
// feature). The centre's radius squared, in float as misfit's lanes compare.
float centre_radius_squared(int half_size) {
  return 0.25f * static_cast<float>(half_size * half_size);
}

// The lanes where `mask` (a comparison's all-ones or zero per lane) is set, zero elsewhere.
Lanes where(const LaneIndices& mask, const Lanes& l) {
  return reinterpret_cast<Lanes>(mask & reinterpret_cast<LaneIndices>(l));
}

double lane_sum(const Lanes& l) {
  double sum = 0;
  for (int lane = 0; lane < ReferencePatch::kLanes; ++lane) sum += l[lane];
  return sum;
}

// The sum of w v (kPower 1) or w v^2 (kPower 2) over the first n entries, in double, in kLanes
// partial sums: summed one after the other, each addition waited for the last, a fifth of
// extract's time.
template <int kPower>
double weighted_sum(const float* w, const float* v, Eigen::Index n) {
  double partial[kLanes] = {};
  Eigen::Index k = 0;
  for (; k + kLanes <= n; k += kLanes)
    for (int lane = 0; lane < kLanes; ++lane) {
      const double value = v[k + lane];
      partial[lane] += static_cast<double>(w[k + lane]) * (kPower == 2 ? value * value : value);
    }
  for (; k < n; ++k) {
    const double value = v[k];
    partial[0] += static_cast<double>(w[k]) * (kPower == 2 ? value * value : value);
  }
  double sum = 0;
  for (const double p : partial) sum += p;
  return sum;
}

// Takes the weighted mean off the first n values and returns their weighted contrast (the square
// root of sum w v^2 after): a template's norm. The weights sum to 1.
double centre_on_weighted_mean(const float* weights, float* values, Eigen::Index n) {
  const double mean = weighted_sum<1>(weights, values, n);
  for (Eigen::Index k = 0; k < n; ++k) values[k] = static_cast<float>(values[k] - mean);
  return std::sqrt(weighted_sum<2>(weights, values, n));
}

// The pixels a patch of this half size about `feature` reads: those about the nearest pixel
// (cx, cy), one more around for central-difference gradients, and its Gaussian window (sigma: the
// half size), separable: a weight per column and per row, which multiply to the pixel's.
struct PatchWindow {
  int cx = 0, cy = 0;
  Eigen::Vector2d phase{0, 0};  // from the feature to (cx, cy)
  Eigen::ArrayXd column_weight, row_weight;
};

// Bilinear sampling at a sub-pixel phase phi smooths the image it reads with the kernel
// (1 - phi, phi), of variance phi (1 - phi) along each axis: 1/6 on average over phases. A
// template read at whole pixels is smoothed by as much, with (1/12, 5/6, 1/12) along each axis.
// Left sharper, it made an alignment trade the patch's shape for that smoothing: on exact
// renderings of the lab's brick walls, patches scaled 8 % too large whose features sat 0.1 px
// off at the median and 0.3 at the 95th percentile, where with the smoothed template they sit
// 0.03 and 0.10 px off.
constexpr float kSampleSmoothing = 1.0f / 12;

// The (2 reach + 1)^2 pixels about (cx, cy), row by row, smoothed with (w, 1 - 2 w, w) along
// each axis (variance 2 w; reads one more ring of pixels).
void smoothed_square(const cv::Mat& image, int cx, int cy, int reach, float side_weight,
                     std::vector<float>* square) {
  const int side = 2 * reach + 1;
  const float centre_weight = 1 - 2 * side_weight;
  std::vector<float> across(static_cast<size_t>(side) * (side + 2));
  for (int r = 0; r < side + 2; ++r) {
    const float* row = image.ptr<float>(cy - reach - 1 + r) + cx - reach;
    float* out = &across[static_cast<size_t>(r) * side];
    for (int x = 0; x < side; ++x)
      out[x] = centre_weight * row[x] + side_weight * (row[x - 1] + row[x + 1]);
  }
  square->resize(static_cast<size_t>(side) * side);
  for (int y = 0; y < side; ++y)
    for (int x = 0; x < side; ++x)
      (*square)[static_cast<size_t>(y) * side + x] =
          centre_weight * across[static_cast<size_t>(y + 1) * side + x] +
          side_weight * (across[static_cast<size_t>(y) * side + x] +
                         across[static_cast<size_t>(y + 2) * side + x]);
}

// The largest blur added to a template (variance, px^2, along a direction: a patch shrunk to
// 0.68 of its size, where it nears the tracker's shape limit), and its kernel's reach (3 sigma).
constexpr double kMaxAddedBlur = 1.0;
constexpr int kBlurReach = 3;
// A template's smoothing below sampling's (where its patch grows) is retaken once it should
// change by this share of sampling's: 0.05 px^2. The whole range is 1/6 px^2, so a step of the
// Gaussian's tolerance would never come: on a texture growing 2.5 % a frame the tracks' median
// error was 0.035 px, where it is 0.021.
constexpr double kSampledShareStep = 0.3;
// A Gaussian narrower than this (variance, px^2, summed over two directions) is not added: its
// kernel sampled at whole pixels is nearly a single tap.
constexpr double kLeastAddedBlur = 0.05;

// A symmetric 2 x 2 matrix's eigen-decomposition in closed form: its eigenvalues are the mean
// of its diagonal plus and minus a radius, and its larger eigenvalue's eigenvector lies at the
// angle t with (cos 2t, sin 2t) = ((a - b) / 2, c) / radius.
class SymmetricEigen {
 public:
  explicit SymmetricEigen(const Eigen::Matrix2d& m)
      : mean_(0.5 * (m(0, 0) + m(1, 1))),
        half_difference_(0.5 * (m(0, 0) - m(1, 1))),
        off_diagonal_(0.5 * (m(0, 1) + m(1, 0))),
        radius_(std::sqrt(half_difference_ * half_difference_ + off_diagonal_ * off_diagonal_)) {}
  double largest() const { return mean_ + radius_; }
  double smallest() const { return mean_ - radius_; }
  double largest_magnitude() const { return std::abs(mean_) + radius_; }
  // The matrix with the same eigenvectors and these eigenvalues.
  Eigen::Matrix2d with(double larger, double smaller) const {
    const double mean = 0.5 * (larger + smaller), half_spread = 0.5 * (larger - smaller);
    // An isotropic matrix: any axes.
    const double cos2 = radius_ > 0 ? half_difference_ / radius_ : 1;
    const double sin2 = radius_ > 0 ? off_diagonal_ / radius_ : 0;
    Eigen::Matrix2d m;
    m << mean + half_spread * cos2, half_spread * sin2, half_spread * sin2,
        mean - half_spread * cos2;
    return m;
  }

 private:
  double mean_, half_difference_, off_diagonal_, radius_;
};

// The (2 reach + 1)^2 pixels about the centre of `pixels` (a square of 2 pixels_reach + 1, rows
// `stride` apart and padded by kLanes for the last register's reads), blurred by `covariance`,
// a register of a row at a time; into *square, rows *square_stride apart. A
// blur small enough is the 3 x 3 kernel whose second moments are the covariance's exactly (a
// Gaussian sampled at whole pixels blurs by much less: by 0.013 px^2 where 0.1 is asked); a
// wider one a sampled Gaussian (kept just positive definite where it is flat along a direction).
void blurred_square(const std::vector<float>& pixels, int stride, int pixels_reach, int reach,
                    const Eigen::Matrix2d& covariance, std::vector<float>* square,
                    int* square_stride) {
  float kernel[2 * kBlurReach + 1][2 * kBlurReach + 1] = {};
  int kernel_reach = 1;
  const double a = covariance(0, 0), b = covariance(1, 1), c = covariance(0, 1);
  const double corner = std::abs(c);
  if (a >= corner && b >= corner && a + b - corner <= 0.75) {
    auto tap = [&](int x, int y) -> float& { return kernel[y + kBlurReach][x + kBlurReach]; };
    tap(0, 0) = static_cast<float>(1 - (a + b - corner));
    tap(1, 0) = tap(-1, 0) = static_cast<float>(0.5 * (a - corner));
    tap(0, 1) = tap(0, -1) = static_cast<float>(0.5 * (b - corner));
    if (c > 0)
      tap(1, 1) = tap(-1, -1) = static_cast<float>(0.5 * corner);
    else
      tap(1, -1) = tap(-1, 1) = static_cast<float>(0.5 * corner);
  } else {
    const Eigen::Matrix2d information = (covariance + 1e-4 * Eigen::Matrix2d::Identity()).inverse();
    // Three sigmas along its widest direction.
    kernel_reach =
        std::min(kBlurReach, static_cast<int>(std::ceil(3 * std::sqrt(covariance.trace()))));
    float kernel_sum = 0;
    for (int y = -kernel_reach; y <= kernel_reach; ++y)
      for (int x = -kernel_reach; x <= kernel_reach; ++x) {
        const Eigen::Vector2d d(x, y);
        kernel_sum += kernel[y + kBlurReach][x + kBlurReach] =
            static_cast<float>(std::exp(-0.5 * d.dot(information * d)));
      }
    for (auto& row : kernel)
      for (float& tap : row) tap /= kernel_sum;
  }
  const int side = 2 * reach + 1;
  const int row_lanes = (side + kLanes - 1) / kLanes;
  *square_stride = row_lanes * kLanes;
  square->resize(static_cast<size_t>(*square_stride) * side);
  // The kernel's taps that weigh anything, as offsets into `pixels` and weights.
  int offsets[(2 * kBlurReach + 1) * (2 * kBlurReach + 1)];
  float weights[(2 * kBlurReach + 1) * (2 * kBlurReach + 1)];
  int taps = 0;
  for (int ky = -kernel_reach; ky <= kernel_reach; ++ky)
    for (int kx = -kernel_reach; kx <= kernel_reach; ++kx) {
      const float weight = kernel[ky + kBlurReach][kx + kBlurReach];
      if (weight == 0) continue;
      offsets[taps] = ky * stride + kx;
      weights[taps++] = weight;
    }
  // A register's sum over the taps in four partial sums, kept in registers: one sum would wait
  // on each addition's latency.
  for (int y = 0; y < side; ++y)
    for (int lane = 0; lane < row_lanes; ++lane) {
      const float* in = &pixels[static_cast<size_t>(pixels_reach - reach + y) * stride +
                                pixels_reach - reach + lane * kLanes];
      Lanes sum0 = {}, sum1 = {}, sum2 = {}, sum3 = {};
      int t = 0;
      for (; t + 4 <= taps; t += 4) {
        sum0 += weights[t] * load(in + offsets[t]);
        sum1 += weights[t + 1] * load(in + offsets[t + 1]);
        sum2 += weights[t + 2] * load(in + offsets[t + 2]);
        sum3 += weights[t + 3] * load(in + offsets[t + 3]);
      }
      for (; t < taps; ++t) sum0 += weights[t] * load(in + offsets[t]);
      store(&(*square)[static_cast<size_t>(y) * *square_stride + lane * kLanes],
            (sum0 + sum1) + (sum2 + sum3));
    }
}

// The square of the reference image's pixels a patch keeps for blurring its template later: about
// the feature's nearest pixel, reaching the template's pixels and the blur's kernel, each row
// padded for the last register's reads.
struct KeptPixels {
  int reach, side, stride;
  explicit KeptPixels(int half_size)
      : reach(half_size + 2 + kBlurReach), side(2 * reach + 1), stride(side + kLanes) {}
};

Eigen::Vector2i nearest_pixel(const Eigen::Vector2d& p) {
  return {static_cast<int>(std::lround(p.x())), static_cast<int>(std::lround(p.y()))};
}

// False when the patch and the pixels its smoothed values and their gradients read do not fit in
// the image.
bool patch_window(const cv::Mat& image, const Eigen::Vector2d& feature, int half_size,
                  PatchWindow* w) {
  const Eigen::Vector2i nearest = nearest_pixel(feature);
  w->cx = nearest.x();
  w->cy = nearest.y();
  const int reach = half_size + 2;
  if (!(w->cx - reach >= 0 && w->cy - reach >= 0 && w->cx + reach < image.cols &&
        w->cy + reach < image.rows))
    return false;
  w->phase = Eigen::Vector2d(w->cx - feature.x(), w->cy - feature.y());
  const int side = 2 * half_size + 1;
  const double sigma = half_size;
  w->column_weight.resize(side);
  w->row_weight.resize(side);
  for (int i = 0; i < side; ++i) {
    const double u = i - half_size + w->phase.x(), v = i - half_size + w->phase.y();
    w->column_weight(i) = std::exp(-u * u / (2 * sigma * sigma));
    w->row_weight(i) = std::exp(-v * v / (2 * sigma * sigma));
  }
  return true;
}

}  // namespace

double patch_distortion(const Eigen::Matrix2d& A) {
  // A 2 x 2 matrix's singular values are half the sum and half the difference of the norms of
  // its conformal (rotation and scale) and anti-conformal parts.
  // (Square roots of sums of squares: std::hypot's care for overflow cost more than the rest.)
  const auto norm = [](double x, double y) { return std::sqrt(x * x + y * y); };
  const double conformal = norm(A(0, 0) + A(1, 1), A(1, 0) - A(0, 1));
  const double anti_conformal = norm(A(0, 0) - A(1, 1), A(1, 0) + A(0, 1));
  const double largest = 0.5 * (conformal + anti_conformal);
  const double smallest = 0.5 * std::abs(conformal - anti_conformal);
  return std::max(std::abs(largest - 1), std::abs(smallest - 1));
}

bool ReferencePatch::extract(const cv::Mat& image, const Eigen::Vector2d& feature, int half_size,
                             ReferencePatch* patch) {
  return extract_smoothed(image, feature, half_size, kSampleSmoothing, patch);
}

bool ReferencePatch::extract_smoothed(const cv::Mat& image, const Eigen::Vector2d& feature,
                                      int half_size, float side_weight, ReferencePatch* patch) {
  CV_Assert(image.type() == CV_32FC1 && half_size >= 1);
  PatchWindow window;
  if (!patch_window(image, feature, half_size, &window)) return false;
  const int cx = window.cx, cy = window.cy;
  const Eigen::Vector2d& phase = window.phase;
  const Eigen::ArrayXd& column_weight = window.column_weight;
  const Eigen::ArrayXd& row_weight = window.row_weight;

  ReferencePatch p;
  p.half_size_ = half_size;
  const int side = 2 * half_size + 1;
  const Eigen::Index count = side * side;
  // Zero beyond the pixels: a padded pixel weighs nothing, sits on the feature and has no
  // steepest-descent image, so it changes no sum.
  const Eigen::Index padded = (count + kLanes - 1) / kLanes * kLanes;
  for (Eigen::ArrayXf* a :
       {&p.offsets_x_, &p.offsets_y_, &p.weights_, &p.values_, &p.weighted_gx_, &p.weighted_gy_})
    a->setZero(padded);
  const double weight_sum = column_weight.sum() * row_weight.sum();
  // The values and, one pixel beyond them, the gradients' pixels.
  const int reach = half_size + 1, stride = 2 * reach + 1;
  std::vector<float> smoothed;
  smoothed_square(image, cx, cy, reach, side_weight, &smoothed);
  Eigen::Index k = 0;
  for (int y = -half_size; y <= half_size; ++y)
    for (int x = -half_size; x <= half_size; ++x, ++k) {
      p.offsets_x_(k) = static_cast<float>(x + phase.x());
      p.offsets_y_(k) = static_cast<float>(y + phase.y());
      p.weights_(k) =
          static_cast<float>(column_weight(x + half_size) * row_weight(y + half_size) / weight_sum);
      p.values_(k) = smoothed[static_cast<size_t>(y + reach) * stride + x + reach];
    }
  p.norm_ = centre_on_weighted_mean(p.weights_.data(), p.values_.data(), count);
  if (p.norm_ < kMinContrast) return false;

  // The Hessian of the six steepest-descent images (w gx u, w gx v, w gy u, w gy v, w gx, w gy)
  // holds only the gradients' products (gx gx, gx gy, gy gy) times 1, u, v, uu, uv, vv: 18 sums.
  // The parts need the products' sums over the left, top and centre parts (right and bottom: the
  // whole less left and top). Along a row v is fixed, so a row needs only each product's sums
  // times 1, u and uu, over the row and over its left and centre pixels: kLanes pixels at a time
  // in float, each row's sums then added up in double (extract runs for every new, renewed or
  // re-blurred reference; pixel by pixel in double it took most of extract's time).
  struct Moments {
    double one = 0, u = 0, v = 0, uu = 0, uv = 0, vv = 0;
  } moments[3];
  struct PartMoments {
    double one[3] = {}, u[3] = {}, v[3] = {};  // of gx gx, gx gy, gy gy
  } left, top, centre;
  const int row_lanes = (side + kLanes - 1) / kLanes;
  // Lane reads run up to a register past each row's end; those lanes are masked off, and the
  // last row's reach past the square reads this padding.
  smoothed.resize(smoothed.size() + kLanes, 0.0f);
  const float centre_radius2 = centre_radius_squared(half_size);
  for (int y = -half_size; y <= half_size; ++y) {
    const Eigen::Index row_start = static_cast<Eigen::Index>(y + half_size) * side;
    const float* row = &smoothed[static_cast<size_t>(y + reach) * stride + reach - half_size];
    const float v_float = p.offsets_y_(row_start);
    // Per product: the sums times 1, u and uu, and times 1 and u over the left and the centre.
    Lanes sums[3][7] = {};
    for (int lane = 0; lane < row_lanes; ++lane) {
      const int x = lane * kLanes;  // from the row's first pixel
      const Eigen::Index first = row_start + x;
      const LaneIndices column = {x, x + 1, x + 2, x + 3};
      const LaneIndices in_row = column < side;
      const Lanes u = where(in_row, load(p.offsets_x_.data() + first));
      const Lanes w = where(in_row, load(p.weights_.data() + first));
      // Past the row's end, pixels the gradients never read (zeroed: they might not be finite).
      const Lanes gx = where(in_row, 0.5f * (load(row + x + 1) - load(row + x - 1)));
      const Lanes gy = where(in_row, 0.5f * (load(row + x + stride) - load(row + x - stride)));
      const Lanes wgx = w * gx, wgy = w * gy;
      // Past the row's end these write zeros where the next row then writes its own.
      store(p.weighted_gx_.data() + first, wgx);
      store(p.weighted_gy_.data() + first, wgy);
      const Lanes products[3] = {wgx * gx, wgx * gy, wgy * gy};
      const LaneIndices in_left = u < 0;
      const LaneIndices in_centre = u * u + v_float * v_float <= centre_radius2;
      const Lanes uu = u * u;
      for (int i = 0; i < 3; ++i) {
        const Lanes g = products[i], gu = g * u;
        sums[i][0] += g;
        sums[i][1] += gu;
        sums[i][2] += g * uu;
        sums[i][3] += where(in_left, g);
        sums[i][4] += where(in_left, gu);
        sums[i][5] += where(in_centre, g);
        sums[i][6] += where(in_centre, gu);
      }
    }
    const double v = v_float;
    for (int i = 0; i < 3; ++i) {
      const double one = lane_sum(sums[i][0]), u = lane_sum(sums[i][1]);
      Moments& m = moments[i];
      m.one += one;
      m.u += u;
      m.v += v * one;
      m.uu += lane_sum(sums[i][2]);
      m.uv += v * u;
      m.vv += v * v * one;
      const double left_one = lane_sum(sums[i][3]), centre_one = lane_sum(sums[i][5]);
      left.one[i] += left_one;
      left.u[i] += lane_sum(sums[i][4]);
      left.v[i] += v * left_one;
      centre.one[i] += centre_one;
      centre.u[i] += lane_sum(sums[i][6]);
      centre.v[i] += v * centre_one;
      if (v_float < 0) {
        top.one[i] += one;
        top.u[i] += u;
        top.v[i] += v * one;
      }
    }
  }
  const Moments &xx = moments[0], &xy = moments[1], &yy = moments[2];
  // Columns 0-5: gx u, gx v, gy u, gy v, gx, gy.
  Eigen::Matrix<double, 6, 6> hessian;
  hessian << xx.uu, xx.uv, xy.uu, xy.uv, xx.u, xy.u,  //
      0, xx.vv, xy.uv, xy.vv, xx.v, xy.v,             //
      0, 0, yy.uu, yy.uv, xy.u, yy.u,                 //
      0, 0, 0, yy.vv, xy.v, yy.v,                     //
      0, 0, 0, 0, xx.one, xy.one,                     //
      0, 0, 0, 0, 0, yy.one;
  hessian.triangularView<Eigen::StrictlyLower>() = hessian.transpose();
  // Each part's rows of the translation in its own Hessian: the gradients' moments over the
  // part, as the Hessian's rows 4 and 5 are over the whole.
  const auto coupling = [](const PartMoments& m) {
    Eigen::Matrix<double, 2, 6> c;
    c << m.u[0], m.v[0], m.u[1], m.v[1], m.one[0], m.one[1],  //
        m.u[1], m.v[1], m.u[2], m.v[2], m.one[1], m.one[2];
    return c;
  };
  const Eigen::Matrix<double, 2, 6> whole = hessian.bottomRows<2>();
  auto solves = std::make_shared<Solves>();
  solves->part_coupling[0] = coupling(left);
  solves->part_coupling[1] = whole - solves->part_coupling[0];
  solves->part_coupling[2] = coupling(top);
  solves->part_coupling[3] = whole - solves->part_coupling[2];
  solves->part_coupling[4] = coupling(centre);
  for (int h = 0; h < kParts; ++h) {
    const Eigen::Matrix2d part_hessian = solves->part_coupling[h].rightCols<2>();
    const SymmetricEigen eigen(part_hessian);
    const bool placeable = eigen.smallest() > 1e-6 * eigen.largest();
    solves->part_hessian_inverse[h] =
        placeable ? Eigen::Matrix2d(part_hessian.inverse()) : Eigen::Matrix2d::Zero();
  }
  // Too nearly singular to solve when its eigenvalues' ratio may be below 1e-9: the smallest is
  // at least 1 / trace(H^-1), the largest at most trace(H), so the bound is within a factor 36
  // of the ratio itself (an eigen-solver cost more than the rest of extract).
  const Eigen::LLT<Eigen::Matrix<double, 6, 6>> cholesky(hessian);
  if (cholesky.info() != Eigen::Success) return false;
  solves->hessian_inverse = cholesky.solve(Eigen::Matrix<double, 6, 6>::Identity());
  if (!(1 / solves->hessian_inverse.trace() > 1e-9 * hessian.trace())) return false;
  p.solves_ = std::move(solves);
  // The pixels a template blurred later reads.
  p.feature_ = feature;
  const KeptPixels kept(half_size);
  if (cx - kept.reach >= 0 && cy - kept.reach >= 0 && cx + kept.reach < image.cols &&
      cy + kept.reach < image.rows) {
    p.pixels_.assign(static_cast<size_t>(kept.stride) * kept.side, 0.0f);
    for (int y = 0; y < kept.side; ++y) {
      const float* row = image.ptr<float>(cy - kept.reach + y) + cx - kept.reach;
      std::copy(row, row + kept.side, &p.pixels_[static_cast<size_t>(y) * kept.stride]);
    }
  }
  *patch = std::move(p);
  return true;
}

Eigen::Vector2d ReferencePatch::best_located_offset() const {
  // Parameters (a11, a12, a21, a22, bx, by): a point x moves by (a11 x + a12 y + bx,
  // a21 x + a22 y + by). Its variance's trace is quadratic in x; its minimum solves a 2 x 2
  // system of the inverse Hessian's blocks.
  const Eigen::Matrix<double, 6, 6>& S = solves_->hessian_inverse;
  const Eigen::Matrix2d shape = S.block<2, 2>(0, 0) + S.block<2, 2>(2, 2);
  const Eigen::Vector2d coupling(S(0, 4) + S(2, 5), S(1, 4) + S(3, 5));
  Eigen::Vector2d offset = -shape.ldlt().solve(coupling);
  if (!offset.allFinite()) return Eigen::Vector2d::Zero();
  if (offset.norm() > half_size_) offset *= half_size_ / offset.norm();
  return offset;
}

bool ReferencePatch::match_blur(const Eigen::Matrix2d& A, double image_blur_variance,
                                double tolerance) {
  if (pixels_.empty() || !(std::abs(A.determinant()) > 1e-6)) return false;
  // The image's blur and sampling's in template coordinates, less the reference image's own
  // blur: what the template's pixels are to be smoothed by. Where the patch grows that falls
  // below sampling's 1/6 (the magnified image is sharper in the template's coordinates), and the
  // template's smoothing is lessened (to none at about 1.1 times); where it shrinks, a Gaussian
  // adds the rest, its variances held within [0, kMaxAddedBlur] along its axes (which are
  // wanted's: a multiple of the identity moves none).
  const Eigen::Matrix2d A_inverse = A.inverse();
  const double sampled_variance = 2.0 * kSampleSmoothing;
  const SymmetricEigen wanted((image_blur_variance + sampled_variance) * A_inverse *
                                  A_inverse.transpose() -
                              image_blur_variance * Eigen::Matrix2d::Identity());
  const double sampled_share = std::clamp(wanted.smallest() / sampled_variance, 0.0, 1.0);
  const auto as_blur = [](double variance) { return std::clamp(variance, 0.0, kMaxAddedBlur); };
  const double from_sampling = sampled_share * sampled_variance;
  const Eigen::Matrix2d added = wanted.with(as_blur(wanted.largest() - from_sampling),
                                            as_blur(wanted.smallest() - from_sampling));
  // Checked for every track in every frame, in closed form: most checks change nothing.
  if (!(SymmetricEigen(added - added_).largest_magnitude() > tolerance) &&
      !(std::abs(sampled_share - sampled_share_) > kSampledShareStep))
    return false;

  const bool blur = added.trace() > kLeastAddedBlur;
  const float side_weight = static_cast<float>(0.5 * sampled_share * sampled_variance);
  const KeptPixels kept_square(half_size_);
  const cv::Mat kept(kept_square.side, kept_square.side, CV_32FC1, pixels_.data(),
                     kept_square.stride * sizeof(float));
  if (!blur && added_.isZero()) {
    // Less smoothing than sampling's, where the patch grows, on a template that had no more:
    // the values and steepest-descent images anew, the Hessian kept (retaking it would cost five
    // times as much; it changes by at most sampling's smoothing, and it only sizes an
    // alignment's steps, not where it stops).
    if (!retake_values(kept, kept_square.reach, side_weight)) return false;
    sampled_share_ = sampled_share;
    return true;
  }
  // Otherwise the whole template anew, its Hessian too, from the pixels it reads (its values,
  // their gradients' and the smoothing's rings), blurred where a blur is wanted.
  const int reach = half_size_ + 2;
  cv::Mat square = kept;
  Eigen::Vector2i square_centre(kept_square.reach, kept_square.reach);
  std::vector<float> blurred;
  if (blur) {
    int stride = 0;
    blurred_square(pixels_, kept_square.stride, kept_square.reach, reach, added, &blurred, &stride);
    square =
        cv::Mat(2 * reach + 1, 2 * reach + 1, CV_32FC1, blurred.data(), stride * sizeof(float));
    square_centre = Eigen::Vector2i(reach, reach);
  }
  ReferencePatch p;
  if (!extract_smoothed(square, feature_ - (nearest_pixel(feature_) - square_centre).cast<double>(),
                        half_size_, side_weight, &p))
    return false;
  // The new template in place of the old; the kept pixels and the feature stay.
  p.feature_ = feature_;
  p.pixels_ = std::move(pixels_);
  p.added_ = blur ? added : Eigen::Matrix2d::Zero();
  p.sampled_share_ = sampled_share;
  *this = std::move(p);
  return true;
}

Eigen::Matrix2d ReferencePatch::smoothing() const {
  return 2.0 * kSampleSmoothing * sampled_share_ * Eigen::Matrix2d::Identity() + added_;
}

bool ReferencePatch::retake_values(const cv::Mat& pixels, int centre, float side_weight) {
  std::vector<float> smoothed;
  smoothed_square(pixels, centre, centre, half_size_ + 1, side_weight, &smoothed);
  const int side = 2 * half_size_ + 1, smoothed_side = side + 2;
  const Eigen::Index count = static_cast<Eigen::Index>(side) * side;
  Eigen::ArrayXf values(count);
  for (int y = 0, k = 0; y < side; ++y)
    for (int x = 0; x < side; ++x, ++k)
      values(k) = smoothed[static_cast<size_t>(y + 1) * smoothed_side + x + 1];
  const double norm = centre_on_weighted_mean(weights_.data(), values.data(), count);
  if (!(norm >= kMinContrast)) return false;
  values_.head(count) = values;
  norm_ = norm;
  for (int y = 0, k = 0; y < side; ++y) {
    const float* row = &smoothed[static_cast<size_t>(y + 1) * smoothed_side + 1];
    for (int x = 0; x < side; ++x, ++k) {
      weighted_gx_(k) = weights_(k) * 0.5f * (row[x + 1] - row[x - 1]);
      weighted_gy_(k) = weights_(k) * 0.5f * (row[x + smoothed_side] - row[x - smoothed_side]);
    }
  }
  return true;
}

void ReferencePatch::prefetch(const cv::Mat& image, const Eigen::Vector2d& at, int half_size) {
  const int reach = half_size + 2;
  // Compared before the casts: a point Lucas-Kanade lost may be anywhere, or not finite.
  if (!(at.x() >= reach && at.y() >= reach && at.x() + reach < image.cols - 1 &&
        at.y() + reach < image.rows - 1))
    return;
  const int x0 = static_cast<int>(at.x()) - reach, x1 = static_cast<int>(at.x()) + reach;
  const int y0 = static_cast<int>(at.y()) - reach, y1 = static_cast<int>(at.y()) + reach;
  for (int y = y0; y <= y1; ++y) {
    const uchar* row = image.ptr(y);
    __builtin_prefetch(row + x0 * image.elemSize());
    __builtin_prefetch(row + x1 * image.elemSize());
  }
}

double ReferencePatch::contrast_at(const cv::Mat& image, const Eigen::Vector2d& feature,
                                   int half_size) {
  CV_Assert(image.type() == CV_32FC1 && half_size >= 1);
  PatchWindow w;
  if (!patch_window(image, feature, half_size, &w)) return 0;
  std::vector<float> smoothed;
  smoothed_square(image, w.cx, w.cy, half_size, kSampleSmoothing, &smoothed);
  const int side = 2 * half_size + 1;
  double sum_w = 0, sum_wv = 0, sum_wvv = 0;
  for (int y = -half_size; y <= half_size; ++y) {
    const float* row = &smoothed[static_cast<size_t>(y + half_size) * side + half_size];
    for (int x = -half_size; x <= half_size; ++x) {
      const double weight = w.row_weight(y + half_size) * w.column_weight(x + half_size);
      const double v = row[x];
      sum_w += weight;
      sum_wv += weight * v;
      sum_wvv += weight * v * v;
    }
  }
  const double mean = sum_wv / sum_w;
  return std::sqrt(std::max(0.0, sum_wvv / sum_w - mean * mean));
}

double ReferencePatch::sample(const cv::Mat& image, const AffineWarp& warp, float* values,
                              double* mean, double* gain) const {
  const int side = 2 * half_size_ + 1;
  const Eigen::Index count = side * side;
  // The patch's corners bound it (an affine image of a square is a parallelogram), a hundredth
  // of a pixel inside the last pixel's centre: the pixels' places are computed in float, whose
  // rounding must not reach a row or column beyond it (4.9e-4 px at 4,000 px).
  const double x_limit = image.cols - 1.01, y_limit = image.rows - 1.01;
  for (const Eigen::Index corner :
       {Eigen::Index{0}, Eigen::Index(side - 1), count - side, count - 1}) {
    const Eigen::Vector2d at =
        warp.A * Eigen::Vector2d(offsets_x_(corner), offsets_y_(corner)) + warp.b;
    if (!(at.x() >= 0 && at.y() >= 0 && at.x() < x_limit && at.y() < y_limit)) return -1;
  }
  // kLanes pixels at a time: only the reads of each pixel's four neighbours are one at a time.
  // This is the tracker's innermost loop.
  const float a00 = static_cast<float>(warp.A(0, 0)), a01 = static_cast<float>(warp.A(0, 1));
  const float a10 = static_cast<float>(warp.A(1, 0)), a11 = static_cast<float>(warp.A(1, 1));
  const float bx = static_cast<float>(warp.b.x()), by = static_cast<float>(warp.b.y());
  const int step = static_cast<int>(image.step1());
  const float float_step = static_cast<float>(step);
  const float* data = image.ptr<float>();
  const float *offsets_x = offsets_x_.data(), *offsets_y = offsets_y_.data();
  const float *weights = weights_.data(), *template_values = values_.data();
  // The sums of w v, w v^2 and w v t. A pixel's index is computed in float where that is exact
  // (an image of fewer than 2^24 floats): a vector multiply of integers is several instructions
  // on SSE2.
  struct Sums {
    Lanes wv = {}, wvv = {}, wvt = {};
  };
  const auto sums = [&](auto index_in_float) {
    Sums sum;
    for (Eigen::Index k = 0; k < values_.size(); k += kLanes) {
      const Lanes u = load(offsets_x + k), v = load(offsets_y + k);
      const Lanes x = a00 * u + a01 * v + bx, y = a10 * u + a11 * v + by;
      // Inside the image (checked above), so truncation is the floor.
      const LaneIndices x0 = __builtin_convertvector(x, LaneIndices);
      const LaneIndices y0 = __builtin_convertvector(y, LaneIndices);
      const Lanes x_floor = __builtin_convertvector(x0, Lanes);
      const Lanes y_floor = __builtin_convertvector(y0, Lanes);
      const Lanes fx = x - x_floor, fy = y - y_floor;
      LaneIndices index;
      if constexpr (decltype(index_in_float)::value)
        index = __builtin_convertvector(y_floor * float_step + x_floor, LaneIndices);
      else
        index = y0 * step + x0;
      // Each pixel's left and right neighbours are adjacent in memory: one 8-byte read per
      // row, and shuffles deal the pairs out into lanes (inserting floats one by one costs twice
      // as many instructions).
      const float* p0 = data + index[0];
      const float* p1 = data + index[1];
      const float* p2 = data + index[2];
      const float* p3 = data + index[3];
      const Lanes top01 = join(load_pair(p0), load_pair(p1));
      const Lanes top23 = join(load_pair(p2), load_pair(p3));
      const Lanes bottom01 = join(load_pair(p0 + step), load_pair(p1 + step));
      const Lanes bottom23 = join(load_pair(p2 + step), load_pair(p3 + step));
      const Lanes top_left = __builtin_shufflevector(top01, top23, 0, 2, 4, 6);
      const Lanes top_right = __builtin_shufflevector(top01, top23, 1, 3, 5, 7);
      const Lanes bottom_left = __builtin_shufflevector(bottom01, bottom23, 0, 2, 4, 6);
      const Lanes bottom_right = __builtin_shufflevector(bottom01, bottom23, 1, 3, 5, 7);
      const Lanes top = top_left + fx * (top_right - top_left);
      const Lanes bottom = bottom_left + fx * (bottom_right - bottom_left);
      const Lanes sampled = top + fy * (bottom - top);
      std::memcpy(values + k, &sampled, sizeof sampled);
      const Lanes weighted = load(weights + k) * sampled;
      sum.wv += weighted;
      sum.wvv += weighted * sampled;
      sum.wvt += weighted * load(template_values + k);
    }
    return sum;
  };
  const Sums sum = static_cast<double>(image.rows) * step < (1 << 24) ? sums(std::true_type())
                                                                      : sums(std::false_type());
  // Weights sum to 1 and the template has weighted mean 0, so sum w (v - m) t = sum w v t.
  const double m = lane_sum(sum.wv);
  const double variance = std::max(0.0, lane_sum(sum.wvv) - m * m);
  const double norm = std::sqrt(variance);
  *mean = m;
  *gain = norm > 0 ? norm_ / norm : 0;
  return norm > 0 ? lane_sum(sum.wvt) / (norm * norm_) : 0;
}

double ReferencePatch::ncc(const cv::Mat& image, const AffineWarp& warp) const {
  Eigen::ArrayXf values(values_.size());
  double mean, gain;
  return sample(image, warp, values.data(), &mean, &gain);
}

Eigen::Matrix<double, 6, 1> ReferencePatch::residuals_and_gradient(float mean, float gain,
                                                                   Eigen::ArrayXf* values) const {
  Lanes sums[6] = {};
  float* r = values->data();
  const float *wgx = weighted_gx_.data(), *wgy = weighted_gy_.data();
  const float *offsets_x = offsets_x_.data(), *offsets_y = offsets_y_.data();
  const float* template_values = values_.data();
  for (Eigen::Index k = 0; k < values->size(); k += kLanes) {
    const Lanes residual = (load(r + k) - mean) * gain - load(template_values + k);
    store(r + k, residual);
    const Lanes along_x = residual * load(wgx + k), along_y = residual * load(wgy + k);
    const Lanes u = load(offsets_x + k), v = load(offsets_y + k);
    sums[0] += along_x * u;
    sums[1] += along_x * v;
    sums[2] += along_y * u;
    sums[3] += along_y * v;
    sums[4] += along_x;
    sums[5] += along_y;
  }
  Eigen::Matrix<double, 6, 1> g;
  for (int i = 0; i < 6; ++i) g(i) = lane_sum(sums[i]);
  return g;
}

double ReferencePatch::misfit(const Eigen::ArrayXf& residuals, const AffineWarp& warp,
                              const Eigen::Matrix<double, 6, 1>& last_step) const {
  // One Gauss-Newton step of the feature's position per part, from the same residuals: each
  // part's gradient of the translation, summed where the part is (the right half is the whole
  // less the left, the bottom the whole less the top).
  Lanes whole_x = {}, whole_y = {}, left_x = {}, left_y = {}, top_x = {}, top_y = {};
  Lanes centre_x = {}, centre_y = {};
  const float quarter_square = centre_radius_squared(half_size_);
  const float *r = residuals.data(), *wgx = weighted_gx_.data(), *wgy = weighted_gy_.data();
  const float *offsets_x = offsets_x_.data(), *offsets_y = offsets_y_.data();
  for (Eigen::Index k = 0; k < residuals.size(); k += kLanes) {
    const Lanes along_x = load(r + k) * load(wgx + k), along_y = load(r + k) * load(wgy + k);
    const Lanes u = load(offsets_x + k), v = load(offsets_y + k);
    whole_x += along_x;
    whole_y += along_y;
    const LaneIndices left = u < 0, top = v < 0, central = u * u + v * v <= quarter_square;
    left_x += where(left, along_x);
    left_y += where(left, along_y);
    top_x += where(top, along_x);
    top_y += where(top, along_y);
    centre_x += where(central, along_x);
    centre_y += where(central, along_y);
  }
  const Eigen::Vector2d whole(lane_sum(whole_x), lane_sum(whole_y));
  const Eigen::Vector2d left(lane_sum(left_x), lane_sum(left_y));
  const Eigen::Vector2d top(lane_sum(top_x), lane_sum(top_y));
  const Eigen::Vector2d part_gradients[kParts] = {
      left, whole - left, top, whole - top, {lane_sum(centre_x), lane_sum(centre_y)}};
  double worst = 0;
  for (int h = 0; h < kParts; ++h) {
    if (solves_->part_hessian_inverse[h].isZero()) continue;  // too flat to place on its own
    // The part's gradient as the last step leaves it: the step removed the residuals' part
    // along each steepest-descent image.
    const Eigen::Vector2d gradient_after =
        part_gradients[h] - solves_->part_coupling[h] * last_step;
    const Eigen::Vector2d step = warp.A * (solves_->part_hessian_inverse[h] * gradient_after);
    worst = std::max(worst, step.norm());
  }
  return worst;
}

AlignmentResult ReferencePatch::align(const cv::Mat& image, AffineWarp* warp, int max_iterations,
                                      double step_tolerance_px) const {
  CV_Assert(image.type() == CV_32FC1 && !empty());
  AlignmentResult result;
  Eigen::ArrayXf values(values_.size());
  for (result.iterations = 1; result.iterations <= max_iterations; ++result.iterations) {
    double mean, gain;
    result.ncc = sample(image, *warp, values.data(), &mean, &gain);
    if (result.ncc == -1) return result;
    const Eigen::Matrix<double, 6, 1> dp =
        solves_->hessian_inverse *
        residuals_and_gradient(static_cast<float>(mean), static_cast<float>(gain), &values);

    // Inverse composition: W <- W o W(dp)^-1.
    Eigen::Matrix2d A_dp;
    A_dp << 1 + dp(0), dp(1), dp(2), 1 + dp(3);
    if (!(std::abs(A_dp.determinant()) > 1e-6)) return result;
    const Eigen::Matrix2d A = warp->A * A_dp.inverse();
    const Eigen::Vector2d step = A * dp.tail<2>();
    warp->A = A;
    warp->b -= step;
    const double det = A.determinant();
    if (!(det > 0.25 && det < 4)) return result;
    // The correlation measured before this last, tiny step stands for the one after it: at
    // the optimum it changes only with the square of the step, and sampling again would cost a
    // fifth of the alignment.
    if (step.norm() < step_tolerance_px) {
      result.converged = true;
      result.misfit_px = misfit(values, *warp, dp);
      result.residual_rms = std::sqrt((weights_ * values.square()).sum());
      return result;
    }
  }
  result.iterations = max_iterations;
  return result;
}

}  // namespace omnisfm::track
