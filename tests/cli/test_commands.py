#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""The commands and options of `smpm` besides a run's input: the stability and spectrum tables
(and the figure of one), their options parsed strictly with their caps and checked before the
work, --help, --version and an unknown command; SMPM_THREADS (one and two threads write the same
bits), thread binding, and run --timings.

Run by ctest (cli.commands) with SMPM (the binary) and SMPM_SOURCE (the source tree) in the
environment.
"""
import os
import pathlib
import re
import subprocess
import sys
import time
import unittest

import h5py
import numpy as np

from example_runs import BAR, EXAMPLES, SMPM, SOURCE, Base, one_line, read_table, smpm


class Stability(Base):
    def test_stability_table_and_figure(self):
        out = self.dir / "stab.csv"
        r = smpm("stability", EXAMPLES / "vibrating_bar.toml", "--order", "1,4", "--blend-alpha", "0.8", "--blend-every", "2", "--periodic-cx", "2",
                 "--method", "both", "--shifts", "2", "-q", "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        screen = r.stdout.splitlines()
        lines = out.read_text().splitlines()
        self.assertEqual(lines[0], "velocity,order,blend_alpha,blend_every,periodic_cx,position_alpha,critical_courant,"
                                   "configuration,spectral_status,stable_from,small_courant,simulation_courant,"
                                   "energy_change,interval_low")
        rows = read_table(out)
        self.assertEqual([r["velocity"] for r in rows], ["FLIP", "FMPM", "FMPM", "FMPM", "FMPM", "exact"])
        for r in rows:  # the input's position_alpha (1) is used and recorded for every row
            self.assertEqual(r["position_alpha"], "1")
            self.assertEqual(r["spectral_status"], "converged")
            # The standard transfer on the bar: no unstable small C on either shift, down to C -> 0
            # (periodic FMPM's small C are not examined: its T(C) spans ceil(C_X / C) steps).
            self.assertEqual(r["stable_from"], "" if r["periodic_cx"] else "0")
            self.assertEqual(r["small_courant"], "not examined below 0.05" if r["periodic_cx"] else "stable to 0")
        flip = rows[0]
        # FLIP by bisection over five-period runs: the paper's 0.84, within 0.05 here.
        self.assertAlmostEqual(float(flip["simulation_courant"]), 0.84, delta=0.05)
        fmpm4 = rows[2]
        self.assertEqual(fmpm4["order"], "4")
        self.assertAlmostEqual(float(fmpm4["simulation_courant"]), 0.539, delta=0.03)  # the paper's FMPM(4) limit
        # The screen's table: the same cells under the results' symbols and words.
        self.assertRegex(screen[0], r"position_alpha +C\* spectral configuration +C\* simulation +energy change"
                                    r" +below C\* spectral$")
        self.assertEqual(screen[1].split()[-8:], [flip["critical_courant"], *flip["configuration"].split(),
                                                  flip["simulation_courant"], flip["energy_change"],
                                                  *flip["small_courant"].split()])
        png = self.dir / "fig.png"
        r = subprocess.run(["/usr/bin/python3", SOURCE / "analysis" / "fig12a.py", out, "-o", png], capture_output=True, text=True)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertGreater(png.stat().st_size, 10000)

    def test_polynomial_rows(self):
        # The other members of FMPM's polynomial family (docs/studies/polynomials.md), on the
        # interval [lambda_min(m^-1 m~), 1] of the configuration at t = 0 (0.25 on the bar).
        out = self.dir / "poly.csv"
        r = smpm("stability", EXAMPLES / "vibrating_bar.toml", "--order", "2,8", "--polynomial",
                 "chebyshev,chebyshev_squared", "--blend-alpha", "none", "--periodic-cx", "none",
                 "--no-exact", "--shifts", "2", "-q", "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = {(r["velocity"], r["order"]): r for r in read_table(out)}
        self.assertEqual(sorted(rows), [("FLIP", ""), ("FMPM", "2"), ("FMPM", "8"), ("chebyshev", "2"),
                                        ("chebyshev", "8"), ("chebyshev_squared", "2"), ("chebyshev_squared", "8")])
        for key in [("chebyshev", "2"), ("chebyshev_squared", "8")]:
            self.assertAlmostEqual(float(rows[key]["interval_low"]), 0.25, places=9)
        self.assertEqual(rows[("FMPM", "8")]["interval_low"], "")
        # Chebyshev(2): R = (1 - l)(1 - l/theta) < 0 on (theta, 1), so the particle update carries
        # those modes by 1 - R > 1 and no C is stable.
        self.assertEqual(rows[("chebyshev", "2")]["critical_courant"], "0")
        # Squared Chebyshev with k - 1 = 1 is the series' one pass: FMPM(2) exactly.
        self.assertEqual(rows[("chebyshev_squared", "2")]["critical_courant"], rows[("FMPM", "2")]["critical_courant"])
        r = smpm("stability", EXAMPLES / "vibrating_bar.toml", "--polynomial", "series", "-o", self.dir / "x.csv")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--polynomial series", r.stderr)

    def test_velocity_option(self):
        # smpm run --velocity NAME is --set step.velocity="NAME" (before the --set entries): the
        # same file, bit for bit; a bad name is refused on one line naming the key.
        common = ["--set", "step.order=4", "--set", "step.interval_low=0.25", "--set", "time.end=5", "-q"]
        a, b = self.dir / "a.h5", self.dir / "b.h5"
        r = smpm("run", EXAMPLES / "vibrating_bar.toml", "--velocity", "chebyshev_squared", *common, "-o", a)
        self.assertEqual(r.returncode, 0, r.stderr)
        r = smpm("run", EXAMPLES / "vibrating_bar.toml", "--set", 'step.velocity="chebyshev_squared"', *common, "-o", b)
        self.assertEqual(r.returncode, 0, r.stderr)
        va, vb = (h5py.File(f, "r")["particles"] for f in (a, b))
        last = sorted(va)[-1]
        self.assertTrue(np.array_equal(va[last]["V"][()], vb[last]["V"][()]))
        r = smpm("run", EXAMPLES / "vibrating_bar.toml", "--velocity", "cheb", "-o", self.dir / "c.h5")
        self.assertEqual(r.returncode, 2)
        self.assertEqual(len(r.stderr.strip().splitlines()), 1)
        self.assertIn("step.velocity", r.stderr)
        self.assertFalse((self.dir / "c.h5").exists())

    def test_spectrum_table(self):
        out = self.dir / "spec.csv"
        r = smpm("spectrum", EXAMPLES / "vibrating_bar.toml", "--order", "1,2,4", "--blend-alpha", "1,0.8", "--courant", "0.4", "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        text = out.read_text()
        # A plain CSV (no comment lines), read as it is by csv and numpy.genfromtxt; the
        # configuration's rho(A) (0.75 for the bar's CPDI lattice, docs/studies/stability.md) on every row.
        rows = read_table(text.splitlines())
        self.assertEqual(list(rows[0]), ["order", "blend_alpha", "blend_every", "truncation_error",
                                         "courant", "rho_T", "rho_A", "min_eig_minv_mt", "cond_mt",
                                         "active_nodes"])
        self.assertEqual(len(rows), 3 * 2 + 3)  # m = 1: two alphas; m = 2: alpha 0.8 only
        self.assertEqual(len({r["rho_A"] for r in rows}), 1)
        self.assertAlmostEqual(float(rows[0]["rho_A"]), 0.75, delta=1e-6)
        table = np.genfromtxt(out, delimiter=",", names=True)
        self.assertEqual(table.shape, (9,))

    def test_transport_stability_table(self):
        # F* of the conduction bar: the columns are the results' names in C++ and Python
        # (CriticalFourier.critical_fourier, rho_T, evaluations), the screen shows F* and rho(T).
        out = self.dir / "transport.csv"
        r = smpm("transport-stability", EXAMPLES / "conduction_bar.toml", "--order", "1,2", "--shifts", "2",
                 "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertEqual(out.read_text().splitlines()[0],
                         "transport,order,critical_fourier,rho_T,configuration,evaluations,stable_from,"
                         "small_fourier")
        rows = read_table(out)
        self.assertEqual([(row["transport"], row["order"]) for row in rows],
                         [("lumped", ""), ("FMPM", "1"), ("FMPM", "2"), ("exact", "")])
        screen = r.stdout.splitlines()
        self.assertEqual(screen[0].split(), ["transport", "order", "F*", "rho(T)", "configuration", "below", "F*"])
        for row, line in zip(rows, screen[1:]):
            # The conduction bar has no unstable small F: the screen ends with "stable to 0".
            self.assertEqual(row["small_fourier"], "stable to 0")
            self.assertEqual(row["stable_from"], "0")
            cells = line[:-len(" stable to 0")].split()
            self.assertTrue(line.endswith(" stable to 0"), line)
            self.assertEqual(cells[-4], row["critical_fourier"])
            self.assertEqual(" ".join(cells[-2:]), row["configuration"])
            self.assertGreater(int(row["evaluations"]), 0)
        # FMPM(1) is PIC: F* of the lumped update is larger (the conduction bar of docs/studies/heat.md).
        self.assertGreater(float(rows[0]["critical_fourier"]), float(rows[1]["critical_fourier"]))

    def test_frames_sweep(self):
        # The configurations stored in a run's frames join the lattice shifts in the sweep.
        run = self.dir / "bar.h5"
        r = smpm("run", EXAMPLES / "vibrating_bar.toml", "-o", run, "-q", "--set", "time.end=40", "--set", "output.every=20")
        self.assertEqual(r.returncode, 0, r.stderr)
        out = self.dir / "frames.csv"
        r = smpm("stability", EXAMPLES / "vibrating_bar.toml", "--order", "4", "--blend-alpha", "none", "--periodic-cx", "none",
                 "--shifts", "1", "--frames", run, "--no-exact", "-q", "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = read_table(out)
        self.assertEqual(len(rows), 2)
        for row in rows:  # the minimum is named: the unshifted lattice or one of the frames
            self.assertRegex(row["configuration"], r"^(shift 0|frame [0-9]+)$")

    def test_earlier_option_names(self):
        # One release of aliases (docs/guide/vocabulary.md): --k, --blend m:alpha and --periodic
        # of stability, --k, --alpha and --every of spectrum give the tables of the current
        # names, with a note on standard error for each.
        bar = EXAMPLES / "vibrating_bar.toml"
        common = ["--method", "spectral", "--shifts", "1", "--no-exact", "-q"]
        tables = {}
        for name, args in (("current", ["--order", "1,2", "--blend-alpha", "0.8", "--blend-every", "2",
                                        "--periodic-cx", "2"]),
                           ("earlier", ["--k", "1,2", "--blend", "2:0.8", "--periodic", "2"])):
            out = self.dir / (name + ".csv")
            r = smpm("stability", bar, *args, *common, "-o", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            tables[name] = out.read_text()
            notes = [l for l in r.stderr.splitlines() if l.startswith("smpm: note:")]
            self.assertEqual(len(notes), 3 if name == "earlier" else 0, r.stderr)
        self.assertEqual(tables["current"], tables["earlier"])
        self.assertEqual(len(tables["current"].splitlines()), 1 + 1 + 2 + 1 + 1)  # FLIP, FMPM(1, 2), blend, periodic
        spectra = []
        for args in (["--order", "1,4", "--blend-alpha", "0.8", "--blend-every", "2"],
                     ["--k", "1,4", "--alpha", "0.8", "--every", "2"]):
            out = self.dir / "spec.csv"
            r = smpm("spectrum", bar, *args, "-o", out)
            self.assertEqual(r.returncode, 0, r.stderr)
            spectra.append(out.read_text())
        self.assertEqual(spectra[0], spectra[1])

    def test_a_model_at_rest(self):
        # The two blocks start at rest (the piston moves them): the spectrum's truncation errors
        # are 0 (they were 0/0, printed -nan) and the run's summary prints no relative change of
        # an energy that starts at 0 (it printed +0.0000%).
        blocks = EXAMPLES / "two_block_compression.toml"
        out = self.dir / "rest.csv"
        r = smpm("spectrum", blocks, "--order", "1,4", "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = [l.split(",") for l in out.read_text().splitlines() if l[0].isdigit()]
        self.assertTrue(rows and all(float(row[3]) == 0 for row in rows), rows)
        r = smpm("run", blocks, "-o", self.dir / "rest.h5", "--set", "time.end=0.5")
        self.assertEqual(r.returncode, 0, r.stderr)
        summary = r.stdout.strip().splitlines()[-1]
        self.assertIn("total energy 0 -> ", summary)
        self.assertNotIn("%", summary)

    def test_bad_method(self):
        r = smpm("stability", EXAMPLES / "vibrating_bar.toml", "--method", "guess")
        self.assertEqual(r.returncode, 2)
        self.assertIn("--method guess", r.stderr)


class Options(Base):
    """Item 12: options are validated, with caps, before any work starts."""

    def test_option_values(self):
        cases = (
            ("spectrum", "--blend-every", "0"), ("spectrum", "--order", "0"), ("spectrum", "--order", "-1"),
            ("spectrum", "--blend-alpha", "5"), ("spectrum", "--blend-alpha", "nan"), ("spectrum", "--courant", "-1"),
            ("stability", "--order", "1000000"), ("stability", "--shifts", "1000000000"),
            ("stability", "--frame-stride", "0"),
        )
        for cmd, opt, value in cases:
            with self.subTest(cmd=cmd, opt=opt, value=value):
                line = one_line(self, smpm(cmd, BAR, opt, value, "-o", self.dir / "t.csv", timeout=30), 2)
                self.assertIn(opt, line)
                self.assertIn(opt + " " + value, line)  # the value as given (nan was shown empty)
        self.assertFalse((self.dir / "t.csv").exists())

    def test_bad_output_found_before_the_work(self):
        r = smpm("stability", BAR, "-o", self.dir / "no" / "t.csv", timeout=30)
        line = one_line(self, r, 2)  # one line: no progress line of a computed row before it
        self.assertIn("does not exist", line)


class StrictOptions(Base):
    """Every number of a stability option is all of its text, finite and within its cap; these
    were accepted (std::stod read "2abc" as 2, a NaN --position-alpha meant "not given")."""

    def test_malformed_and_out_of_range_values_are_refused(self):
        long_list = ",".join(["2:0.5"] * 1001)
        cases = {
            ("--blend", "20000:0.5"): "--blend 20000:0.5: m must lie in [1, 10000]",
            ("--blend", "2junk:0.8zzz"): "--blend 2junk:0.8zzz: expected m:alpha, e.g. 2:0.8",
            ("--blend", "2:0.8zzz"): "--blend 2:0.8zzz: expected m:alpha",
            ("--periodic", "2abc"): "--periodic-cx 2abc: expected a Courant budget C_X or none",
            ("--periodic-cx", "1e999"): "--periodic-cx 1e999: expected a Courant budget",
            ("--periodic-cx", "-2"): "--periodic-cx -2: must be non-negative (0: no rows)",
            ("--blend-alpha", "+-0.5"): "--blend-alpha +-0.5: expected a number",
            ("--blend-alpha", "0.5x"): "--blend-alpha 0.5x: expected a number in [0, 1] or none",
            ("--blend-alpha", "nan"): "--blend-alpha nan: expected a number",
            ("--position-alpha", "nan"): "--position-alpha nan: must lie in [0, 1]",
            ("--order", "20000"): "--order 20000: must lie in [1, 10000]",
            ("--blend-every", "20000"): "--blend-every 20000: must lie in [1, 10000]",
            ("--blend", long_list): "--blend: give 1 to 1000 values",
            ("--periodic-cx", ",".join(["2"] * 1001)): "--periodic-cx: give 1 to 1000 values",
        }
        out = self.dir / "t.csv"
        for (option, value), message in cases.items():
            r = smpm("stability", BAR, option, value, "-o", out, "-q")
            self.assertEqual(r.returncode, 2, (option, r.stderr))
            self.assertIn("smpm: error: " + message, r.stderr.splitlines()[-1], option)
            self.assertFalse(out.exists())

    def test_an_unknown_command_is_named(self):
        line = one_line(self, smpm("bogus"), 2)
        self.assertEqual(line, "smpm: error: unknown command 'bogus' (expected run, stability, "
                               "spectrum, transport-stability or info; smpm --help lists them)")


class Help(Base):
    def test_no_stable_courant_number_is_none(self):
        # A simulation search where no C holds (an energy-change limit no run meets) says "none"
        # in the table and the CSV (it left both empty, as for a row not searched).
        out = self.dir / "st.csv"
        r = smpm("stability", BAR, "--method", "simulation", "--order", "1", "--blend-alpha",
                 "none", "--periodic-cx", "none", "--no-exact", "--max-energy-change", "1e-15",
                 "-q", "-o", out)
        self.assertEqual(r.returncode, 0, r.stderr)
        rows = read_table(out)
        self.assertEqual([row["simulation_courant"] for row in rows], ["none", "none"])
        self.assertEqual([row["critical_courant"] for row in rows], ["", ""])  # not searched
        self.assertEqual(r.stdout.splitlines()[1].split()[-1], "none")

    def test_stability_help_shows_defaults(self):
        # --help printed "--no-exact{false}" and no default for --position-alpha and
        # --max-energy-change.
        r = smpm("stability", "--help")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertNotIn("{false}", r.stdout)
        self.assertRegex(r.stdout, r"--no-exact +leave out the exact consistent-mass row")
        self.assertRegex(r.stdout, r"--shifts INT=4 ")
        self.assertIn("(default: the input's, else 1 for FLIP and 1/2 for the others)", r.stdout)
        self.assertIn("(default: no limit)", r.stdout)
        rows = []
        for extra in ([], ["--no-exact"]):
            out = self.dir / ("t%d.csv" % len(extra))
            r = smpm("stability", BAR, "--order", "1", "--method", "spectral", "--shifts", "1",
                     "-q", "-o", out, *extra)
            self.assertEqual(r.returncode, 0, r.stderr)
            rows.append([l.split(",")[0] for l in out.read_text().splitlines()[1:]])
        self.assertEqual(rows, [["FLIP", "FMPM", "exact"], ["FLIP", "FMPM"]])


class Version(Base):
    def test_the_version_names_the_commit(self):
        # `smpm --version` printed a bare number; now the release and the checkout's commit.
        git = subprocess.run(["git", "describe", "--always", "--dirty", "--abbrev=12"],
                             cwd=SOURCE, capture_output=True, text=True)
        commit = git.stdout.strip() if git.returncode == 0 and git.stdout.strip() else "unknown"
        r = smpm("--version")
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertRegex(r.stdout.strip(), r"^smpm \d+\.\d+\.\d+ \(commit [0-9a-z-]+\)$")
        self.assertTrue(r.stdout.strip().endswith("(commit %s)" % commit), r.stdout)


class Threads(Base):
    """SMPM_THREADS: 1 and 2 threads write the same bits; a bad value is one line, exit 2."""

    def run_with(self, threads, name):
        out = self.dir / (name + ".h5")
        env = dict(os.environ, SMPM_THREADS=threads)
        r = subprocess.run([SMPM, "run", EXAMPLES / "block_impact.toml", "-o", out, "-q",
                            "--set", "time.end=0.03", "--set", "output.every=0.01",
                            "--set", "step.velocity=FMPM", "--set", "step.order=4"],
                           capture_output=True, text=True, env=env, timeout=600)
        return r, out

    def test_one_and_two_threads_write_the_same_bits(self):
        (r1, one), (r2, two) = self.run_with("1", "one"), self.run_with("2", "two")
        self.assertEqual(r1.returncode, 0, r1.stderr)
        self.assertEqual(r2.returncode, 0, r2.stderr)
        with h5py.File(one, "r") as a, h5py.File(two, "r") as b:
            self.assertEqual(sorted(a["particles"]), sorted(b["particles"]))
            self.assertGreaterEqual(len(a["particles"]), 4)
            for name in a["particles"]:
                for field in ("X", "V", "F", "stress"):
                    self.assertTrue(np.array_equal(a["particles"][name][field][:], b["particles"][name][field][:]), f"{name}/{field}")
            for s in ("kinetic", "strain", "total", "momentum"):
                self.assertTrue(np.array_equal(a["series"][s][:], b["series"][s][:]), s)

    def test_bad_thread_count(self):
        for bad in ("0", "two", "-1"):
            r, out = self.run_with(bad, "bad")
            self.assertEqual(r.returncode, 2, r.stderr)
            self.assertEqual(r.stderr.strip().splitlines(),
                             [f"smpm: error: SMPM_THREADS='{bad}': expected a positive integer (at most 4096), the number of threads"])
            self.assertFalse(out.exists())


@unittest.skipUnless(sys.platform.startswith("linux") and len(os.sched_getaffinity(0)) >= 2,
                     "needs Linux and two CPUs")
class BoundThreads(Base):
    """With thread binding chosen (OMP_PROC_BIND, OMP_PLACES; no wait policy), smpm restarts
    itself with passive waiting after libgomp has bound its first thread to the first place: the
    restarted program must not inherit that one place, where libgomp put both threads (the run
    then took 3.95 s against 2.16-2.22 s on two cores)."""

    def threads_and_environment(self, pid):
        cpus = []
        for task in pathlib.Path(f"/proc/{pid}/task").glob("*"):
            try:
                status = (task / "status").read_text()
            except OSError:
                continue
            cpus.append(re.search(r"Cpus_allowed_list:\s*(\S+)", status).group(1))
        try:
            environ = pathlib.Path(f"/proc/{pid}/environ").read_bytes().split(b"\0")
        except OSError:
            environ = []
        return cpus, environ

    def cpus_of_threads(self, bind, name):
        env = {k: v for k, v in os.environ.items()
               if k not in ("OMP_WAIT_POLICY", "GOMP_SPINCOUNT", "SMPM_THREADS", "OMP_PLACES",
                            "OMP_PROC_BIND", "GOMP_CPU_AFFINITY", "OMP_DYNAMIC",
                            "OMP_THREAD_LIMIT")}
        env.update(OMP_NUM_THREADS="2", **bind)
        # 40,000 particles, so that every step's loops run on both threads.
        p = subprocess.Popen([SMPM, "run", EXAMPLES / "vibrating_plate.toml", "-q", "-o",
                              self.dir / (name + ".h5"), "--set", "grid.cells=[204,54]",
                              "--set", "body.0.max=[200.0,50.0]", "--set", "time.end=30"],
                             env=env, stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        cpus, environ = [], []
        try:
            deadline = time.monotonic() + 60
            while p.poll() is None and time.monotonic() < deadline:
                # The program before the restart has one thread; the worker appears in the
                # restarted one, at its first parallel loop. A new thread takes its place a
                # moment after it appears: read again a little later.
                if len(self.threads_and_environment(p.pid)[0]) >= 2:
                    time.sleep(0.05)
                    cpus, environ = self.threads_and_environment(p.pid)
                    break
                time.sleep(0.005)
        finally:
            p.kill()
            err = p.communicate()[1].decode(errors="replace")
        # Two OpenMP threads, and at a frame the thread that syncs and names the frame file
        # (created by the first, whose CPUs it inherits).
        self.assertIn(len(cpus), (2, 3), f"{bind}: the run never had two threads: {err}")
        self.assertIn(b"OMP_WAIT_POLICY=passive", environ, f"{bind}: smpm did not restart")
        return cpus

    def test_bound_threads_run_on_two_cpus(self):
        a, b = sorted(os.sched_getaffinity(0))[:2]
        for i, bind in enumerate(({"OMP_PROC_BIND": "true"}, {"OMP_PLACES": "threads"},
                                  {"OMP_PROC_BIND": "spread", "OMP_PLACES": f"{{{b}}},{{{a}}}"})):
            cpus = self.cpus_of_threads(bind, f"bound{i}")
            # Each thread bound to a place of one CPU, and not both to the same one.
            self.assertEqual(len(set(cpus)), 2, f"{bind}: threads on CPUs {cpus}")


class Timings(Base):
    """smpm run --timings: the parts are disjoint intervals of the time loop, so they sum to at
    most its wall time, and a part the run has not (contact, heat transport) takes none."""

    def timings(self, example, *sets):
        args = ["run", EXAMPLES / example, "-o", self.dir / "t.h5", "-q", "--timings"]
        for s in sets:
            args += ["--set", s]
        r = smpm(*args)
        self.assertEqual(r.returncode, 0, r.stderr)
        parts = {}
        for line in r.stdout.splitlines()[1:]:
            m = re.match(r"^(.+?)\s+(-?[0-9.]+)\s+(-?[0-9.]+)%\s+(-?[0-9.]+)$", line.strip())
            self.assertIsNotNone(m, line)
            parts[m.group(1)] = float(m.group(2))
        return parts

    def check_sum(self, parts):
        loop = parts.pop("time loop")
        other = parts.pop("other")
        for name, seconds in parts.items():
            self.assertGreaterEqual(seconds, 0.0, name)
        # Eleven numbers printed to 0.1 ms: the identity holds to their rounding.
        self.assertAlmostEqual(sum(parts.values()) + other, loop, delta=6e-4)
        self.assertGreaterEqual(other, -6e-4)
        self.assertGreater(parts["assemble (S, G, m, patterns)"], 0.0)
        self.assertGreater(parts["step stages"], 0.0)
        self.assertGreater(parts["frames"], 0.0)
        self.assertEqual(parts["transport operators"], 0.0)

    def test_contact_run(self):
        parts = self.timings("two_block_compression.toml", "time.end=1.0393")
        self.assertGreater(parts["contact nodes"], 0.0)
        self.check_sum(parts)

    def test_single_material_run_has_no_contact_time(self):
        parts = self.timings("vibrating_bar.toml", "step.velocity=FMPM", "step.order=4")
        self.assertEqual(parts["contact nodes"], 0.0)
        self.assertGreater(parts["consistent mass"], 0.0)
        self.check_sum(parts)


if __name__ == "__main__":
    unittest.main(verbosity=2)
