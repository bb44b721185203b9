#pragma once
// The stream MRPT deserializes an object from: the bytes BoundedObjectCopy copied, then, when the
// copy stopped at a class whose layout it does not know, the rest of the file.

#include <mrpt/io/CStream.h>

#include <cstdint>
#include <vector>

namespace omnisfm::mrpt_plugin {

class CopiedObjectStream : public mrpt::io::CStream {
 public:
  // `rest` is null when `copied` holds the whole object: reading past it is then its end.
  CopiedObjectStream(const std::vector<std::uint8_t>& copied, mrpt::io::CStream* rest)
      : copied_(copied), rest_(rest) {}

  size_t Read(void* buffer, size_t count) override;
  size_t Write(const void* buffer, size_t count) override;
  uint64_t Seek(int64_t offset, TSeekOrigin origin = sFromBeginning) override;
  uint64_t getTotalBytesCount() const override { return copied_.size(); }
  uint64_t getPosition() const override { return position_; }
  std::string getStreamDescription() const override { return "a rawlog object"; }

 private:
  const std::vector<std::uint8_t>& copied_;
  mrpt::io::CStream* rest_;
  uint64_t position_ = 0;
};

}  // namespace omnisfm::mrpt_plugin
