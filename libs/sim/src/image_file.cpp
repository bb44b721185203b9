#include "omnisfm/sim/image_file.h"

#include <opencv2/imgcodecs.hpp>
#include <stdexcept>
#include <vector>

#include "omnisfm/io/atomic_write.h"

namespace omnisfm::sim {

void write_png(const std::string& path, const cv::Mat& image, int compression) {
  const std::vector<int> parameters = {cv::IMWRITE_PNG_COMPRESSION, compression};
  io::write_atomically(path, [&](const std::string& temporary_path) {
    bool written = false;
    try {
      written = cv::imwrite(temporary_path, image, parameters);
    } catch (const cv::Exception& e) {
      throw std::runtime_error(path + ": cannot write the image: " + e.what());
    }
    if (!written) throw std::runtime_error(path + ": cannot write the image");
  });
}

}  // namespace omnisfm::sim
