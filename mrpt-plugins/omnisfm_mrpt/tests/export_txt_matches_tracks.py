#!/usr/bin/env python3
"""export_txt_matches_tracks.py RAWLOG_EDIT PLUGIN RAWLOG TRACKS_VNL

Runs stock `rawlog-edit -p PLUGIN --export-txt` on RAWLOG and checks that the table it writes for
the tracked features (RAWLOG's stem + "_OMNI_TRACKS.txt", beside it) holds exactly the
observations of TRACKS_VNL, the tracks.vnl written with the rawlog: one row per frame,
"TIME FRAME COUNT" then "TRACK U V" per feature.

rawlog-edit 2.5 names its tables by joining the input's folder and stem with no separator
("dir/x.rawlog" gives "dirx_OMNI_TRACKS.txt"), so it is run in the rawlog's folder on its bare
name, as the README says to."""
import pathlib
import subprocess
import sys

rawlog_edit, plugin, rawlog, tracks_vnl = sys.argv[1:5]
rawlog = pathlib.Path(rawlog).resolve()
plugin = str(pathlib.Path(plugin).resolve())
table = rawlog.with_name(rawlog.stem + "_OMNI_TRACKS.txt")
table.unlink(missing_ok=True)
subprocess.run([rawlog_edit, "-p", plugin, "--export-txt", "-i", rawlog.name], check=True,
               stdout=subprocess.DEVNULL, cwd=rawlog.parent)

exported = []
lines = table.read_text().splitlines()
assert lines[0].startswith("%") and "FRAME FEATURE_COUNT" in lines[0], lines[0]
previous_time = None
for number, line in enumerate(lines[1:], start=2):
    fields = line.split()
    time, frame, count = float(fields[0]), int(fields[1]), int(fields[2])
    assert len(fields) == 3 + 3 * count, f"{table}:{number}: {count} features, {len(fields)} fields"
    assert previous_time is None or time > previous_time, f"{table}:{number}: time goes back"
    previous_time = time
    for i in range(count):
        track, u, v = fields[3 + 3 * i: 6 + 3 * i]
        exported.append((frame, int(track), float(u), float(v)))

expected = []
for line in pathlib.Path(tracks_vnl).read_text().splitlines():
    if line.startswith("#") or not line.strip():
        continue
    frame, track, u, v = line.split()
    expected.append((int(frame), int(track), float(u), float(v)))

if sorted(exported) != sorted(expected):
    missing = sorted(set(expected) - set(exported))[:5]
    extra = sorted(set(exported) - set(expected))[:5]
    sys.exit(f"{table}: {len(exported)} observations, {tracks_vnl}: {len(expected)}; "
             f"missing {missing}, unexpected {extra}")
frames = len(lines) - 1
print(f"{table}: {frames} frames, {len(exported)} observations, the same as {tracks_vnl}")
