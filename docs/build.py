#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Builds the documentation site from a fresh copy of docs/ into OUT/html, warnings as errors.

    docs/build.py --build build            # the CMake build tree: its smpm, module and Doxygen XML
                  [--out build/docs]       # default BUILD/docs

The steps, each printed with its time:
  1. a fresh staging tree OUT/source: the pages of docs/, with examples/ and analysis/ linked
     beside them, so that the pages' commands run there as a user runs them in a clone
     (`smpm run examples/vibrating_bar.toml`) and write their files into the build tree;
  2. what the pages show that a command makes: the input reference (reference.py, from the
     reader's own table of keys and the errors smpm prints), every analysis script on its short
     case for the study pages (short_cases.py) and the getting-started figures;
  3. sphinx-build -W -E -b html: any warning fails, nothing of an earlier build is reused
     (the pages' command-output blocks run their commands here: the command-line reference
     is smpm's own --help, the run-file layout `smpm info --layout`);
  4. with --check, check_site.py: links, anchors, images, every page in headless Chromium, and
     two screenshots (into $SMPM_DOCS_SCREENSHOTS, else OUT/screenshots).
"""

import argparse
import os
import pathlib
import random
import shutil
import subprocess
import sys
import time

sys.dont_write_bytecode = True  # nothing written into the source tree
HERE = pathlib.Path(__file__).resolve().parent
SOURCE = HERE.parent
sys.path.insert(0, str(HERE))
import short_cases  # noqa: E402


def step(name, started):
    print(f"docs: {name}: {time.monotonic() - started:.1f} s", flush=True)


def run(cmd, cwd, env):
    print("docs: $ " + " ".join(str(c) for c in cmd), flush=True)
    status = subprocess.run([str(c) for c in cmd], cwd=cwd, env=env).returncode
    if status != 0:
        sys.exit(f"docs: failed (exit status {status}): {' '.join(str(c) for c in cmd)}")


def run_on_display(cmd, cwd, env, tries=4):
    """run() under `xvfb-run -a`, again when ParaView could not connect to the X server it was
    given: xvfb-run -a takes the first display number without a lock file, and two servers
    started in the same moment (other programs of a shared machine) can take the same one, so
    that ParaView aborts with "bad X server connection". Any other failure ends the build."""
    cmd = ["xvfb-run", "-a"] + [str(c) for c in cmd]
    print("docs: $ " + " ".join(cmd), flush=True)
    for attempt in range(1, tries + 1):
        p = subprocess.run(cmd, cwd=cwd, env=env, capture_output=True, text=True,
                           errors="replace")
        sys.stdout.write(p.stdout)
        sys.stderr.write(p.stderr)
        if p.returncode == 0:
            return
        if "bad X server connection" not in p.stdout + p.stderr or attempt == tries:
            sys.exit(f"docs: failed (exit status {p.returncode}): {' '.join(cmd)}")
        print(f"docs: no connection to the X server (attempt {attempt} of {tries}): again",
              flush=True)
        time.sleep(random.uniform(0.5, 3.0))  # not in step with the server that took the display


def stage(out):
    """A fresh copy of the pages, with the repository's examples and analysis linked in."""
    src = out / "source"
    if src.exists():
        shutil.rmtree(src)
    shutil.copytree(HERE, src, ignore=shutil.ignore_patterns("__pycache__", "CMakeLists.txt",
                                                               "Doxyfile.in", "*.cmake"))
    for name in ("examples", "analysis"):
        (src / name).symlink_to(SOURCE / name, target_is_directory=True)
    (src / "generated").mkdir()
    return src


def header_pages(src, xml):
    """One page per public header of Doxygen's index (api/headers/<name>.md): a header's
    namespace is declared once on its page, and a new header gets its page."""
    from xml.etree import ElementTree
    index = ElementTree.parse(xml / "index.xml").getroot()
    headers = sorted(c.findtext("name") for c in index.iter("compound") if c.get("kind") == "file")
    pages = src / "api" / "headers"
    pages.mkdir(parents=True)
    for h in headers:
        (pages / (h.removesuffix(".hpp") + ".md")).write_text(
            f"# {h}\n\n`#include <sparsempm/{h}>`\n\n```{{doxygenfile}} {h}\n```\n")
    return len(headers)


def figures(src, env):
    """The getting-started page's figures, made by the commands the page shows."""
    run(["smpm", "run", "examples/vibrating_bar.toml", "--quiet"], src, env)
    run(["/usr/bin/python3", "analysis/plot_energy.py", "vibrating_bar.h5", "-o",
         "generated/vibrating_bar_energy"], src, env)
    run(["smpm", "run", "examples/two_disks.toml", "--quiet"], src, env)
    run_on_display(["pvbatch", "analysis/paraview_view.py", "./two_disks.xmf", "--time", "2.4",
                    "--field", "stress", "--component", "0", "--label", "stress xx", "-o",
                    "generated/paraview_two_disks"], src, env)


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--build", required=True, type=pathlib.Path, help="the CMake build tree")
    ap.add_argument("--out", type=pathlib.Path, help="where source/ and html/ go (BUILD/docs)")
    ap.add_argument("--check", action="store_true", help="then check the site (check_site.py)")
    a = ap.parse_args()
    build = a.build.resolve()
    out = (a.out or build / "docs").resolve()
    env = dict(os.environ, SMPM_BUILD=str(build), PYTHONDONTWRITEBYTECODE="1", SMPM_THREADS=os.environ.get("SMPM_THREADS", "2"),
               PYTHONPATH=str(build / "python"),
               PATH=os.pathsep.join([str(build / "apps"), "/usr/bin", os.environ["PATH"]]))
    if not (build / "docs" / "doxygen" / "xml" / "index.xml").exists():
        sys.exit(f"docs: no Doxygen XML in {build / 'docs' / 'doxygen' / 'xml'}: build the "
                 "docs target (cmake --build BUILD --target docs) or run scripts/docs")
    t0 = time.monotonic()
    src = stage(out)
    count = header_pages(src, build / "docs" / "doxygen" / "xml")
    step(f"staged the pages ({count} header pages)", t0)
    t = time.monotonic()
    run([sys.executable, HERE / "reference.py", src / "generated" / "input-keys.md"], src, env)
    step("the input reference", t)
    t = time.monotonic()
    manifest = short_cases.draw_all(src / "generated" / "figures", build)
    step(f"the analysis scripts on their short cases ({len(manifest)})", t)
    t = time.monotonic()
    figures(src, env)
    step("getting-started figures", t)
    t = time.monotonic()
    html = out / "html"
    if html.exists():
        shutil.rmtree(html)
    run([sys.executable, "-m", "sphinx", "-W", "--keep-going", "-E", "-q", "-b", "html", src,
         html], src, env)
    step("sphinx-build", t)
    print(f"docs: {html / 'index.html'}")
    if a.check:
        t = time.monotonic()
        shots = os.environ.get("SMPM_DOCS_SCREENSHOTS", str(out / "screenshots"))
        run([sys.executable, HERE / "check_site.py", html, "--screenshots", shots], src, env)
        step("check_site", t)
    step("the site", t0)


if __name__ == "__main__":
    main()
