#include "decodable_jpeg.h"

// clang-format off
#include <cstdio>  // before jpeglib.h, which uses FILE
#include <jpeglib.h>
// clang-format on

#include <csetjmp>

namespace omnisfm::mrpt_plugin {
namespace {

// The most pixels a stored JPEG may claim: a 16,384 x 16,384 picture, 768 MB in colour.
constexpr double kMostPixels = 16384.0 * 16384.0;

enum class Decoding { kDecodable, kUndecodable, kTooLarge };

// libjpeg's error manager, leaving by longjmp instead of exit(); its warnings unprinted.
struct ReturningErrors {
  jpeg_error_mgr manager;
  std::jmp_buf back;
};

void leave(j_common_ptr info) {
  std::longjmp(reinterpret_cast<ReturningErrors*>(info->err)->back, 1);
}

void say_nothing(j_common_ptr) {}

// MRPT's calls, in its order: the header, the start, every scanline, the finish. No object with
// a destructor lives here, since an error leaves by longjmp.
Decoding decode_as_mrpt_does(const std::uint8_t* data, std::size_t size) {
  jpeg_decompress_struct info{};
  ReturningErrors errors{};
  info.err = jpeg_std_error(&errors.manager);
  errors.manager.error_exit = leave;
  errors.manager.output_message = say_nothing;
  if (setjmp(errors.back)) {
    jpeg_destroy_decompress(&info);
    return Decoding::kUndecodable;
  }
  jpeg_create_decompress(&info);
  jpeg_mem_src(&info, data, static_cast<unsigned long>(size));
  jpeg_read_header(&info, TRUE);
  if (static_cast<double>(info.image_width) * info.image_height > kMostPixels) {
    jpeg_destroy_decompress(&info);
    return Decoding::kTooLarge;
  }
  info.scale_num = 1;
  info.scale_denom = 8;
  jpeg_start_decompress(&info);
  JSAMPARRAY row = (*info.mem->alloc_sarray)(reinterpret_cast<j_common_ptr>(&info), JPOOL_IMAGE,
                                              info.output_width * info.output_components, 1);
  while (info.output_scanline < info.output_height) jpeg_read_scanlines(&info, row, 1);
  jpeg_finish_decompress(&info);
  jpeg_destroy_decompress(&info);
  return Decoding::kDecodable;
}

}  // namespace

std::string jpeg_problem(const std::uint8_t* data, std::size_t size) {
  switch (decode_as_mrpt_does(data, size)) {
    case Decoding::kDecodable:
      return "";
    case Decoding::kTooLarge:
      return "its JPEG image claims over " + std::to_string(static_cast<long>(kMostPixels)) +
             " pixels";
    case Decoding::kUndecodable:
      break;
  }
  return "its JPEG image cannot be decoded";
}

}  // namespace omnisfm::mrpt_plugin
