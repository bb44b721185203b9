#!/usr/bin/env python3
"""Kills each writing verb with SIGKILL at random moments and checks what is left.

usage: kill_test.py OMNISFM SHARE_DIR REAL_DATA_DIR [--trials N] [--seed S]

For every verb the output first holds an earlier run's result (made from other input). After
each kill, every output must be exactly that earlier result, or the new result whole (the file
set of an uninterrupted run, each file complete): never a half-written file. Writers' temporaries
a kill leaves are hidden names that the next run removes, which is checked at the end.
"""

import argparse
import filecmp
import gzip
import os
import random
import shutil
import signal
import subprocess
import sys
import tempfile
import time
import zlib

PNG_END = b"IEND\xaeB`\x82"


def run(cmd, **kwargs):
    result = subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, **kwargs)
    if result.returncode != 0:
        sys.exit("failed: %s\n%s" % (" ".join(cmd), result.stderr.decode(errors="replace")))
    return result


def tree(path):
    """Relative paths of the files under path (path itself when it is a file); None if absent."""
    if not os.path.exists(path):
        return None
    if os.path.isfile(path):
        return {""}
    return {os.path.relpath(os.path.join(d, f), path) for d, _, fs in os.walk(path) for f in fs}


def same_tree(a, b):
    files = tree(a)
    if files != tree(b):
        return False
    return all(filecmp.cmp(os.path.join(a, f) if f else a, os.path.join(b, f) if f else b,
                           shallow=False) for f in files)


def whole(path):
    """A written file's own sign of completeness: PNG's end chunk, a text's final newline."""
    with open(path, "rb") as f:
        data = f.read()
    if path.endswith(".png"):
        return data.endswith(PNG_END)
    if data.startswith(b"\x1f\x8b"):  # gzip (MRPT's scenes): its trailer checks the whole
        try:
            gzip.decompress(data)
            return True
        except (EOFError, OSError, zlib.error):
            return False
    return len(data) > 0 and data.endswith(b"\n")


class Verb:
    def __init__(self, name, outputs, old_cmd, new_cmd):
        self.name, self.outputs, self.old_cmd, self.new_cmd = name, outputs, old_cmd, new_cmd


def check_output(output, earlier, reference):
    """'earlier', 'new' or a description of what is wrong."""
    if same_tree(output, earlier):
        return "earlier"
    files = tree(output)
    if files is None:
        return "the earlier output is gone and no new one is there"
    if files != tree(reference):
        return "neither the earlier output nor the new one: files %s" % sorted(files)[:8]
    for f in files:
        path = os.path.join(output, f) if f else output
        if not whole(path):
            return "a half-written file: %s" % path
    return "new"


