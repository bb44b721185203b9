"""Stock mrcal (python3-mrcal) reads the model `omnisfm export-mrcal` writes, and projects points
on the camera's reflected rays to omnisfm's pixels within the error omnisfm reports.

Usage: python3 mrcal_interop_test.py OMNISFM CAMERA.ini
"""

import os
import subprocess
import sys
import tempfile

import numpy as np
import mrcal

DISTANCE_M = 2.0
# The checked pixels lie between the fitted grid's, so the fit error there may exceed the reported
# one a little.
ERROR_SLACK = 1.5
ERROR_FLOOR_PX = 0.01


def run(command, stdin=None):
    result = subprocess.run(command, input=stdin, capture_output=True, text=True)
    if result.returncode != 0:
        sys.exit(f"FAIL: {' '.join(command)} exited with {result.returncode}:\n{result.stderr}")
    return result.stdout


def vnlog(text):
    """Column name -> array of a vnlog table ('-' is NaN)."""
    lines = text.splitlines()
    header = next(line for line in lines if line.startswith("# "))
    names = header[2:].split()
    rows = [line.split() for line in lines if line.strip() and not line.startswith("#")]
    values = np.array([[np.nan if field == "-" else float(field) for field in row] for row in rows])
    return {name: values[:, i] for i, name in enumerate(names)}


def check(condition, message):
    if not condition:
        sys.exit("FAIL: " + message)
    print("ok: " + message)


def main():
    omnisfm, camera = sys.argv[1], sys.argv[2]
    with tempfile.TemporaryDirectory(prefix="omnisfm-mrcal-interop-") as folder:
        model_path = os.path.join(folder, "approx.cameramodel")
        report = vnlog(run([omnisfm, "export-mrcal", "--camera", camera,
                            "--distance", str(DISTANCE_M), "--out", model_path]))
        model = mrcal.cameramodel(model_path)

        lensmodel, intrinsics = model.intrinsics()
        check(lensmodel.startswith("LENSMODEL_SPLINED_STEREOGRAPHIC_order=3_"),
              f"the model is splined stereographic: {lensmodel}")
        check(tuple(model.imagersize()) == (1024, 768), "the image size is the camera's")
        # The model looks along the mirror's -z axis (the camera's -z when aligned).
        axis = mrcal.rotate_point_r(model.extrinsics_rt_fromref()[:3], np.array((0., 0., -1.)))
        check(axis[2] > 0.99, f"the model's z axis is about frame C's -z: {axis}")

        # Pixels off the fitted grid, over the whole image; invalid ones come back as '-'.
        u, v = np.meshgrid(np.arange(5.25, 1024, 23), np.arange(3.75, 768, 19))
        pixels = np.column_stack((u.ravel(), v.ravel()))
        rays = vnlog(run([omnisfm, "unproject", "--camera", camera],
                         "# u v\n" + "".join(f"{p[0]} {p[1]}\n" for p in pixels)))
        origin = np.column_stack((rays["ox"], rays["oy"], rays["oz"]))
        direction = np.column_stack((rays["dx"], rays["dy"], rays["dz"]))
        valid = np.isfinite(origin[:, 0])
        pixels, origin, direction = pixels[valid], origin[valid], direction[valid]
        check(len(pixels) > 300, f"{len(pixels)} pixels see through the mirror")

        within = mrcal.is_within_valid_intrinsics_region(pixels, model)
        check(np.mean(within) > 0.97,
              f"{np.mean(within):.1%} of them lie in the model's valid_intrinsics_region")

        for row, distance in enumerate(report["distance_m"]):
            if not np.isfinite(distance):
                continue
            points = mrcal.transform_point_rt(model.extrinsics_rt_fromref(),
                                              origin + distance * direction)
            projected = mrcal.project(points, lensmodel, intrinsics)
            error = np.linalg.norm(projected - pixels, axis=1)
            rms, worst = np.sqrt(np.mean(error ** 2)), np.max(error)
            reported_rms, reported_worst = report["rms_px"][row], report["worst_px"][row]
            print(f"at {distance:g} m: mrcal RMS {rms:.3g} px, worst {worst:.3g} px; "
                  f"omnisfm reported RMS {reported_rms:.3g} px, worst {reported_worst:.3g} px")
            check(rms <= ERROR_SLACK * reported_rms + ERROR_FLOOR_PX,
                  f"the RMS at {distance:g} m agrees with the reported one")
            check(worst <= ERROR_SLACK * reported_worst + ERROR_FLOOR_PX,
                  f"the worst error at {distance:g} m agrees with the reported one")

        check(report["distance_m"][0] == DISTANCE_M and report["rms_px"][0] < 0.01,
              "the fit is within 0.01 px RMS at the fitted distance")
        check(report["rms_px"][1] > 10 * report["rms_px"][0],
              "ten times farther, the noncentral error shows")

        # mrcal's own unprojection inverts its projection of the exported model.
        directions = mrcal.unproject(pixels, lensmodel, intrinsics)
        roundtrip = mrcal.project(directions, lensmodel, intrinsics)
        check(np.max(np.abs(roundtrip - pixels)) < 1e-6, "mrcal.unproject inverts mrcal.project")


if __name__ == "__main__":
    main()
