#include "omnisfm/io/gnuplot.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace omnisfm::io {

bool run_gnuplot(const std::string& folder, const std::string& script) {
  const std::string command = "cd '" + folder + "' && gnuplot '" + script + "' > /dev/null 2> '" +
                              script + ".log'";
  if (std::system(command.c_str()) != 0) return false;
  std::error_code ignored;
  std::filesystem::remove(std::filesystem::path(folder) / (script + ".log"), ignored);
  return true;
}

double round_down_125(double value) {
  const double decade = std::pow(10.0, std::floor(std::log10(value)));
  for (double step : {5.0, 2.0, 1.0})
    if (step * decade <= value) return step * decade;
  return decade;
}

}  // namespace omnisfm::io
