#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""smpm-mpi writes smpm's tables across ranks.

spectrum: smpm-mpi spectrum on 2 and 3 ranks writes the table of smpm spectrum (with ρ(T) at
C = 0.5 on the bar): every number equal to 1e-8 relative (1e-12 absolute for truncation errors at
round-off: the sums run in another order across ranks); a bad input is reported once, by rank 0,
with exit status 2 and no table.

stability: smpm-mpi stability on 1, 2 and 3 ranks writes the spectral columns of smpm stability's
table (FLIP, FMPM(k), blended, periodic and exact rows of the bar over two lattice shifts, and
the plate with uGIMP on 2 ranks, whose T is above the dense limit): the same C* and
configuration in every row. C* is a point of the search's bisection (resolution
1e-3), decided by ρ(T(C)) ≤ 1 + 10⁻⁶ with ρ equal across ranks to 1e-8, so the rows are equal
unless a ρ lies within 1e-8 of the threshold: the test allows one resolution step (1e-3) and
prints the largest difference. --method simulation is refused with exit status 2.

Usage: compare_tables.py spectrum|stability SMPM SMPM_MPI MPIEXEC EXAMPLES_DIR
"""
import math
import os
import pathlib
import subprocess
import sys
import tempfile

command, smpm, smpm_mpi, mpiexec, examples = sys.argv[1:6]
env = dict(os.environ, OMP_NUM_THREADS="1", OMPI_ALLOW_RUN_AS_ROOT="1",
           OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1", OMPI_MCA_rmaps_base_oversubscribe="1")
failures = []


def _tables_module():
    """python/sparsempm/tables.py of this checkout, loaded by its path (the standard library
    only): the one reader of the tables, which takes their earlier column names too."""
    import importlib.util
    file = pathlib.Path(__file__).resolve().parents[2] / "python" / "sparsempm" / "tables.py"
    spec = importlib.util.spec_from_file_location("_sparsempm_tables", file)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


table = _tables_module().read_table


def bad_input(tmp, args):
    """A bad input or option: one message (rank 0), exit status 2, no table."""
    out = tmp / "bad.csv"
    r = subprocess.run([mpiexec, "-n", "2", smpm_mpi, *args, "-o", str(out)], env=env,
                       capture_output=True, text=True)
    lines = [l for l in r.stderr.splitlines() if l.startswith("smpm-mpi: error:")]
    if r.returncode != 2 or len(lines) != 1 or out.exists():
        failures.append(f"{args}: exit {r.returncode}, messages {lines}, table {out.exists()}")
    else:
        print("refused:", lines[0])
    return lines


def spectrum(tmp):
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
    bad = tmp / "bad.toml"
    bad.write_text("[grid]\ndim = 7\n")
    lines = bad_input(tmp, ["spectrum", str(bad)])
    if lines and "bad.toml" not in lines[0]:
        failures.append(f"the message does not name the file: {lines[0]}")


def stability(tmp):
    toml = f"{examples}/vibrating_bar.toml"
    options = ["--order", "1,4,16", "--blend-alpha", "0.8", "--blend-every", "2",
               "--periodic-cx", "2", "--shifts", "2", "-q"]
    ref = tmp / "serial.csv"
    subprocess.run([smpm, "stability", toml, *options, "-o", str(ref)], env=env, check=True,
                   capture_output=True)
    tables = {"smpm": table(ref)}
    for ranks in (1, 2, 3):
        out = tmp / f"stability_{ranks}.csv"
        subprocess.run([mpiexec, "-n", str(ranks), smpm_mpi, "stability", toml, *options, "-o",
                        str(out)], env=env, check=True, capture_output=True)
        tables[f"{ranks} ranks"] = table(out)
    one = tables["1 ranks"]
    for name, t in tables.items():
        if name == "1 ranks":
            continue
        if len(t) != len(one):
            failures.append(f"stability on {name}: {len(t)} rows, 1 rank {len(one)}")
            continue
        worst = 0.0
        for ra, rb in zip(one, t):
            row = f"{ra['velocity']} order {ra['order']} alpha {ra['blend_alpha']} " \
                  f"cx {ra['periodic_cx']}"
            for key in ("velocity", "order", "blend_alpha", "blend_every", "periodic_cx",
                        "position_alpha", "configuration", "spectral_status", "small_courant"):
                if ra[key] != rb[key]:
                    failures.append(f"{name}, {row}: {key} '{rb[key]}' against '{ra[key]}'")
            x, y = float(ra["critical_courant"]), float(rb["critical_courant"])
            if not (math.isfinite(x) and math.isfinite(y)):
                if not x == y:  # inf equals inf; NaN (no C* found) fails
                    failures.append(f"{name}, {row}: C* {y} against {x} on 1 rank")
                continue
            worst = max(worst, abs(x - y))
            if abs(x - y) > 1e-3:  # one step of the search's resolution
                failures.append(f"{name}, {row}: C* {y} against {x} on 1 rank")
        print(f"stability on {name} against 1 rank: {len(t)} rows, largest |dC*| {worst:.1e}")
    for r in one:
        print(f"  {r['velocity']:5} {r['order']:>3} {r['blend_alpha']:>4} {r['periodic_cx']:>3} "
              f"C* {r['critical_courant']} ({r['configuration']}, {r['spectral_status']})")
    # The plate with uGIMP: 3840 rows of T, above the dense limit, where ρ(T) is the power
    # iterations' growth from the serial start vector on every rank count.
    plate = f"{examples}/vibrating_plate.toml"
    options = ["--order", "1,4", "--blend-alpha", "0.8", "--blend-every", "2", "--periodic-cx",
               "none", "--shifts", "2", "-q", "--set", "step.shape=gimp"]
    subprocess.run([smpm, "stability", plate, "--method", "spectral", *options, "-o",
                    str(tmp / "plate.csv")], env=env, check=True, capture_output=True)
    subprocess.run([mpiexec, "-n", "2", smpm_mpi, "stability", plate, *options, "-o",
                    str(tmp / "plate_2.csv")], env=env, check=True, capture_output=True)
    worst = 0.0
    for ra, rb in zip(table(tmp / "plate.csv"), table(tmp / "plate_2.csv")):
        x, y = float(ra["critical_courant"]), float(rb["critical_courant"])
        worst = max(worst, abs(x - y))
        if abs(x - y) > 1e-3 or ra["configuration"] != rb["configuration"]:
            failures.append(f"plate {ra['velocity']} {ra['order']}: C* {y} "
                            f"({rb['configuration']}) against {x} ({ra['configuration']})")
    print(f"plate (uGIMP) on 2 ranks against smpm: largest |dC*| {worst:.1e}")
    bad_input(tmp, ["stability", toml, "--method", "simulation"])


with tempfile.TemporaryDirectory() as tmp:
    {"spectrum": spectrum, "stability": stability}[command](pathlib.Path(tmp))

for f in failures:
    print("FAILED:", f)
sys.exit(1 if failures else 0)
