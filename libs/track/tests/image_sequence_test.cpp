#include "omnisfm/track/image_sequence.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>
#include <opencv2/videoio.hpp>
#include <string>
#include <utility>

#include "omnisfm/io/input_error.h"
#include "omnisfm/track/frames_file.h"

namespace omnisfm::track {
namespace {

namespace fs = std::filesystem;

class ImageSequenceTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("omnisfm-images-" + std::to_string(::getpid()) + "-" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // A grey ramp whose first pixel is `value`.
  static cv::Mat image(int width, int height, int value) {
    cv::Mat m(height, width, CV_8UC1);
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) m.at<uchar>(y, x) = static_cast<uchar>((value + x + y) % 256);
    return m;
  }

  std::string write_image(const std::string& name, const cv::Mat& m) const {
    const std::string path = (dir_ / name).string();
    cv::imwrite(path, m);
    return path;
  }

  // The message of the io::InputError that reading all of `path` throws, or "" when none.
  static std::string read_error(const std::string& path) {
    try {
      ImageSequence sequence(path);
      SequenceFrame frame;
      while (sequence.next(&frame)) {
      }
    } catch (const io::InputError& e) {
      return e.what();
    }
    return "";
  }

  fs::path dir_;
};

TEST_F(ImageSequenceTest, ReadsAFolderInNameOrderAsGrey) {
  write_image("b.png", image(40, 30, 2));
  write_image("a.png", image(40, 30, 1));
  cv::Mat colour;
  cv::cvtColor(image(40, 30, 3), colour, cv::COLOR_GRAY2BGR);
  write_image("c.jpg", colour);
  std::ofstream(dir_ / "notes.txt") << "not an image\n";

  ImageSequence sequence(dir_.string());
  EXPECT_FALSE(sequence.is_video());
  EXPECT_EQ(sequence.expected_frames(), 3);
  SequenceFrame frame;
  std::vector<std::string> names;
  while (sequence.next(&frame)) {
    EXPECT_EQ(frame.image.type(), CV_8UC1);
    EXPECT_EQ(frame.image.size(), cv::Size(40, 30));
    EXPECT_EQ(frame.index, static_cast<int>(names.size()));
    EXPECT_TRUE(std::isnan(frame.timestamp));
    names.push_back(fs::path(frame.file).filename().string());
    if (names.size() < 3) {
      EXPECT_EQ(frame.image.at<uchar>(0, 0), names.size());
    }
  }
  EXPECT_EQ(names, (std::vector<std::string>{"a.png", "b.png", "c.jpg"}));
}

// Skipped frames are not decoded: a damaged one passed over costs nothing, and the frame after
// them comes with its own index.
TEST_F(ImageSequenceTest, SkipsFramesWithoutDecodingThem) {
  std::ofstream(dir_ / "a.png") << "not a PNG";
  write_image("b.png", image(40, 30, 2));
  write_image("c.png", image(40, 30, 3));
  ImageSequence sequence(dir_.string());
  EXPECT_EQ(sequence.skip(2), 2);
  SequenceFrame frame;
  ASSERT_TRUE(sequence.next(&frame));
  EXPECT_EQ(frame.index, 2);
  EXPECT_EQ(frame.image.at<uchar>(0, 0), 3);
  EXPECT_EQ(sequence.skip(5), 0);  // none left
  EXPECT_FALSE(sequence.next(&frame));
}

TEST_F(ImageSequenceTest, BadInputIsAnInputErrorNamingTheFile) {
  EXPECT_NE(read_error((dir_ / "missing").string()).find("no such file"), std::string::npos);
  fs::create_directories(dir_ / "empty");
  EXPECT_NE(read_error((dir_ / "empty").string()).find("no PNG or JPG"), std::string::npos);

  fs::create_directories(dir_ / "mixed");
  write_image("mixed/0.png", image(40, 30, 0));
  write_image("mixed/1.png", image(40, 31, 0));
  const std::string mixed = read_error((dir_ / "mixed").string());
  EXPECT_NE(mixed.find("1.png: is 40x31 but the first image is 40x30"), std::string::npos) << mixed;

  fs::create_directories(dir_ / "corrupt");
  write_image("corrupt/0.png", image(40, 30, 0));
  std::ofstream(dir_ / "corrupt/1.png") << "not a PNG";
  const std::string corrupt = read_error((dir_ / "corrupt").string());
  EXPECT_NE(corrupt.find("1.png: cannot read this image"), std::string::npos) << corrupt;

  // An image's name on a link round in a loop, or to nothing: the file is named, and no
  // library's text.
  for (const std::string target : {"1.png", "missing.png"}) {
    const fs::path folder = dir_ / ("link-to-" + target);
    fs::create_directories(folder);
    cv::imwrite((folder / "0.png").string(), image(40, 30, 0));
    fs::create_symlink(target, folder / "1.png");
    const std::string link = read_error(folder.string());
    EXPECT_NE(link.find("1.png: cannot read it: "), std::string::npos) << link;
    EXPECT_EQ(link.find("filesystem error"), std::string::npos) << link;
  }

  std::ofstream(dir_ / "video.mp4") << "not a video";
  const std::string video = read_error((dir_ / "video.mp4").string());
  EXPECT_NE(video.find("video.mp4: not a folder of images, and no video reader opens it"),
            std::string::npos)
      << video;
}

TEST_F(ImageSequenceTest, ReadsAVideoWithItsTimes) {
  const std::string path = (dir_ / "clip.avi").string();
  {
    cv::VideoWriter writer(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10, {64, 48}, false);
    if (!writer.isOpened()) GTEST_SKIP() << "no video writer for MJPG in AVI";
    for (int f = 0; f < 5; ++f) writer.write(image(64, 48, 20 * f));
  }
  ImageSequence sequence(path);
  EXPECT_TRUE(sequence.is_video());
  SequenceFrame frame;
  int frames = 0;
  double last_time = -1;
  while (sequence.next(&frame)) {
    EXPECT_EQ(frame.image.type(), CV_8UC1);
    EXPECT_EQ(frame.image.size(), cv::Size(64, 48));
    EXPECT_TRUE(frame.file.empty());
    EXPECT_GT(frame.timestamp, last_time);
    last_time = frame.timestamp;
    ++frames;
  }
  EXPECT_EQ(frames, 5);
  ImageSequence skipping(path);
  EXPECT_EQ(skipping.skip(3), 3);
  ASSERT_TRUE(skipping.next(&frame));
  EXPECT_EQ(frame.index, 3);
  EXPECT_NEAR(frame.image.at<uchar>(0, 0), 60, 8);  // MJPG is lossy
  EXPECT_EQ(skipping.skip(9), 1);
}

TEST_F(ImageSequenceTest, FramesFileNamesImagesBesideItAndTakesTimesByName) {
  const std::vector<TrackedFrame> frames{{0, (dir_ / "images/a.png").string(), 0.5},
                                         {1, "", std::nan("")}};
  fs::create_directories(dir_ / "out");
  write_frames_file((dir_ / "out/frames.vnl").string(), frames);
  std::ifstream in(dir_ / "out/frames.vnl");
  const std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_EQ(text, "# frame timestamp image\n0 0.5 ../images/a.png\n1 1 -\n");

  std::ofstream(dir_ / "times.vnl")
      << "# frame timestamp image\n0 10.25 x/a.png\n1 10.75 x/b.png\n";
  const auto times = read_image_timestamps((dir_ / "times.vnl").string());
  std::vector<TrackedFrame> named{{0, "elsewhere/b.png", std::nan("")}};
  apply_timestamps(times, "times.vnl", &named);
  EXPECT_EQ(named[0].timestamp, 10.75);
  std::vector<TrackedFrame> unknown{{0, "c.png", std::nan("")}};
  EXPECT_THROW(apply_timestamps(times, "times.vnl", &unknown), io::InputError);
  // The images' times must increase in their order.
  std::vector<TrackedFrame> backwards{{0, "b.png", std::nan("")}, {1, "a.png", std::nan("")}};
  try {
    apply_timestamps(times, "times.vnl", &backwards);
    ADD_FAILURE() << "times out of order were taken";
  } catch (const io::InputError& e) {
    EXPECT_EQ(e.line(), 2);
    EXPECT_NE(e.message().find("image a.png's time 10.25 is not after that of the image before it, "
                               "b.png at 10.75"),
              std::string::npos)
        << e.what();
  }
  std::ofstream(dir_ / "twice.vnl") << "# timestamp image\n1 a.png\n2 y/a.png\n";
  EXPECT_THROW(read_image_timestamps((dir_ / "twice.vnl").string()), io::InputError);
}

// A video damaged or cut short is read as far as its decoder can, and says what was lost (the
// decoder passes over what it cannot read: cut at 60 % the clip gave 7 of its 20 frames, with a
// stretch zeroed 17, and nothing said either); a whole one says nothing.
TEST_F(ImageSequenceTest, AVideoThatGivesFewerFramesThanItsContainerSaysSaysSo) {
  const std::string path = (dir_ / "clip.avi").string();
  {
    cv::VideoWriter writer(path, cv::VideoWriter::fourcc('M', 'J', 'P', 'G'), 10, {64, 48}, false);
    if (!writer.isOpened()) GTEST_SKIP() << "no video writer for MJPG in AVI";
    for (int f = 0; f < 20; ++f) writer.write(image(64, 48, 10 * f));
  }
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::ofstream(dir_ / "cut.avi", std::ios::binary) << bytes.substr(0, bytes.size() * 6 / 10);
  std::string zeroed = bytes;
  std::fill(zeroed.begin() + zeroed.size() * 4 / 10, zeroed.begin() + zeroed.size() / 2, '\0');
  std::ofstream(dir_ / "zeroed.avi", std::ios::binary) << zeroed;
  const auto frames_and_shortfall = [](const fs::path& video) {
    ImageSequence sequence(video.string());
    SequenceFrame frame;
    int frames = 0;
    while (sequence.next(&frame)) ++frames;
    return std::make_pair(frames, sequence.shortfall());
  };
  EXPECT_EQ(frames_and_shortfall(path), std::make_pair(20, std::string()));
  for (const char* damaged : {"cut.avi", "zeroed.avi"}) {
    const auto [frames, shortfall] = frames_and_shortfall(dir_ / damaged);
    EXPECT_LT(frames, 20) << damaged;
    EXPECT_EQ(shortfall.rfind("the video gave " + std::to_string(frames) +
                                  " frames where its container says 20: damaged or cut short",
                              0),
              0u)
        << damaged << ": " << shortfall;
  }
}

}  // namespace
}  // namespace omnisfm::track
