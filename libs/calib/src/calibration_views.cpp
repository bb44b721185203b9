#include "omnisfm/calib/calibration_views.h"

#include "omnisfm/io/input_error.h"

namespace omnisfm::calib {

std::vector<CalibrationView> target_views(const std::map<int, Eigen::Vector3d>& targets,
                                          const std::vector<io::TargetObservationRow>& rows,
                                          const std::string& observations_file) {
  std::map<int, CalibrationView> by_image;
  for (const io::TargetObservationRow& row : rows) {
    const auto target = targets.find(row.target);
    if (target == targets.end()) {
      throw io::InputError(observations_file, row.line,
                           "target " + std::to_string(row.target) +
                               " has no survey entry in the targets file");
    }
    CalibrationView& view = by_image[row.image];
    view.name = "image " + std::to_string(row.image);
    view.points.push_back(target->second);
    view.pixels.push_back(row.pixel);
    view.point_ids.push_back(row.target);
  }
  std::vector<CalibrationView> views;
  for (auto& [image, view] : by_image) views.push_back(std::move(view));
  return views;
}

std::vector<CalibrationView> board_views(const std::vector<io::ImageCorners>& images,
                                         const std::vector<Eigen::Vector3d>& board,
                                         const std::string& corners_file,
                                         const std::string& board_source) {
  std::vector<CalibrationView> views;
  for (const io::ImageCorners& image : images) {
    if (image.pixels.empty()) continue;
    if (image.pixels.size() != board.size()) {
      throw io::InputError(corners_file, image.first_line,
                           "image '" + image.filename + "' has " +
                               std::to_string(image.pixels.size()) + " corners but the board (" +
                               board_source + ") has " + std::to_string(board.size()) + " points");
    }
    CalibrationView view;
    view.name = image.filename;
    for (std::size_t i = 0; i < board.size(); ++i) {
      if (!image.detected[i]) continue;
      view.points.push_back(board[i]);
      view.pixels.push_back(image.pixels[i]);
      view.point_ids.push_back(static_cast<int>(i));
    }
    if (!view.points.empty()) views.push_back(std::move(view));
  }
  return views;
}

}  // namespace omnisfm::calib
