// The camera model through MRPT serialization: every camera of the camera contract comes back
// bit for bit, and a stored model that is not a camera is refused with a reason.

#include <gtest/gtest.h>

#include <sstream>

#include "omnisfm/mrpt_plugin/catadioptric_camera_model.h"
#include "serialization_helpers.h"
#include "test_cameras.h"

namespace omnisfm::mrpt_plugin {
namespace {

using camera::CatadioptricCamera;
using testing::Bytes;

constexpr const char* kClassName = "omnisfm::mrpt_plugin::CCatadioptricCameraModel";

void expect_same_camera(const CatadioptricCamera& a, const CatadioptricCamera& b) {
  EXPECT_EQ(a.inner().kind(), b.inner().kind());
  EXPECT_EQ(a.mirror().kind(), b.mirror().kind());
  EXPECT_EQ(a.image_width(), b.image_width());
  EXPECT_EQ(a.image_height(), b.image_height());
  EXPECT_EQ(a.param_names(), b.param_names());
  EXPECT_EQ(a.params(), b.params());  // exactly: doubles are stored as they are
  EXPECT_EQ(a.mirror().s_min(), b.mirror().s_min());
  EXPECT_EQ(a.mirror().s_max(), b.mirror().s_max());
  const auto* table_a = dynamic_cast<const camera::TableProfile*>(&a.mirror());
  const auto* table_b = dynamic_cast<const camera::TableProfile*>(&b.mirror());
  ASSERT_EQ(table_a == nullptr, table_b == nullptr);
  if (table_a) {
    EXPECT_EQ(table_a->rho_samples(), table_b->rho_samples());
    EXPECT_EQ(table_a->z_samples(), table_b->z_samples());
  }
  const auto* mrcal_a = dynamic_cast<const camera::MrcalCamera*>(&a.inner());
  const auto* mrcal_b = dynamic_cast<const camera::MrcalCamera*>(&b.inner());
  ASSERT_EQ(mrcal_a == nullptr, mrcal_b == nullptr);
  if (mrcal_a) {
    EXPECT_EQ(mrcal_a->lensmodel_name(), mrcal_b->lensmodel_name());
  }
  // The same pixels for points all around the rig.
  for (double angle = 0; angle < 6.28; angle += 0.5) {
    const Eigen::Vector3d X(2 * std::cos(angle), 2 * std::sin(angle), 0.3);
    Eigen::Vector2d pa, pb;
    const bool valid = a.project(X, &pa);
    EXPECT_EQ(valid, b.project(X, &pb));
    if (valid) {
      EXPECT_EQ(pa, pb);
    }
  }
}

class StoredCamera : public ::testing::TestWithParam<camera::testing::NamedCamera> {};

TEST_P(StoredCamera, ComesBackBitForBit) {
  const CatadioptricCamera original = GetParam().make();
  const auto read =
      testing::round_trip<CCatadioptricCameraModel>(CCatadioptricCameraModel(original));
  ASSERT_TRUE(read);
  ASSERT_TRUE(read->has_camera());
  expect_same_camera(original, read->camera());
}

INSTANTIATE_TEST_SUITE_P(CameraContract, StoredCamera,
                         ::testing::ValuesIn(camera::testing::contract_cameras()),
                         [](const auto& param_info) { return param_info.param.name; });

TEST(CameraModel, EmptyModelStaysEmpty) {
  const auto read = testing::round_trip<CCatadioptricCameraModel>(CCatadioptricCameraModel());
  ASSERT_TRUE(read);
  EXPECT_FALSE(read->has_camera());
  EXPECT_THROW(read->camera(), std::logic_error);
}

TEST(CameraModel, RefusesAStoredModelThatIsNoCamera) {
  const CCatadioptricCameraModel model(camera::testing::contract_cameras().front().make());
  Bytes unknown_kind = testing::to_bytes(model);
  testing::patch(&unknown_kind, "equiangular", "equiangulaz");
  try {
    testing::from_bytes(unknown_kind);
    FAIL() << "an unknown mirror kind was accepted";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find("unknown mirror kind 'equiangulaz'"),
              std::string::npos)
        << error.what();
  }

  // fx = 800 stored as -800: a pinhole needs positive focal lengths.
  Bytes negative_focal_length = testing::to_bytes(model);
  const double fx = 800, negative = -800;
  testing::patch(&negative_focal_length, std::string(reinterpret_cast<const char*>(&fx), 8),
                 std::string(reinterpret_cast<const char*>(&negative), 8));
  try {
    testing::from_bytes(negative_focal_length);
    FAIL() << "a negative focal length was accepted";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find("not a valid camera"), std::string::npos)
        << error.what();
  }
}

TEST(CameraModel, RefusesACameraFlagThatIsNoBool) {
  Bytes bytes = testing::to_bytes(CCatadioptricCameraModel());
  const std::size_t at = testing::version_byte(bytes, kClassName);
  ASSERT_LT(at + 1, bytes.size());
  ASSERT_EQ(bytes[at + 1], 0) << "the flag follows the version";
  bytes[at + 1] = 7;
  try {
    testing::from_bytes(bytes);
    FAIL() << "a camera flag of 7 was accepted";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find("its camera flag is 7, not 0 or 1"),
              std::string::npos)
        << error.what();
  }
}

TEST(CameraModel, RefusesAVersionItDoesNotKnow) {
  Bytes bytes = testing::to_bytes(
      CCatadioptricCameraModel(camera::testing::contract_cameras().front().make()));
  const std::size_t at = testing::version_byte(bytes, kClassName);
  ASSERT_LT(at, bytes.size());
  EXPECT_EQ(bytes[at], 0) << "version 0 is the first";
  bytes[at] = 7;
  try {
    testing::from_bytes(bytes);
    FAIL() << "version 7 was accepted";
  } catch (const std::exception& error) {
    EXPECT_NE(std::string(error.what()).find("unknown serialization version number: '7'"),
              std::string::npos)
        << error.what();
  }
}

TEST(CameraModel, DescribesEveryParameter) {
  const CCatadioptricCameraModel model(camera::testing::contract_cameras().front().make());
  std::ostringstream text;
  model.getDescriptionAsText(text);
  EXPECT_NE(text.str().find("pinhole camera, equiangular mirror, 1024x768 pixels"),
            std::string::npos)
      << text.str();
  for (const std::string& name : model.camera().param_names())
    EXPECT_NE(text.str().find("  " + name + " = "), std::string::npos) << name;
}

}  // namespace
}  // namespace omnisfm::mrpt_plugin
