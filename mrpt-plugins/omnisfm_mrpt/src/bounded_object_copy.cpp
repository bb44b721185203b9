#include "bounded_object_copy.h"

#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/rtti/CObject.h>

#include <algorithm>
#include <limits>

#include "class_layouts.h"

namespace omnisfm::mrpt_plugin {
namespace {

// The most bytes taken from the file ahead of their arrival: a stored length is copied in
// chunks of this size, so that memory follows what the file holds, not what a length claims.
constexpr std::size_t kChunkBytes = std::size_t{1} << 20;
// Past this the memory an object leaves behind is given back, so that an endless rawlog is read
// in the memory of its largest recent object, not its largest ever.
constexpr std::size_t kKeptBytes = std::size_t{16} << 20;
// No rawlog nests objects (a sensory frame's observations, an observation's pose) deeper; MRPT
// would recurse as deep as damage says.
constexpr int kMaxNesting = 32;
// MRPT's own limit on a stored class name.
constexpr std::size_t kMaxClassName = 120;

}  // namespace

bool BoundedObjectCopy::next() {
  if (bytes_.capacity() > kKeptBytes) std::vector<std::uint8_t>().swap(bytes_);
  bytes_.clear();
  whole_ = true;
  class_name_.clear();
  depth_ = 0;
  std::uint8_t lead = 0;
  if (source_.Read(&lead, 1) != 1) return false;
  bytes_.push_back(lead);
  try {
    object_after(lead, nullptr);
  } catch (const LayoutUnknown&) {
    whole_ = false;
  }
  return true;
}

void BoundedObjectCopy::copy_exactly(std::uint64_t bytes, bool stored_length) {
  std::uint64_t copied = 0;
  while (copied < bytes) {
    const std::size_t chunk =
        static_cast<std::size_t>(std::min<std::uint64_t>(bytes - copied, kChunkBytes));
    const std::size_t at = bytes_.size();
    bytes_.resize(at + chunk);
    std::size_t got = 0;
    while (got < chunk) {
      const std::size_t n = source_.Read(bytes_.data() + at + got, chunk - got);
      if (n == 0) break;
      got += n;
    }
    bytes_.resize(at + got);
    copied += got;
    if (got == chunk) continue;
    std::string what = "the file ends inside it (truncated)";
    if (stored_length)
      what += ": a length stored in it claims " + std::to_string(bytes) +
              " bytes, of which the file holds " + std::to_string(copied);
    throw ObjectDamage(what);
  }
}

void BoundedObjectCopy::skip(std::size_t bytes) { copy_exactly(bytes, false); }

bool BoundedObjectCopy::flag() {
  const auto byte = value<std::uint8_t>();
  if (byte > 1) throw ObjectDamage("it is corrupt: a flag stored in it is neither 0 nor 1");
  return byte == 1;
}

void BoundedObjectCopy::string() { counted(value<std::uint32_t>(), 1); }

std::string BoundedObjectCopy::text() {
  const auto length = value<std::uint32_t>();
  counted(length, 1);
  return std::string(bytes_.end() - static_cast<std::ptrdiff_t>(length), bytes_.end());
}

std::uint32_t BoundedObjectCopy::array(std::size_t element_bytes) {
  const auto count = value<std::uint32_t>();
  counted(count, element_bytes);
  return count;
}

void BoundedObjectCopy::counted(std::uint64_t count, std::size_t element_bytes) {
  // A product past 64 bits is past any file: claim the most there is, which the file ends inside.
  const std::uint64_t most = std::numeric_limits<std::uint64_t>::max();
  const std::uint64_t bytes =
      element_bytes != 0 && count > most / element_bytes ? most : count * element_bytes;
  copy_exactly(bytes, true);
}

void BoundedObjectCopy::object(const mrpt::rtti::TRuntimeClassId* expected) {
  object_after(value<std::uint8_t>(), expected);
}

// What a place holds: a rawlog's entries are sensory frames, action collections and observations,
// as MRPT's CRawlog reads them (it stops at any other class); a member is of the class its
// place expects. MRPT reads the rest as it finds them, and some (a laser scan, say) have
// layouts the copy does not know: the classes it may meet are the fewer for this.
void BoundedObjectCopy::check_place(const mrpt::rtti::TRuntimeClassId* id,
                                    const mrpt::rtti::TRuntimeClassId* expected) const {
  if (expected) {
    if (!id->derivedFrom(expected))
      throw ObjectDamage(std::string("it is corrupt: it holds a ") + id->className + " where a " +
                         expected->className + " belongs");
    return;
  }
  if (id != CLASS_ID(mrpt::obs::CSensoryFrame) && id != CLASS_ID(mrpt::obs::CActionCollection) &&
      !id->derivedFrom(CLASS_ID(mrpt::obs::CObservation)))
    throw ObjectDamage(std::string("it is no rawlog entry: a ") + id->className +
                       " is none of a sensory frame, an action collection and an observation");
}

// MRPT's object header: a length byte with its top bit set (an old-format object, before MRPT
// 0.5.5, has the bit clear, three zero bytes, and no end flag), the class name, its version (a
// byte; an old-format object's a 32-bit number), then the fields and an end flag.
void BoundedObjectCopy::object_after(std::uint8_t lead,
                                     const mrpt::rtti::TRuntimeClassId* expected) {
  const bool old_format = (lead & 0x80) == 0;
  if (old_format)
    for (int i = 0; i < 3; ++i)
      if (value<std::uint8_t>() != 0) layout_unknown();  // MRPT rejects it here
  const std::size_t name_length = lead & 0x7f;
  if (name_length > kMaxClassName) layout_unknown();
  skip(name_length);
  // MRPT takes the name as a C string: a damaged name ends at its first zero byte.
  const std::string name(
      std::string(bytes_.end() - static_cast<std::ptrdiff_t>(name_length), bytes_.end()).c_str());
  if (depth_ == 0) class_name_ = name;
  int version = 0;
  if (old_format) {
    version = value<std::int32_t>();
    if (version < 0 || version >= 255) layout_unknown();
  } else if (name != "nullptr") {
    version = value<std::uint8_t>();
  }
  if (name != "nullptr") {
    const mrpt::rtti::TRuntimeClassId* id = mrpt::rtti::findRegisteredClass(name);
    if (!id) layout_unknown();  // MRPT says it is not registered
    check_place(id, expected);
    const ClassLayout layout = layout_of(id);
    if (!layout) layout_unknown();
    if (depth_ == kMaxNesting) out_of_range("its objects nest deeper than " +
                                            std::to_string(kMaxNesting) + " levels");
    ++depth_;
    layout(*this, version);
    --depth_;
  }
  if (!old_format) skip(1);  // the end flag, which MRPT checks
}

void BoundedObjectCopy::layout_unknown() { throw LayoutUnknown{}; }

void BoundedObjectCopy::out_of_range(const std::string& what) {
  throw ObjectDamage("it is corrupt: " + what);
}

}  // namespace omnisfm::mrpt_plugin
