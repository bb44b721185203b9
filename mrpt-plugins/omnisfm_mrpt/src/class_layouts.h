#pragma once
// The stored layouts of the classes omnisfm takes from a rawlog, for BoundedObjectCopy: stock
// MRPT observations and actions (sensory frames, action collections with 2D and 3D robot
// movements, odometry, IMU, GPS, images, comments), the members they store (poses, pose PDFs,
// matrices, camera parameters, images), and the plugin's classes; and, of what else a real
// rawlog holds, 2D laser scans and range arrays; each at every serialization version that MRPT
// 2.5 (or the plugin) reads.

#include <mrpt/rtti/CObject.h>

#include "bounded_object_copy.h"

namespace omnisfm::mrpt_plugin {

// The layout of the registered class `id`, or nullptr when the copy does not know it.
ClassLayout layout_of(const mrpt::rtti::TRuntimeClassId* id);

// The layouts, by group (class_layouts.cpp puts them in one table).
struct ClassLayoutEntry {
  const mrpt::rtti::TRuntimeClassId* id;
  ClassLayout layout;
};
std::vector<ClassLayoutEntry> stock_record_layouts();
std::vector<ClassLayoutEntry> stock_member_layouts();
std::vector<ClassLayoutEntry> plugin_class_layouts();
std::vector<ClassLayoutEntry> range_sensor_layouts();

// mrpt::obs::CObservationImage's fields, which the plugin's CObservationOmniImage stores too.
void observation_image_layout(BoundedObjectCopy& in, int version);
// mrpt::obs::CObservationGPS's fields.
void gps_layout(BoundedObjectCopy& in, int version);

}  // namespace omnisfm::mrpt_plugin
