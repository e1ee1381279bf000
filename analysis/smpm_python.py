# SPDX-License-Identifier: BSD-3-Clause
"""The Python module sparsempm for the analysis scripts that can call the library directly.

A script adds the options with add_arguments() and calls sparsempm(args): the module from
--build (the directory holding the package, default build/python), else an installed one; None
with --cli or when it does not import, and the script then runs the `smpm` command instead.
"""
import pathlib
import sys

ROOT = pathlib.Path(__file__).resolve().parents[1]


def add_arguments(ap):
    ap.add_argument("--build", default=str(ROOT / "build" / "python"),
                    help="directory holding the Python package sparsempm (default build/python)")
    ap.add_argument("--cli", action="store_true",
                    help="run the smpm command even when the module imports")


def sparsempm(args):
    """The module sparsempm, or None (--cli, or not importable)."""
    if args.cli:
        return None
    build = str(pathlib.Path(args.build).resolve())
    if build not in sys.path:
        sys.path.insert(0, build)
    try:
        import sparsempm as module
    except ImportError:
        return None
    return module
