#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""The reader's table of keys (lib/io/src/input_keys.cpp; `smpm info --keys`), from which the
site's input reference is made (docs/reference.py): every key is described, every value it
states the reader refuses is refused, and every default it states as a value is the value the
reader takes.

Run by ctest (cli.input_keys) with SMPM (the binary) and SMPM_SOURCE (the source tree) in the
environment.
"""
import copy
import re
import sys
import tempfile
import tomllib
import unittest

import h5py
import numpy as np
import tomli_w

from example_runs import EXAMPLES, SANITIZED, SMPM, SOURCE, Base, one_line, smpm

sys.dont_write_bytecode = True  # nothing written into the source tree
sys.path.insert(0, str(SOURCE / "docs"))
import reference  # noqa: E402

KEYS = reference.read_keys(SMPM)


def name(k):
    return f"{k['table']}.{k['key']}" if k["table"] else k["key"]


def datasets(path):
    """Every dataset of a run file by path, and the root's attributes but the input's text, its
    overrides and its name (which differ between the two inputs by construction)."""
    out = {}
    with h5py.File(path, "r") as f:
        def visit(p, obj):
            if isinstance(obj, h5py.Dataset):
                out[p] = obj[()]
        f.visititems(visit)
        for name, value in f.attrs.items():
            if name not in ("input", "overrides", "source"):
                out["@" + name] = value
    return out


class Table(unittest.TestCase):
    def test_every_key_is_described_once(self):
        seen = set()
        for k in KEYS:
            self.assertNotIn(name(k), seen)
            seen.add(name(k))
            for field in ("type", "fallback", "description"):
                self.assertTrue(k[field].strip(), f"{name(k)}: no {field}")
            if k["literal"]:  # the TOML text of a value
                tomllib.loads("v = " + k["fallback"])
        # The top-level tables are the tables of the keys, and every table has keys.
        top = {k["key"] for k in KEYS if not k["table"]}
        self.assertEqual(top, {k["table"].split(".")[0] for k in KEYS if k["table"]})
        self.assertGreater(len(KEYS), 100)

    def test_an_unknown_key_is_one_the_table_lacks(self):
        # The schema is the table: a key it lists is known to --set, one it does not is not.
        r = smpm("run", str(SOURCE / "examples" / "vibrating_bar.toml"), "--set",
                 "step.velocityy=FLIP", "-o", "x.h5")
        self.assertIn("unknown key 'step.velocityy' (did you mean 'velocity'?)",
                      one_line(self, r, 2))


# "smpm: error: FILE[:LINE]: KEY = VALUE: what" or "...: KEY: what": the key a message names.
NAMED = re.compile(r"smpm: error: [^:]+(?::\d+)?: (\S+?)(?: = |: )")


def names_key(message, k):
    """Whether `message` names the key k: its path ends in the key's table and name, an entry of
    an array of tables given by index or name ("material.0.model", "material.bar.model")."""
    m = NAMED.match(message)
    if not m:
        return False
    parts, plain = m[1].split("."), []
    i = 0
    while i < len(parts):
        plain.append(parts[i])
        # an entry of an array of tables named by index or name, with more of the path after it
        if ".".join(plain) in reference.ARRAYS and i + 2 < len(parts):
            i += 1
        i += 1
    return plain == f"{k['table']}.{k['key']}".split(".")


class Refusals(Base):
    def test_every_refused_value_is_refused_naming_its_key(self):
        # Each value the table states the reader refuses, set in the first example whose entry
        # of the key's table sets the key (else the first with the table): exit status 2, one
        # line naming that key (not another key the value conflicts with), nothing written.
        checked = 0
        for k in KEYS:
            if not k["bad"]:
                continue
            with tempfile.TemporaryDirectory() as work:
                spec, example, status, err, left = reference.refusal(SMPM, k, work)
            with self.subTest(spec=spec, example=example.name):
                self.assertEqual(status, 2, err)
                self.assertEqual(len(err.strip().splitlines()), 1, err)
                self.assertEqual(left, [])
                self.assertTrue(names_key(err, k), err)
            checked += 1
        self.assertGreater(checked, 80)


def without(doc, path):
    """A copy of the parsed input `doc` without the key at the --set path `path`."""
    doc = copy.deepcopy(doc)
    *parents, last = path.split(".")
    del reference.lookup(doc, ".".join(parents))[last]
    return doc


def candidates(k):
    """(example, --set prefix, parsed input, whether it sets the key) in the order tried: the
    examples that set the key (where it acts), then the first with an entry of its table."""
    docs = [(p, tomllib.loads(p.read_text())) for p in sorted(EXAMPLES.glob("*.toml"))]
    for path, doc in docs:
        for prefix in reference.entry_paths(doc, k["table"]):
            if reference.lookup(doc, f"{prefix}.{k['key']}") is not None:
                yield path, prefix, doc, True
    for path, doc in docs:
        prefix = reference.entry_path(doc, k["table"])
        if prefix:
            yield path, prefix, doc, False
            return


@unittest.skipIf(SANITIZED, "two short runs a default (the Release build's check)")
class Defaults(Base):
    def without_and_with_default(self, k, example, prefix, doc, n):
        """The datasets of a few steps of `doc` without the key and with it set to its stated
        default; None when the input without the key is refused."""
        doc = copy.deepcopy(doc)
        end = doc["time"]["end"] / 200
        doc["time"]["end"], doc.setdefault("output", {})["every"] = end, end
        path = f"{prefix}.{k['key']}"
        unset = without(doc, path) if reference.lookup(doc, path) is not None else doc
        given = copy.deepcopy(unset)
        *parents, last = path.split(".")
        reference.lookup(given, ".".join(parents))[last] = \
            tomllib.loads("v = " + k["fallback"])["v"]
        runs = []
        for i, variant in enumerate((unset, given)):
            toml = self.dir / f"{n}_{i}.toml"
            toml.write_text(tomli_w.dumps(variant))
            out = self.dir / f"{n}_{i}.h5"
            r = smpm("run", str(toml), "-o", str(out), "--quiet")
            if i == 0 and r.returncode == 2:
                return None
            self.assertEqual(r.returncode, 0, (path, example.name, r.stderr))
            runs.append(datasets(out))
        return runs

    def test_a_default_set_explicitly_changes_nothing(self):
        # A key set to the default the table states gives the run file of the input without
        # it, dataset for dataset and attribute for attribute: on the first example that sets
        # the key (where it acts) and runs without it, the key removed, else on the first with
        # its table (where a key that acts in no example cannot show a wrong default); tomli_w
        # writes both inputs, beside the examples' images; a few steps of each.
        checked = 0
        for path in EXAMPLES.glob("*.png"):
            (self.dir / path.name).symlink_to(path)
        for k in KEYS:
            if not k["literal"]:
                continue
            for example, prefix, doc, sets in candidates(k):
                runs = self.without_and_with_default(k, example, prefix, doc, checked)
                if runs is None and sets:
                    continue  # the example needs the key (a temperature condition, transport)
                self.assertIsNotNone(runs, (k, example.name))
                with self.subTest(key=f"{prefix}.{k['key']}", example=example.name):
                    self.assertEqual(runs[0].keys(), runs[1].keys())
                    for p in runs[0]:
                        np.testing.assert_array_equal(runs[0][p], runs[1][p], err_msg=p)
                checked += 1
                break
        self.assertGreater(checked, 30)


if __name__ == "__main__":
    unittest.main(verbosity=2)
