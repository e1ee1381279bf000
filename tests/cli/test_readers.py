#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""What reads a run file: scipy (the CSR matrices), the XDMF sidecar (it points at existing
datasets, and is XML whatever the run file's name holds), smpm info and info --layout (whose
print the site's run-file page shows, made by the site's build), the analysis scripts (their
PNGs), and a run in progress read by smpm info and by an XML parser (never half written). ParaView's and meshio's XDMF readers are
io.readers' (tests/io/test_readers.py).

Run by ctest (cli.readers) with SMPM (the binary) and SMPM_SOURCE (the source tree) in the
environment.
"""
import os
import pathlib
import subprocess
import tempfile
import time
import unittest
import xml.etree.ElementTree as ET

import h5py
import numpy as np
import scipy.sparse

from example_runs import BAR, EXAMPLES, SMPM, SOURCE, Base, smpm


class RunFiles(Base):
    @classmethod
    def setUpClass(cls):
        cls.tmpc = tempfile.TemporaryDirectory()
        d = pathlib.Path(cls.tmpc.name)
        cls.disks = d / "disks.h5"
        r = smpm("run", EXAMPLES / "two_disks.toml", "-o", cls.disks, "-q", "--set", "time.end=1.0", "--set", "output.matrices=true", "--set", "output.every=0.5")
        assert r.returncode == 0, r.stderr

    @classmethod
    def tearDownClass(cls):
        cls.tmpc.cleanup()

    def test_csr_matrices_load_with_scipy(self):
        with h5py.File(self.disks, "r") as f:
            for name, frame in f["matrices"].items():
                g = frame["S"]
                S = scipy.sparse.csr_matrix((g["data"][:], g["indices"][:], g["indptr"][:]), shape=tuple(g["shape"][:]))
                # Partition of unity, S 1 = 1 (round-off: 1e-13).
                self.assertLess(np.abs(S @ np.ones(S.shape[1]) - 1).max(), 1e-13)
                c = frame["consistent_mass"]
                mt = scipy.sparse.csr_matrix((c["data"][:], c["indices"][:], c["indptr"][:]), shape=tuple(c["shape"][:]))
                g = f["grid"][name]  # the nodes with mass, by index
                m = np.zeros(mt.shape[0])
                m[g["nodes"][:]] = g["m"][:]
                # Rows of the consistent mass sum to the lumped mass (round-off relative 1e-13).
                self.assertLess(np.abs(mt @ np.ones(mt.shape[1]) - m).max(), 1e-13 * m.max())

    def test_xdmf_points_at_existing_datasets(self):
        xmf = self.disks.with_suffix(".xmf")
        root = ET.parse(xmf).getroot()
        grids = root.findall(".//Grid[@GridType='Uniform']")
        with h5py.File(self.disks, "r") as f:
            self.assertEqual(len(grids), len(f["particles"]))
            checked = 0
            for item in root.iter("DataItem"):
                if item.get("Format") != "HDF":
                    continue
                file, path = item.text.strip().split(":", 1)
                self.assertEqual(file, self.disks.name)
                self.assertIn(path, f)
                dims = tuple(int(x) for x in item.get("Dimensions").split())
                self.assertEqual(f[path].shape, dims)
                checked += 1
            self.assertGreater(checked, 10)

    def test_info(self):
        r = smpm("info", self.disks)
        self.assertEqual(r.returncode, 0, r.stderr)
        self.assertIn("frames:   3", r.stdout)
        self.assertIn("status:   completed", r.stdout)
        self.assertIn("energy:", r.stdout)
        # It walks the file: every dataset of the last frame and of the series is listed with
        # its shape and its layout entry (none "not of the sparsempm layout").
        with h5py.File(self.disks, "r") as f:
            names = []
            f.visititems(lambda n, o: names.append(n) if isinstance(o, h5py.Dataset) else None)
            last = sorted(f["particles"].keys())[-1]
            for n in names:
                if n.startswith("series/") or f"/{last}" in n:
                    line = next(l for l in r.stdout.splitlines() if l.split() and l.split()[0] == "/" + n)
                    self.assertIn(" x ".join(map(str, f[n].shape)) or "scalar", line)
        self.assertNotIn("not of the sparsempm layout", r.stdout)

    def test_units_stated_in_the_input_label_the_plots(self):
        # output.units is stored as /@units (the layout's) and the plotting scripts' labels
        # follow it unless --units says otherwise; a run that states none is "input units".
        import pickle
        for units, expected in (("SI", "time $t$ (s)"), ("none", "time $t$ (input units)")):
            out = self.dir / f"bar_{units}.h5"
            r = smpm("run", str(BAR), "--set", f'output.units="{units}"', "--set", "time.end=4",
                     "-o", str(out), "--quiet")
            self.assertEqual(r.returncode, 0, r.stderr)
            with h5py.File(out, "r") as f:
                self.assertEqual(f.attrs["units"], units)
            for given, label in (([], expected), (["--units", "mm-ms-g"], "time $t$ (ms)")):
                r = subprocess.run(["/usr/bin/python3", SOURCE / "analysis" / "plot_energy.py",
                                    out, "-o", self.dir / "e", *given], capture_output=True,
                                   text=True, env={**os.environ, "SMPM_FIGURE_DUMP": str(self.dir)})
                self.assertEqual(r.returncode, 0, r.stderr)
                with open(self.dir / "e.pickle", "rb") as f:
                    self.assertEqual(pickle.load(f).axes[-1].get_xlabel(), label)

    def test_analysis_scripts_write_pngs(self):
        # -o is an output prefix (p writes p.png); a trailing .png is the same prefix.
        for script, args in (("plot_energy.py", []), ("plot_particles.py", ["--frame", "1", "--field", "stress_xx"])):
            for out in ("p.png", "q"):
                r = subprocess.run(["/usr/bin/python3", SOURCE / "analysis" / script, self.disks, "-o", self.dir / out, *args], capture_output=True, text=True)
                self.assertEqual(r.returncode, 0, r.stderr)
                self.assertGreater((self.dir / (out.removesuffix(".png") + ".png")).stat().st_size, 10000)
            self.assertFalse((self.dir / "p.png.png").exists() or (self.dir / "q").exists())
            for f in ("p.png", "q.png"):
                (self.dir / f).unlink()


class Sidecar(Base):
    """The XDMF sidecar is XML whatever the run file's name holds."""

    def test_name_with_markup(self):
        import xml.etree.ElementTree as ET
        out = self.dir / "a&b<c>'d\".h5"
        r = smpm("run", BAR, "-o", out, "-q", "--set", "time.end=20")
        self.assertEqual(r.returncode, 0, r.stderr)
        items = [d.text for d in ET.parse(self.dir / "a&b<c>'d\".xmf").iter("DataItem") if d.text]
        self.assertTrue(any(t.startswith("a&b<c>'d\".h5:/particles/000000/") for t in items), items[:3])


