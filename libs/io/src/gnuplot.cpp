#include "omnisfm/io/gnuplot.h"

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <string>

namespace omnisfm::io {

namespace {

// `text` as one word for the shell: inside single quotes, each quote closed, escaped and reopened
// (a folder named with a quote broke every plot, and one naming a command would have run it).
std::string shell_word(const std::string& text) {
  std::string word = "'";
  for (char c : text) word += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return word + "'";
}

}  // namespace

bool run_gnuplot(const std::string& folder, const std::string& script) {
  const std::string command = "cd " + shell_word(folder) + " && gnuplot " + shell_word(script) +
                              " > /dev/null 2> " + shell_word(script + ".log");
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
