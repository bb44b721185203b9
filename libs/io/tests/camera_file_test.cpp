#include "omnisfm/io/camera_file.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "omnisfm/camera/conic_profile.h"
#include "omnisfm/camera/equiangular_profile.h"
#include "omnisfm/camera/mrcal_camera.h"
#include "omnisfm/camera/orthographic_camera.h"
#include "omnisfm/camera/pinhole_camera.h"
#include "omnisfm/camera/table_profile.h"
#include "omnisfm/io/input_error.h"
#include "omnisfm/io/shared_data.h"

namespace omnisfm::io {
namespace {

namespace fs = std::filesystem;
using camera::CatadioptricCamera;

class CameraFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    dir_ = fs::temp_directory_path() /
           ("omnisfm-io-" + std::to_string(::getpid()) + "-" + test->name());
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }

  std::string path(const std::string& name) const { return (dir_ / name).string(); }
  std::string write(const std::string& name, const std::string& text) const {
    std::ofstream(path(name)) << text;
    return path(name);
  }

  fs::path dir_;
};

void expect_same_camera(const CatadioptricCamera& a, const CatadioptricCamera& b) {
  EXPECT_EQ(a.image_width(), b.image_width());
  EXPECT_EQ(a.image_height(), b.image_height());
  EXPECT_EQ(a.inner().kind(), b.inner().kind());
  EXPECT_EQ(a.mirror().kind(), b.mirror().kind());
  EXPECT_EQ(a.mirror().s_min(), b.mirror().s_min());
  EXPECT_EQ(a.mirror().s_max(), b.mirror().s_max());
  ASSERT_EQ(a.num_params(), b.num_params());
  for (int i = 0; i < a.num_params(); ++i) {
    EXPECT_EQ(a.params()[i], b.params()[i]) << a.param_names()[i];
  }
}

// Digits that round-trip only when written in full, in a pose whose camera still sees its mirror
// (a file of a camera that sees nothing is refused).
camera::MirrorPose awkward_pose() {
  return {0.01, -0.02, (0.1 + 0.2) * 1e-3, -1e-3 / 3.0, 1e-3 / 7.0};
}

TEST_F(CameraFileTest, EquiangularPinholeRoundTrip) {
  const CatadioptricCamera original(
      std::make_unique<camera::PinholeCamera>(camera::PinholeIntrinsics{
          800.1, 799.7, 511.3, 383.9, -0.1, 0.01 / 3, 1e-4, -2e-4, 1e-5}),
      std::make_unique<camera::EquiangularProfile>(5.0, 0.05, 0.02, 1.0 / 3.0), awkward_pose(),
      1024, 768);
  write_camera_file(path("cam.ini"), original);
  expect_same_camera(read_camera_file(path("cam.ini")), original);
  // Nothing but the camera file is left behind.
  EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 1);
}

TEST_F(CameraFileTest, ConicOrthographicRoundTrip) {
  const CatadioptricCamera original(
      std::make_unique<camera::OrthographicCamera>(
          camera::OrthographicIntrinsics{12500.3, 12499.1, 510.25, 384.125}),
      std::make_unique<camera::ConicProfile>(1e-3, 1 / 0.02, -1.0, 0.001, 0.03), awkward_pose(),
      1024, 768);
  write_camera_file(path("para.ini"), original);
  expect_same_camera(read_camera_file(path("para.ini")), original);
}

TEST_F(CameraFileTest, TablePinholeRoundTripWritesTheProfileBesideIt) {
  std::vector<double> rho, z;
  for (int i = 0; i <= 20; ++i) {
    rho.push_back(0.03 * i / 20);
    z.push_back(0.05 + 10 * rho.back() * rho.back() / 3);
  }
  const CatadioptricCamera original(
      std::make_unique<camera::PinholeCamera>(
          camera::PinholeIntrinsics{900, 900, 511.5, 383.5, 0, 0, 0, 0, 0}),
      std::make_unique<camera::TableProfile>(rho, z, 0.002, 0.029), camera::MirrorPose{}, 1024,
      768);
  fs::create_directories(dir_ / "sub");
  write_camera_file(path("sub/table.ini"), original);
  ASSERT_TRUE(fs::exists(dir_ / "sub/table.profile.vnl"));

  // Read from another working directory: the table is found relative to the INI file.
  const CatadioptricCamera back = read_camera_file(path("sub/table.ini"));
  expect_same_camera(back, original);
  const auto& table = dynamic_cast<const camera::TableProfile&>(back.mirror());
  EXPECT_EQ(table.rho_samples(), rho);
  EXPECT_EQ(table.z_samples(), z);
}

