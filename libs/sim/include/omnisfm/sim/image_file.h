#pragma once
// Writing rendered images as PNG files: 8-bit grey, lossless.

#include <opencv2/core.hpp>
#include <string>

namespace omnisfm::sim {

// zlib levels: 1 is fastest (a dataset's many frames), 9 smallest (images kept in the repository).
inline constexpr int kFastPngCompression = 1;
inline constexpr int kSmallPngCompression = 9;

// Writes `image` to `path` (which should end in .png), replacing it whole or not at all. Throws
// std::runtime_error naming the path when the image cannot be encoded or the file written.
void write_png(const std::string& path, const cv::Mat& image,
               int compression = kFastPngCompression);

}  // namespace omnisfm::sim
