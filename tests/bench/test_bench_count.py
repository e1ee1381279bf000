#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""scripts/bench-count's counts repeat: two counts of its small problem (the example's plate,
640 particles, 9 steps between the short and the long run) give the same instructions per
particle-step, on 1 and on 2 threads, to five significant digits: every number within 0.1 of
about 3,300 per particle-step (576 instructions of the 19 million counted), frames taken with
other (below). Under a loaded ctest the total moved by 0.016 and frames alone by 0.45. The small
plate is below the library's threshold for splitting work (1,024 rows), so its 2-thread run
works on one thread: this tests the counting, not the threads' split."""
import csv
import os
import pathlib
import subprocess
import sys
import tempfile

SOURCE = pathlib.Path(os.environ["SMPM_SOURCE"])
BUILD = pathlib.Path(os.environ["SMPM_BUILD"])


def count(path):
    subprocess.run([sys.executable, str(SOURCE / "scripts" / "bench-count"), "--build", str(BUILD),
                    "--small", "--csv", str(path)], check=True, stdout=subprocess.DEVNULL)
    with open(path) as f:
        return list(csv.DictReader(f))


with tempfile.TemporaryDirectory() as tmp:
    first, second = count(pathlib.Path(tmp) / "a.csv"), count(pathlib.Path(tmp) / "b.csv")
# Frames are written by a thread of their own, begun by write_frame: how much of the writing
# runs under write_frame on the main thread (`frames`) and how much in that thread (`other`)
# follows the scheduler, under a loaded ctest by up to 0.5 per particle-step. Their sum repeats.
NUMBERS = ["total", "balance", "assembly", "contact", "heat prep", "m~", "stages", "energies",
           "series", "frames + other"]
for a, b in zip(first, second, strict=True):
    for r in (a, b):
        if r["frames"]:
            r["frames + other"] = str(float(r.pop("frames")) + float(r.pop("other")))
    for k in a:
        if k in NUMBERS and a[k]:
            assert abs(float(a[k]) - float(b[k])) <= 0.1, f"{k} moved: {a[k]} -> {b[k]}"
        else:
            assert a[k] == b[k], f"{k}: {a[k]} -> {b[k]}"
assert [(r["threads"], r["steps"], r["particles"]) for r in first] == [("1", "9", "640"),
                                                                       ("2", "9", "640")], first
one = first[0]
# The plate's step: assembly and the stages are most of it (both positive), no contact or heat.
assert float(one["assembly"]) > 0 and float(one["stages"]) > 0, one
assert float(one["contact"]) == 0 and float(one["heat prep"]) == 0, one
print("bench-count: two counts within 0.1 per particle-step:",
      [(r["total"], s["total"]) for r, s in zip(first, second)])