const char* const kOpencv8Model =
    "{\n"
    "    'lensmodel': 'LENSMODEL_OPENCV8',\n"
    "    'intrinsics': [ 801.5, 799.25, 511.5, 383.5, -0.01, 0.002, 0.0001, -0.0002, 0.0003,"
    " 0.001, -0.0005, 0.0001 ],\n"
    "    'imagersize': [ 1024, 768 ],\n"
    "    'extrinsics': [ 0, 0, 0, 0, 0, 0 ],\n"
    "}\n";

TEST_F(CameraFileTest, MrcalInnerCameraRoundTrip) {
  write("lens.cameramodel", kOpencv8Model);
  write("cam.ini",
        "[omni_camera]\nimage_width = 1024\nimage_height = 768\ninner = mrcal\n"
        "inner_cameramodel = lens.cameramodel\nmirror = equiangular\nequiangular_alpha = 5\n"
        "equiangular_r0 = 0.05\nmirror_theta_min = 0.02\nmirror_theta_max = 0.35\n");
  const CatadioptricCamera read = read_camera_file(path("cam.ini"));
  ASSERT_EQ(read.inner().kind(), camera::InnerKind::kMrcal);
  const auto& lens = dynamic_cast<const camera::MrcalCamera&>(read.inner());
  EXPECT_EQ(lens.lensmodel_name(), "LENSMODEL_OPENCV8");
  ASSERT_EQ(lens.params().size(), 12);
  EXPECT_EQ(lens.params()[0], 801.5);
  EXPECT_EQ(lens.params()[11], 0.0001);

  fs::create_directories(dir_ / "out");
  write_camera_file(path("out/copy.ini"), read);
  EXPECT_TRUE(fs::exists(dir_ / "out/copy.inner.cameramodel"));
  expect_same_camera(read_camera_file(path("out/copy.ini")), read);
}

TEST_F(CameraFileTest, ShippedCamerasRead) {
  for (const char* name : {"equiangular.ini", "hyperbolic.ini", "parabolic-orthographic.ini"}) {
    SCOPED_TRACE(name);
    const CatadioptricCamera camera =
        read_camera_file(find_shared_file(std::string("cameras/") + name));
    EXPECT_EQ(camera.image_width(), 1024);
    EXPECT_EQ(camera.image_height(), 768);
    // The rim and the inner edge of the mirror both image inside the frame.
    for (double s : {camera.mirror().s_min(), camera.mirror().s_max()}) {
      for (double phi = 0; phi < 6.28; phi += 0.5) {
        camera::MeridianPoint meridian;
        camera.mirror().evaluate(s, &meridian, nullptr);
        const Eigen::Vector3d m_M(meridian.rho * std::cos(phi), meridian.rho * std::sin(phi),
                                  meridian.z);
        const Eigen::Vector3d m_C =
            camera.mirror_pose().rotation() * m_M + camera.mirror_pose().translation();
        Eigen::Vector2d pixel;
        ASSERT_TRUE(camera.inner().project(m_C, &pixel, nullptr, nullptr));
        EXPECT_TRUE(camera.in_image(pixel)) << pixel.transpose();
      }
    }
  }
}

TEST_F(CameraFileTest, DefaultCameraIsTheEquiangularOne) {
  const CatadioptricCamera camera = read_camera_file(default_camera_file());
  EXPECT_EQ(camera.mirror().kind(), camera::MirrorKind::kEquiangular);
  EXPECT_EQ(camera.inner().kind(), camera::InnerKind::kPinhole);
  const auto& profile = dynamic_cast<const camera::EquiangularProfile&>(camera.mirror());
  EXPECT_EQ(profile.alpha(), 5.0);
  EXPECT_EQ(profile.r0(), 0.05);
}

TEST_F(CameraFileTest, HyperbolicCameraIsCentral) {
  const CatadioptricCamera camera =
      read_camera_file(find_shared_file("cameras/hyperbolic.ini"));
  const auto& conic = dynamic_cast<const camera::ConicProfile&>(camera.mirror());
  // The pinhole sits at the outer focus.
  EXPECT_NEAR(conic.outer_focus_z() + camera.mirror_pose().tz, 0, 1e-12);
  // Every reflected ray passes through the inner focus.
  const Eigen::Vector3d focus(0, 0, conic.inner_focus_z() + camera.mirror_pose().tz);
  for (double u = 150; u < 900; u += 50) {
    Eigen::Vector3d origin, direction;
    if (!camera.unproject({u, 400}, &origin, &direction)) continue;
    EXPECT_NEAR((focus - origin).cross(direction).norm(), 0, 1e-9) << u;
  }
}

