#include "copied_object_stream.h"

#include <algorithm>
#include <cstring>
#include <stdexcept>

namespace omnisfm::mrpt_plugin {

size_t CopiedObjectStream::Read(void* buffer, size_t count) {
  auto* out = static_cast<std::uint8_t*>(buffer);
  size_t done = 0;
  if (position_ < copied_.size()) {
    done = std::min<size_t>(count, copied_.size() - position_);
    std::memcpy(out, copied_.data() + position_, done);
  }
  if (done < count && rest_) done += rest_->Read(out + done, count - done);
  position_ += done;
  return done;
}

size_t CopiedObjectStream::Write(const void*, size_t) {
  throw std::logic_error("CopiedObjectStream: a stream to read from");
}

uint64_t CopiedObjectStream::Seek(int64_t, TSeekOrigin) {
  throw std::logic_error("CopiedObjectStream: a stream read once, in order");
}

}  // namespace omnisfm::mrpt_plugin
