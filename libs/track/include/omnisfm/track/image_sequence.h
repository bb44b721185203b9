#pragma once
// The images a tracker reads: a folder of PNG or JPG files taken in file-name order, or a video
// file that OpenCV opens. Frames come out as 8-bit grey, all of one size.

#include <limits>
#include <memory>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

namespace cv {
class VideoCapture;
}

namespace omnisfm::track {

struct SequenceFrame {
  int index = 0;
  cv::Mat image;     // CV_8UC1
  std::string file;  // the image file, or empty for a video's frame
  // A video's presentation time in seconds; NaN when there is none.
  double timestamp = std::numeric_limits<double>::quiet_NaN();
};

class ImageSequence {
 public:
  // Throws io::InputError naming `path` when it does not exist, is a folder without PNG or JPG
  // files, or is a file no video reader opens; naming the image when an image's name in the
  // folder is a link that cannot be followed (a loop, or to nothing).
  explicit ImageSequence(const std::string& path);
  ~ImageSequence();
  ImageSequence(ImageSequence&&) noexcept;
  ImageSequence& operator=(ImageSequence&&) noexcept;

  // The next frame; false after the last. Throws io::InputError naming the image (or the video and
  // frame) when it cannot be decoded or its size differs from the first frame's, and for a video
  // with no frame at all.
  bool next(SequenceFrame* frame);
  // Passes over the next `count` frames without decoding them (a video's are grabbed); returns
  // how many there were.
  int skip(int count);

  // Once next() has returned false: for a video that gave fewer frames than its container says
  // (damaged or cut short, which the decoder passes over), what was lost; else "".
  std::string shortfall() const;

  bool is_video() const { return video_ != nullptr; }
  // Frames in all: exact for a folder; for a video what its container says (0 when unknown).
  int expected_frames() const;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
  std::vector<std::string> files_;
  std::unique_ptr<cv::VideoCapture> video_;
  int next_index_ = 0;
  cv::Size size_;
};

}  // namespace omnisfm::track