// A camera file as lines, edited per test.
class IniText {
 public:
  explicit IniText(std::vector<std::string> lines) : lines_(std::move(lines)) {}
  IniText& set(const std::string& key, const std::string& value) {
    for (std::string& line : lines_) {
      if (line.rfind(key + " =", 0) == 0) {
        line = key + " = " + value;
        return *this;
      }
    }
    lines_.push_back(key + " = " + value);
    return *this;
  }
  IniText& remove(const std::string& key) {
    for (auto line = lines_.begin(); line != lines_.end(); ++line) {
      if (line->rfind(key + " =", 0) == 0) {
        lines_.erase(line);
        return *this;
      }
    }
    ADD_FAILURE() << "no key " << key;
    return *this;
  }
  IniText& add(const std::string& line) {
    lines_.push_back(line);
    return *this;
  }
  int line_of(const std::string& text) const {
    for (std::size_t i = 0; i < lines_.size(); ++i) {
      if (lines_[i].rfind(text, 0) == 0) return static_cast<int>(i) + 1;
    }
    ADD_FAILURE() << "no line " << text;
    return 0;
  }
  const std::vector<std::string>& lines() const { return lines_; }
  std::string text() const {
    std::string all;
    for (const std::string& line : lines_) all += line + "\n";
    return all;
  }

 private:
  std::vector<std::string> lines_;
};

IniText equiangular_pinhole() {
  return IniText({"# a test camera", "", "[omni_camera]",
                  "image_width = 1024", "image_height = 768", "inner = pinhole", "fx = 800",
                  "fy = 800", "cx = 511.5", "cy = 383.5", "dist = 0 0 0 0 0",
                  "mirror = equiangular", "equiangular_alpha = 5.0", "equiangular_r0 = 0.05",
                  "mirror_theta_min = 0.02", "mirror_theta_max = 0.35", "mirror_tz = 0"});
}

IniText conic_orthographic() {
  return IniText({"[omni_camera]", "image_width = 1024", "image_height = 768",
                  "inner = orthographic", "fx = 12500", "fy = 12500", "cx = 511.5", "cy = 383.5",
                  "mirror = conic", "conic_z0 = 0", "conic_c = 50", "conic_kappa = -1",
                  "mirror_rho_min = 0.001", "mirror_rho_max = 0.03", "mirror_tz = 0.1"});
}

IniText table_pinhole() {
  return IniText({"[omni_camera]", "image_width = 1024", "image_height = 768", "inner = pinhole",
                  "fx = 800", "fy = 800", "cx = 511.5", "cy = 383.5", "mirror = table",
                  "mirror_table = profile.vnl", "mirror_rho_min = 0.002",
                  "mirror_rho_max = 0.025"});
}

const char* const kGoodTable =
    "# rho z\n0 0.05\n0.01 0.051\n0.02 0.054\n0.03 0.059\n";

class MalformedCameraFile : public CameraFileTest {
 protected:
  // What reading `ini` as bad.ini throws; a test failure when it reads.
  InputError error_reading(const IniText& ini) const {
    write("bad.ini", ini.text());
    try {
      read_camera_file(path("bad.ini"));
    } catch (const InputError& error) {
      return error;
    }
    ADD_FAILURE() << "no error for\n" << ini.text();
    return InputError("", 0, "");
  }

  // Reading `ini` fails with a message naming bad.ini, `key` and `line`.
  void expect_error(const IniText& ini, const std::string& key, int line,
                    const std::string& detail = "") const {
    const InputError error = error_reading(ini);
    const std::string message = error.what();
    EXPECT_NE(message.find("bad.ini:" + std::to_string(line) + ": "), std::string::npos)
        << message;
    EXPECT_NE(message.find("'" + key + "'"), std::string::npos) << message;
    EXPECT_NE(message.find(detail), std::string::npos) << message;
    EXPECT_EQ(error.line(), line);
  }
};

