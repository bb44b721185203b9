#include "omnisfm/calib/parameter_gauge.h"

#include <algorithm>

namespace omnisfm::calib {

std::vector<HeldParameter> hold_unobservable_parameters(const camera::CatadioptricCamera& camera,
                                                        std::vector<bool>* estimate) {
  const std::vector<std::string> names = camera.param_names();
  auto index = [&](const std::string& name) {
    return static_cast<int>(std::find(names.begin(), names.end(), name) - names.begin());
  };
  auto estimated = [&](const std::string& name) {
    const int i = index(name);
    return i < static_cast<int>(names.size()) && (*estimate)[i];
  };
  std::vector<HeldParameter> held;
  auto hold = [&](const std::string& name, const std::string& reason) {
    if (!estimated(name)) return;
    (*estimate)[index(name)] = false;
    held.push_back({name, reason});
  };

  const bool telecentric = camera.inner().is_orthographic();
  const bool any_translation =
      estimated("mirror_tx") || estimated("mirror_ty") || estimated("mirror_tz");
  const bool focal_lengths = estimated("fx") || estimated("fy");
  const bool shape_with_size_trade = telecentric ? focal_lengths : any_translation;
  if (telecentric) {
    hold("mirror_tz", "a telecentric camera cannot see the mirror move along its viewing direction");
    hold("conic_z0", "a telecentric camera cannot see the mirror move along its axis");
    if (estimated("cx")) hold("mirror_tx", "a telecentric camera sees it as a change of cx");
    if (estimated("cy")) hold("mirror_ty", "a telecentric camera sees it as a change of cy");
  } else if (estimated("mirror_tz")) {
    hold("conic_z0", "it duplicates mirror_tz, a move of the mirror along its axis");
  }
  if (shape_with_size_trade) {
    const std::string trade = telecentric ? "the focal lengths fx, fy" : "the mirror's distance";
    hold("conic_c", "the mirror's size trades against " + trade + ", so it stays as given");
    hold("equiangular_r0", "the mirror's size trades against " + trade + ", so it stays as given");
  }
  std::sort(held.begin(), held.end(), [&](const HeldParameter& a, const HeldParameter& b) {
    return index(a.name) < index(b.name);
  });
  return held;
}

}  // namespace omnisfm::calib
