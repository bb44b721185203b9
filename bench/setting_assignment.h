#pragma once
// A bench program's NAME=VALUE arguments, each applied through a table of setters by name.

#include <cstdlib>
#include <functional>
#include <map>
#include <string>

namespace omnisfm::bench {

using Setters = std::map<std::string, std::function<void(double)>>;

// `text` as a number, whole: false for empty text or text with anything after the number.
inline bool parse_number(const char* text, double* value) {
  char* end = nullptr;
  *value = std::strtod(text, &end);
  return end != text && *end == '\0';
}

// Calls the setter `assignment` names with its value; false, changing nothing, when it has no
// '=', names no setter or its value is not a number.
inline bool apply_assignment(const std::string& assignment, const Setters& setters) {
  const size_t equals = assignment.find('=');
  if (equals == std::string::npos) return false;
  const auto setter = setters.find(assignment.substr(0, equals));
  double value = 0;
  if (setter == setters.end() || !parse_number(assignment.c_str() + equals + 1, &value))
    return false;
  setter->second(value);
  return true;
}

}  // namespace omnisfm::bench
