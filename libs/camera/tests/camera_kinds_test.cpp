#include "omnisfm/camera/camera_kinds.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "omnisfm/camera/mrcal_camera.h"
#include "omnisfm/camera/table_profile.h"

namespace omnisfm::camera {
namespace {

TEST(CameraKinds, EveryKindHasOneNameThatNamesItBack) {
  for (InnerKind kind : inner_kinds()) {
    InnerKind named = kind == InnerKind::kPinhole ? InnerKind::kMrcal : InnerKind::kPinhole;
    ASSERT_TRUE(inner_kind_named(name_of(kind), &named)) << name_of(kind);
    EXPECT_EQ(named, kind);
  }
  for (MirrorKind kind : mirror_kinds()) {
    MirrorKind named = kind == MirrorKind::kConic ? MirrorKind::kTable : MirrorKind::kConic;
    ASSERT_TRUE(mirror_kind_named(name_of(kind), &named)) << name_of(kind);
    EXPECT_EQ(named, kind);
  }
  InnerKind inner = InnerKind::kOrthographic;
  EXPECT_FALSE(inner_kind_named("fisheye", &inner));
  EXPECT_EQ(inner, InnerKind::kOrthographic);
  MirrorKind mirror = MirrorKind::kTable;
  EXPECT_FALSE(mirror_kind_named("Conic", &mirror));
  EXPECT_EQ(mirror, MirrorKind::kTable);
}

TEST(CameraKinds, InnerCamerasAreMadeFromTheParametersTheyGiveBack) {
  Eigen::VectorXd pinhole(9);
  pinhole << 400, 410, 320, 240, -0.1, 0.01, 0.001, -0.002, 0.0005;
  const Eigen::VectorXd orthographic = Eigen::Vector4d(900, 905, 512, 384);
  Eigen::VectorXd opencv8(12);
  opencv8 << 500, 500, 320, 240, 0.1, -0.05, 0.001, 0.002, 0.01, 0, 0, 0;
  const MrcalLens lens{"LENSMODEL_OPENCV8", 640, 480};
  for (const auto& [kind, params] : {std::pair{InnerKind::kPinhole, pinhole},
                                     std::pair{InnerKind::kOrthographic, orthographic},
                                     std::pair{InnerKind::kMrcal, opencv8}}) {
    const auto inner = make_inner(kind, params, lens);
    EXPECT_EQ(inner->kind(), kind);
    EXPECT_EQ(inner->params(), params) << name_of(kind);
  }
  const auto mrcal = make_inner(InnerKind::kMrcal, opencv8, lens);
  EXPECT_EQ(static_cast<const MrcalCamera&>(*mrcal).lensmodel_name(), lens.lensmodel);
  EXPECT_THROW(make_inner(InnerKind::kPinhole, orthographic), std::invalid_argument);
  EXPECT_THROW(make_inner(InnerKind::kOrthographic, pinhole), std::invalid_argument);
  EXPECT_THROW(make_inner(InnerKind::kMrcal, pinhole, lens), std::invalid_argument);
}

TEST(CameraKinds, MirrorsAreMadeFromTheShapeTheyGiveBack) {
  const auto equiangular =
      make_mirror(MirrorKind::kEquiangular, Eigen::Vector2d(11, 0.014), 0.1, 0.2);
  EXPECT_EQ(equiangular->kind(), MirrorKind::kEquiangular);
  EXPECT_EQ(equiangular->shape_params(), Eigen::Vector2d(11, 0.014));
  EXPECT_EQ(equiangular->s_min(), 0.1);
  EXPECT_EQ(equiangular->s_max(), 0.2);
  const auto conic = make_mirror(MirrorKind::kConic, Eigen::Vector3d(0.03, 25, -1.5), 0.002, 0.03);
  EXPECT_EQ(conic->kind(), MirrorKind::kConic);
  EXPECT_EQ(conic->shape_params(), Eigen::Vector3d(0.03, 25, -1.5));

  ProfileTable table;
  for (int i = 0; i <= 20; ++i) {
    table.rho.push_back(0.002 * i);
    table.z.push_back(0.01 + 5 * table.rho.back() * table.rho.back());
  }
  const auto tabulated = make_mirror(MirrorKind::kTable, Eigen::VectorXd(0), 0.004, 0.036, table);
  EXPECT_EQ(tabulated->kind(), MirrorKind::kTable);
  EXPECT_EQ(static_cast<const TableProfile&>(*tabulated).rho_samples(), table.rho);
  EXPECT_EQ(static_cast<const TableProfile&>(*tabulated).z_samples(), table.z);

  EXPECT_THROW(make_mirror(MirrorKind::kConic, Eigen::Vector2d(11, 0.014), 0.1, 0.2),
               std::invalid_argument);
  EXPECT_THROW(make_mirror(MirrorKind::kTable, Eigen::Vector2d(11, 0.014), 0.004, 0.036, table),
               std::invalid_argument);
}

}  // namespace
}  // namespace omnisfm::camera
