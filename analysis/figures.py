# SPDX-License-Identifier: BSD-3-Clause
"""What the figure scripts of analysis/ share."""


def unlabelled_axes(fig):
    """The axes of `fig` (plots and colour bars) without a label on an axis they show: a
    figure a reviewer accepts has units and labels on every axis."""
    fig.canvas.draw()  # the tick labels are set when drawn

    def shows(labels):
        return any(t.get_visible() and t.get_text() for t in labels)

    missing = []
    for ax in fig.axes:
        if not ax.axison:
            continue
        name = ax.get_title() or ax.get_label() or "axes"
        if shows(ax.get_xticklabels()) and not ax.get_xlabel():
            missing.append(f"{name}: x")
        if shows(ax.get_yticklabels()) and not ax.get_ylabel():  # not a shared, hidden y
            missing.append(f"{name}: y")
    return missing


def save_figure(fig, out):
    """Writes <out>.png from `fig` and names the two files a script wrote (<out>.csv too).
    Refuses (ValueError) a figure with an unlabelled axis (unlabelled_axes)."""
    missing = unlabelled_axes(fig)
    if missing:
        raise ValueError(f"{out}.png: axes without a label: {', '.join(missing)}")
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
