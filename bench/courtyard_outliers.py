#!/usr/bin/python3
"""Outlier rejection on sequences the simulator did not make.

A courtyard (walls with points up to 4 m high, and ground points), a camera carried 1 m above the
ground along an arc, tracks that start and end, and tracks that drift away from their point
slowly (as a tracker's do on a repetitive texture), not the simulator's slides and drifts. The
pixels come from `omnisfm project` on the given camera; everything else is made here. Each seed's
sequence goes through `omnisfm sfm` (filter and batch), and the rejected tracks are scored against
the drifting ones.

usage: courtyard_outliers.py OMNISFM CAMERA.ini WORKDIR [SEEDS] [--filter-only] [--noise PX]
       [--noise-correlation RHO]
       [--drift-min PX_PER_FRAME] [--drift-max PX_PER_FRAME] [--frames N] [--length M]
       [--points N] [--drifting N] [--config INI] [--sfm-camera CAL.ini] [--verbose]
"""
import argparse
import math
import os
import subprocess
import sys

import numpy as np


def rotation_z(angle):
    c, s = math.cos(angle), math.sin(angle)
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def rotation_xy(rx, ry):
    cx, sx, cy, sy = math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry)
    about_x = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    about_y = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    return about_x @ about_y


def quaternion(r):
    """x y z w of a rotation matrix."""
    w = math.sqrt(max(0.0, 1 + r[0, 0] + r[1, 1] + r[2, 2])) / 2
    x = math.copysign(math.sqrt(max(0.0, 1 + r[0, 0] - r[1, 1] - r[2, 2])) / 2, r[2, 1] - r[1, 2])
    y = math.copysign(math.sqrt(max(0.0, 1 - r[0, 0] + r[1, 1] - r[2, 2])) / 2, r[0, 2] - r[2, 0])
    z = math.copysign(math.sqrt(max(0.0, 1 - r[0, 0] - r[1, 1] + r[2, 2])) / 2, r[1, 0] - r[0, 1])
    return x, y, z, w


def courtyard_points(rng, count):
    """Points on four walls of a 12 x 9 m courtyard (up to 4 m high) and on its ground."""
    points = []
    while len(points) < count:
        if rng.random() < 0.35:
            points.append([rng.uniform(-5.5, 5.5), rng.uniform(-4, 4), 0.0])
            continue
        wall = rng.integers(4)
        height = rng.uniform(0.2, 4.0)
        if wall < 2:
            points.append([rng.uniform(-6, 6), -4.5 if wall == 0 else 4.5, height])
        else:
            points.append([-6.0 if wall == 2 else 6.0, rng.uniform(-4.5, 4.5), height])
    return np.array(points)


def trajectory(rng, frames, length):
    """world_from_cam poses: an arc of `length` metres turning 25-50 deg, 1 m up, with a wobble."""
    turn = math.radians(rng.uniform(25, 50)) * (1 if rng.random() < 0.5 else -1)
    heading0 = rng.uniform(-math.pi, math.pi)
    radius = length / abs(turn)
    poses = []
    for k in range(frames):
        s = k / (frames - 1)
        heading = heading0 + turn * s
        centre_offset = np.array([-math.sin(heading0), math.cos(heading0), 0]) * radius * np.sign(turn)
        start = np.array([-2.0 * math.cos(heading0), -2.0 * math.sin(heading0), 1.0])
        position = start + centre_offset + np.array(
            [math.sin(heading), -math.cos(heading), 0]) * radius * np.sign(turn)
        position[2] = 1.0 + 0.01 * math.sin(7 * s)
        wobble = rotation_xy(math.radians(0.8) * math.sin(11 * s), math.radians(0.6) * math.cos(5 * s))
        poses.append((rotation_z(heading) @ wobble, position))
    return poses


def project(omnisfm, camera, xyz):
    """Pixels of points in frame C, NaN where the camera does not see them."""
    table = "# x y z\n" + "".join("%.12g %.12g %.12g\n" % tuple(p) for p in xyz)
    out = subprocess.run([omnisfm, "project", "--camera", camera], input=table, text=True,
                         capture_output=True, check=True).stdout
    pixels = []
    for line in out.splitlines():
        if line.startswith("#") or not line.strip():
            continue
        u, v = line.split()[:2]
        pixels.append([float("nan")] * 2 if u == "-" else [float(u), float(v)])
    return np.array(pixels)


