"""What the figure scripts of analysis/ share."""


def save_figure(fig, out):
    """Writes <out>.png from `fig` and names the two files a script wrote (<out>.csv too)."""
    fig.tight_layout()
    fig.savefig(out + ".png", dpi=130)
    print(f"{out}.csv, {out}.png")


def run_smpm(smpm, src, out, sets):
    """Runs `smpm run src -o out -q --set s ...`; returns (the finished process, seconds)."""
    import subprocess
    import time
    args = [smpm, "run", str(src), "-o", str(out), "-q"]
    for s in sets:
        args += ["--set", s]
    start = time.time()
    r = subprocess.run(args, capture_output=True, text=True)
    return r, time.time() - start
