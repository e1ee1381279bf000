#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""smpm-mpi spectrum on 2 and 3 ranks writes the table of smpm spectrum (with ρ(T) at C = 0.5
on the bar): every number equal to 1e-8 relative (1e-12 absolute for truncation errors at round-off: the sums run in another
order across ranks); a bad input is reported once, by rank 0, with exit status 2 and no table.

Usage: compare_spectrum.py SMPM SMPM_MPI MPIEXEC EXAMPLES_DIR
"""
import csv
import os
import pathlib
import subprocess
import sys
import tempfile

smpm, smpm_mpi, mpiexec, examples = sys.argv[1:5]
env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1",
           OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
failures = []


def table(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


with tempfile.TemporaryDirectory() as tmp:
    tmp = pathlib.Path(tmp)
    for example in ("vibrating_bar", "vibrating_plate"):
        toml = f"{examples}/{example}.toml"
        ref = tmp / f"{example}_serial.csv"
        courant = ["--courant", "0.5"] if example == "vibrating_bar" else []
        subprocess.run([smpm, "spectrum", toml, "--order", "1,4,16", "--blend-every", "1,2",
                        *courant, "-o", str(ref)], env=env, check=True, capture_output=True)
        for ranks in (2, 3):
            out = tmp / f"{example}_{ranks}.csv"
            subprocess.run([mpiexec, "-n", str(ranks), smpm_mpi, "spectrum", toml, "--order",
                            "1,4,16", "--blend-every", "1,2", *courant, "-o", str(out)],
                           env=env, check=True, capture_output=True)
            a, b = table(ref), table(out)
            if len(a) != len(b):
                failures.append(f"{example} on {ranks} ranks: {len(b)} rows, serial {len(a)}")
                continue
            worst = 0.0
            for ra, rb in zip(a, b):
                for key, va in ra.items():
                    if va in ("", None):
                        if rb[key] != va:
                            failures.append(f"{example} {ranks}: {key} '{rb[key]}' not empty")
                        continue
                    x, y = float(va), float(rb[key])
                    tol = 1e-8 * abs(x) + (1e-12 if key == "truncation_error" else 0.0)
                    worst = max(worst, abs(x - y) / max(abs(x), 1e-300))
                    if abs(x - y) > tol:
                        failures.append(f"{example} on {ranks} ranks, order {ra['order']}: "
                                        f"{key} {y} against {x}")
            print(f"{example} on {ranks} ranks: {len(b)} rows, largest relative difference "
                  f"{worst:.1e}")
    # A bad input: one message (rank 0), exit status 2, no table.
    bad = tmp / "bad.toml"
    bad.write_text("[grid]\ndim = 7\n")
    out = tmp / "bad.csv"
    r = subprocess.run([mpiexec, "-n", "2", smpm_mpi, "spectrum", str(bad), "-o", str(out)],
                       env=env, capture_output=True, text=True)
    lines = [l for l in r.stderr.splitlines() if l.startswith("smpm-mpi: error:")]
    if r.returncode != 2 or len(lines) != 1 or "bad.toml" not in lines[0] or out.exists():
        failures.append(f"bad input: exit {r.returncode}, messages {lines}, table {out.exists()}")
    else:
        print("bad input:", lines[0])

for f in failures:
    print("FAILED:", f)
sys.exit(1 if failures else 0)
