#include "simulated_rawlog_output.h"

#include <cstdio>
#include <stdexcept>

#ifdef OMNISFM_WITH_MRPT_PLUGIN
#include "omnisfm/mrpt_plugin/gps_ground_truth.h"
#include "omnisfm/mrpt_plugin/simulated_rawlog.h"
#endif

namespace omnisfm::app {

#ifdef OMNISFM_WITH_MRPT_PLUGIN

bool can_write_rawlogs() { return true; }

sim::FolderWriter simulated_rawlog_writer(const sim::Dataset& dataset, std::uint64_t seed,
                                          bool with_images, bool with_gps, std::string* summary) {
  return [&dataset, seed, with_images, with_gps, summary](const std::string& dir) {
    mrpt_plugin::SimulatedRawlogOptions options;
    options.sensors.seed = seed;
    if (with_gps) {
      options.gps = sim::GpsOptions();
      options.gps->seed = seed;
    }
    if (with_images) {
      // Where sim::write_dataset puts the rendered images.
      options.image_file = [dir](int frame) {
        char name[32];
        std::snprintf(name, sizeof name, "/images/%06d.png", frame);
        return dir + name;
      };
    }
    const mrpt_plugin::SimulatedRawlogSummary written =
        mrpt_plugin::write_simulated_rawlog(dataset, dir + "/dataset.rawlog", options);
    *summary = "dataset.rawlog with " + std::to_string(written.images) + " images, " +
               std::to_string(written.tracked_frames) + " tracked frames, " +
               std::to_string(written.odometry) + " odometry, " + std::to_string(written.gyro) +
               " gyro" + (with_gps ? " and " + std::to_string(written.gps) + " GPS" : "") +
               " readings";
    if (with_gps)
      mrpt_plugin::write_gps_ground_truth(dataset, written.gps_track, options.start_time, dir);
  };
}

#else

bool can_write_rawlogs() { return false; }

sim::FolderWriter simulated_rawlog_writer(const sim::Dataset&, std::uint64_t, bool, bool,
                                          std::string*) {
  throw std::logic_error("omnisfm was built without the MRPT plugin");
}

#endif

}  // namespace omnisfm::app
