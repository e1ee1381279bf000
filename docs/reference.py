#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""The input reference, made from the reader's own table of keys and from what smpm does.

    docs/reference.py OUT.md [--smpm build/apps/smpm]

`smpm info --keys` prints the reader's table (lib/io/src/input_keys.cpp: the schema every
input is checked against): each key's type, default, accepted values, unit and description.
For each key with a refused value in that table, `smpm run` is run on the first example that
has the key's table with `--set table.key=value`, and what it prints is the reference's
example error: the error each bad value gets is the program's, not a copy of it.
tests/cli/test_input_keys.py checks the same runs (exit status 2, the key named, no file) and
that every default stated as a value is the value the reader takes.
"""

import argparse
import pathlib
import subprocess
import sys
import tempfile
import tomllib

SOURCE = pathlib.Path(__file__).resolve().parent.parent
EXAMPLES = SOURCE / "examples"
# Tables that are arrays of tables ([[material]]): a key is set in entry 0 (or the first entry
# that has the key's inline table, for bc.wall and the like).
ARRAYS = ("material", "body", "bc", "contact", "loads.body_force", "loads.traction")


def read_keys(smpm):
    """The reader's table of keys, as `smpm info --keys` prints it."""
    out = subprocess.run([smpm, "info", "--keys"], capture_output=True, text=True, check=True)
    return tomllib.loads(out.stdout)["key"]


def lookup(doc, dotted):
    """The value at a --set path of a parsed input ("step.order", "bc.2.wall.depth"), or None."""
    for part in dotted.split("."):
        if isinstance(doc, list) and part.isdigit() and int(part) < len(doc):
            doc = doc[int(part)]
        else:
            doc = doc.get(part) if isinstance(doc, dict) else None
    return doc


def entry_paths(doc, table):
    """The --set prefixes of `table` in the parsed input `doc` (none if it has no such table):
    ["step"], ["material.0", "material.1"], ["bc.2.wall"], ["loads.traction.0.box"]."""
    if table in ARRAYS:
        return [f"{table}.{i}" for i in range(len(lookup(doc, table) or []))]
    parent, _, inner = table.rpartition(".")
    if parent in ARRAYS:
        return [f"{parent}.{i}.{inner}" for i, entry in enumerate(lookup(doc, parent) or [])
                if isinstance(entry.get(inner), dict)]
    return [table]  # a plain table: --set makes it where it is absent


def entry_path(doc, table):
    """The first --set prefix of `table` in `doc`, or None."""
    paths = entry_paths(doc, table)
    return paths[0] if paths else None


def base_input(key):
    """(example, --set prefix) of a key: the first example, by name, with an entry of the key's
    table that sets the key (so that a refused value stands where a valid one did), else the
    first with the table."""
    examples = [(p, tomllib.loads(p.read_text())) for p in sorted(EXAMPLES.glob("*.toml"))]
    for path, doc in examples:
        for prefix in entry_paths(doc, key["table"]):
            if lookup(doc, f"{prefix}.{key['key']}") is not None:
                return path, prefix
    for path, doc in examples:
        prefix = entry_path(doc, key["table"])
        if prefix:
            return path, prefix
    return None, None


def refusal(smpm, key, workdir):
    """What `smpm run` does with key['bad']: (the --set given, example, exit status, stderr,
    the files the run left in workdir)."""
    example, prefix = base_input(key)
    if example is None:
        raise SystemExit(f"reference: no example has the table [{key['table']}]")
    spec = f"{prefix}.{key['key']}={key['bad']}"
    out = pathlib.Path(workdir) / "refused.h5"
    r = subprocess.run([smpm, "run", str(example), "--set", spec, "-o", str(out), "--quiet"],
                       capture_output=True, text=True, timeout=120, cwd=workdir)
    return spec, example, r.returncode, r.stderr, sorted(p.name for p in
                                                         pathlib.Path(workdir).iterdir())


def cell(text):
    return (text or "").replace("|", "\\|").replace("\n", " ")


def title(table):
    if table in ARRAYS:
        return f"`[[{table}]]`"
    parent, _, last = table.rpartition(".")
    if parent in ARRAYS:
        return f"`[[{parent}]]` `{last} = {{...}}`"
    return f"`[{table}]`"


def markdown(smpm, keys):
    lines = ["The tables of an input file, as the reader lists them:", "",
             "| table | what it holds | |", "| --- | --- | --- |"]
    top = [k for k in keys if k["table"] == ""]
    for k in top:
        lines.append(f"| {title(k['key'])} | {cell(k['description'])} | {cell(k['fallback'])} |")
    tables = []
    for k in keys:
        if k["table"] and k["table"] not in tables:
            tables.append(k["table"])
    for table in tables:
        rows = [k for k in keys if k["table"] == table]
        lines += ["", f"### {title(table)}", "",
                  "| key | type | default | values | unit | what it sets |",
                  "| --- | --- | --- | --- | --- | --- |"]
        for k in rows:
            default = f"`{k['fallback']}`" if k["literal"] else cell(k["fallback"])
            values = cell(k["values"])
            lines.append(f"| `{k['key']}` | {cell(k['type'])} | {default} | {values} | "
                         f"{cell(k['unit'])} | {cell(k['description'])} |")
        bad = [k for k in rows if k["bad"]]
        if not bad:
            continue
        lines += ["", "What a refused value gets (`smpm run EXAMPLE --set KEY=VALUE`, exit status "
                  "2, nothing written):", "", "```text"]
        for k in bad:
            with tempfile.TemporaryDirectory() as work:
                spec, example, status, err, left = refusal(smpm, k, work)
            if status != 2 or left:
                raise SystemExit(f"reference: --set {spec} on {example.name}: exit status "
                                 f"{status}, left {left} (expected 2 and nothing): {err}")
            lines += [f"$ smpm run examples/{example.name} --set '{spec}'",
                      err.rstrip().replace(str(EXAMPLES) + "/", "examples/")]
        lines.append("```")
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("out", type=pathlib.Path, help="the Markdown file to write")
    ap.add_argument("--smpm", default="smpm", help="the smpm program (default: on the PATH)")
    a = ap.parse_args()
    keys = read_keys(a.smpm)
    a.out.write_text(markdown(a.smpm, keys))
    print(f"reference: {len(keys)} keys in {a.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
