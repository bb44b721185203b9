#include "omnisfm/io/residual_vectors_plot.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "io_test_folder.h"
#include "omnisfm/io/gnuplot.h"

namespace omnisfm::io {
namespace {

using ResidualVectorsPlotTest = TestFolder;

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

TEST_F(ResidualVectorsPlotTest, GnuplotDrawsInliersOutliersAndObservationsFromTheGivenColumns) {
  // Columns: frame, x, y, du, dv, outlier.
  write("residuals.vnl",
        "# frame x y du dv outlier\n"
        "0 100 80 0.2 -0.1 0\n0 300 200 -0.3 0.1 0\n1 150 120 2.5 1.0 1\n");
  ResidualVectorsPlot plot;
  plot.image_width = 400, plot.image_height = 300;
  plot.scale = 50;
  plot.title = "Residuals";
  plot.x_column = 2, plot.y_column = 3, plot.du_column = 4, plot.dv_column = 5;
  plot.outlier_column = 6;
  plot.observation_dots = true;
  const std::string script = residual_vectors_script(plot);
  EXPECT_NE(script.find("using 2:($6 == 0 ? $3 : 1/0):($4*50):($5*50)"), std::string::npos)
      << script;
  EXPECT_NE(script.find("using 2:($6 == 1 ? $3 : 1/0):($4*50):($5*50)"), std::string::npos);
  EXPECT_NE(script.find("set yrange [299.5:-0.5]"), std::string::npos);  // y down
  EXPECT_EQ(count(script, "with vectors lc"), 1u);
  write("residuals.gp", script);
  ASSERT_TRUE(run_gnuplot(path(""), "residuals.gp"));
  EXPECT_GT(std::filesystem::file_size(path("residuals.png")), 1000u);
}

// A folder whose name holds quotes and the shell's own characters is one word to the shell.
TEST_F(ResidualVectorsPlotTest, GnuplotRunsInAFolderOfAnyName) {
  const std::filesystem::path odd = path("it's a \"$(odd)\" name;");
  std::filesystem::create_directories(odd);
  {
    std::ofstream script(odd / "plot.gp");
    script << "set terminal pngcairo size 200,100\nset output 'plot.png'\nplot x\n";
  }
  ASSERT_TRUE(run_gnuplot(odd.string(), "plot.gp"));
  EXPECT_GT(std::filesystem::file_size(odd / "plot.png"), 100u);
  EXPECT_FALSE(std::filesystem::exists(odd / "plot.gp.log"));
}

TEST_F(ResidualVectorsPlotTest, LeavesOutliersOutWithoutTheirLabel) {
  ResidualVectorsPlot plot;
  plot.image_width = 400, plot.image_height = 300;
  plot.outlier_label.clear();
  plot.arrow_heads = false;
  const std::string script = residual_vectors_script(plot);
  EXPECT_EQ(count(script, "with vectors nohead"), 1u) << script;
  EXPECT_EQ(script.find("== 1 ?"), std::string::npos);
  EXPECT_EQ(script.find("with points"), std::string::npos);
}

}  // namespace
}  // namespace omnisfm::io
