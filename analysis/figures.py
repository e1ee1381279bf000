# SPDX-License-Identifier: BSD-3-Clause
"""What the figure scripts of analysis/ share: one style, one meaning of -o, one way to save,
one reader of run files.

Every script calls style() before it draws, takes its output with add_output(), and writes its
PNG through save_figure(), which refuses a figure drawn without the style or with an axis (or
colour bar) that has no label.

    -o PREFIX   writes PREFIX.png (and PREFIX.csv where the script writes a table; fig3.py
                PREFIXa.png and PREFIXb.png). A trailing .png is dropped: -o fig12a.png is
                -o fig12a.

The tables of `smpm stability`, `transport-stability` and `spectrum` are read with
read_table(path), which takes their earlier column names too (sparsempm.tables, loaded the same
way as the run file reader).

Every script reads the files of `smpm run` with read_run(path): sparsempm.read_run (frames and
times, series, particles(k), grid(k), matrices(k); complete frames only) when the package
imports, and otherwise the same reader, python/sparsempm/runfile.py of this checkout, loaded by
its path (it needs numpy and h5py, not the compiled extension), so the scripts run from a
checkout where the module is not built or not on the path.
"""
import os
import pathlib
import threading

# Paul Tol's "muted" qualitative colours (chosen to stay distinct to colour-blind readers),
# ordered so that neighbours in the cycle differ most.
COLOURS = ["#332288", "#CC6677", "#117733", "#AA4499", "#44AA99", "#999933", "#882255",
           "#88CCEE", "#DDCC77"]

# The rcParams of every figure: sizes a printed page keeps legible, a light grid, the colours
# above and the resolution of the PNGs.
RC = {
    "font.size": 10,
    "axes.titlesize": 10,
    "axes.labelsize": 10,
    "xtick.labelsize": 9,
    "ytick.labelsize": 9,
    "legend.fontsize": 8,
    "legend.framealpha": 0.9,
    "figure.titlesize": 11,
    "axes.grid": True,
    "grid.alpha": 0.35,
    "grid.linewidth": 0.6,
    "lines.linewidth": 1.5,
    "lines.markersize": 5,
    "image.cmap": "viridis",
    "figure.dpi": 100,
    "savefig.dpi": 150,
    "savefig.bbox": "tight",  # legends placed outside the axes stay in the picture
    "savefig.pad_inches": 0.05,
}

# The units of the quantities the scripts plot, for the unit systems of the examples: "input"
# (whatever consistent units the input uses: the vibrating bar's are dimensionless), "mm-ms-g"
# (mm, ms, g, MPa: the contact and shock examples) and "SI".
UNITS = {
    "input": dict.fromkeys(("length", "time", "velocity", "stress", "energy", "mass", "volume",
                            "momentum"), "input units"),
    "mm-ms-g": {"length": "mm", "time": "ms", "velocity": "m/s", "stress": "MPa", "energy": "mJ",
                "mass": "g", "volume": "mm$^3$", "momentum": "g m/s"},
    "none": dict.fromkeys(("length", "time", "velocity", "stress", "energy", "mass", "volume",
                           "momentum"), "input units"),  # output.units = "none"
    "SI": {"length": "m", "time": "s", "velocity": "m/s", "stress": "Pa", "energy": "J",
           "mass": "kg", "volume": "m$^3$", "momentum": "kg m/s"},
}

_styled = False


def style():
    """Sets the shared rcParams (RC, with COLOURS as the colour cycle) on matplotlib's Agg
    backend; returns matplotlib.pyplot. Call it before drawing."""
    global _styled
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from cycler import cycler
    plt.rcParams.update(RC)
    plt.rcParams["axes.prop_cycle"] = cycler(color=COLOURS)
    _styled = True
    return plt


def output_prefix(path):
    """The prefix named by -o: `path` without a trailing .png (fig12a.png → fig12a)."""
    text = str(path)
    return text[:-4] if text.lower().endswith(".png") else text


def add_output(ap, default, what="PREFIX.png"):
    """Adds -o/--output (also spelt --out) to the parser `ap`: the output prefix (`default`
    when not given; `what` says the files written), read back as args.out, to which the
    script applies output_prefix()."""
    ap.add_argument("-o", "--output", "--out", dest="out", default=default, metavar="PREFIX",
                    help=f"output prefix: writes {what}; a trailing .png is dropped"
                         + (f" (default: {default})" if default else ""))


def add_sets(ap):
    """Adds --set section.key=value (repeatable): entries of the input changed in every run a
    script makes, after its own (e.g. --set time.end=1 for a short run)."""
    ap.add_argument("--set", dest="sets", action="append", default=[], metavar="SECTION.KEY=VALUE",
                    help="change an input entry in every run, as smpm run --set (repeatable)")


def add_units(ap):
    """Adds --units (a key of UNITS) to the parser `ap`; unset, units_of() takes the run file's."""
    ap.add_argument("--units", choices=sorted(UNITS), default=None,
                    help="the input's unit system, for the axis labels (default: the run file's "
                         "output.units; input, when it states none, labels 'input units'; "
                         "mm-ms-g: mm, ms, g, MPa; SI)")


def units_of(given, run):
    """The key of UNITS for a run's labels: `given` (--units) if set, else the unit system the
    run file states (output.units, /@units: none, SI or mm-ms-g; none is "input")."""
    if given:
        return given
    stated = getattr(run, "units", "none")
    return stated if stated in UNITS else "input"


