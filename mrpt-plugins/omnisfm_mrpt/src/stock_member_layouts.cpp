// The stored layouts of what the stock records store inside them: poses, pose PDFs, matrices,
// camera parameters and images, as MRPT 2.5's serializeFrom reads them. MRPT allocates a matrix
// and an image from the dimensions stored before their bytes: the copy takes those bytes as a
// length, so that dimensions the file does not back end the copy before MRPT sees them.
#include <mrpt/img/CImage.h>
#include <mrpt/img/TCamera.h>
#include <mrpt/math/CMatrixD.h>
#include <mrpt/math/CMatrixF.h>
#include <mrpt/poses/CPose2D.h>
#include <mrpt/poses/CPose3D.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>
#include <mrpt/poses/CPosePDFGaussian.h>

#include <limits>

#include "class_layouts.h"
#include "decodable_jpeg.h"

namespace omnisfm::mrpt_plugin {
namespace {

constexpr std::size_t kFloat = 4, kDouble = 8;

void pose_2d(BoundedObjectCopy& in, int version) {
  if (version > 1) in.layout_unknown();
  in.skip(3 * (version == 0 ? kFloat : kDouble));
}

void pose_3d(BoundedObjectCopy& in, int version) {
  if (version > 3) in.layout_unknown();
  if (version == 0) {
    in.object<mrpt::math::CMatrixF>();  // the homogeneous matrix
  } else if (version == 1) {
    in.object<mrpt::math::CMatrixD>();
  } else {
    in.skip((version == 2 ? 7 : 12) * kDouble);  // a quaternion pose; a translation and rotation
  }
}

void pose_pdf_gaussian(BoundedObjectCopy& in, int version) {
  if (version > 2) in.layout_unknown();
  in.object<mrpt::poses::CPose2D>();  // the mean
  if (version == 0) {
    in.object<mrpt::math::CMatrixF>();  // the covariance matrix
  } else {
    in.skip(6 * (version == 1 ? kFloat : kDouble));  // its upper triangle
  }
}

void pose_3d_pdf_gaussian(BoundedObjectCopy& in, int version) {
  if (version != 1) in.layout_unknown();
  in.object<mrpt::poses::CPose3D>();  // the mean
  in.skip(21 * kDouble);    // the covariance's upper triangle
}

template <std::size_t kElement>
void matrix(BoundedObjectCopy& in, int version) {
  if (version != 0) in.layout_unknown();
  const auto rows = in.value<std::uint32_t>();
  const auto cols = in.value<std::uint32_t>();
  in.counted(std::uint64_t{rows} * cols, kElement);
}

void camera_parameters(BoundedObjectCopy& in, int version) {
  if (version > 6) in.layout_unknown();
  in.skip(kDouble + 5 * kDouble);  // the focal length and distortion
  if (version >= 3) in.skip(3 * kDouble);
  if (version < 4) {
    in.object<mrpt::math::CMatrixD>();  // the intrinsic matrix
  } else {
    in.skip(4 * kDouble);
  }
  if (version == 0) in.object<mrpt::math::CMatrixD>();  // the distortion as it was
  if (version >= 2) in.skip(2 * 4);  // rows and columns
  if (version >= 5) in.string();    // the camera's name
  if (version >= 6) in.skip(1);     // the distortion model
}

// The bytes of a pixel of the stored depth as OpenCV allocates it: CV_MAKETYPE keeps the depth's
// three low bits (0-6 MRPT's PixelDepth, 7 half floats), whatever damage made of the rest.
std::size_t bytes_per_pixel(std::int32_t depth) {
  constexpr std::size_t kBytes[8] = {1, 1, 2, 2, 4, 4, 8, 2};
  return kBytes[static_cast<std::uint32_t>(depth) & 7u];
}

// A grey image (versions 2 to 9): MRPT allocates its pixels from its width and height, then
// reads the stored size's bytes into them.
void grey_pixels(BoundedObjectCopy& in, int version) {
  const auto width = in.value<std::int32_t>();
  const auto height = in.value<std::int32_t>();
  in.skip(4);  // its origin
  const auto size = in.value<std::uint32_t>();
  const std::int32_t depth = version >= 9 ? in.value<std::int32_t>() : 0;
  const std::size_t pixel = bytes_per_pixel(depth);
  if (width < 0 || height < 0 ||
      std::uint64_t{static_cast<std::uint32_t>(width)} * static_cast<std::uint32_t>(height) *
              pixel > size)
    in.out_of_range("a length stored in it is far beyond what the file holds");
  bool zipped = version == 3 || (version == 4 && size > 16 * 1024);
  if (version >= 5) zipped = in.flag();
  // MRPT 2.5 allocates the pixels, then refuses to read a compressed image.
  if (zipped) throw ObjectDamage("its image is stored zip-compressed, which MRPT 2.5 cannot read");
  if (size != 0) in.counted(size, 1);
}

// JPEG bytes, which MRPT decodes with an error handler that ends the process.
void jpeg(BoundedObjectCopy& in) {
  const std::uint32_t size = in.array(1);
  const std::string problem = jpeg_problem(in.last(size), size);
  if (!problem.empty()) in.out_of_range(problem);
}

// A colour image: JPEG bytes, or since version 8 raw RGB rows (its width and height negated).
void colour_pixels(BoundedObjectCopy& in, int version) {
  if (version >= 7) {
    const auto width = in.value<std::int32_t>();
    const auto height = in.value<std::int32_t>();
    const std::int32_t lowest = std::numeric_limits<std::int32_t>::min();
    if (width < 0 && height < 0 && width != lowest && height != lowest) {
      in.counted(std::uint64_t{static_cast<std::uint32_t>(-width)} *
                     static_cast<std::uint32_t>(-height),
                 3);
      return;
    }
    if (width < 1 || height < 1) {
      // An empty image, which MRPT sizes as stored.
      if (width < 0 || height < 0)
        in.out_of_range("its image's size is " + std::to_string(width) + "x" +
                        std::to_string(height));
      return;
    }
  }
  jpeg(in);
}

void image(BoundedObjectCopy& in, int version) {
  if (version == 100) {  // stored by an MRPT without OpenCV: the external file's name only
    if (in.flag()) in.string();
    return;
  }
  if (version > 9) in.layout_unknown();
  if (version == 0) {
    const auto width = in.value<std::uint32_t>();
    const auto height = in.value<std::uint32_t>();
    const auto channels = in.value<std::uint32_t>();
    in.skip(1);  // its origin
    const auto size = in.value<std::uint32_t>();
    if (channels != 1 && channels != 3)
      in.out_of_range("its image has " + std::to_string(channels) + " channels");
    // MRPT reads the stored size's bytes into the pixels it allocated from the dimensions.
    if (std::uint64_t{width} * height * channels != size)
      in.out_of_range("a length stored in it is far beyond what the file holds");
    in.counted(size, 1);
    return;
  }
  if (version == 1) {
    jpeg(in);
    return;
  }
  if (version >= 6 && in.flag()) {
    in.string();  // the external file's name
    return;
  }
  if (in.value<std::uint8_t>() == 0) {
    grey_pixels(in, version);
  } else {
    colour_pixels(in, version);
  }
}

}  // namespace

std::vector<ClassLayoutEntry> stock_member_layouts() {
  using namespace mrpt::poses;
  return {{CLASS_ID(CPose2D), pose_2d},
          {CLASS_ID(CPose3D), pose_3d},
          {CLASS_ID(CPosePDFGaussian), pose_pdf_gaussian},
          {CLASS_ID(CPose3DPDFGaussian), pose_3d_pdf_gaussian},
          {CLASS_ID(mrpt::math::CMatrixF), matrix<kFloat>},
          {CLASS_ID(mrpt::math::CMatrixD), matrix<kDouble>},
          {CLASS_ID(mrpt::img::TCamera), camera_parameters},
          {CLASS_ID(mrpt::img::CImage), image}};
}

}  // namespace omnisfm::mrpt_plugin
