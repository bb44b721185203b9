#pragma once
// One MRPT object's stored bytes, copied from a rawlog before MRPT deserializes them.
//
// MRPT 2.5 sizes a stored string, vector, matrix or image from the length stored before it, and
// allocates (and zeroes) that much before reading a byte of it: a damaged length makes it take
// gigabytes before it finds the file too short. This copy reads the object with the layouts of
// its classes (class_layouts.h) and copies each length's bytes in bounded chunks as they arrive,
// so that a length claiming more than the file holds ends as damage having held no more than the
// file; MRPT then deserializes the copy, in which every length it reads is backed by its bytes.
// At a class whose layout it does not know the copy stops (whole() is false) and MRPT reads the
// rest of the object from the file itself.

#include <mrpt/io/CStream.h>
#include <mrpt/rtti/CObject.h>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace omnisfm::mrpt_plugin {

// Damage the copy found, in a reader's words ("the file ends inside it (truncated)...").
class ObjectDamage : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class BoundedObjectCopy {
 public:
  explicit BoundedObjectCopy(mrpt::io::CStream& source) : source_(source) {}

  // Copies the next object. False when the file ends before its first byte. Throws ObjectDamage.
  bool next();
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }
  // True when bytes() holds the whole object; false when the copy stopped at a class (or a class
  // version) whose layout it does not know, the rest of the object still in the file.
  bool whole() const { return whole_; }
  // The outermost object's class as stored, once its whole name has been read.
  const std::string& class_name() const { return class_name_; }

  // The stored items the class layouts are made of; each copies its bytes.
  void skip(std::size_t bytes);
  template <typename T>
  T value() {
    skip(sizeof(T));
    T v;
    std::memcpy(&v, bytes_.data() + bytes_.size() - sizeof(T), sizeof(T));
    return v;
  }
  // A bool that decides what follows: MRPT reads it as a raw byte into a bool, and a byte other
  // than 0 or 1 there would be undefined behaviour.
  bool flag();
  // A std::string: a 32-bit length and its bytes. text() also returns it.
  void string();
  std::string text();
  // A vector of fixed-size elements: a 32-bit count and the elements. Returns the count.
  std::uint32_t array(std::size_t element_bytes);
  // `count` elements whose count (or dimensions) were read already.
  void counted(std::uint64_t count, std::size_t element_bytes);
  // The last `count` bytes copied.
  const std::uint8_t* last(std::size_t count) const { return bytes_.data() + bytes_.size() - count; }
  // A nested object of the class `T` or one derived from it, as its place in the layout expects
  // (MRPT creates and reads a polymorphic member, such as a sensory frame's observation, whatever
  // its stored class, before it finds the class wrong).
  template <typename T>
  void object() {
    object(CLASS_ID(T));
  }
  void object(const mrpt::rtti::TRuntimeClassId* expected);
  // `count` elements of at least `least_bytes` each, each copied by `element()`. MRPT allocates
  // them all before reading the first: when the copy stops inside them (at a class it has no
  // layout for), the bytes the rest take at least are copied first, so that a damaged count ends
  // inside the file rather than in MRPT's allocation.
  template <typename Element>
  void elements(std::uint32_t count, std::size_t least_bytes, Element element) {
    for (std::uint32_t i = 0; i < count; ++i) {
      try {
        element();
      } catch (const LayoutUnknown&) {
        copy_exactly(std::uint64_t{count - i - 1} * least_bytes, true);
        throw;
      }
    }
  }
  // The fewest bytes an object takes: a length byte, a version byte and an end flag.
  static constexpr std::size_t kLeastObjectBytes = 3;
  // The layout goes on in a way this copy does not know (or MRPT rejects what was read so far).
  [[noreturn]] void layout_unknown();
  // A value MRPT would trust to allocate or index with, out of any sane range.
  [[noreturn]] void out_of_range(const std::string& what);

 private:
  // What stops the copy where its layout is not known; caught at the outermost object.
  struct LayoutUnknown {};

  void object_after(std::uint8_t lead, const mrpt::rtti::TRuntimeClassId* expected);
  void check_place(const mrpt::rtti::TRuntimeClassId* id,
                   const mrpt::rtti::TRuntimeClassId* expected) const;
  void copy_exactly(std::uint64_t bytes, bool stored_length);

  mrpt::io::CStream& source_;
  std::vector<std::uint8_t> bytes_;
  bool whole_ = true;
  std::string class_name_;
  int depth_ = 0;
};

// The layout of one class's stored fields at one of its serialization versions: the bytes of
// everything between its version byte and its end flag.
using ClassLayout = void (*)(BoundedObjectCopy& in, int version);

}  // namespace omnisfm::mrpt_plugin
