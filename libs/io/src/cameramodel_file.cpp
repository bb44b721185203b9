#include "omnisfm/io/cameramodel_file.h"

#include <Eigen/Geometry>
#include <ostream>
#include <stdexcept>

#include "omnisfm/camera/mrcal_lensmodel.h"
#include "omnisfm/io/atomic_write.h"
#include "omnisfm/io/number_text.h"

namespace omnisfm::io {
namespace {

void write_numbers(std::ostream& out, const double* values, int count) {
  out << "[";
  for (int i = 0; i < count; ++i) {
    out << (i % 6 == 0 ? "\n        " : " ") << format_double(values[i]) << ",";
  }
  out << " ]";
}

}  // namespace

void write_cameramodel(const std::string& path, const MrcalCameraModel& model,
                       const std::vector<std::string>& notes) {
  const mrcal_lensmodel_t lensmodel = camera::mrcal_lensmodel_named(model.lensmodel);
  const int num_intrinsics = mrcal_lensmodel_num_params(&lensmodel);
  if (model.intrinsics.size() != num_intrinsics || !model.intrinsics.allFinite())
    throw std::runtime_error(path + ": " + model.lensmodel + " needs " +
                             std::to_string(num_intrinsics) + " finite intrinsics");
  const Eigen::AngleAxisd rotation(model.R_model_from_C);
  Eigen::Matrix<double, 6, 1> rt;
  rt << rotation.angle() * rotation.axis(), model.t_model_from_C;
  write_text_atomically(path, [&](std::ostream& out) {
    for (const std::string& note : notes) out << "# " << note << "\n";
    out << "{\n    'lensmodel':  '" << model.lensmodel << "',\n\n";
    out << "    # intrinsics are fx,fy,cx,cy,distortion0,distortion1,....\n";
    out << "    'intrinsics': ";
    write_numbers(out, model.intrinsics.data(), num_intrinsics);
    out << ",\n\n    'valid_intrinsics_region': [";
    for (const Eigen::Vector2d& corner : model.valid_region)
      out << "\n        [ " << format_double(corner.x()) << ", " << format_double(corner.y())
          << " ],";
    out << " ],\n\n    # extrinsics are rt_fromref\n    'extrinsics': ";
    write_numbers(out, rt.data(), 6);
    out << ",\n\n    'imagersize': [ " << model.image_width << ", " << model.image_height
        << ", ],\n}\n";
  });
}

}  // namespace omnisfm::io
