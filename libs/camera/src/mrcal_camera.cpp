#include "omnisfm/camera/mrcal_camera.h"

#include "omnisfm/camera/mrcal_lensmodel.h"

#include <cmath>
#include <fstream>
#include <iterator>
#include <stdexcept>
#include <vector>

namespace omnisfm::camera {

struct MrcalCamera::Lensmodel {
  mrcal_lensmodel_t model;
};

mrcal_lensmodel_t mrcal_lensmodel_named(const std::string& name) {
  mrcal_lensmodel_t model;
  if (!mrcal_lensmodel_from_name(&model, name.c_str()) ||
      !mrcal_lensmodel_type_is_valid(model.type))
    throw std::invalid_argument("mrcal: unknown lens model '" + name + "'");
  return model;
}

namespace {

// The file's text, checked first for what libmrcal 2.2's parser does not survive (found by
// fuzzing): a string that does not end makes it read past the end of its buffer. A .cameramodel
// is ASCII text without control characters (other bytes only in comments) whose strings end on
// their line.
std::string checked_cameramodel_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw std::runtime_error(path + ": cannot be read");
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (text.size() > (1u << 26)) throw std::runtime_error(path + ": too large for a .cameramodel");
  int line = 1;
  char quote = 0;
  bool comment = false;
  const auto fail = [&](const std::string& what) {
    throw std::runtime_error(path + ":" + std::to_string(line) + ": " + what);
  };
  for (const char c : text) {
    const auto byte = static_cast<unsigned char>(c);
    if (c == '\n') {
      if (quote) fail("a string that does not end on its line");
      comment = false;
      ++line;
      continue;
    }
    if (byte < 0x20 && c != '\t' && c != '\r') fail("a control character");
    if (comment) continue;
    if (byte >= 0x7f) fail("a byte that is not ASCII text");
    if (quote) {
      if (c == '\'' || c == '"') quote = 0;  // its lexer ends a string at either quote
    } else if (c == '#') {
      comment = true;
    } else if (c == '\'' || c == '"') {
      quote = c;
    }
  }
  if (quote) fail("a string that does not end");
  // Its lexer takes a comment to the next newline, past the end of the text when there is none.
  if (!text.empty() && text.back() != '\n') text += '\n';
  return text;
}

}  // namespace

MrcalCamera MrcalCamera::from_file(const std::string& path) {
  const std::string text = checked_cameramodel_text(path);
  // Given as a 0-terminated string (len 0): given a length, libmrcal 2.2 lexes past the end.
  mrcal_cameramodel_t* model =
      text.empty() ? nullptr : mrcal_read_cameramodel_string(text.c_str(), 0);
  if (!model) throw std::runtime_error(path + ": not a readable mrcal .cameramodel");
  char name[1024];
  if (!mrcal_lensmodel_name(name, sizeof name, &model->lensmodel)) {
    mrcal_free_cameramodel(&model);
    throw std::runtime_error(path + ": unsupported lens model");
  }
  const int n = mrcal_lensmodel_num_params(&model->lensmodel);
  const Eigen::VectorXd intrinsics = Eigen::Map<const Eigen::VectorXd>(model->intrinsics, n);
  const int width = static_cast<int>(model->imagersize[0]);
  const int height = static_cast<int>(model->imagersize[1]);
  mrcal_free_cameramodel(&model);
  try {
    return MrcalCamera(name, intrinsics, width, height);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(path + ": " + e.what());
  }
}

MrcalCamera::MrcalCamera(const std::string& lensmodel, const Eigen::VectorXd& intrinsics,
                         int image_width, int image_height)
    : lensmodel_(std::make_unique<Lensmodel>(Lensmodel{mrcal_lensmodel_named(lensmodel)})),
      lensmodel_name_(lensmodel),
      width_(image_width),
      height_(image_height) {
  if (!mrcal_lensmodel_metadata(&lensmodel_->model).has_gradients)
    throw std::invalid_argument("mrcal: lens model " + lensmodel + " has no gradients");
  if (!set_params(intrinsics))
    throw std::invalid_argument("mrcal: " + lensmodel + " needs " +
                                std::to_string(num_params()) + " finite intrinsics");
}

MrcalCamera::~MrcalCamera() = default;

