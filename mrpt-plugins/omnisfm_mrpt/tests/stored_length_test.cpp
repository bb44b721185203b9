// A damaged length stored in a rawlog costs no more memory than the file holds: MRPT 2.5 sizes
// a string, vector, matrix, image (or a JPEG's picture) or list from its stored length before
// reading it, and the reader copies each object's bytes with its own bounds before MRPT sees
// them. Each case stores a length (or dimensions, or a count) far beyond a small file, reads it,
// and checks the problem and that the process's peak memory stayed where it was.

#include <gtest/gtest.h>
#include <mrpt/img/CImage.h>
#include <mrpt/obs/CActionCollection.h>
#include <mrpt/obs/CObservation2DRangeScan.h>
#include <mrpt/obs/CObservationRange.h>
#include <mrpt/obs/CActionRobotMovement2D.h>
#include <mrpt/obs/CObservationComment.h>
#include <mrpt/obs/CObservationIMU.h>
#include <mrpt/obs/CObservationImage.h>
#include <mrpt/obs/CObservationOdometry.h>
#include <mrpt/obs/CSensoryFrame.h>
#include <mrpt/poses/CPoses2DSequence.h>
#include <sys/resource.h>

#include <cstring>

#include "omnisfm/camera/camera_kinds.h"
#include "omnisfm/mrpt_plugin/observation_tracked_features.h"
#include "omnisfm/mrpt_plugin/rawlog_reader.h"
#include "omnisfm/sim/scenario.h"
#include "serialization_helpers.h"

