#!/usr/bin/python3
"""mrcal's splined model on a checkerboard set, measured as calibration_results measures omnisfm's
and OpenCV's: the RMS over all views, and leave-one-view-out (each view left out of a calibration,
its board's pose then solved with that camera fixed, every corner counted). Prints one line:
  views N rms RMS rejected R loo_rms RMS_LOO observations M
RMS per coordinate (mrcal's convention). Calibrated by mrcal-calibrate-cameras itself (its seeding,
outlier rejection, regularisation and board warp).

A catadioptric image is a mirror image of the scene, which no central model of mrcal's can be
(its rotations keep handedness): --flip-x gives mrcal the corners mirrored left to right, and the
residuals are measured there (a flip changes no distance).
  mrcal_cross_validation.py CORNERS.vnl --imagersize W H --object-spacing S --object-width-n W
      --object-height-n H --focal F [--lensmodel MODEL] [--flip-x]
"""

import argparse
import os
import subprocess
import sys
import tempfile

import mrcal
import numpy as np
import scipy.optimize


def read_corners(path, flip_width):
    """Per image, its corners in file order; images with a missing corner are left out."""
    images, order, incomplete = {}, [], set()
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            name, x, y, level = line.split()[:4]
            if name not in images:
                images[name] = []
                order.append(name)
            if "-" in (x, y, level) or float(level) < 0:
                incomplete.add(name)
                continue
            x = float(x)
            images[name].append((flip_width - 1 - x if flip_width else x, float(y)))
    return [(n, np.array(images[n])) for n in order if n not in incomplete and images[n]]


def write_corners(path, views):
    with open(path, "w") as f:
        f.write("# filename x y level\n")
        for name, pixels in views:
            for x, y in pixels:
                f.write("%s %.4f %.4f 0\n" % (name, x, y))


def calibrate(views, args, folder):
    cache = os.path.join(folder, "corners.vnl")
    write_corners(cache, views)
    subprocess.run([sys.executable, "/usr/bin/mrcal-calibrate-cameras", "--corners-cache", cache,
                    "--imagersize", str(args.imagersize[0]), str(args.imagersize[1]),
                    "--lensmodel", args.lensmodel,
                    "--focal", str(args.focal), "--object-spacing", str(args.object_spacing),
                    "--object-width-n", str(args.object_width_n), "--object-height-n",
                    str(args.object_height_n), "--outdir", folder, "*"],
                   check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return mrcal.cameramodel(os.path.join(folder, "camera-0.cameramodel"))


def fitted_residuals(model, args):
    """Each calibration view's corners against the model at the board poses it was fitted with."""
    inputs = model.optimization_inputs()
    board = mrcal.ref_calibration_object(args.object_width_n, args.object_height_n,
                                         args.object_spacing,
                                         calobject_warp=inputs["calobject_warp"])
    lensmodel, intrinsics = model.intrinsics()
    residuals = []
    for rt, observed in zip(inputs["frames_rt_toref"], inputs["observations_board"]):
        projected = mrcal.project(mrcal.transform_point_rt(rt, board), lensmodel, intrinsics)
        inlier = observed[..., 2] > 0
        residuals.append((projected - observed[..., :2])[inlier].ravel())
    return np.concatenate(residuals)


def rejected(model):
    """Corners mrcal's outlier rejection left out of its fit."""
    return int(np.sum(model.optimization_inputs()["observations_board"][..., 2] <= 0))


def held_out_residuals(model, pixels, args):
    """The board's pose with the model fixed, from a homography on the corners' rays (any
    direction, also beyond 90 degrees from the axis), refined on the pixels."""
    warp = model.optimization_inputs()["calobject_warp"]
    board = mrcal.ref_calibration_object(args.object_width_n, args.object_height_n,
                                         args.object_spacing, calobject_warp=warp).reshape(-1, 3)
    lensmodel, intrinsics = model.intrinsics()
    rays = mrcal.unproject(pixels, lensmodel, intrinsics, normalize=True)
    rows = []
    for (bx, by, _), v in zip(board, rays):
        p = np.array([bx, by, 1.0])
        rows.append(np.concatenate([np.zeros(3), -v[2] * p, v[1] * p]))
        rows.append(np.concatenate([v[2] * p, np.zeros(3), -v[0] * p]))
    H = np.linalg.svd(np.array(rows))[2][-1].reshape(3, 3)
    if np.mean([v @ (H @ np.array([b[0], b[1], 1.0])) for b, v in zip(board, rays)]) < 0:
        H = -H
    scale = 1 / np.linalg.norm(H[:, 0])
    r1, r2 = H[:, 0] * scale, H[:, 1] * scale
    u, _, vt = np.linalg.svd(np.column_stack([r1, r2, np.cross(r1, r2)]))
    R = u @ vt
    rt = np.concatenate([mrcal.r_from_R(R), H[:, 2] * scale])

    def residuals(rt):
        points = mrcal.transform_point_rt(rt, board)
        return (mrcal.project(points, lensmodel, intrinsics) - pixels).ravel()

    return scipy.optimize.least_squares(residuals, rt, method="lm").fun


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("corners")
    parser.add_argument("--imagersize", type=int, nargs=2, required=True)
    parser.add_argument("--object-spacing", type=float, required=True)
    parser.add_argument("--object-width-n", type=int, required=True)
    parser.add_argument("--object-height-n", type=int, required=True)
    parser.add_argument("--focal", type=float, required=True)
    parser.add_argument("--lensmodel",
                        default="LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_Nx=8_Ny=6_fov_x_deg=300")
    parser.add_argument("--flip-x", action="store_true")
    args = parser.parse_args()
    views = read_corners(args.corners, args.imagersize[0] if args.flip_x else 0)
    with tempfile.TemporaryDirectory() as folder:
        model = calibrate(views, args, folder)
        rms = np.sqrt(np.mean(np.square(fitted_residuals(model, args))))
        outliers = rejected(model)
        held = []
        for k in range(len(views)):
            fold = calibrate(views[:k] + views[k + 1:], args, folder)
            held.append(held_out_residuals(fold, views[k][1], args))
    held = np.concatenate(held)
    print("views %d rms %.4f rejected %d loo_rms %.4f observations %d" %
          (len(views), rms, outliers, np.sqrt(np.mean(np.square(held))), len(held) // 2))


if __name__ == "__main__":
    sys.exit(main())
