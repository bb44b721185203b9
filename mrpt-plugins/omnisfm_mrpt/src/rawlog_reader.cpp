#include "omnisfm/mrpt_plugin/rawlog_reader.h"

#include <mrpt/io/CFileGZInputStream.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CActionRobotMovement3D.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/rtti/CObject.h>
#include <mrpt/serialization/CArchive.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <optional>
#include <regex>
#include <sstream>

#include "bounded_object_copy.h"
#include "copied_object_stream.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/number_text.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"

namespace omnisfm::mrpt_plugin {
namespace {

// The class of the outermost object being read when it failed, when MRPT says (it does not when
// the class name itself is cut short).
std::string failed_class(const std::string& text) {
  static const std::regex pattern(R"(parsing typed object '([A-Za-z_][A-Za-z0-9_:]*)' from)");
  std::smatch match;
  return std::regex_search(text, match, pattern) ? match[1].str() : std::string();
}

// The class name MRPT found no class for (perhaps empty), or nothing when that is not the problem.
std::optional<std::string> unregistered_class(const std::string& text) {
  static const std::regex pattern(R"(Stored object has class '([^']*)' which is not registered)");
  std::smatch match;
  if (!std::regex_search(text, match, pattern)) return std::nullopt;
  return match[1].str();
}

std::string unknown_version(const std::string& text) {
  static const std::regex pattern(R"(unknown serialization version number: '(-?\d+)')");
  std::smatch match;
  return std::regex_search(text, match, pattern) ? match[1].str() : std::string();
}

// The class whose stored bytes ran past their end-of-object flag.
std::string overrun_class(const std::string& text) {
  static const std::regex pattern(R"(end-flag missing: [^']*'([^']*)')");
  std::smatch match;
  return std::regex_search(text, match, pattern) ? match[1].str() : std::string();
}

bool is_qualified_name(const std::string& name) {
  static const std::regex pattern(R"([A-Za-z_][A-Za-z0-9_]*(::[A-Za-z_][A-Za-z0-9_]*)*)");
  return std::regex_match(name, pattern);
}

// How damage makes `name` of a registered class: one or two bytes changed in place, or the name
// cut short by a changed length byte (a newer class's name differs in more). Empty when it is no
// registered class's.
std::string damage_to_registered_name(const std::string& name) {
  for (const mrpt::rtti::TRuntimeClassId* id : mrpt::rtti::getAllRegisteredClasses()) {
    const std::string registered = id->className;
    if (registered.size() > name.size() && registered.compare(0, name.size(), name) == 0)
      return "the beginning of '" + registered + "'";
    if (registered.size() != name.size()) continue;
    int changed = 0;
    for (std::size_t i = 0; i < name.size(); ++i) changed += name[i] != registered[i];
    if (changed <= 2) return "'" + registered + "' with bytes changed";
  }
  return "";
}

std::string unregistered_class_problem(const std::string& name) {
  if (!is_qualified_name(name))
    return "it is corrupt: its class name '" + name + "' is no C++ name";
  const std::string damage = damage_to_registered_name(name);
  if (!damage.empty()) return "it is corrupt: its class name '" + name + "' is " + damage;
  return "its class '" + name + "' is not registered: " + unregistered_class_advice(name);
}

// What MRPT's text says is wrong with an object's bytes, in a reader's words: MRPT's own phrases
// blame its code ("There is a bug in the deserialization method") or name its internals.
std::string corruption_of(const std::string& mrpt_message, const std::string& object_class) {
  const std::string overrun = overrun_class(mrpt_message);
  const auto says = [&](const char* text) { return mrpt_message.find(text) != std::string::npos; };
  if (!overrun.empty() && overrun != object_class)
    return "the " + overrun + " stored in it does not end where that class's format says";
  if (!overrun.empty()) return "its bytes do not end where its class's format says";
  if (says("while parsing old streaming header") || says("Class name has more than"))
    return "it does not begin as an MRPT object does";
  if (says("Stored class does not match")) return "it holds another class than its place expects";
  if (says("bad_alloc") || says("max_size") || says("bad_array_new_length") ||
      says("Insufficient memory"))
    return "a length stored in it is far beyond what the file holds";
  if (says("Assert condition failed") || says("ASSERT_"))
    return "a value stored in it is out of its range";
  return mrpt_error_reason(mrpt_message);
}

bool is_finite(const mrpt::poses::CPose2D& p) {
  return std::isfinite(p.x()) && std::isfinite(p.y()) && std::isfinite(p.phi());
}

bool is_finite(const mrpt::poses::CPose3D& p) {
  return p.m_coords.asEigen().allFinite() && p.getRotationMatrix().asEigen().allFinite();
}

// MRPT reads an IMU's presence flags as raw bytes into bools: a damaged byte that is neither 0
// nor 1 is looked at as a byte, since reading it as a bool would be undefined behaviour.
bool presence_flags_are_bits(const mrpt::obs::CObservationIMU& imu) {
  for (const bool& flag : imu.dataIsPresent) {
    unsigned char byte = 0;
    std::memcpy(&byte, &flag, 1);
    if (byte > 1) return false;
  }
  return true;
}

// Damage that MRPT's format cannot see, in what the estimators take: a number that is not finite
// (NaN bytes are a double like any other), or a flag that is not a bool. Empty when there is none.
std::string damage_in(const mrpt::obs::CObservation& observation) {
  mrpt::poses::CPose3D sensor_pose;
  observation.getSensorPose(sensor_pose);
  if (!is_finite(sensor_pose)) return "its sensor pose is not a finite number";
  if (const auto* odometry = dynamic_cast<const mrpt::obs::CObservationOdometry*>(&observation))
    if (!is_finite(odometry->odometry)) return "its odometry is not a finite number";
  if (const auto* imu = dynamic_cast<const mrpt::obs::CObservationIMU*>(&observation)) {
    if (!presence_flags_are_bits(*imu)) return "a presence flag is neither 0 nor 1";
    for (std::size_t i = 0; i < imu->rawMeasurements.size(); ++i)
      if (imu->dataIsPresent[i] && !std::isfinite(imu->rawMeasurements[i]))
        return "a reading is not a finite number";
  }
  if (const auto* tracked = dynamic_cast<const CObservationTrackedFeatures*>(&observation))
    for (const TrackedFeature& feature : tracked->features) {
      if (!std::isfinite(feature.u) || !std::isfinite(feature.v))
        return "a feature's pixel is not a finite number";
      // With its camera, a pixel beyond the image is one no camera measured (a stored -1e305 had
      // the batch diverge and the run end as if it had succeeded).
      if (!tracked->model.has_camera()) continue;
      const camera::CatadioptricCamera& camera = tracked->model.camera();
      if (!camera.in_image(Eigen::Vector2d(feature.u, feature.v)))
        return "track " + std::to_string(feature.track) + "'s pixel (" +
               io::format_double(feature.u) + ", " + io::format_double(feature.v) +
               ") lies outside its camera's " + std::to_string(camera.image_width()) + "x" +
               std::to_string(camera.image_height()) + " image";
    }
  return "";
}

std::string damage_in(const mrpt::serialization::CSerializable& object) {
  if (const auto* observation = dynamic_cast<const mrpt::obs::CObservation*>(&object))
    return damage_in(*observation);
  if (const auto* frame = dynamic_cast<const mrpt::obs::CSensoryFrame*>(&object))
    for (const auto& observation : *frame) {
      const std::string what = observation ? damage_in(*observation) : "";
      if (!what.empty()) return what + " (in a " + observation->GetRuntimeClass()->className + ")";
    }
  if (const auto* actions = dynamic_cast<const mrpt::obs::CActionCollection*>(&object))
    for (std::size_t i = 0; i < actions->size(); ++i) {
      const auto* motion = dynamic_cast<const mrpt::obs::CActionRobotMovement2D*>(&actions->get(i));
      if (motion && !is_finite(motion->rawOdometryIncrementReading))
        return "its odometry is not a finite number";
      const auto* spatial =
          dynamic_cast<const mrpt::obs::CActionRobotMovement3D*>(&actions->get(i));
      if (spatial && !is_finite(spatial->poseChange.mean))
        return "its odometry is not a finite number";
    }
  return "";
}

}  // namespace

std::string mrpt_error_reason(const std::string& what) {
  // MRPT nests the exceptions of an object's members, each after "Original exception:", as
  // "Message:  text" when it is MRPT's own; the innermost one says what went wrong.
  const std::string nesting = "Original exception:";
  const std::size_t innermost = what.rfind(nesting);
  const std::string inner =
      innermost == std::string::npos ? what : what.substr(innermost + nesting.size());
  static const std::regex message(R"(Message:\s+([^\n]*))");
  std::smatch match;
  if (std::regex_search(inner, match, message)) return match[1].str();
  // Otherwise the first line that is not MRPT's "==== MRPT exception ====" banner (an OpenCV
  // error, say, which MRPT passes on as it is).
  std::istringstream lines(inner);
  for (std::string line; std::getline(lines, line);) {
    const std::size_t first = line.find_first_not_of(" \t");
    if (first != std::string::npos && line[first] != '=') return line.substr(first);
  }
  return what.substr(0, what.find('\n'));
}

std::string describe_damage(std::size_t index, const std::string& object_class,
                            const std::string& what) {
  const std::string n = std::to_string(index);
  const std::string before = index == 0   ? "nothing before it was read"
                             : index == 1 ? "the 1 object before it was read"
                                          : "the " + n + " objects before it were read";
  return io::printable_text("object " + n +
                            (object_class.empty() ? "" : " (" + object_class + ")") + ": " + what +
                            "; " + before);
}

std::string unregistered_class_advice(const std::string& class_name) {
  if (class_name.rfind("omnisfm::", 0) == 0) {
    return "it is one of omnisfm's classes: load the plugin library that defines it, "
           "libomnisfm_mrpt_classes.so (rawlog-edit -p /path/to/libomnisfm_mrpt_classes.so; a "
           "rawlog from a newer omnisfm needs that version's library)";
  }
  return "load the library that defines it (MRPT tools: -p /path/to/plugin.so)";
}

RawlogReader::RawlogReader(const std::string& path)
    : path_(path), file_(std::make_unique<mrpt::io::CFileGZInputStream>()) {
  std::string why;
  try {
    if (file_->open(path)) {
      copy_ = std::make_unique<BoundedObjectCopy>(*file_);
      return;
    }
  } catch (const std::exception& error) {
    why = std::string(": ") + error.what();
  }
  std::error_code ec;
  if (!std::filesystem::exists(path, ec)) why = ": no such file";
  throw io::InputError(path, 0, "cannot open the rawlog" + why);
}

RawlogReader::~RawlogReader() = default;

mrpt::serialization::CSerializable::Ptr RawlogReader::next() {
  while (!finished_) {
    try {
      if (!copy_->next()) {
        finished_ = true;  // the file ends between two objects: a clean end
        return nullptr;
      }
    } catch (const ObjectDamage& damage) {
      finished_ = true;
      problem_ = describe_damage(index_, copy_->class_name(), damage.what());
      return nullptr;
    }
    mrpt::serialization::CSerializable::Ptr object = deserialize_copy();
    if (finished_) return nullptr;
    if (object) {
      const std::string damage = damage_in(*object);
      if (!damage.empty()) {
        finished_ = true;
        problem_ = describe_damage(index_, object->GetRuntimeClass()->className,
                                   "it is corrupt: " + damage);
        return nullptr;
      }
    }
    ++index_;
    if (object) return object;
  }
  return nullptr;
}

// MRPT's reading of the copied object (and, when the copy stopped at a class it does not know,
// of the rest of it in the file). Null for a stored null, and on failure with finished_ set.
mrpt::serialization::CSerializable::Ptr RawlogReader::deserialize_copy() {
  CopiedObjectStream stream(copy_->bytes(), copy_->whole() ? nullptr : file_.get());
  auto archive = mrpt::serialization::archiveFrom(stream);
  try {
    return archive.ReadObject();
  } catch (const std::exception& error) {
    finished_ = true;
    problem_ = describe_failure(error.what());
    return nullptr;
  }
}

std::string RawlogReader::describe_failure(const std::string& mrpt_message) {
  std::string what;
  const std::string object_class = failed_class(mrpt_message);
  const std::optional<std::string> unregistered = unregistered_class(mrpt_message);
  const std::string version = unknown_version(mrpt_message);
  if (unregistered) {
    what = unregistered_class_problem(*unregistered);
  } else if (!version.empty()) {
    what = "it was stored by a newer version (" + version + ") of its class than this reader knows";
  } else if (!copy_->whole() && file_->checkEOF()) {
    // Only MRPT's reading of an object the copy could not take whole reaches the file's end.
    what = "the file ends inside it (truncated)";
  } else if (!copy_->whole() &&
             mrpt_message.find("Cannot read object streaming version") != std::string::npos) {
    // The stream ran dry before the object's end flag, which a compressed stream does not
    // report as its end: a length in the object claimed more than the file holds.
    what = "the file ends inside it (a length stored in it runs past the end)";
  } else {
    what = "it is corrupt: " + corruption_of(mrpt_message, object_class);
  }
  return describe_damage(index_, object_class, what);
}

}  // namespace omnisfm::mrpt_plugin
