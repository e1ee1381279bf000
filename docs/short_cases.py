# SPDX-License-Identifier: BSD-3-Clause
"""The analysis scripts on their short cases, for the study pages (docs/build.py).

The cases are tests/python/figure_cases.py's, the ones the figure test (python.figures) draws:
each script runs as a user runs it (/usr/bin/python3 analysis/NAME.py ARGS, one thread, two
at a time) in OUT/NAME/, and OUT/manifest.json records its command line (relative to its
directory) and its PNGs, which the `short-case` directive of the pages shows.
"""

import concurrent.futures
import json
import os
import pathlib
import subprocess
import sys
import time

SOURCE = pathlib.Path(__file__).resolve().parent.parent


def draw(name, case, out, env):
    w = out / name.removesuffix(".py")
    w.mkdir()
    start = time.monotonic()
    args, pngs, _ = case(w)
    r = subprocess.run(["/usr/bin/python3", SOURCE / "analysis" / name, *map(str, args)],
                       capture_output=True, text=True, cwd=w, env=env, timeout=600)
    if r.returncode != 0:
        raise RuntimeError(f"analysis/{name} on its short case: exit status {r.returncode}: "
                           f"{r.stderr.strip()[-2000:]}")
    shown = [str(a).replace(f"{w}/", "").replace(f"{SOURCE}/", "")
             .replace(str(pathlib.Path(os.environ["SMPM"]).parents[1]), "build") for a in args]
    return {"command": " ".join(["python3", f"analysis/{name}", *shown]),
            "pngs": [f"{name.removesuffix('.py')}/{pathlib.Path(p).name}.png" for p in pngs],
            "seconds": round(time.monotonic() - start, 1)}


def draw_all(out, build):
    """Draws every case into `out` (made anew) with the programs of the CMake build tree
    `build`; returns the manifest."""
    os.environ["SMPM"], os.environ["SMPM_SOURCE"] = str(build / "apps" / "smpm"), str(SOURCE)
    sys.path[:0] = [str(build / "python"), str(SOURCE / "tests" / "python")]
    import figure_cases  # noqa: E402  (reads SMPM and SMPM_SOURCE)
    out.mkdir(parents=True)
    env = dict(figure_cases.env(), PYTHONDONTWRITEBYTECODE="1")
    with concurrent.futures.ThreadPoolExecutor(2) as pool:
        futures = {n: pool.submit(draw, n, c, out, env) for n, c in figure_cases.CASES.items()}
        manifest = {n.removesuffix(".py"): f.result() for n, f in futures.items()}
    (out / "manifest.json").write_text(json.dumps(manifest, indent=1))
    return manifest