namespace omnisfm::mrpt_plugin {
namespace {

using testing::Bytes;

// What reading may add to the process's peak memory: far less than any of the lengths below.
constexpr long kMostGrowthKb = 256 * 1024;

long peak_resident_kb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

// The problem reading `bytes` as a rawlog finds, checking that it read no object and that
// memory did not grow by what the damaged length claims.
std::string problem_reading(const Bytes& bytes) {
  const std::string path = testing::temporary_path("stored_length.rawlog");
  testing::write_file(path, bytes);
  const long before = peak_resident_kb();
  RawlogReader reader(path);
  EXPECT_EQ(reader.next(), nullptr);
  EXPECT_LT(peak_resident_kb() - before, kMostGrowthKb);
  return reader.problem();
}

// `bytes` with the 32-bit number at `offset` replaced by `value`.
Bytes with_u32(Bytes bytes, std::size_t offset, std::uint32_t value) {
  std::memcpy(&bytes[offset], &value, sizeof value);
  return bytes;
}

// Where the 32-bit number `value` is first stored in `bytes`.
std::size_t offset_of_u32(const Bytes& bytes, std::uint32_t value) {
  std::string text(sizeof value, '\0');
  std::memcpy(text.data(), &value, sizeof value);
  return testing::find(bytes, text);
}

TEST(StoredLength, AStringLongerThanTheFileEndsInsideIt) {
  mrpt::obs::CObservationComment comment;
  comment.text = "a comment";
  const Bytes bytes = testing::to_bytes(comment);
  const std::size_t length = testing::find(bytes, comment.text) - 4;
  EXPECT_EQ(problem_reading(with_u32(bytes, length, 3806520035u)),
            "object 0 (mrpt::obs::CObservationComment): the file ends inside it (truncated): a "
            "length stored in it claims 3806520035 bytes, of which the file holds 18; nothing "
            "before it was read");
}

// Found by fuzzing: MRPT takes a stored class name as a C string, so a name damaged into
// "...CObservationComment\0..." is still that class (and a damaged namespace is ignored); the
// copy must know it as MRPT does, or MRPT reads it unchecked (1.8 GB for this string).
TEST(StoredLength, AClassNameEndsAtAZeroByteAsMrptReadsIt) {
  mrpt::obs::CObservationComment comment;
  comment.text = "a comment";
  const Bytes bytes = testing::to_bytes(comment);
  Bytes damaged = with_u32(bytes, testing::find(bytes, comment.text) - 4, 1767055395u);
  const std::string stored = "mrpt::obs::CObservationComment";
  const std::size_t name = testing::find(damaged, stored);
  const std::string renamed = "\xae" "A::CObservationComment";
  Bytes named(damaged.begin(), damaged.begin() + static_cast<std::ptrdiff_t>(name));
  named.insert(named.end(), renamed.begin(), renamed.end());
  named.insert(named.end(), stored.size() - renamed.size(), '\0');
  named.insert(named.end(), damaged.begin() + static_cast<std::ptrdiff_t>(name + stored.size()),
               damaged.end());
  const std::string problem = problem_reading(named);
  EXPECT_NE(problem.find("object 0 (\\xaeA::CObservationComment): the file ends inside it "
                         "(truncated): a length stored in it claims 1767055395 bytes"),
            std::string::npos)
      << problem;
}

TEST(StoredLength, AVectorLongerThanTheFileEndsInsideIt) {
  CObservationTrackedFeatures features;
  const camera::CatadioptricCamera rig = sim::default_rig(1024, 768);
  features.model.set_camera(rig);
  const Bytes bytes = testing::to_bytes(features);
  const std::string inner = camera::name_of(rig.inner().kind());
  const std::size_t count = testing::find(bytes, inner) + inner.size();
  const std::string problem = problem_reading(with_u32(bytes, count, 0x7fffffffu));
  EXPECT_NE(problem.find("object 0 (omnisfm::mrpt_plugin::CObservationTrackedFeatures): the file "
                         "ends inside it (truncated): a length stored in it claims 17179869176 "
                         "bytes"),
            std::string::npos)
      << problem;
}

TEST(StoredLength, MoreObservationsThanTheFileHoldsEndInsideIt) {
  mrpt::obs::CSensoryFrame frame;
  frame.insert(std::make_shared<mrpt::obs::CObservationOdometry>());
  const Bytes bytes = testing::to_bytes(frame);
  const std::size_t count = testing::version_byte(bytes, "mrpt::obs::CSensoryFrame") + 1;
  EXPECT_EQ(problem_reading(with_u32(bytes, count, 0xffffffffu)),
            "object 0 (mrpt::obs::CSensoryFrame): the file ends inside it (truncated); nothing "
            "before it was read");
}

// A pose of version 1, as older MRPT stored an IMU's: a 4 x 4 matrix, here claiming 65536 x 65536.
TEST(StoredLength, MatrixDimensionsBeyondTheFileEndInsideIt) {
  mrpt::obs::CObservationIMU imu;
  const Bytes bytes = testing::to_bytes(imu);
  const std::string pose_class = "mrpt::poses::CPose3D", matrix_class = "mrpt::math::CMatrixD";
  const std::size_t pose = testing::find(bytes, pose_class) - 1;
  Bytes pose_v1 = {static_cast<uint8_t>(0x80 | pose_class.size())};
  pose_v1.insert(pose_v1.end(), pose_class.begin(), pose_class.end());
  pose_v1.push_back(1);
  pose_v1.push_back(static_cast<uint8_t>(0x80 | matrix_class.size()));
  pose_v1.insert(pose_v1.end(), matrix_class.begin(), matrix_class.end());
  pose_v1.push_back(0);
  for (int dimension = 0; dimension < 2; ++dimension)
    for (const uint8_t byte : {0x00, 0x00, 0x01, 0x00}) pose_v1.push_back(byte);  // 65536
  Bytes damaged(bytes.begin(), bytes.begin() + static_cast<std::ptrdiff_t>(pose));
  damaged.insert(damaged.end(), pose_v1.begin(), pose_v1.end());
  const std::string problem = problem_reading(damaged);
  EXPECT_NE(problem.find("object 0 (mrpt::obs::CObservationIMU): the file ends inside it "
                         "(truncated): a length stored in it claims 34359738368 bytes"),
            std::string::npos)
      << problem;
}

// MRPT allocates an image's pixels from its width and height, then reads its stored size's bytes.
TEST(StoredLength, ImageDimensionsBeyondItsStoredSizeAreCorrupt) {
  mrpt::obs::CObservationImage observation;
  observation.image.resize(4, 2, mrpt::img::CH_GRAY);
  const Bytes bytes = testing::to_bytes(observation);
  const std::size_t width = testing::version_byte(bytes, "CImage") + 1 + 1 + 1;  // external, colour
  ASSERT_EQ(bytes[width], 4);
  EXPECT_EQ(problem_reading(with_u32(with_u32(bytes, width, 40000), width + 4, 40000)),
            "object 0 (mrpt::obs::CObservationImage): it is corrupt: a length stored in it is far "
            "beyond what the file holds; nothing before it was read");
}

// MRPT 2.5 allocates a compressed image's pixels, then refuses to read it.
TEST(StoredLength, ACompressedImageIsRefusedBeforeItsPixels) {
  mrpt::obs::CObservationImage observation;
  observation.image.resize(4, 2, mrpt::img::CH_GRAY);
  Bytes bytes = testing::to_bytes(observation);
  const std::size_t width = testing::version_byte(bytes, "CImage") + 1 + 1 + 1;
  bytes = with_u32(with_u32(with_u32(bytes, width, 40000), width + 4, 40000), width + 12,
                   1600000000u);
  ASSERT_EQ(bytes[width + 20], 0);  // whether it is compressed
  bytes[width + 20] = 1;
  EXPECT_EQ(problem_reading(bytes),
            "object 0 (mrpt::obs::CObservationImage): its image is stored zip-compressed, which "
            "MRPT 2.5 cannot read; nothing before it was read");
}

// Thrun's motion model draws as many particles as it stores, with no bytes behind them.
TEST(StoredLength, AMotionModelOfBillionsOfParticlesIsCorrupt) {
  mrpt::obs::CActionRobotMovement2D movement;
  mrpt::obs::CActionRobotMovement2D::TMotionModelOptions model;
  model.modelSelection = mrpt::obs::CActionRobotMovement2D::mmThrun;
  model.thrunModel.nParticlesCount = 12345;
  movement.computeFromOdometry(mrpt::poses::CPose2D(0.1, 0, 0), model);
  mrpt::obs::CActionCollection actions;
  actions.insert(movement);
  const Bytes bytes = testing::to_bytes(actions);
  EXPECT_EQ(problem_reading(with_u32(bytes, offset_of_u32(bytes, 12345), 2000000000u)),
            "object 0 (mrpt::obs::CActionCollection): it is corrupt: its motion model draws "
            "2000000000 particles; nothing before it was read");
}

// MRPT reads a bool as a raw byte: one that decides what follows must be 0 or 1.
TEST(StoredLength, AFlagNeitherZeroNorOneIsCorrupt) {
  mrpt::obs::CObservationOdometry odometry;
  odometry.sensorLabel = "ODOMETRY";
  odometry.hasEncodersInfo = false;
  Bytes bytes = testing::to_bytes(odometry);
  const std::size_t flag = testing::find(bytes, odometry.sensorLabel) + 8 + 8;  // after the time
  ASSERT_EQ(bytes[flag], 0);
  bytes[flag] = 2;
  EXPECT_EQ(problem_reading(bytes),
            "object 0 (mrpt::obs::CObservationOdometry): it is corrupt: a flag stored in it is "
            "neither 0 nor 1; nothing before it was read");
}

// MRPT reads an object of any registered class where a rawlog's entry or a polymorphic member
// (a sensory frame's observation) is, and only then finds the class wrong; classes that no place
// expects are refused before, so that only those a rawlog holds can be read without a layout.
// Found by fuzzing: a CPoses2DSequence claiming 4.6 billion poses took 73 GB.
TEST(StoredLength, AClassNoPlaceExpectsIsRefusedBeforeMrptReadsIt) {
  mrpt::poses::CPoses2DSequence sequence;
  mrpt::poses::CPose2D pose(1, 2, 0);
  sequence.appendPose(pose);
  const Bytes poses = testing::to_bytes(sequence);
  const std::size_t count = testing::version_byte(poses, "CPoses2DSequence") + 1;
  EXPECT_EQ(problem_reading(with_u32(poses, count, 0xffffffffu)),
            "object 0 (mrpt::poses::CPoses2DSequence): it is no rawlog entry: a "
            "mrpt::poses::CPoses2DSequence is none of a sensory frame, an action collection and an "
            "observation; nothing before it was read");
  mrpt::obs::CSensoryFrame frame;
  frame.insert(std::make_shared<mrpt::obs::CObservationComment>());
  Bytes in_a_frame = testing::to_bytes(frame);
  const std::size_t member = testing::find(in_a_frame, "mrpt::obs::CObservationComment") - 1;
  in_a_frame.resize(member);
  in_a_frame.insert(in_a_frame.end(), poses.begin(), poses.end());
  in_a_frame.push_back(0x88);  // the frame's end flag
  EXPECT_EQ(problem_reading(in_a_frame),
            "object 0 (mrpt::obs::CSensoryFrame): it is corrupt: it holds a "
            "mrpt::poses::CPoses2DSequence where a mrpt::obs::CObservation belongs; nothing before "
            "it was read");
}

// What a real rawlog holds beside omnisfm's classes: a laser scan's beams, a range array's
// measurements (the latter found by fuzzing, 3.4 GB for a deque of measurements).
TEST(StoredLength, RangeSensorsCountsBeyondTheFileEndInsideIt) {
  mrpt::obs::CObservation2DRangeScan scan;
  scan.resizeScan(54321);
  const Bytes scan_bytes = testing::to_bytes(scan);
  const std::size_t beams = offset_of_u32(scan_bytes, 54321);
  const std::string scan_problem = problem_reading(with_u32(scan_bytes, beams, 0x7fffffffu));
  EXPECT_NE(scan_problem.find("object 0 (mrpt::obs::CObservation2DRangeScan): the file ends "
                              "inside it (truncated): a length stored in it claims 8589934588 "
                              "bytes"),
            std::string::npos)
      << scan_problem;
  mrpt::obs::CObservationRange range;
  range.sensedData.resize(2);
  const Bytes range_bytes = testing::to_bytes(range);
  const std::string range_problem =
      problem_reading(with_u32(range_bytes, offset_of_u32(range_bytes, 2), 0x7fffffffu));
  EXPECT_EQ(range_problem.rfind("object 0 (mrpt::obs::CObservationRange): the file ends inside it "
                                "(truncated)",
                                0),
            0u)
      << range_problem;
}

// A colour image stored as JPEG, in an observation.
Bytes jpeg_observation() {
  mrpt::obs::CObservationImage observation;
  observation.image.resize(64, 48, mrpt::img::CH_RGB);
  for (int y = 0; y < 48; ++y)
    for (int x = 0; x < 64; ++x)
      for (int c = 0; c < 3; ++c) *observation.image(x, y, c) = static_cast<uint8_t>(x * y + c);
  const bool was_disabled = mrpt::img::CImage::DISABLE_JPEG_COMPRESSION();
  mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(false);
  const Bytes bytes = testing::to_bytes(observation);
  mrpt::img::CImage::DISABLE_JPEG_COMPRESSION(was_disabled);
  return bytes;
}

std::size_t jpeg_start(const Bytes& bytes) { return testing::find(bytes, "\xff\xd8\xff"); }

TEST(StoredJpeg, AValidOneIsRead) {
  const Bytes bytes = jpeg_observation();
  ASSERT_NE(jpeg_start(bytes), std::string::npos);
  const std::string path = testing::temporary_path("jpeg.rawlog");
  testing::write_file(path, bytes);
  RawlogReader reader(path);
  const auto observation = std::dynamic_pointer_cast<mrpt::obs::CObservationImage>(reader.next());
  ASSERT_NE(observation, nullptr) << reader.problem();
  EXPECT_EQ(observation->image.getWidth(), 64u);
  EXPECT_TRUE(observation->image.isColor());
}

// MRPT's JPEG decoder keeps libjpeg's default error handler, which ended the whole process with
// exit(1) and libjpeg's message on each of these (the last found by fuzzing).
TEST(StoredJpeg, ADamagedJpegIsCorruptNotTheProcessEnd) {
  const Bytes bytes = jpeg_observation();
  const std::size_t start = jpeg_start(bytes);
  ASSERT_LT(start + 3, bytes.size());
  Bytes not_a_jpeg = bytes;  // "Not a JPEG file: starts with 0x61 0xd8"
  not_a_jpeg[start] = 'a';
  Bytes lossless = bytes;  // "Unsupported JPEG process: SOF type 0xc3"
  lossless[start + 3] = 0xc3;
  Bytes second_start = bytes;  // "Invalid JPEG file structure: two SOI markers", at its end
  const std::size_t end = testing::find(Bytes(bytes.begin() + static_cast<std::ptrdiff_t>(start),
                                              bytes.end()),
                                        "\xff\xd9");
  second_start[start + end + 1] = 0xd8;
  for (const Bytes& damaged : {not_a_jpeg, lossless, second_start})
    EXPECT_EQ(problem_reading(damaged),
              "object 0 (mrpt::obs::CObservationImage): it is corrupt: its JPEG image cannot be "
              "decoded; nothing before it was read");
}

// The picture's size is the JPEG's own: MRPT allocated 1.2 GB for this 20,000 x 20,000.
TEST(StoredJpeg, AHeaderClaimingGigapixelsIsCorrupt) {
  Bytes bytes = jpeg_observation();
  const std::size_t frame = testing::find(bytes, "\xff\xc0");  // baseline start of frame
  ASSERT_NE(frame, std::string::npos);
  for (const std::size_t at : {frame + 5, frame + 7}) {  // height, width: 16 bits big-endian
    bytes[at] = 20000 >> 8;
    bytes[at + 1] = 20000 & 0xff;
  }
  EXPECT_EQ(problem_reading(bytes),
            "object 0 (mrpt::obs::CObservationImage): it is corrupt: its JPEG image claims over "
            "268435456 pixels; nothing before it was read");
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
