#include "omnisfm/track/image_sequence.h"

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <opencv2/videoio/registry.hpp>

#include "omnisfm/io/input_error.h"

namespace omnisfm::track {
namespace {

namespace fs = std::filesystem;

bool is_image_file(const fs::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return extension == ".png" || extension == ".jpg" || extension == ".jpeg";
}

// An image's name on something that is not a file (a folder named x.png) is not an image; one
// whose target cannot be reached (a symbolic link loop, a dangling link) is a bad image.
bool is_image_to_read(const fs::directory_entry& entry) {
  std::error_code error;
  const fs::file_status status = entry.status(error);
  if (error) throw io::InputError(entry.path().string(), 0, "cannot read it: " + error.message());
  return fs::is_regular_file(status);
}

std::string size_text(const cv::Size& size) {
  return std::to_string(size.width) + "x" + std::to_string(size.height);
}

cv::Mat to_grey(const cv::Mat& image) {
  cv::Mat grey = image;
  if (image.channels() == 3)
    cv::cvtColor(image, grey, cv::COLOR_BGR2GRAY);
  else if (image.channels() == 4)
    cv::cvtColor(image, grey, cv::COLOR_BGRA2GRAY);
  if (grey.depth() != CV_8U) grey.convertTo(grey, CV_8U, grey.depth() == CV_16U ? 1.0 / 257 : 1.0);
  return grey;
}

}  // namespace

ImageSequence::ImageSequence(const std::string& path) : path_(path) {
  std::error_code error;
  const fs::file_status status = fs::status(path, error);
  if (error || !fs::exists(status)) throw io::InputError(path, 0, "no such file or folder");
  if (fs::is_directory(status)) {
    for (const auto& entry : fs::directory_iterator(path, error))
      if (is_image_file(entry.path()) && is_image_to_read(entry))
        files_.push_back(entry.path().string());
    if (error) throw io::InputError(path, 0, "cannot list the folder: " + error.message());
    if (files_.empty()) throw io::InputError(path, 0, "the folder holds no PNG or JPG images");
    std::sort(files_.begin(), files_.end());
    return;
  }
  // The backends that read files, in OpenCV's order, but not gphoto2's: it takes a file name for
  // a camera's and probes every USB device for it (slowly, and keeping what it allocates).
  video_ = std::make_unique<cv::VideoCapture>();
  for (const cv::VideoCaptureAPIs api : cv::videoio_registry::getStreamBackends()) {
    if (api == cv::CAP_GPHOTO2) continue;
    try {
      if (video_->open(path, api)) break;
    } catch (const cv::Exception&) {
    }
  }
  if (!video_->isOpened())
    throw io::InputError(path, 0, "not a folder of images, and no video reader opens it");
}

ImageSequence::~ImageSequence() = default;
ImageSequence::ImageSequence(ImageSequence&&) noexcept = default;
ImageSequence& ImageSequence::operator=(ImageSequence&&) noexcept = default;

int ImageSequence::expected_frames() const {
  if (!video_) return static_cast<int>(files_.size());
  const double count = video_->get(cv::CAP_PROP_FRAME_COUNT);
  return count > 0 ? static_cast<int>(count) : 0;
}

std::string ImageSequence::shortfall() const {
  const int expected = expected_frames();
  // Containers without a frame count (MKV, variable rates) have it estimated from the duration:
  // a frame or 1 % short of it is no damage.
  if (!video_ || next_index_ >= expected - std::max(2, expected / 100)) return "";
  return "the video gave " + std::to_string(next_index_) + " frames where its container says " +
         std::to_string(expected) +
         ": damaged or cut short (its decoder passes over what it cannot read, so the frames "
         "after a damaged stretch may also carry wrong times)";
}

int ImageSequence::skip(int count) {
  int skipped = 0;
  for (; skipped < count; ++skipped, ++next_index_) {
    if (video_ ? !video_->grab() : next_index_ >= static_cast<int>(files_.size())) break;
  }
  return skipped;
}

bool ImageSequence::next(SequenceFrame* frame) {
  cv::Mat image;
  if (video_) {
    bool grabbed = false;
    try {
      grabbed = video_->read(image);
    } catch (const cv::Exception& e) {
      throw io::InputError(path_, 0, "frame " + std::to_string(next_index_) + ": " + e.what());
    }
    if (!grabbed || image.empty()) {
      if (next_index_ == 0) throw io::InputError(path_, 0, "the video has no frame that decodes");
      return false;
    }
    frame->file.clear();
    const double msec = video_->get(cv::CAP_PROP_POS_MSEC);
    frame->timestamp = msec >= 0 ? msec / 1000 : std::numeric_limits<double>::quiet_NaN();
  } else {
    if (next_index_ >= static_cast<int>(files_.size())) return false;
    frame->file = files_[next_index_];
    frame->timestamp = std::numeric_limits<double>::quiet_NaN();
    try {
      image = cv::imread(frame->file, cv::IMREAD_UNCHANGED);
    } catch (const cv::Exception&) {
      image.release();
    }
    if (image.empty()) throw io::InputError(frame->file, 0, "cannot read this image");
  }
  image = to_grey(image);
  if (size_.empty())  // the first frame decoded
    size_ = image.size();
  else if (image.size() != size_)
    throw io::InputError(video_ ? path_ : frame->file, 0,
                         (video_ ? "frame " + std::to_string(next_index_) + " is " : "is ") +
                             size_text(image.size()) + " but the first image is " +
                             size_text(size_));
  frame->image = image;
  frame->index = next_index_++;
  return true;
}

}  // namespace omnisfm::track
