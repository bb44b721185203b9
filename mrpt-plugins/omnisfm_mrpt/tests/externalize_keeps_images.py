#!/usr/bin/env python3
"""externalize_keeps_images.py RAWLOG_EDIT PLUGIN RAWLOG OMNISFM IMAGES OMNISFM_SLAM

Stock `rawlog-edit --externalize` on a rawlog that `omnisfm simulate --rawlog --render` wrote:
every one of the IMAGES camera images must be stored as a PNG file beside the new rawlog, stock
`--list-images` must list them, and omnisfm must track the externalised rawlog's images (their
model from the rawlog's CObservationCameraModel) into exactly the tracks of the original; so
must omnisfm-slam, which reads it through MRPT, started from another folder."""
import pathlib
import subprocess
import sys
import tempfile

rawlog_edit, plugin, rawlog, omnisfm, images, omnisfm_slam = sys.argv[1:7]
images = int(images)

with tempfile.TemporaryDirectory() as work:
    work = pathlib.Path(work)
    external = work / "external.rawlog"
    subprocess.run([rawlog_edit, "-p", plugin, "--externalize", "-i", rawlog, "-o", str(external)],
                   check=True, capture_output=True)
    stored = sorted((work / "external_Images").glob("*.png"))
    assert len(stored) == images, f"{len(stored)} image files for {images} images"
    for png in stored:
        data = png.read_bytes()
        assert data.startswith(b"\x89PNG") and data.endswith(b"IEND\xaeB`\x82"), png

    listed = work / "list.txt"
    subprocess.run([rawlog_edit, "-p", plugin, "--list-images", "-i", str(external),
                    "--text-file-output",
                    str(listed)], check=True, capture_output=True, cwd=work)
    names = listed.read_text().split()
    assert sorted(names) == [p.name for p in stored], names[:3]

    for name, source in (("original", rawlog), ("external", str(external))):
        subprocess.run([omnisfm, "track", "--images", source, "--out",
                        str(work / name / "tracks.vnl")], check=True, capture_output=True)
    original = (work / "original" / "tracks.vnl").read_text()
    assert len(original.splitlines()) > images
    assert (work / "external" / "tracks.vnl").read_text() == original, "the tracks differ"
    slam = subprocess.run([omnisfm_slam, str(external), "--out", str(work / "slam"),
                           "--scene-every", "0"], check=True, capture_output=True, text=True,
                          cwd="/")
    assert f"omnisfm-slam: {images} camera frames" in slam.stdout, slam.stdout
print(f"{images} images externalised, listed and tracked as the original's")
