#!/usr/bin/env python3
"""graph_slam_reads_batch_graph.py GRAPH_SLAM BATCH_GRAPH

Runs stock `graph-slam --3d` on the batch.graph that omnisfm sfm wrote: --info must count every
vertex and edge of the file, and --levmarq must leave the vertices where they are, the batch's
poses being already the optimum of its relative poses (up to the 6 digits graph-slam writes)."""
import pathlib
import subprocess
import sys
import tempfile

graph_slam, batch_graph = sys.argv[1:3]
lines = pathlib.Path(batch_graph).read_text().splitlines()
vertices = {int(l.split()[1]): [float(x) for x in l.split()[2:8]]
            for l in lines if l.startswith("VERTEX3 ")}
edges = sum(1 for l in lines if l.startswith("EDGE3 "))
assert len(vertices) > 10 and edges == len(vertices) - 1, (len(vertices), edges)

info = subprocess.run([graph_slam, "--3d", "--info", "-i", batch_graph], check=True,
                      capture_output=True, text=True).stdout
for expected in (f"Edge count                         : {edges}",
                 f"Nodes count (in VERTEX2/3 entries) : {len(vertices)}"):
    assert expected in info, f"graph-slam --info did not say '{expected}':\n{info}"

with tempfile.TemporaryDirectory() as work:
    optimised = pathlib.Path(work) / "optimised.graph"
    subprocess.run([graph_slam, "--3d", "--levmarq", "--no-span", "-i", batch_graph,
                    "-o", str(optimised)], check=True, capture_output=True)
    moved = 0.0
    for l in optimised.read_text().splitlines():
        if not l.startswith("VERTEX3 "):
            continue
        fields = l.split()
        after = [float(x) for x in fields[2:8]]
        before = vertices.pop(int(fields[1]))
        moved = max(moved, max(abs(a - b) / max(1.0, abs(b)) for a, b in zip(after, before)))
assert not vertices, f"graph-slam's result lacks vertices {sorted(vertices)[:5]}"
assert moved < 1e-5, f"graph-slam --levmarq moved a vertex by {moved} (relative)"
print(f"graph-slam read {edges + 1} vertices and {edges} edges; --levmarq moved none "
      f"(at most {moved:.1e})")