class LiveReaders(Base):
    def test_sidecars_are_never_read_half_written(self):
        # A reader parsing run.partial.xmf during the run got torn XML in 2-13 of ~100 reads:
        # the sidecars are now written under a temporary name and renamed.
        out = self.dir / "live.h5"
        p = subprocess.Popen([SMPM, "run", EXAMPLES / "block_impact.toml", "-o", out, "-q",
                              "--set", "time.end=100", "--set", "output.every=0.01"],
                             stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        xmf = self.dir / "live.partial.xmf"
        reads, grids = 0, []
        try:
            deadline = time.time() + 120
            while reads < 150 and time.time() < deadline and p.poll() is None:
                if xmf.exists():
                    text = xmf.read_text()
                    root = ET.fromstring(text)  # raises on torn XML
                    grids.append(len(root.findall(".//Grid[@GridType='Uniform']")))
                    reads += 1
                time.sleep(0.005)
            self.assertIsNone(p.poll(), "the run ended before the reads")
        finally:
            p.kill()
            p.wait()
        self.assertEqual(reads, 150)
        self.assertGreater(grids[-1], grids[0])  # it was read while frames were added


class LiveRun(Base):
    """A run in progress can be read: `smpm info` of its partial file lists the frames completed
    so far (HDF5's file lock kept every reader out: "cannot be opened now")."""

    def test_info_of_a_live_run(self):
        out = self.dir / "live.h5"
        p = subprocess.Popen([SMPM, "run", EXAMPLES / "block_impact.toml", "-o", out, "-q",
                              "--set", "time.end=100", "--set", "output.every=0.01"],
                             stderr=subprocess.PIPE, text=True)
        partial = self.dir / "live.partial.h5"
        try:
            seen = 0
            deadline = time.time() + 300
            while seen < 3 and time.time() < deadline and p.poll() is None:
                time.sleep(0.2)
                if not partial.exists():
                    continue
                info = smpm("info", partial)
                self.assertEqual(info.returncode, 0, info.stderr)
                found = [int(l.split()[1]) for l in info.stdout.splitlines()
                         if l.startswith("frames:")]
                seen = found[0] if found else 0
            self.assertIsNone(p.poll(), p.stderr.read() if p.poll() is not None else "")
            self.assertGreaterEqual(seen, 3)
        finally:
            p.kill()
            p.wait()
            p.stderr.close()


if __name__ == "__main__":
    unittest.main(verbosity=2)
