#pragma once
// The gnuplot script of residual vectors drawn over the image they were measured in (y down, as
// pixels are), each drawn `scale` times its length beside a bar of one pixel of residual: how
// calibration and shape-from-motion show where in the image their models miss.

#include <string>

namespace omnisfm::io {

struct ResidualVectorsPlot {
  int image_width = 0, image_height = 0;
  double scale = 1;
  std::string data = "residuals.vnl", output = "residuals.png";
  std::string title;  // followed by how the vectors are scaled
  // 1-based columns of `data`: pixel, residual, and the outlier flag (0 or 1).
  int x_column = 1, y_column = 2, du_column = 3, dv_column = 4, outlier_column = 5;
  std::string inlier_label = "inliers";
  std::string outlier_label = "outliers";  // empty: outliers are not drawn
  bool arrow_heads = true;
  bool observation_dots = false;  // every observation's pixel as a grey dot
};

std::string residual_vectors_script(const ResidualVectorsPlot& plot);

}  // namespace omnisfm::io
