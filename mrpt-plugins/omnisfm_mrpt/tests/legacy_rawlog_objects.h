#pragma once
// The objects of the committed reference rawlogs (data/version0.rawlog), as the current classes
// store them, and the writer of such a file. A class's next version adds data/version1.rawlog,
// written by write_legacy_rawlog after reference_objects() is changed to what the new version
// stores; a file is never rewritten.

#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/serialization/CArchive.h>

#include <string>
#include <vector>

#include "omnisfm/mrpt_plugin/observation_omni_image.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/sim/scenario.h"
#include "test_cameras.h"

namespace omnisfm::mrpt_plugin::testing {

inline mrpt::obs::CObservation::Ptr omni_image() {
  auto obs = CObservationOmniImage::Create();
  obs->timestamp = mrpt::Clock::fromDouble(1e9 + 0.5);
  obs->sensorLabel = "OMNI_CAMERA";
  obs->cameraPose = mrpt::poses::CPose3D(0.01, -0.02, 0.6, 0.1, 0.0, M_PI);
  obs->set_camera(sim::default_rig(64, 48));
  obs->image = mrpt::img::CImage(64, 48, mrpt::img::CH_GRAY);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x) obs->image.at<uint8_t>(x, y) = static_cast<uint8_t>(4 * x + y);
  return obs;
}

inline mrpt::obs::CObservation::Ptr features(int frame, const std::string& camera_name) {
  auto obs = CObservationTrackedFeatures::Create();
  obs->timestamp = mrpt::Clock::fromDouble(1e9 + 0.5 * frame);
  obs->sensorLabel = "OMNI_TRACKS";
  obs->frame = frame;
  obs->sensorPose = mrpt::poses::CPose3D(0, 0, 0.6, 0, 0, 0);
  for (const auto& named : camera::testing::contract_cameras())
    if (named.name == camera_name) obs->model.set_camera(named.make());
  for (int track = 0; track < 5; ++track)
    obs->features.push_back({track * 7 + frame, 100.0 + track / 3.0, 200.0 - frame / 7.0});
  return obs;
}

inline std::vector<mrpt::obs::CObservation::Ptr> reference_objects() {
  return {omni_image(), features(0, "ParabolicOrthographicMisaligned"),
          features(1, "EquiangularMrcalOpencv8"), features(2, "TablePinhole"), features(3, "")};
}

// Writes reference_objects() to `path` as a compressed rawlog, as MRPT tools write them; MRPT's
// exception when the file cannot be made.
inline void write_reference_rawlog(const std::string& path) {
  mrpt::io::CFileGZOutputStream file(path, mrpt::io::OpenMode::TRUNCATE, 9);
  auto archive = mrpt::serialization::archiveFrom(file);
  for (const auto& object : reference_objects()) archive << *object;
}

}  // namespace omnisfm::mrpt_plugin::testing
