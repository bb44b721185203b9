#pragma once
// The batch adjustment in MRPT's terms: a rawlog (either format) or a CSimpleMap of sensory frames
// in; per camera frame the robot's pose as a CPose3DPDFGaussian, and the points as a
// CSimplePointsMap, out. It reads what `omnisfm run` reads (the camera's tracked features or
// images, odometry, gyro, GPS; rawlog_replay_input.h) and runs what it runs (the online filter,
// then the batch with the motion sensors' terms: sfm::run_fused_sfm).
//
// Frames: as OmniSfmEstimator's, the map is the robot's frame at the first camera frame (x
// forward, y left, z up), or with GPS fixes the local east-north-up frame the fixes define
// (map_is_enu); fixes too few or on a line to place the map (a straight drive) are left out, the
// map then the robot's, and estimate.gps_left_out says why. Each pose's covariance is the batch's,
// carried to MRPT's (x, y, z, yaw, pitch, roll); the first frame's is zero in the robot's map,
// which it defines.
//
// MRPT headers: the including target must link MRPT (mrpt::obs, mrpt::poses, mrpt::maps) itself.

#include <mrpt/core/Clock.h>
#include <mrpt/maps/CSimpleMap.h>
#include <mrpt/maps/CSimplePointsMap.h>
#include <mrpt/poses/CPose3DPDFGaussian.h>

#include <string>
#include <vector>

#include "omnisfm/mrpt_plugin/omni_sfm_estimator.h"
#include "omnisfm/mrpt_plugin/rawlog_replay_input.h"
#include "omnisfm/sfm/pipeline.h"

namespace omnisfm::mrpt_plugin {

struct OmniSfmBatchResult {
  std::vector<mrpt::Clock::time_point> timestamps;            // per camera frame
  std::vector<mrpt::poses::CPose3DPDFGaussian> robot_poses;   // map_from_robot, per frame
  mrpt::maps::CSimplePointsMap points;                        // the batch's, in the map frame
  bool map_is_enu = false;
  sfm::SfmResult estimate;  // everything the pipeline gave, in its own frames
  std::string problem;      // the rawlog's damage, when it was read up to it; else empty
};

class OmniSfmBatchEstimator {
 public:
  // The options' filter, tracker, camera, labels and sensor noise; the batch's own settings.
  explicit OmniSfmBatchEstimator(const OmniSfmEstimatorOptions& options,
                                 const sfm::BatchSettings& batch = {});

  // Throws io::InputError naming the rawlog when it holds too little to estimate from, and
  // std::runtime_error when the batch fails.
  OmniSfmBatchResult estimate(const std::string& rawlog_path) const;
  // The map's sensory frames in order (their poses are not used).
  OmniSfmBatchResult estimate(const mrpt::maps::CSimpleMap& map) const;

 private:
  OmniSfmBatchResult estimate(ReplayInput input, const std::string& source) const;
  OmniSfmEstimatorOptions options_;
  sfm::BatchSettings batch_;
};

}  // namespace omnisfm::mrpt_plugin
