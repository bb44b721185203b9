#pragma once
// The kinds of inner camera and mirror profile, under the names camera files and MRPT archives
// store them by, and the one place that makes each from its numbers: the camera file's reader
// (io/camera_file.h) and the MRPT plugin's archive both go through it, and code that treats a
// kind apart switches on the enum.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "omnisfm/camera/inner_camera.h"
#include "omnisfm/camera/mirror_profile.h"

namespace omnisfm::camera {

// "pinhole", "orthographic", "mrcal"; "equiangular", "conic", "table".
const char* name_of(InnerKind kind);
const char* name_of(MirrorKind kind);
const std::vector<InnerKind>& inner_kinds();
const std::vector<MirrorKind>& mirror_kinds();
// The kind of that name; false, leaving `kind`, for none.
bool inner_kind_named(const std::string& name, InnerKind* kind);
bool mirror_kind_named(const std::string& name, MirrorKind* kind);

// What a mrcal inner camera holds beyond its intrinsics.
struct MrcalLens {
  std::string lensmodel;  // mrcal's name, e.g. "LENSMODEL_OPENCV8"
  int image_width = 0, image_height = 0;
};

// An inner camera of `kind` with the parameters its params() gives back: pinhole fx fy cx cy k1
// k2 p1 p2 k3, orthographic fx fy cx cy, mrcal its intrinsics (the rest of its model in `mrcal`).
// Throws std::invalid_argument naming the kind when they do not fit it.
std::unique_ptr<InnerCamera> make_inner(InnerKind kind, const Eigen::VectorXd& params,
                                        const MrcalLens& mrcal = {});

// A tabulated meridian: rho increasing, with z at each.
struct ProfileTable {
  std::vector<double> rho, z;
};

// A mirror of `kind` with the shape its shape_params() gives back (equiangular alpha r0, conic
// z0 c kappa, table none: its samples in `table`) and the valid range [s_min, s_max]. Throws
// std::invalid_argument naming the kind when they do not fit it.
std::unique_ptr<MirrorProfile> make_mirror(MirrorKind kind, const Eigen::VectorXd& shape,
                                           double s_min, double s_max,
                                           const ProfileTable& table = {});

}  // namespace omnisfm::camera
