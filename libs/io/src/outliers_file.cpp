#include "omnisfm/io/outliers_file.h"

namespace omnisfm::io {

OutliersTableWriter::OutliersTableWriter(std::ostream& out) : writer_(out, {"track", "frame"}) {}

void OutliersTableWriter::outlier(int track, int frame) {
  writer_.row({double(track), double(frame)});
}

}  // namespace omnisfm::io
