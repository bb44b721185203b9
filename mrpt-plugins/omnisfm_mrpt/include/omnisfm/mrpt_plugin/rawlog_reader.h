#pragma once
// Reading an MRPT rawlog object by object: either format (a sequence of observations, or of
// sensory frames and actions), gzip-compressed or not.
//
// A rawlog has no index and no object lengths, so nothing after a damaged object can be found
// again: reading stops there. Every object before it has been delivered; problem() then names the
// object's index (counting from 0) and what is wrong: the file ends inside the object
// (truncated), its class is not registered (and which library defines it), its class version is
// newer than this reader, or its bytes are corrupt (a class name that is a registered one with
// bytes changed, or no C++ name, is corruption, and so is a number the estimators take - a
// sensor pose, odometry, an IMU reading, a tracked pixel - that is not finite). The caller names
// the file, as io::InputError does. A file cut exactly between two objects reads as a shorter, complete rawlog: the format
// cannot tell the difference.
//
// Each object's bytes are copied (BoundedObjectCopy) before MRPT deserializes them, with the
// layouts of the classes omnisfm takes (and of laser scans), so that a damaged length in them
// costs no more memory than the file holds; a class no rawlog holds where it stands is damage;
// an observation of another class (a 3D range scan, say) is read by MRPT from the file as it
// stands, its lengths unchecked.
//
// MRPT headers: the including target must link MRPT (mrpt::obs) itself.

#include <mrpt/serialization/CSerializable.h>

#include <cstddef>
#include <memory>
#include <string>

namespace mrpt::io {
class CFileGZInputStream;
}

namespace omnisfm::mrpt_plugin {

class BoundedObjectCopy;

class RawlogReader {
 public:
  // Throws io::InputError naming the file when it cannot be opened.
  explicit RawlogReader(const std::string& path);
  ~RawlogReader();
  RawlogReader(const RawlogReader&) = delete;
  RawlogReader& operator=(const RawlogReader&) = delete;

  // The next object, or nullptr at the end of the file or at the first object that cannot be
  // read (then problem() is not empty). Objects stored as null are skipped.
  mrpt::serialization::CSerializable::Ptr next();

  // How many objects next() has returned (plus stored nulls): the index of the object it reads
  // next, and after a problem that of the damaged object.
  std::size_t index() const { return index_; }
  // Empty while reading goes well and after a clean end; otherwise
  // "object N: what is wrong; the N objects before it were read".
  const std::string& problem() const { return problem_; }
  const std::string& path() const { return path_; }

 private:
  std::string describe_failure(const std::string& mrpt_message);
  mrpt::serialization::CSerializable::Ptr deserialize_copy();

  std::string path_;
  std::unique_ptr<mrpt::io::CFileGZInputStream> file_;
  std::unique_ptr<BoundedObjectCopy> copy_;
  std::size_t index_ = 0;
  bool finished_ = false;
  std::string problem_;
};

// The sentence that tells a user how to read a rawlog holding the class `class_name`, which is
// not registered: for omnisfm's classes, to load libomnisfm_mrpt_classes.so.
std::string unregistered_class_advice(const std::string& class_name);

// How damage is reported: "object N (CLASS): WHAT; the N objects before it were read" (without
// the class when it is empty), made printable (a damaged class name may hold any bytes).
std::string describe_damage(std::size_t index, const std::string& object_class,
                            const std::string& what);

// The innermost message of an MRPT exception's text, without MRPT's call stacks.
std::string mrpt_error_reason(const std::string& what);

}  // namespace omnisfm::mrpt_plugin
