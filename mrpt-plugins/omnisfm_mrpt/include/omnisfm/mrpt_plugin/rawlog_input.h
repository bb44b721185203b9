#pragma once
// What omnisfm takes from an MRPT rawlog, without MRPT types (so that the omnisfm command needs
// no MRPT headers): the images of an omnidirectional camera, and feature tracks.
//
// Images come from either omnisfm's CObservationOmniImage, which carries its camera model, or a
// stock mrpt::obs::CObservationImage (rawlog-grabber's cameras), whose camera model the caller
// takes from a camera INI file. Externally stored images are looked for where MRPT's tools look:
// the folder `<rawlog name>_Images` beside the rawlog, else `Images` (as CRawlog::
// detectImagesDirectory documents; this sets MRPT's global CImage::setImagesPathBase, as MRPT's
// tools do).
//
// Damage: the valid part is processed, then reading stops. Everything before the damaged object
// has been delivered, and the result's `problem` says where and why (see RawlogReader); the
// caller decides whether what it got is enough.

#include <Eigen/Geometry>
#include <cstddef>
#include <functional>
#include <opencv2/core.hpp>
#include <optional>
#include <string>
#include <vector>

#include "omnisfm/camera/catadioptric_camera.h"
#include "omnisfm/io/tracks_file.h"

namespace omnisfm::mrpt_plugin {

struct RawlogReadResult {
  std::size_t objects = 0;  // objects read, before any damaged one
  std::size_t used = 0;     // of which the caller was given something
  std::string problem;      // empty when the whole file was read
  bool complete() const { return problem.empty(); }
};

struct RawlogImage {
  std::size_t object_index = 0;  // counting from 0, as in RawlogReader
  double timestamp = 0;          // seconds since the Unix epoch
  std::string sensor_label;
  cv::Mat grey;  // CV_8UC1; colour images are converted
  // From a CObservationOmniImage, or for a stock CObservationImage the CObservationCameraModel
  // before it under its label; empty when neither is there.
  std::optional<camera::CatadioptricCamera> camera;
  Eigen::Isometry3d robot_from_cam = Eigen::Isometry3d::Identity();
};

// Points MRPT (mrpt::img::CImage's images path, a process-wide setting) at the rawlog's external
// images, where its tools put them (`rawlog-edit --externalize`: X_Images beside X.rawlog). The
// readers here call it; a program reading rawlogs through MRPT itself calls it once per rawlog
// (MRPT 2.5's CRawlog::detectImagesDirectory drops the separator before the folder's name).
void use_external_images_of(const std::string& rawlog_path);

// Calls `visit` for every image observation in file order, including those inside sensory
// frames; with a non-empty `sensor_label`, only for that sensor's. An external image that cannot
// be loaded is damage at its object. Throws io::InputError when the file cannot be opened; rethrows
// what `visit` throws.
RawlogReadResult for_each_rawlog_image(const std::string& path,
                                       const std::function<void(RawlogImage&)>& visit,
                                       const std::string& sensor_label = "");

struct RawlogFrame {
  int frame = 0;
  double timestamp = 0;  // seconds since the Unix epoch
};

struct RawlogTracks {
  std::vector<core::TrackObservation> observations;    // in file order
  std::vector<RawlogFrame> frames;                   // one per CObservationTrackedFeatures
  std::optional<camera::CatadioptricCamera> camera;  // the first model the features carried
};

// Every CObservationTrackedFeatures of the rawlog (of `sensor_label`'s, when not empty).
RawlogReadResult read_rawlog_tracks(const std::string& path, RawlogTracks* tracks,
                                    const std::string& sensor_label = "");

}  // namespace omnisfm::mrpt_plugin