def set_values(sets):
    """--set texts as the {key: value} overrides of sparsempm.Model.from_toml: each value read
    as a TOML value (numbers, booleans, arrays), else kept as a string."""
    import tomllib
    out = {}
    for s in sets:
        key, sep, value = s.partition("=")
        if not sep:
            raise SystemExit(f"--set {s}: expected section.key=value")
        try:
            out[key.strip()] = tomllib.loads(f"v = {value}")["v"]
        except tomllib.TOMLDecodeError:
            out[key.strip()] = value
    return out


# Two curves coincide to plotting precision when they differ by less than this fraction of the
# plot's range at every point (a line is about 0.5% of the axis high).
COINCIDE = 0.002


def coincidences(curves):
    """{name: the earlier name whose curve it coincides with} for the curves (name: (x, y), in
    drawing order) that lie on an earlier one at every point, to COINCIDE of the range of all
    the y (NaN, a gap, where the other has one too)."""
    import numpy as np
    ys = np.concatenate([np.asarray(y, float) for _, y in curves.values()] or [np.zeros(1)])
    tol = COINCIDE * max(np.nanmax(ys) - np.nanmin(ys), 1e-12) if np.isfinite(ys).any() else 0
    first, same = [], {}
    for name, (x, y) in curves.items():
        x, y = np.asarray(x, float), np.asarray(y, float)
        for other in first:
            xo, yo = (np.asarray(v, float) for v in curves[other])
            if len(x) == len(xo) and np.allclose(x, xo) and \
                    np.array_equal(np.isnan(y), np.isnan(yo)) and \
                    np.nanmax(np.abs(y - yo), initial=0) <= tol:
                same[name] = other
                break
        else:
            first.append(name)
    return same


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


def save_figure(fig, prefix, tables=(), report=True):
    """Writes <prefix>.png from `fig`, prints the files written (the `tables` first; not with
    report=False) and returns the PNG's name.
    Refuses (ValueError) a figure drawn before style() or with an unlabelled axis
    (unlabelled_axes). With SMPM_FIGURE_DUMP=dir in the environment it also pickles the figure
    to dir/<name of prefix>.pickle, for tests that inspect it through matplotlib."""
    png = f"{prefix}.png"
    if not _styled:
        raise ValueError(f"{png}: drawn without figures.style()")
    missing = unlabelled_axes(fig)
    if missing:
        raise ValueError(f"{png}: axes without a label: {', '.join(missing)}")
    fig.tight_layout()
    from matplotlib.legend import Legend
    legends = [a for ax in fig.axes for a in ax.get_children() if isinstance(a, Legend)]
    # The picture holds what matplotlib counts (titles, labels, ...) and every legend beside
    # the axes, also those added with add_artist, which it leaves out.
    fig.savefig(png, bbox_extra_artists=fig.get_default_bbox_extra_artists() + legends)
    dump = os.environ.get("SMPM_FIGURE_DUMP")
    if dump:
        import pickle
        with open(pathlib.Path(dump) / (pathlib.Path(prefix).name + ".pickle"), "wb") as f:
            pickle.dump(fig, f)
    if report:
        print(", ".join([str(t) for t in tables] + [png]))
    return png


def run_smpm(smpm, src, out, sets):
    """Runs `smpm run src -o out -q --set s ...`; returns (the finished process, seconds).

    The scripts run --jobs of these at a time to use the cores, so each run takes one thread
    unless SMPM_THREADS is set (the results do not depend on it)."""
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


_readers = {}
_reader_lock = threading.Lock()  # the scripts read from several threads


def _package_reader(module, name):
    """sparsempm's function `name` (of python/sparsempm/`module`.py) when `import sparsempm`
    succeeds, else that file of this checkout loaded by its path (importlib)."""
    with _reader_lock:
        if name not in _readers:
            try:
                import sparsempm
                reader = getattr(sparsempm, name)
            except (ImportError, AttributeError):  # not built, not on the path, or older
                import importlib.util
                import sys
                file = pathlib.Path(__file__).resolve().parents[1] / "python" / "sparsempm" \
                    / f"{module}.py"
                if not file.exists():
                    raise ImportError(f"no {name}: sparsempm does not import and {file} is "
                                      f"missing")
                spec = importlib.util.spec_from_file_location(f"_sparsempm_{module}", file)
                loaded = importlib.util.module_from_spec(spec)
                sys.modules[spec.name] = loaded
                spec.loader.exec_module(loaded)
                reader = getattr(loaded, name)
            _readers[name] = reader
    return _readers[name]


def read_run(path):
    """The run file at `path` as a sparsempm Run: run.frames (the complete frames' numbers,
    ascending, so in time order) and run.times, run.series (one row per step), run.status,
    run.particles(k) (arrays of frame index k, -1 the last, with "@time" and "@step"),
    run.grid(k), run.matrices(k). The reader is sparsempm.read_run when `import sparsempm`
    succeeds, else python/sparsempm/runfile.py loaded by its path (importlib)."""
    return _package_reader("runfile", "read_run")(path)


def read_table(table):
    """The rows of a table of `smpm stability`, `transport-stability` or `spectrum` (a path or its
    lines) as dicts keyed by the current column names (critical_courant, simulation_courant,
    critical_fourier, configuration, ...), also from a table of the earlier names: sparsempm's
    read_table (python/sparsempm/tables.py, loaded as read_run's reader is)."""
    return _package_reader("tables", "read_table")(table)
