#include "omnisfm/eval/timestamp_pairing.h"

#include <cmath>

namespace omnisfm::eval {

PairedPoses pair_by_timestamp(const std::vector<io::StampedPose>& estimate,
                              const std::vector<io::StampedPose>& truth, double tolerance_s) {
  PairedPoses paired;
  size_t j = 0;
  for (const io::StampedPose& p : estimate) {
    while (j < truth.size() && truth[j].timestamp < p.timestamp - tolerance_s) ++j;
    if (j < truth.size() && std::abs(truth[j].timestamp - p.timestamp) <= tolerance_s) {
      paired.estimate.push_back(p.world_from_cam);
      paired.truth.push_back(truth[j].world_from_cam);
    }
  }
  return paired;
}

}  // namespace omnisfm::eval