def make_sequence(args, seed, folder):
    rng = np.random.default_rng(seed)
    points = courtyard_points(rng, 400)
    poses = trajectory(rng, args.frames, args.length)
    in_camera = []
    for rotation, position in poses:
        in_camera.append((points - position) @ rotation)  # cam_from_world applied to each row
    pixels = project(args.omnisfm, args.camera, np.concatenate(in_camera)).reshape(
        args.frames, len(points), 2)

    # Tracks: a point is followed over a random stretch of the frames where it is seen; ids are
    # handed out as tracks start, up to `points` live at once.
    seen = ~np.isnan(pixels[:, :, 0])
    tracks = []  # (point, first, last)
    for p in rng.permutation(len(points)):
        frames = np.flatnonzero(seen[:, p])
        if len(frames) < 10:
            continue
        first = int(frames[0]) if rng.random() < 0.6 else int(rng.integers(frames[0], frames[-1] - 8))
        last = min(int(frames[-1]), first + int(rng.integers(30, args.frames)))
        if not seen[first:last + 1, p].all():
            continue
        tracks.append((p, first, last))
        if len(tracks) == args.points:
            break
    tracks.sort(key=lambda t: (t[1], t[0]))

    drifting = set(rng.choice(len(tracks), size=args.drifting, replace=False).tolist())
    lines = ["# frame track u v"]
    truth_outliers = []
    rows = []
    for track_id, (p, first, last) in enumerate(tracks):
        drift_start = first + int(rng.integers(3, max(4, (last - first) // 2)))
        rate = rng.uniform(args.drift_min, args.drift_max)
        direction = rng.normal(size=2)
        direction /= np.linalg.norm(direction)
        if track_id in drifting:
            truth_outliers.append((track_id, drift_start, rate * (last - drift_start)))
        noise = None
        for f in range(first, last + 1):
            # AR(1) in time with the given correlation from frame to frame, at the same sigma.
            draw = rng.normal(scale=args.noise, size=2)
            rho = args.noise_correlation
            noise = draw if noise is None else rho * noise + math.sqrt(1 - rho * rho) * draw
            uv = pixels[f, p] + noise
            if track_id in drifting and f > drift_start:
                uv = uv + direction * rate * (f - drift_start)
            rows.append((f, track_id, uv[0], uv[1]))
    rows.sort()
    lines += ["%d %d %.6f %.6f" % r for r in rows]
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, "tracks.vnl"), "w") as f:
        f.write("\n".join(lines) + "\n")
    with open(os.path.join(folder, "outliers_gt.vnl"), "w") as f:
        f.write("# track frame\n" + "".join("%d %d\n" % t[:2] for t in truth_outliers))
    with open(os.path.join(folder, "ground_truth.tum"), "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        for k, (rotation, position) in enumerate(poses):
            f.write("%g %.9f %.9f %.9f %.12f %.12f %.12f %.12f\n" %
                    ((0.5 * k,) + tuple(position) + quaternion(rotation)))
    return tracks, truth_outliers


def rejected(folder):
    ids = set()
    with open(os.path.join(folder, "outliers.vnl")) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            ids.add(int(line.split()[0]))
    return ids


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    parser.add_argument("omnisfm")
    parser.add_argument("camera")
    parser.add_argument("workdir")
    parser.add_argument("seeds", nargs="?", default="1-10")
    parser.add_argument("--frames", type=int, default=120)
    parser.add_argument("--length", type=float, default=5.0)
    parser.add_argument("--points", type=int, default=80)
    parser.add_argument("--drifting", type=int, default=6)
    parser.add_argument("--noise-correlation", type=float, default=0.0,
                        help="the tracks' noise correlated from frame to frame (AR(1), 0 <= it < 1)")
    parser.add_argument("--noise", type=float, default=0.2)
    parser.add_argument("--drift-min", type=float, default=0.05)
    parser.add_argument("--drift-max", type=float, default=0.3)
    parser.add_argument("--config", default=None)
    parser.add_argument("--sfm-camera", default=None,
                        help="the camera file sfm is given (default: CAMERA.ini, the one that made "
                             "the pixels); a calibration's error")
    parser.add_argument("--filter-only", action="store_true")
    parser.add_argument("--verbose", action="store_true")
    args = parser.parse_args()
    if not 0 <= args.noise_correlation < 1:
        parser.error("--noise-correlation must be at least 0 and below 1 (an AR(1) coefficient; "
                     "1 or more never forgets or grows without bound)")

    first, _, last = args.seeds.partition("-")
    seeds = range(int(first), int(last or first) + 1)
    config = args.config
    if args.filter_only:
        config = os.path.join(args.workdir, "filter_only.ini")
        os.makedirs(args.workdir, exist_ok=True)
        with open(config, "w") as f:
            f.write("[sfm]\nbatch = 0\n")

    print("# seed tracks drifting rejected right missed precision recall")
    totals = np.zeros(3)
    for seed in seeds:
        folder = os.path.join(args.workdir, "seed%d" % seed)
        tracks, truth = make_sequence(args, seed, folder)
        command = [args.omnisfm, "sfm", "--camera", args.sfm_camera or args.camera, "--tracks",
                   os.path.join(folder, "tracks.vnl"), "--out", os.path.join(folder, "out"),
                   "--ground-truth", os.path.join(folder, "ground_truth.tum")]
        if config:
            command += ["--config", config]
        subprocess.run(command, check=True, capture_output=True)
        found = rejected(os.path.join(folder, "out"))
        outliers = {t[0] for t in truth}
        if args.verbose:
            for t, _, drift in truth:
                print("#   track %d drifts %.1f px by its end: %s" % (t, drift, "rejected" if t in found else "kept"))
        right = len(found & outliers)
        totals += [len(found), right, len(outliers)]
        print("%d %d %d %d %d %d %.2f %.2f" % (seed, len(tracks), len(outliers), len(found), right,
                                            len(outliers) - right,
                                            right / len(found) if found else 1.0,
                                            right / len(outliers) if outliers else 1.0))
        sys.stdout.flush()
    print("# all: rejected %d, right %d, precision %.3f, recall %.3f" %
          (totals[0], totals[1], totals[1] / max(totals[0], 1), totals[1] / max(totals[2], 1)))


if __name__ == "__main__":
    main()