def hidden_leftovers(folder):
    return sorted(n for n in os.listdir(folder) if ".partial-" in n or ".previous-" in n or
                  ".tmp-" in n)


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("omnisfm")
    parser.add_argument("share")
    parser.add_argument("real_data")
    parser.add_argument("--trials", type=int, default=8)
    parser.add_argument("--seed", type=int, default=1)
    args = parser.parse_args()
    rng = random.Random(args.seed)
    o = args.omnisfm
    work = tempfile.mkdtemp(prefix="omnisfm-kill-")
    inputs = os.path.join(work, "inputs")
    os.makedirs(inputs)
    out = os.path.join(work, "out")

    # Inputs of two kinds for each verb: the earlier run's and the killed run's.
    for seed in (1, 2):
        run([o, "simulate", "--scenario", "lab", "--seed", str(seed), "--rawlog",
             "--out", os.path.join(inputs, "lab%d" % seed)])
        run([o, "simulate", "--scenario", "rover", "--seed", str(seed), "--render", "--width",
             "160", "--height", "120", "--samples", "1",
             "--out", os.path.join(inputs, "rover%d" % seed)])
    lab = lambda s, f: os.path.join(inputs, "lab%d" % s, f)
    rover = lambda s, f: os.path.join(inputs, "rover%d" % s, f)
    vmr = os.path.join(args.real_data, "vmr")
    cameras = os.path.join(args.share, "cameras")

    # The real checkerboards where the shared data is at hand, else the simulated lab's surveyed
    # targets (a shorter solve, so fewer kills land inside it).
    real = os.path.exists(os.path.join(vmr, "corners.vnl"))
    if not real:
        print("calibrate: %s not found, the simulated lab's targets instead" % vmr)

    def calibrate(estimate):
        if not real:
            s = 1 if estimate == "mirror-pose" else 2
            return lambda dest: [o, "calibrate", "--camera", lab(s, "camera.ini"), "--targets",
                                 lab(s, "targets.vnl"), "--observations",
                                 lab(s, "observations.vnl"), "--out",
                                 os.path.join(dest, "vmr.ini")]
        return lambda dest: [o, "calibrate", "--camera", os.path.join(cameras, "vmr-initial.ini"),
                             "--corners", os.path.join(vmr, "corners.vnl"), "--board",
                             os.path.join(vmr, "board.vnl"), "--estimate", estimate,
                             "--out", os.path.join(dest, "vmr.ini")]

    verbs = [
        Verb("simulate", ["sim"],
             lambda d: [o, "simulate", "--scenario", "lab", "--seed", "3", "--out",
                        os.path.join(d, "sim")],
             lambda d: [o, "simulate", "--scenario", "crane", "--out", os.path.join(d, "sim")]),
        Verb("sfm", ["sfm"],
             lambda d: [o, "sfm", "--camera", lab(1, "camera.ini"), "--tracks",
                        lab(1, "tracks.vnl"), "--out", os.path.join(d, "sfm")],
             lambda d: [o, "sfm", "--camera", lab(2, "camera.ini"), "--tracks",
                        lab(2, "tracks.vnl"), "--out", os.path.join(d, "sfm")]),
        Verb("run", ["run"],
             lambda d: [o, "run", lab(1, "dataset.rawlog"), "--camera", lab(1, "camera.ini"),
                        "--out", os.path.join(d, "run")],
             lambda d: [o, "run", lab(2, "dataset.rawlog"), "--camera", lab(2, "camera.ini"),
                        "--out", os.path.join(d, "run")]),
        Verb("calibrate", ["vmr.ini", "vmr.report"], calibrate("mirror-pose"),
             calibrate("mirror-pose,intrinsics")),
        Verb("track", ["track/tracks.vnl", "track/frames.vnl"],
             lambda d: [o, "track", "--camera", rover(1, "camera.ini"), "--images",
                        rover(1, "images"), "--out", os.path.join(d, "track", "tracks.vnl")],
             lambda d: [o, "track", "--camera", rover(2, "camera.ini"), "--images",
                        rover(2, "images"), "--out", os.path.join(d, "track", "tracks.vnl")]),
        Verb("export-mrcal", ["model.cameramodel"],
             lambda d: [o, "export-mrcal", "--camera", os.path.join(cameras, "hyperbolic.ini"),
                        "--distance", "10", "--out", os.path.join(d, "model.cameramodel")],
             lambda d: [o, "export-mrcal", "--distance", "10", "--out",
                        os.path.join(d, "model.cameramodel")]),
    ]

    # Boards in raw images, where the real ones are at hand: an image, then two others.
    if real:
        for name, images in (("boards1", ["VMRImage0.jpg"]),
                             ("boards2", ["VMRImage3.jpg", "VMRImage8.jpg"])):
            os.makedirs(os.path.join(inputs, name))
            for image in images:
                shutil.copy(os.path.join(vmr, image), os.path.join(inputs, name, image))
        verbs.append(Verb(
            "detect-corners", ["corners.vnl", "corners.report"],
            *[(lambda n: lambda d: [o, "detect-corners", "--images", os.path.join(inputs, n),
                                    "--object-width-n", "6", "--object-height-n", "7", "--out",
                                    os.path.join(d, "corners.vnl")])(n)
              for n in ("boards1", "boards2")]))

    failures = []
    for verb in verbs:
        earlier, reference = os.path.join(work, verb.name, "earlier"), os.path.join(
            work, verb.name, "reference")
        os.makedirs(earlier)
        os.makedirs(reference)
        run(verb.old_cmd(earlier))
        start = time.monotonic()
        run(verb.new_cmd(reference))
        duration = time.monotonic() - start
        outcomes = {"earlier": 0, "new": 0}
        output_folders = sorted({os.path.dirname(p) for p in verb.outputs})
        leftovers = os.path.join(work, verb.name, "leftovers")
        shutil.copytree(earlier, leftovers, symlinks=True)
        for trial in range(args.trials):
            shutil.rmtree(out, ignore_errors=True)
            shutil.copytree(earlier, out, symlinks=True)
            delay = rng.uniform(0.05, 1.1) * duration
            process = subprocess.Popen(verb.new_cmd(out), stdout=subprocess.DEVNULL,
                                       stderr=subprocess.DEVNULL)
            time.sleep(delay)
            process.send_signal(signal.SIGKILL)
            process.wait()
            for output in verb.outputs:
                verdict = check_output(os.path.join(out, output), os.path.join(earlier, output),
                                       os.path.join(reference, output))
                if verdict in outcomes:
                    outcomes[verdict] += 1
                else:
                    failures.append("%s killed after %.2f s: %s: %s" %
                                    (verb.name, delay, output, verdict))
            # What the killed writers left is gathered, for a completed run to remove.
            for folder in output_folders:
                os.makedirs(os.path.join(leftovers, folder), exist_ok=True)
                for name in hidden_leftovers(os.path.join(out, folder)):
                    source = os.path.join(out, folder, name)
                    target = os.path.join(leftovers, folder, name)
                    if os.path.isdir(source):
                        shutil.copytree(source, target, symlinks=True)
                    else:
                        shutil.copy(source, target)
        abandoned = sum(len(hidden_leftovers(os.path.join(leftovers, f))) for f in output_folders)
        run(verb.new_cmd(leftovers))
        remaining = 0
        for folder in output_folders:
            left = hidden_leftovers(os.path.join(leftovers, folder))
            remaining += len(left)
            if left:
                failures.append("%s: a completed run left the killed runs' %s" % (verb.name, left))
        print("%-12s %.2f s uninterrupted; after %d kills: %d outputs the earlier result, %d the "
              "new one; %d temporaries left by the kills, %d of them removed by the next run" %
              (verb.name, duration, args.trials, outcomes["earlier"], outcomes["new"], abandoned,
               abandoned - remaining))

    shutil.rmtree(work, ignore_errors=True)
    for failure in failures:
        print("FAILED:", failure)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
