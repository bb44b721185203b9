// Reading rawlogs object by object, and what happens at damage: everything before the damaged
// object is delivered, and the problem names the object's index and the kind of damage.

#include "omnisfm/mrpt_plugin/rawlog_reader.h"

#include <gtest/gtest.h>
#include <mrpt/io/CFileGZOutputStream.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationOdometry.h>

#include <cstring>
#include <filesystem>
#include <limits>

#include "omnisfm/io/input_error.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/sim/scenario.h"
#include "serialization_helpers.h"

namespace omnisfm::mrpt_plugin {
namespace {

using testing::Bytes;

// Six objects of four classes, two of them the plugin's.
class DamagedRawlog : public ::testing::Test {
 protected:
  void SetUp() override {
    comment_.text = "a rawlog for the damage tests";
    for (int i = 0; i < 2; ++i) {
      odometry_[i].timestamp = mrpt::Clock::fromDouble(1e9 + i);
      odometry_[i].sensorLabel = "ODOMETRY";
      odometry_[i].odometry = mrpt::poses::CPose2D(0.1 * i, 0, 0);
      features_[i].timestamp = mrpt::Clock::fromDouble(1e9 + i);
      features_[i].sensorLabel = "OMNI_TRACKS";
      features_[i].frame = i;
      features_[i].features = {{1, 10.0 + i, 20.0}, {2, 30.0, 40.0 + i}};
    }
    features_[0].model.set_camera(sim::default_rig(1024, 768));
    offsets_ = testing::write_plain_rawlog(
        path_, {&comment_, &odometry_[0], &features_[0], &odometry_[1], &features_[1], &comment_});
    bytes_ = testing::read_file(path_);
  }

  // Reads `bytes` as a rawlog: how many objects came out, and the problem.
  std::pair<std::size_t, std::string> read(const Bytes& bytes) {
    const std::string path = testing::temporary_path("damaged.rawlog");
    testing::write_file(path, bytes);
    RawlogReader reader(path);
    std::size_t objects = 0;
    while (reader.next()) ++objects;
    EXPECT_EQ(reader.index(), objects);
    return {objects, reader.problem()};
  }

  // Reading `bytes` stops at object `index` with a problem that holds `text`; the problem.
  std::string expect_damage(const Bytes& bytes, std::size_t index, const std::string& text) {
    const auto [objects, problem] = read(bytes);
    EXPECT_EQ(objects, index);
    EXPECT_NE(problem.find(text), std::string::npos) << problem;
    return problem;
  }

  // Where `text` first occurs in the file at or after object `index`.
  std::size_t object_offset(std::size_t index, const std::string& text) const {
    const Bytes rest(bytes_.begin() + static_cast<std::ptrdiff_t>(offsets_[index]), bytes_.end());
    return offsets_[index] + testing::find(rest, text);
  }

  // The first occurrence of `from` at or after object `index`, replaced by `to`.
  Bytes patched(std::size_t index, const std::string& from, const std::string& to) const {
    Bytes object(bytes_.begin() + static_cast<std::ptrdiff_t>(offsets_[index]), bytes_.end());
    testing::patch(&object, from, to);
    Bytes result(bytes_.begin(), bytes_.begin() + static_cast<std::ptrdiff_t>(offsets_[index]));
    result.insert(result.end(), object.begin(), object.end());
    return result;
  }