TEST_F(MalformedCameraFile, GoodFilesRead) {
  write("good.ini", equiangular_pinhole().text());
  EXPECT_NO_THROW(read_camera_file(path("good.ini")));
  write("good.ini", conic_orthographic().text());
  EXPECT_NO_THROW(read_camera_file(path("good.ini")));
  write("profile.vnl", kGoodTable);
  write("good.ini", table_pinhole().text());
  EXPECT_NO_THROW(read_camera_file(path("good.ini")));
}

TEST_F(MalformedCameraFile, MissingKeyPointsAtTheSection) {
  IniText ini = equiangular_pinhole();
  ini.remove("fx");
  expect_error(ini, "fx", ini.line_of("[omni_camera]"), "missing");
  ini = equiangular_pinhole();
  ini.remove("mirror_theta_max");
  expect_error(ini, "mirror_theta_max", ini.line_of("[omni_camera]"), "missing");
  ini = equiangular_pinhole();
  ini.remove("image_height");
  expect_error(ini, "image_height", ini.line_of("[omni_camera]"), "missing");
}

TEST_F(MalformedCameraFile, MissingSection) {
  write("bad.ini", "[omni_camera_covariance]\nparameters = fx\nrow_0 = 1\n");
  try {
    read_camera_file(path("bad.ini"));
    ADD_FAILURE();
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("bad.ini: no [omni_camera] section"),
              std::string::npos)
        << error.what();
  }
}

// Values each finite and in range can still make a camera that sees nothing, or one line of the
// world: refused at the file, not where an estimator fails on it.
TEST_F(MalformedCameraFile, ACameraThatSeesNothingIsRefused) {
  IniText ini = equiangular_pinhole();
  ini.set("mirror_rx", "1e10");
  expect_error(ini, "mirror_rx", ini.line_of("mirror_rx"), "within -pi and pi");
  ini = equiangular_pinhole();
  ini.set("fx", "1e308");
  expect_error(ini, "fy", ini.line_of("fy"), "within a factor 10 of fx");
  for (const char* far : {"mirror_tz = 1e10", "mirror_tx = 50"}) {
    ini = equiangular_pinhole();
    const std::string line = far;
    ini.set(line.substr(0, line.find(" =")), line.substr(line.find("= ") + 2));
    const InputError error = error_reading(ini);
    EXPECT_EQ(error.line(), ini.line_of("[omni_camera]")) << far;
    EXPECT_NE(std::string(error.what()).find("sees less than a degree of the world"),
              std::string::npos)
        << error.what();
  }
  ini = equiangular_pinhole();
  ini.set("mirror_rx", "-0.05").set("mirror_tx", "0.001");  // tilted and off the axis, it sees
  write("good.ini", ini.text());
  EXPECT_NO_THROW(read_camera_file(path("good.ini")));
}

TEST_F(MalformedCameraFile, UnknownKey) {
  IniText ini = equiangular_pinhole();
  ini.add("focal = 3");
  expect_error(ini, "focal", ini.line_of("focal"), "unknown");
}

// An unknown section would take the keys after it out of [omni_camera]: mirror_tz would fall
// back to 0 and every point would project to nothing.
TEST_F(MalformedCameraFile, UnknownSectionNamesTheFileAndLine) {
  IniText ini = equiangular_pinhole();
  ini.remove("mirror_tz");
  ini.add("[other_section]").add("mirror_tz = 0.0724");
  const std::string message = error_reading(ini).what();
  EXPECT_NE(message.find("bad.ini:" + std::to_string(ini.line_of("[other_section]")) +
                         ": unknown section [other_section]"),
            std::string::npos)
      << message;
}

TEST_F(MalformedCameraFile, KeyBeforeTheSectionIsAnError) {
  IniText ini({"fx = 800"});
  const IniText camera = equiangular_pinhole();
  for (const std::string& line : camera.lines()) ini.add(line);
  expect_error(ini, "fx", 1, "belongs in the [omni_camera] section");
}

// A calibrated camera's covariance is the one other section a camera file holds.
TEST_F(CameraFileTest, TheCovarianceSectionIsKnown) {
  write("cam.ini", equiangular_pinhole().text() +
                       "[omni_camera_covariance]\nparameters = mirror_tz\nrow_0 = 1e-8\n");
  EXPECT_NO_THROW(read_camera_file(path("cam.ini")));
}

