// Checkerboard corners for the Kaidan images of the real-data set, which come without any: OpenCV's
// detectors (the classic one, then the sector-based one) on each image upsampled twice, for a grid
// of W x H inner corners. The boards are small and strongly bent by the mirror, so only part of
// each board is found, and the same W x H part is used for every image: as a board of its own it
// is the same in every image, whichever part of the physical board it is.
// Writes mrcal's corners.vnl (`# filename x y level`; `filename - - -` where nothing was found).
//   kaidan_corners KAIDAN_DIR W H > corners.vnl

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <algorithm>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

int main(int argc, char** argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: kaidan_corners KAIDAN_DIR W H > corners.vnl\n");
    return 2;
  }
  const std::filesystem::path folder = argv[1];
  const cv::Size grid(std::atoi(argv[2]), std::atoi(argv[3]));
  std::vector<std::filesystem::path> images;
  for (const auto& entry : std::filesystem::directory_iterator(folder)) {
    if (entry.path().extension() == ".jpg") images.push_back(entry.path());
  }
  std::sort(images.begin(), images.end());
  constexpr double kUpsample = 2;
  std::printf("# filename x y level\n");
  int found = 0;
  for (const auto& path : images) {
    const cv::Mat grey = cv::imread(path.string(), cv::IMREAD_GRAYSCALE);
    cv::Mat large;
    cv::resize(grey, large, cv::Size(), kUpsample, kUpsample, cv::INTER_CUBIC);
    std::vector<cv::Point2f> corners;
    bool ok = cv::findChessboardCorners(large, grid, corners,
                                        cv::CALIB_CB_ADAPTIVE_THRESH | cv::CALIB_CB_NORMALIZE_IMAGE);
    if (ok) {
      cv::cornerSubPix(large, corners, cv::Size(5, 5), cv::Size(-1, -1),
                       cv::TermCriteria(cv::TermCriteria::EPS + cv::TermCriteria::COUNT, 50, 1e-3));
    } else {
      ok = cv::findChessboardCornersSB(large, grid, corners,
                                       cv::CALIB_CB_EXHAUSTIVE | cv::CALIB_CB_ACCURACY);
    }
    const std::string name = path.filename().string();
    if (!ok) {
      std::printf("%s - - -\n", name.c_str());
      continue;
    }
    ++found;
    // Pixel centres: (x + 0.5) / s - 0.5 undoes the upsampling.
    for (const cv::Point2f& c : corners) {
      std::printf("%s %.4f %.4f 0\n", name.c_str(), (c.x + 0.5) / kUpsample - 0.5,
                  (c.y + 0.5) / kUpsample - 0.5);
    }
  }
  std::fprintf(stderr, "kaidan_corners: a %dx%d grid in %d of %zu images\n", grid.width,
               grid.height, found, images.size());
  return 0;
}