MrcalCamera::MrcalCamera(const MrcalCamera& other)
    : lensmodel_(std::make_unique<Lensmodel>(*other.lensmodel_)),
      lensmodel_name_(other.lensmodel_name_),
      intrinsics_(other.intrinsics_),
      width_(other.width_),
      height_(other.height_) {}

MrcalCamera& MrcalCamera::operator=(const MrcalCamera& other) {
  if (this != &other) {
    *lensmodel_ = *other.lensmodel_;
    lensmodel_name_ = other.lensmodel_name_;
    intrinsics_ = other.intrinsics_;
    width_ = other.width_;
    height_ = other.height_;
  }
  return *this;
}

std::unique_ptr<InnerCamera> MrcalCamera::clone() const {
  return std::make_unique<MrcalCamera>(*this);
}

int MrcalCamera::num_params() const { return mrcal_lensmodel_num_params(&lensmodel_->model); }

std::vector<std::string> MrcalCamera::param_names() const {
  std::vector<std::string> names;
  const bool has_core = mrcal_lensmodel_metadata(&lensmodel_->model).has_core;
  const char* core[] = {"fx", "fy", "cx", "cy"};
  for (int i = 0; i < num_params(); ++i)
    names.push_back(has_core && i < 4 ? std::string(core[i])
                                      : "distortion" + std::to_string(has_core ? i - 4 : i));
  return names;
}

bool MrcalCamera::set_params(const Eigen::VectorXd& params) {
  if (params.size() != num_params() || !params.allFinite()) return false;
  intrinsics_ = params;
  return true;
}

bool MrcalCamera::project(const Eigen::Vector3d& p, Eigen::Vector2d* pixel,
                          Eigen::Matrix<double, 2, 3>* J_p, ParamsJacobian* J_params) const {
  if (!(p.z() > 0)) return false;
  const mrcal_point3_t point = {{p.x(), p.y(), p.z()}};
  mrcal_point2_t q;
  mrcal_point3_t dq_dp[2];
  const int n = num_params();
  // mrcal writes d q / d intrinsics row-major (2 x n); ours is column-major.
  thread_local std::vector<double> dq_dintrinsics;
  if (J_params) dq_dintrinsics.resize(2 * n);
  if (!mrcal_project(&q, J_p ? dq_dp : nullptr, J_params ? dq_dintrinsics.data() : nullptr,
                     &point, 1, &lensmodel_->model, intrinsics_.data()))
    return false;
  *pixel << q.x, q.y;
  if (!pixel->allFinite()) return false;
  if (J_p)
    *J_p << dq_dp[0].x, dq_dp[0].y, dq_dp[0].z, dq_dp[1].x, dq_dp[1].y, dq_dp[1].z;
  if (J_params)
    *J_params = Eigen::Map<const Eigen::Matrix<double, 2, Eigen::Dynamic, Eigen::RowMajor>>(
        dq_dintrinsics.data(), 2, n);
  return true;
}

bool MrcalCamera::unproject(const Eigen::Vector2d& pixel, Eigen::Vector3d* origin,
                            Eigen::Vector3d* direction) const {
  const mrcal_point2_t q = {{pixel.x(), pixel.y()}};
  mrcal_point3_t v;
  if (!mrcal_unproject(&v, &q, 1, &lensmodel_->model, intrinsics_.data())) return false;
  const Eigen::Vector3d d(v.x, v.y, v.z);
  if (!d.allFinite() || !(d.z() > 0)) return false;
  origin->setZero();
  *direction = d.normalized();
  return true;
}

void MrcalCamera::write(const std::string& path) const {
  const int n = num_params();
  std::vector<unsigned char> storage(sizeof(mrcal_cameramodel_t) + n * sizeof(double));
  auto* model = reinterpret_cast<mrcal_cameramodel_t*>(storage.data());
  for (double& v : model->rt_cam_ref) v = 0;
  model->imagersize[0] = static_cast<unsigned>(width_);
  model->imagersize[1] = static_cast<unsigned>(height_);
  model->lensmodel = lensmodel_->model;
  for (int i = 0; i < n; ++i) model->intrinsics[i] = intrinsics_[i];
  if (!mrcal_write_cameramodel_file(path.c_str(), model))
    throw std::runtime_error(path + ": cannot write the .cameramodel");
}

}  // namespace omnisfm::camera
