# SPDX-License-Identifier: BSD-3-Clause
"""Shared set-up of the Python module's tests: the vibrating-bar example, the `smpm` command
(SMPM, set by ctest) and the source tree (SMPM_SOURCE)."""
import os
import pathlib
import signal
import subprocess
import threading

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


class interrupting:
    """Sends SIGINT to this process every `every` seconds while the `with` block runs (from when
    `started`, an Event, is set, if given), as a user pressing Ctrl-C until the computation
    stops. Python's handler is replaced for the block by one that records each signal in `seen`
    and, at the first, raises KeyboardInterrupt (as Python's own does) when `raises`; the others
    raise nothing, so a signal sent just before or after the computation does no harm."""

    def __init__(self, every=0.2, raises=True, started=None):
        self.every, self.raises, self.started, self.seen = every, raises, started, []

    def _handler(self, signum, frame):
        self.seen.append(signum)
        if self.raises and len(self.seen) == 1:
            raise KeyboardInterrupt

    def __enter__(self):
        self._done = threading.Event()
        self._previous = signal.signal(signal.SIGINT, self._handler)

        def send():
            if self.started is not None:
                while not self.started.wait(0.05):
                    if self._done.is_set():
                        return
            while not self._done.wait(self.every):
                os.kill(os.getpid(), signal.SIGINT)

        self._thread = threading.Thread(target=send, daemon=True)
        self._thread.start()
        return self

    def __exit__(self, *exc):
        self._done.set()
        self._thread.join()
        for _ in range(100):  # a signal still in flight runs the handler here
            pass
        signal.signal(signal.SIGINT, self._previous)
        return False
