#pragma once
// outliers.vnl, as the sfm and run verbs write it: a row per track rejected as an outlier, with
// the frame where it was rejected (track frame).

#include <ostream>

#include "omnisfm/io/vnlog.h"

namespace omnisfm::io {

class OutliersTableWriter {
 public:
  explicit OutliersTableWriter(std::ostream& out);
  void outlier(int track, int frame);

 private:
  VnlogWriter writer_;
};

}  // namespace omnisfm::io
