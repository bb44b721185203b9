#pragma once
// Checkerboards searched in a folder of images or a video (calib/board_detection.h), as the
// detect-corners and calibrate verbs take them.

#include <functional>
#include <optional>
#include <opencv2/core.hpp>
#include <string>
#include <vector>

#include "omnisfm/calib/board_detection.h"
#include "omnisfm/io/checkerboard_files.h"

namespace omnisfm::app {

// The mirror's circles on the mean of the images in `images`. Throws io::InputError naming it when
// they are not found, or when the images are unreadable or of mixed sizes.
calib::MirrorImage mirror_of(const std::string& images);

// Each image searched in order: its corners (one missing corner where no whole board was found),
// `each` told of every image as it is searched. Image names are the files' names, or for a
// video's frames the video's stem and the frame's index; a name with whitespace or '#' is refused
// (io::InputError naming the image), as corners.vnl cannot hold it.
struct BoardImage {
  std::string name;
  cv::Mat grey;
  std::optional<calib::DetectedBoard> board;
  cv::Size board_seen;  // the largest board of any size its views showed (board_seen.h)
};
// With `camera_size`, an image of another size is refused (io::InputError naming it), as the
// tracker refuses it: the camera file is for another camera, and no board would be found.
std::vector<io::ImageCorners> detect_boards(const std::string& images,
                                            calib::BoardDetector* detector,
                                            const std::function<void(const BoardImage&)>& each,
                                            std::optional<cv::Size> camera_size = std::nullopt);

// For an error where the grid was found in too few images: what the others show, from their
// BoardImage::board_seen. The size most of them show (3 x 3 fragments only where nothing larger
// is seen), as options where it cannot hold the grid ("the images show a board of 6x7 points
// (--object-width-n 6 --object-height-n 7)"), or that they show none; "" where there are no
// others.
std::string boards_seen_note(const std::vector<cv::Size>& seen, cv::Size grid);

// The size of the images in `images` (its first), throwing io::InputError naming it when none
// can be read.
cv::Size image_size_of(const std::string& images);

}  // namespace omnisfm::app
