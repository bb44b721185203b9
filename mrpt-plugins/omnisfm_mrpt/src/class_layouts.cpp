#include "class_layouts.h"

#include <unordered_map>

namespace omnisfm::mrpt_plugin {

ClassLayout layout_of(const mrpt::rtti::TRuntimeClassId* id) {
  static const std::unordered_map<const mrpt::rtti::TRuntimeClassId*, ClassLayout> table = [] {
    std::unordered_map<const mrpt::rtti::TRuntimeClassId*, ClassLayout> layouts;
    for (const auto& group :
         {stock_record_layouts(), stock_member_layouts(), plugin_class_layouts(),
          range_sensor_layouts()})
      for (const ClassLayoutEntry& entry : group) layouts.emplace(entry.id, entry.layout);
    return layouts;
  }();
  const auto found = table.find(id);
  return found == table.end() ? nullptr : found->second;
}

}  // namespace omnisfm::mrpt_plugin