TEST_F(MalformedCameraFile, KeyOfAnotherKindIsUnknown) {
  IniText ini = equiangular_pinhole();
  ini.add("conic_c = 3");
  expect_error(ini, "conic_c", ini.line_of("conic_c"), "mirror = equiangular");
  ini = conic_orthographic();
  ini.set("dist", "0 0 0 0 0");
  expect_error(ini, "dist", ini.line_of("dist"), "inner = orthographic");
  ini = conic_orthographic();
  ini.set("mirror_theta_min", "0.1");
  expect_error(ini, "mirror_theta_min", ini.line_of("mirror_theta_min"), "mirror = conic");
}

TEST_F(MalformedCameraFile, DuplicateKey) {
  IniText ini = equiangular_pinhole();
  ini.add("fx = 801");
  expect_error(ini, "fx", ini.line_of("fx = 801"), "duplicate");
}

TEST_F(MalformedCameraFile, UnknownKinds) {
  IniText ini = equiangular_pinhole();
  ini.set("inner", "fisheye");
  expect_error(ini, "inner", ini.line_of("inner ="), "fisheye");
  ini = equiangular_pinhole();
  ini.set("mirror", "spherical");
  expect_error(ini, "mirror", ini.line_of("mirror ="), "spherical");
}

TEST_F(MalformedCameraFile, NonNumbers) {
  for (const char* key : {"fx", "cy", "equiangular_alpha", "mirror_theta_min", "mirror_tz"}) {
    IniText ini = equiangular_pinhole();
    ini.set(key, "12abc");
    expect_error(ini, key, ini.line_of(std::string(key) + " ="), "12abc");
  }
  IniText ini = equiangular_pinhole();
  ini.set("image_width", "1024.5");
  expect_error(ini, "image_width", ini.line_of("image_width"), "integer");
  ini = equiangular_pinhole();
  ini.set("dist", "0 0 x 0 0");
  expect_error(ini, "dist", ini.line_of("dist"), "'x'");
  ini = equiangular_pinhole();
  ini.set("fy", "nan");
  expect_error(ini, "fy", ini.line_of("fy"), "finite");
}

TEST_F(MalformedCameraFile, DistortionNeedsFiveNumbers) {
  IniText ini = equiangular_pinhole();
  ini.set("dist", "0 0 0 0");
  expect_error(ini, "dist", ini.line_of("dist"), "5");
}

TEST_F(MalformedCameraFile, ImageSizeMustBePositive) {
  IniText ini = equiangular_pinhole();
  ini.set("image_width", "0");
  expect_error(ini, "image_width", ini.line_of("image_width"), "positive");
  ini = equiangular_pinhole();
  ini.set("image_height", "-768");
  expect_error(ini, "image_height", ini.line_of("image_height"), "positive");
}

TEST_F(MalformedCameraFile, FocalLengthsMustBePositive) {
  IniText ini = equiangular_pinhole();
  ini.set("fx", "0");
  expect_error(ini, "fx", ini.line_of("fx"), "positive");
  ini = conic_orthographic();
  ini.set("fy", "-1e4");
  expect_error(ini, "fy", ini.line_of("fy"), "positive");
}

TEST_F(MalformedCameraFile, EquiangularShapeMustBePositive) {
  IniText ini = equiangular_pinhole();
  ini.set("equiangular_alpha", "0");
  expect_error(ini, "equiangular_alpha", ini.line_of("equiangular_alpha"), "positive");
  ini = equiangular_pinhole();
  ini.set("equiangular_r0", "-0.05");
  expect_error(ini, "equiangular_r0", ini.line_of("equiangular_r0"), "positive");
}

TEST_F(MalformedCameraFile, ThetaRangeMustBeInsideTheDomain) {
  IniText ini = equiangular_pinhole();
  ini.set("mirror_theta_min", "0.35");
  expect_error(ini, "mirror_theta_max", ini.line_of("mirror_theta_max"), "greater");
  ini = equiangular_pinhole();
  ini.set("mirror_theta_min", "-0.01");
  expect_error(ini, "mirror_theta_min", ini.line_of("mirror_theta_min"), "negative");
  // pi / (1 + 5) = 0.5236
  ini = equiangular_pinhole();
  ini.set("mirror_theta_max", "0.53");
  expect_error(ini, "mirror_theta_max", ini.line_of("mirror_theta_max"), "pi/(1 + ");
}

TEST_F(MalformedCameraFile, ConicCurvatureMustBePositive) {
  IniText ini = conic_orthographic();
  ini.set("conic_c", "0");
  expect_error(ini, "conic_c", ini.line_of("conic_c"), "positive");
  ini = conic_orthographic();
  ini.set("conic_c", "-50");
  expect_error(ini, "conic_c", ini.line_of("conic_c"), "positive");
}

