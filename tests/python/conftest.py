"""Shared set-up of the Python module's tests: the vibrating-bar example, the `smpm` command
(SMPM, set by ctest) and the source tree (SMPM_SOURCE)."""
import os
import pathlib
import subprocess

import pytest

import sparsempm as smpm

SOURCE = pathlib.Path(os.environ.get("SMPM_SOURCE", pathlib.Path(__file__).resolve().parents[2]))
BAR = SOURCE / "examples" / "vibrating_bar.toml"
TWO_BLOCKS = SOURCE / "examples" / "two_block_compression.toml"
SMPM = os.environ.get("SMPM", "smpm")


def run_smpm(*args, cwd=None):
    """`smpm args...` with its exit status, standard output and error."""
    return subprocess.run([SMPM, *map(str, args)], capture_output=True, text=True, cwd=cwd,
                          timeout=600)


@pytest.fixture
def bar():
    """The free-vibrating bar of FMPM 2026 §3.3 (CPDI, FLIP, C = 0.5) as `smpm run` reads it."""
    return smpm.Model.from_toml(str(BAR))
