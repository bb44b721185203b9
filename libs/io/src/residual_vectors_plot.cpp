#include "omnisfm/io/residual_vectors_plot.h"

#include <sstream>

namespace omnisfm::io {
namespace {

// "using X:(FLAG == value ? Y : 1/0):(DU*scale):(DV*scale)": the rows of one kind only.
std::string vector_columns(const ResidualVectorsPlot& p, int flag) {
  std::ostringstream using_;
  using_ << p.x_column << ":($" << p.outlier_column << " == " << flag << " ? $" << p.y_column
         << " : 1/0):($" << p.du_column << "*" << p.scale << "):($" << p.dv_column << "*"
         << p.scale << ")";
  return using_.str();
}

}  // namespace

std::string residual_vectors_script(const ResidualVectorsPlot& p) {
  const int w = p.image_width, h = p.image_height;
  const double bar_x = 0.05 * w, bar_y = 0.95 * h;
  const std::string style = std::string("with vectors") + (p.arrow_heads ? "" : " nohead");
  std::ostringstream gp;
  gp << "# Residual vectors (projected - observed) over the image, y down.\n"
     << "set terminal pngcairo size 1200," << static_cast<int>(1200.0 * h / w + 60)
     << " font 'sans,11'\n"
     << "set output '" << p.output << "'\n"
     << "set datafile missing '-'\n"
     << "set size ratio -1\n"
     << "set xrange [-0.5:" << w - 0.5 << "]\n"
     << "set yrange [" << h - 0.5 << ":-0.5]\n"
     << "set xlabel 'x (pixels)'\nset ylabel 'y (pixels)'\n"
     << "set title '" << p.title << ", drawn " << p.scale
     << " times their length: the bar is 1 px of residual'\n"
     << "set key outside bottom center horizontal\n"
     << "set arrow from " << bar_x << "," << bar_y << " to " << bar_x + p.scale << "," << bar_y
     << " nohead lw 3 lc rgb 'black'\n"
     << "set label '1 px' at " << bar_x << "," << bar_y - 0.02 * h << "\n"
     << "plot '" << p.data << "' using " << vector_columns(p, 0) << " " << style
     << " lc rgb '#1f4e9e' title '" << p.inlier_label << "'";
  if (!p.outlier_label.empty())
    gp << ", \\\n     '" << p.data << "' using " << vector_columns(p, 1) << " " << style
       << " lw 2 lc rgb '#d62728' title '" << p.outlier_label << "'";
  if (p.observation_dots)
    gp << ", \\\n     '" << p.data << "' using " << p.x_column << ":" << p.y_column
       << " with points pt 7 ps 0.3 lc rgb '#808080' title 'observations'";
  gp << "\n";
  return gp.str();
}

}  // namespace omnisfm::io