  static constexpr std::size_t kObjects = 6;
  const std::string path_ = testing::temporary_path("six_objects.rawlog");
  mrpt::obs::CObservationComment comment_;
  mrpt::obs::CObservationOdometry odometry_[2];
  CObservationTrackedFeatures features_[2];
  std::vector<std::size_t> offsets_;
  Bytes bytes_;
};

TEST_F(DamagedRawlog, ReadsAWholeFile) {
  RawlogReader reader(path_);
  std::vector<std::string> classes;
  while (const auto object = reader.next()) classes.push_back(object->GetRuntimeClass()->className);
  EXPECT_TRUE(reader.problem().empty()) << reader.problem();
  ASSERT_EQ(classes.size(), kObjects);
  EXPECT_EQ(classes[2], "omnisfm::mrpt_plugin::CObservationTrackedFeatures");
  EXPECT_EQ(classes[3], "mrpt::obs::CObservationOdometry");
}

TEST_F(DamagedRawlog, TruncatedInsideAnObjectStopsThereNamingIt) {
  for (std::size_t index = 0; index < kObjects; ++index) {
    const std::size_t begin = offsets_[index], end = offsets_[index + 1];
    for (const std::size_t cut : {begin + 1, (begin + end) / 2, end - 1}) {
      const auto [objects, problem] = read(Bytes(bytes_.begin(), bytes_.begin() + cut));
      EXPECT_EQ(objects, index) << "cut at byte " << cut;
      EXPECT_NE(problem.find("object " + std::to_string(index)), std::string::npos) << problem;
      EXPECT_NE(problem.find("the file ends inside it (truncated)"), std::string::npos) << problem;
    }
  }
  // Cut inside the object's data, MRPT names its class; inside the class name it cannot. The
  // file's name is the caller's to give, as io::InputError gives it.
  EXPECT_EQ(read(Bytes(bytes_.begin(), bytes_.begin() + offsets_[5] - 5)).second,
            "object 4 (omnisfm::mrpt_plugin::CObservationTrackedFeatures): the file ends inside "
            "it (truncated); the 4 objects before it were read");
  EXPECT_EQ(read(Bytes(bytes_.begin(), bytes_.begin() + offsets_[1] + 10)).second,
            "object 1: the file ends inside it (truncated); the 1 object before it was read");
}

TEST_F(DamagedRawlog, CutBetweenObjectsReadsAsAShorterRawlog) {
  const auto [objects, problem] = read(Bytes(bytes_.begin(), bytes_.begin() + offsets_[4]));
  EXPECT_EQ(objects, 4u);
  EXPECT_TRUE(problem.empty()) << problem;
}

TEST_F(DamagedRawlog, CorruptObjectStopsThereNamingIt) {
  Bytes bytes = bytes_;
  bytes[offsets_[3] - 1] ^= 0xff;  // object 2's end-of-object flag
  const auto [objects, problem] = read(bytes);
  EXPECT_EQ(objects, 2u);
  // In a reader's words: MRPT's own ("end-flag missing: There is a bug in the deserialization
  // method of class ...") blames MRPT.
  EXPECT_EQ(problem,
            "object 2 (omnisfm::mrpt_plugin::CObservationTrackedFeatures): it is corrupt: its "
            "bytes do not end where its class's format says; the 2 objects before it were read");
}

// The last object's bytes are all in the file: a wrong end flag there is no truncation.
TEST_F(DamagedRawlog, CorruptLastObjectIsNotTruncated) {
  Bytes bytes = bytes_;
  bytes.back() ^= 0xff;  // object 5's end-of-object flag, the file's last byte
  EXPECT_EQ(read(bytes).second,
            "object 5 (mrpt::obs::CObservationComment): it is corrupt: its bytes do not end where "
            "its class's format says; the 5 objects before it were read");
}

TEST_F(DamagedRawlog, CorruptMemberIsNamed) {
  Bytes bytes = bytes_;
  const std::size_t pose = object_offset(1, "mrpt::poses::CPose2D") + 20;  // its version byte
  bytes[pose + 1 + 3 * sizeof(double)] ^= 0xff;  // the pose's end-of-object flag
  const std::string problem = expect_damage(bytes, 1,
                                            "object 1 (mrpt::obs::CObservationOdometry): it is "
                                            "corrupt: the mrpt::poses::CPose2D stored in it does "
                                            "not end where that class's format says");
  EXPECT_EQ(problem.find("bug"), std::string::npos) << problem;
}

// NaN is a double like any other to MRPT's format; in what the estimators take it is damage, and
// reading stops there as at any other (a NaN odometry made the batch fail with exit 1).
TEST_F(DamagedRawlog, NonFiniteReadingIsDamage) {
  Bytes bytes = bytes_;
  const std::size_t x = object_offset(3, "mrpt::poses::CPose2D") + 20 + 1;  // after the version
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::memcpy(&bytes[x], &nan, sizeof nan);
  expect_damage(bytes, 3,
                "object 3 (mrpt::obs::CObservationOdometry): it is corrupt: its odometry is not a "
                "finite number; the 3 objects before it were read");
  // The features' frame alone, read through: what the reader says of it.
  const auto problem_with = [&](double v) {
    features_[1].features[1].v = v;
    const std::string path = testing::temporary_path("bad_pixel.rawlog");
    testing::write_plain_rawlog(path, {&comment_, &features_[1]});
    RawlogReader reader(path);
    while (reader.next()) {
    }
    return reader.problem();
  };
  const std::string object = "object 1 (omnisfm::mrpt_plugin::CObservationTrackedFeatures): ";
  const std::string not_finite = problem_with(nan);
  EXPECT_NE(not_finite.find(object + "it is corrupt: a feature's pixel is not a finite number"),
            std::string::npos)
      << not_finite;
  // With its camera, a pixel beyond the image is damage too.
  features_[1].model.set_camera(sim::default_rig(640, 480));
  const std::string outside = problem_with(-1e305);
  EXPECT_NE(outside.find(object + "it is corrupt: track 2's pixel (30, -1e+305) lies outside its "
                                  "camera's 640x480 image"),
            std::string::npos)
      << outside;
  EXPECT_EQ(problem_with(479.5), "");
}

// Found by fuzzing: an image whose stored size needs 10^19 bytes. OpenCV cannot allocate it,
// and says so through MRPT; the reader names the object and what is wrong.
TEST_F(DamagedRawlog, AnImageSizeBeyondMemoryIsALengthBeyondTheFile) {
  const Bytes bytes =
      testing::read_file(std::string(OMNISFM_MRPT_TEST_DATA) + "/image_size_beyond_memory.rawlog");
  expect_damage(bytes, 3,
                "object 3 (omnisfm::mrpt_plugin::CObservationOmniImage): it is corrupt: a length "
                "stored in it is far beyond what the file holds");
}

TEST(RawlogReader, ErrorReasonSkipsMrptsBanner) {
  EXPECT_EQ(mrpt_error_reason("==== MRPT exception ====\nMessage:  outer\nOriginal exception:\n"
                              "==== MRPT exception ====\nOpenCV(4.6.0) alloc.cpp:73: error: "
                              "(-4:Insufficient memory) Failed to allocate 9 bytes\nCall stack"),
            "OpenCV(4.6.0) alloc.cpp:73: error: (-4:Insufficient memory) Failed to allocate 9 bytes");
  EXPECT_EQ(mrpt_error_reason("==== MRPT exception ====\nMessage:  inner text\nmore"), "inner text");
  EXPECT_EQ(mrpt_error_reason("plain"), "plain");
}

TEST_F(DamagedRawlog, UnregisteredClassSaysWhichLibraryToLoad) {
  const std::string problem = expect_damage(
      patched(2, "CObservationTrackedFeatures", "CObservationFutureFeatures2"), 2,
      "object 2: its class 'omnisfm::mrpt_plugin::CObservationFutureFeatures2' is not registered");
  EXPECT_NE(problem.find("load the plugin library that defines it, libomnisfm_mrpt_classes.so"), std::string::npos)
      << problem;
  expect_damage(patched(1, "CObservationOdometry", "CObservationRadarXYZ"), 1,
                "'mrpt::obs::CObservationRadarXYZ' is not registered: load the library that "
                "defines it");
}

// Damage changes bytes in place: a registered class's name with a byte or two changed, cut short
// by its length byte, or no C++ name at all is corruption, not a class to load a plugin for.
TEST_F(DamagedRawlog, DamagedClassNameIsCorrupt) {
  const std::string changed = expect_damage(
      patched(2, "CObservationTrackedFeatures", "CObservationTrackedFeaturez"), 2,
      "object 2: it is corrupt: its class name 'omnisfm::mrpt_plugin::CObservationTrackedFeaturez' "
      "is 'omnisfm::mrpt_plugin::CObservationTrackedFeatures' with bytes changed");
  EXPECT_EQ(changed.find("load"), std::string::npos) << changed;
  expect_damage(patched(1, "CObservationOdometry", std::string("CObs\xe9rv\x01tionOdometry")), 1,
                "object 1: it is corrupt: its class name "
                "'mrpt::obs::CObs\\xe9rv\\x01tionOdometry' is no C++ name");
  Bytes shortened = bytes_;
  shortened[object_offset(1, "mrpt::obs::CObservationOdometry") - 1] = 0x80 | 19;
  expect_damage(shortened, 1,
                "object 1: it is corrupt: its class name 'mrpt::obs::CObserva' is the beginning "
                "of 'mrpt::obs::CObservation");
}

// A string's stored length that runs past the end of the file: MRPT reads what there is, then
// finds no end flag. Said in a reader's words, the file not named (its caller names it), in a
// plain file and in a compressed one (where the stream does not say it has ended).
TEST_F(DamagedRawlog, LengthPastTheEndSaysTheFileEndsInside) {
  Bytes bytes = bytes_;
  const std::size_t text = object_offset(5, comment_.text);
  const uint32_t too_long = static_cast<uint32_t>(bytes.size() - text + 1000);
  std::memcpy(&bytes[text - 4], &too_long, 4);
  const std::string compressed = testing::temporary_path("long_string.rawlog");
  {
    mrpt::io::CFileGZOutputStream file(compressed);
    file.Write(bytes.data(), bytes.size());
  }
  for (const Bytes& file : {bytes, testing::read_file(compressed)}) {
    const auto [objects, problem] = read(file);
    EXPECT_EQ(objects, 5u);
    EXPECT_NE(problem.find("object 5 (mrpt::obs::CObservationComment): the file ends inside it"),
              std::string::npos)
        << problem;
    EXPECT_EQ(problem.find("omnisfm_mrpt_"), std::string::npos) << problem;
    EXPECT_EQ(problem.find("CFileGZInputStream"), std::string::npos) << problem;
  }
  std::filesystem::remove(compressed);
}

TEST_F(DamagedRawlog, NewerClassVersionSaysSo) {
  const std::string name = "omnisfm::mrpt_plugin::CObservationTrackedFeatures";
  Bytes bytes = bytes_;
  Bytes object(bytes.begin() + static_cast<std::ptrdiff_t>(offsets_[4]), bytes.end());
  bytes[offsets_[4] + testing::version_byte(object, name)] = 3;
  const auto [objects, problem] = read(bytes);
  EXPECT_EQ(objects, 4u);
  EXPECT_NE(problem.find("object 4 (" + name +
                         "): it was stored by a newer version (3) of its "
                         "class"),
            std::string::npos)
      << problem;
}

TEST_F(DamagedRawlog, CompressedAndTruncated) {
  const std::string compressed = testing::temporary_path("compressed.rawlog");
  {
    mrpt::io::CFileGZOutputStream file(compressed);
    file.Write(bytes_.data(), bytes_.size());
  }
  const Bytes whole = testing::read_file(compressed);
  const auto [all, no_problem] = read(whole);
  EXPECT_EQ(all, kObjects);
  EXPECT_TRUE(no_problem.empty()) << no_problem;

  const auto [objects, problem] = read(Bytes(whole.begin(), whole.begin() + whole.size() / 2));
  EXPECT_LT(objects, kObjects);
  EXPECT_NE(problem.find("object " + std::to_string(objects)), std::string::npos) << problem;
  EXPECT_NE(problem.find("truncated"), std::string::npos) << problem;
}

TEST(RawlogReader, MissingFileIsAnInputError) {
  const std::string path = testing::temporary_path("no_such.rawlog");
  try {
    RawlogReader reader(path);
    FAIL() << "a missing file was opened";
  } catch (const io::InputError& error) {
    EXPECT_EQ(std::string(error.what()), path + ": cannot open the rawlog: no such file");
  }
}

TEST(RawlogReader, AdviceForUnregisteredClasses) {
  EXPECT_NE(
      unregistered_class_advice("omnisfm::mrpt_plugin::CObservationX").find("libomnisfm_mrpt_classes.so"),
      std::string::npos);
  EXPECT_EQ(unregistered_class_advice("mrpt::obs::CObservationX").find("libomnisfm_mrpt_classes.so"),
            std::string::npos);
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
