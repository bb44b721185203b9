#pragma once
// A bench program's NAME=VALUE arguments, each applied through a table of setters by name.

#include <cstdlib>
#include <functional>
#include <map>
#include <string>

namespace omnisfm::bench {

using Setters = std::map<std::string, std::function<void(double)>>;

// Calls the setter `assignment` names with its value; false, changing nothing, when it has no
// '=' or names no setter.
inline bool apply_assignment(const std::string& assignment, const Setters& setters) {
  const size_t equals = assignment.find('=');
  if (equals == std::string::npos) return false;
  const auto setter = setters.find(assignment.substr(0, equals));
  if (setter == setters.end()) return false;
  setter->second(std::atof(assignment.c_str() + equals + 1));
  return true;
}

}  // namespace omnisfm::bench