TEST_F(MalformedCameraFile, RhoRangeMustBeValid) {
  IniText ini = conic_orthographic();
  ini.set("mirror_rho_max", "0.001");
  expect_error(ini, "mirror_rho_max", ini.line_of("mirror_rho_max"), "greater");
  ini = conic_orthographic();
  ini.set("mirror_rho_min", "-0.001");
  expect_error(ini, "mirror_rho_min", ini.line_of("mirror_rho_min"), "negative");
  // A sphere of radius 0.02 ends at rho = 0.02.
  ini = conic_orthographic();
  ini.set("conic_kappa", "0");
  expect_error(ini, "mirror_rho_max", ini.line_of("mirror_rho_max"), "edge");
}

TEST_F(MalformedCameraFile, TableFileMissing) {
  IniText ini = table_pinhole();
  expect_error(ini, "mirror_table", ini.line_of("mirror_table"), "profile.vnl");
}

TEST_F(MalformedCameraFile, TableFileMalformed) {
  const IniText ini = table_pinhole();
  write("profile.vnl", "# rho z\n0 0.05\n0.01 high\n0.02 0.054\n0.03 0.059\n");
  expect_error(ini, "mirror_table", ini.line_of("mirror_table"), "profile.vnl:3:");
  write("profile.vnl", "# rho height\n0 0.05\n0.01 0.051\n0.02 0.054\n0.03 0.059\n");
  expect_error(ini, "mirror_table", ini.line_of("mirror_table"), "'z'");
  write("profile.vnl", "# rho z\n0 0.05\n0.01 -\n0.02 0.054\n0.03 0.059\n");
  expect_error(ini, "mirror_table", ini.line_of("mirror_table"), "profile.vnl:3:");
}

TEST_F(MalformedCameraFile, TableNeedsFourRows) {
  const IniText ini = table_pinhole();
  write("profile.vnl", "# rho z\n0 0.05\n0.01 0.051\n0.03 0.059\n");
  expect_error(ini, "mirror_table", ini.line_of("mirror_table"), "4");
}

TEST_F(MalformedCameraFile, TableRhoMustIncrease) {
  const IniText ini = table_pinhole();
  write("profile.vnl", "# rho z\n0 0.05\n0.02 0.051\n0.02 0.054\n0.03 0.059\n");
  expect_error(ini, "mirror_table", ini.line_of("mirror_table"), "profile.vnl:4:");
}

TEST_F(MalformedCameraFile, TableRangeMustLieInsideTheTable) {
  write("profile.vnl", kGoodTable);
  IniText ini = table_pinhole();
  ini.set("mirror_rho_max", "0.04");
  expect_error(ini, "mirror_rho_max", ini.line_of("mirror_rho_max"), "table");
  write("profile.vnl", "# rho z\n0.005 0.05\n0.01 0.051\n0.02 0.054\n0.03 0.059\n");
  ini = table_pinhole();
  expect_error(ini, "mirror_rho_min", ini.line_of("mirror_rho_min"), "table");
}

TEST_F(MalformedCameraFile, MrcalModelUnreadable) {
  IniText ini = equiangular_pinhole();
  ini.remove("fx").remove("fy").remove("cx").remove("cy").remove("dist");
  ini.set("inner", "mrcal").set("inner_cameramodel", "lens.cameramodel");
  expect_error(ini, "inner_cameramodel", ini.line_of("inner_cameramodel"), "lens.cameramodel");
  write("lens.cameramodel", "{ 'lensmodel': 'LENSMODEL_OPENCV8', 'intrinsics': [ 1, 2 ] \n");
  expect_error(ini, "inner_cameramodel", ini.line_of("inner_cameramodel"), "lens.cameramodel");
}

TEST_F(MalformedCameraFile, MrcalImageSizeMustMatch) {
  write("lens.cameramodel", kOpencv8Model);
  IniText ini = equiangular_pinhole();
  ini.remove("fx").remove("fy").remove("cx").remove("cy").remove("dist");
  ini.set("inner", "mrcal").set("inner_cameramodel", "lens.cameramodel").set("image_width", "640");
  expect_error(ini, "inner_cameramodel", ini.line_of("inner_cameramodel"), "1024x768");
}

}  // namespace
}  // namespace omnisfm::io
