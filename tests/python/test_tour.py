# SPDX-License-Identifier: BSD-3-Clause
"""The README's first run: its commands run as written (from the source tree, with this build's
smpm) print the README's block, and its sentences, and the getting-started page's, state what the
runs show (the energy change and swing, PIC's dissipation, the unstable run's exit status 3).
"""
import re
import subprocess

import h5py
import numpy as np

from conftest import SOURCE
from figure_cases import SMPM, env


# The README's first run: its commands, what they print, and its sentences; the getting-started
# page of the site makes the same claims of the same runs (its commands' output is the site
# build's own).

def tour_step_2():
    """(the commands, the printed block, the prose) of the README's first run."""
    readme = (SOURCE / "README.md").read_text()
    step = readme[readme.index("## A first run"):]
    step = step[:step.index("\nThe same step as matrix products")]
    blocks = re.findall(r"```(\w*)\n(.*?)```", step, re.S)
    commands = [line.split("#")[0].split() for line in blocks[0][1].splitlines() if line.strip()]
    assert blocks[0][0] == "sh" and len(blocks) == 2
    printed = " ".join(line.strip() for line in blocks[1][1].splitlines() if line.strip())
    prose = " ".join(step[step.rindex("```") + 3:].split())
    return commands, printed, prose, blocks[0][1]


def getting_started_prose():
    """The getting-started page's paragraph on the same runs."""
    page = (SOURCE / "docs" / "getting-started.md").read_text()
    start = page.index("Kinetic and strain energy exchange")
    return " ".join(page[start:page.index("```", start)].split())


def command(words):
    """A README command line as run from the source tree, with this build's smpm."""
    out = []
    for i, w in enumerate(words):
        if i == 0 and w == "build/apps/smpm":
            out.append(SMPM)
        elif i == 0 and w.startswith("analysis/"):
            out += ["/usr/bin/python3", str(SOURCE / w)]
        elif w.startswith("examples/"):
            out.append(str(SOURCE / w))
        else:
            out.append(w)
    return out


RUN_LINE = (r"completed (\d+) steps in [\d.]+ s \(\d+ steps/s\); total energy (\S+) -> (\S+) "
            r"\(([-+]\d+\.\d+)%\);? (\d+) frames in (\S+) \(ParaView: (\S+)\)")


def test_the_tour_prints_the_readme_numbers(tmp_path):
    commands, printed, prose, block = tour_step_2()
    assert [c[:2] for c in commands] == [["build/apps/smpm", "run"], ["analysis/plot_energy.py",
                                                                      "vibrating_bar.h5"]]
    outputs = []
    for words in commands:
        r = subprocess.run(command(words), capture_output=True, text=True, cwd=tmp_path,
                           env=env(), timeout=120)
        assert r.returncode == 0, r.stderr
        outputs.append(r.stdout)
    # The run prints the README's block: steps, energies and change exactly, the time aside.
    readme = re.fullmatch(RUN_LINE, printed)
    ran = re.search(RUN_LINE, " ".join(outputs[0].split()))
    assert readme and ran, (printed, outputs[0])
    assert readme.groups() == ran.groups()
    steps, e0, e1, change = ran[1], ran[2], ran[3], float(ran[4])
    # plot_energy.py writes the file its comment names and prints the same numbers.
    png = re.search(r"# writes (\S+\.png)", block)[1]
    assert (tmp_path / png).stat().st_size > 20000
    assert f"{png}: {steps} steps, total energy {e0} -> {e1} ({change:+.4f}%)" in outputs[1]
    # "after five periods the total is within 0.041% of its start": the change, rounded.
    for text in (prose, getting_started_prose()):
        within = re.search(r"within (\d+\.\d+)% of its start", text)[1]
        assert within == f"{abs(change):.{len(within.split('.')[1])}f}"
    # "the total swings by up to 0.99%": the largest |E(t) − E(0)|/E(0) of the series.
    with h5py.File(tmp_path / "vibrating_bar.h5") as f:
        total = f["series"]["total"][:]
    for text in (prose, getting_started_prose()):
        swing = re.search(r"swings by up to (\d+\.\d+)%", text)[1]
        largest = 100 * np.max(np.abs(total / total[0] - 1))
        assert swing == f"{largest:.{len(swing.split('.')[1])}f}"


def test_the_tour_pic_and_unstable_claims(tmp_path):
    _, _, prose, _ = tour_step_2()
    run = command(["build/apps/smpm", "run", "examples/vibrating_bar.toml"])
    # "`--set step.velocity=PIC` shows FMPM(1) dissipating 43% of it"
    m = re.search(r"`--set step\.velocity=PIC` shows\s+FMPM\(1\) dissipating (\d+)% of it", prose)
    assert m, prose
    assert m[0] in getting_started_prose()
    r = subprocess.run(run + ["--set", "step.velocity=PIC", "-o", "pic.h5"], capture_output=True,
                       text=True, cwd=tmp_path, env=env(), timeout=120)
    assert r.returncode == 0, r.stderr
    change = float(re.search(RUN_LINE, " ".join(r.stdout.split()))[4])
    assert change < 0 and m[1] == f"{-change:.0f}"
    # "`--set time.courant=1.5` shows the run stopping with the step, time and particle where
    # it became unstable (exit status 3)"
    for text in (prose, getting_started_prose()):
        assert re.search(r"`--set time\.courant=1\.5` shows the run stopping with the step, "
                         r"time and\s+particle where it became unstable \(exit status 3\)", text)
    r = subprocess.run(run + ["--set", "time.courant=1.5", "-o", "unstable.h5", "-q"],
                       capture_output=True, text=True, cwd=tmp_path, env=env(), timeout=120)
    assert r.returncode == 3
    assert re.fullmatch(r"smpm: numerical failure: step \d+ \(t = [\d.e+-]+\): particle \d+ .+\n",
                        r.stderr), r.stderr
