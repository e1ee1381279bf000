# SPDX-License-Identifier: BSD-3-Clause
"""What the figure scripts of analysis/ share."""


def save_figure(fig, out):
    """Writes <out>.png from `fig` and names the two files a script wrote (<out>.csv too)."""
    fig.tight_layout()
    fig.savefig(out + ".png", dpi=130)
    print(f"{out}.csv, {out}.png")


def run_smpm(smpm, src, out, sets):
    """Runs `smpm run src -o out -q --set s ...`; returns (the finished process, seconds).

    The scripts run --jobs of these at a time to use the cores, so each run takes one thread
    unless SMPM_THREADS is set (the results do not depend on it)."""
    import os
    import subprocess
    import time
    args = [smpm, "run", str(src), "-o", str(out), "-q"]
    for s in sets:
        args += ["--set", s]
    env = dict(os.environ)
    env.setdefault("SMPM_THREADS", "1")
    start = time.time()
    r = subprocess.run(args, capture_output=True, text=True, env=env)
    return r, time.time() - start
