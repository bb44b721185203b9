#pragma once
// Checkerboard inputs as mrcal takes them (DESIGN.md section 3):
//   corners.vnl  `# filename x y level`: for each image, its corners in board order. A level of
//                '-' or below 0 marks a corner that was not detected, and `filename - - -` an
//                image with no board; both are kept as missing so that board order is preserved.
//   board.vnl    `# index x y z`: the board's points in its own frame, metres, index 0, 1, ...
// or the board given by its spacing and size (mrcal's --object-spacing/--object-width-n/
// --object-height-n): point i = iy * width_n + ix at (ix * spacing, iy * spacing, 0).

#include <Eigen/Core>
#include <string>
#include <vector>

namespace omnisfm::io {

struct ImageCorners {
  std::string filename;
  std::vector<Eigen::Vector2d> pixels;  // in board order
  std::vector<bool> detected;           // false for missing corners (their pixel is NaN)
  int first_line = 0;                   // the image's first row in corners.vnl
  std::vector<int> lines;               // each corner's row in corners.vnl (read_corners only)
  int num_detected() const;
};

// Images in order of first appearance. Throws InputError naming the file and line for a missing
// column, a non-numeric or non-finite coordinate of a detected corner, or an image whose rows are
// not contiguous.
std::vector<ImageCorners> read_corners(const std::string& path);

// Writes `images` as corners.vnl, atomically (atomic_write.h): a row per corner (level 0, or `-`
// for a missing one) and `filename - - -` for an image without any. Throws std::invalid_argument
// for a file name that is empty or holds whitespace (a vnlog column cannot), std::runtime_error
// when the file cannot be written.
void write_corners(const std::string& path, const std::vector<ImageCorners>& images);

// Throws InputError naming the file and line for a missing column, an index out of sequence, or
// a coordinate that is missing or not finite.
std::vector<Eigen::Vector3d> read_board(const std::string& path);

// Throws std::invalid_argument unless spacing > 0 and both counts are at least 2.
std::vector<Eigen::Vector3d> regular_board(double spacing, int width_n, int height_n);

}  // namespace omnisfm::io
