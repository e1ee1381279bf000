# SPDX-License-Identifier: BSD-3-Clause
# Sphinx configuration of the documentation site. Built by `scripts/docs` or the `docs` target
# (docs/CMakeLists.txt), which set SMPM_BUILD to the CMake build tree: its smpm runs the pages'
# commands, its Python module is the one autodoc reads, and Doxygen's XML there is Breathe's.
import logging
import os
import re
import subprocess
from xml.etree import ElementTree
import pathlib
import sys

HERE = pathlib.Path(__file__).resolve().parent
BUILD = pathlib.Path(os.environ.get("SMPM_BUILD", HERE.parent / "build")).resolve()
sys.path.insert(0, str(BUILD / "python"))
sys.path.insert(0, str(HERE / "_ext"))

import sparsempm  # noqa: E402  (autodoc documents this build's module)

project = "sparsempm"
author = "the sparsempm authors"
copyright = "the sparsempm authors, BSD 3-Clause"
# "0.2.0 (commit 1a2b3c4)": the release and the commit this build's smpm was built from.
release = subprocess.run([str(BUILD / "apps" / "smpm"), "--version"], capture_output=True,
                         text=True, check=True).stdout.strip().removeprefix("smpm ")
version = release  # the theme shows it under the project's name
if not release.startswith(sparsempm.__version__ + " "):
    raise RuntimeError(f"smpm {release} and the module {sparsempm.__version__} differ")

extensions = [
    "myst_parser",
    "sphinx.ext.autodoc",
    "sphinx.ext.mathjax",
    "sphinxcontrib.programoutput",
    "breathe",
    "smpm_docs",
]

# Markdown pages; the headings down to ### get anchors, so links may name them (page.md#anchor).
source_suffix = {".md": "markdown"}
myst_enable_extensions = ["colon_fence", "dollarmath"]
myst_heading_anchors = 3
exclude_patterns = ["_build", "examples", "analysis", "generated/*.md", "Thumbs.db", ".DS_Store"]
# Figures are kept beside the pages (docs/*.png); the analysis scripts write them there.

smartquotes = False  # quotes stay as typed: the values of keys are TOML
html_theme = "sphinx_rtd_theme"
html_title = f"sparsempm {release}"
html_theme_options = {"navigation_depth": 3}
html_static_path = ["_static"]
html_css_files = ["sparsempm.css"]  # wider pages, table cells that wrap
html_show_sourcelink = False

# The commands of the pages run in a fresh directory with this build's smpm and module first.
programoutput_use_ansi = False
os.environ["PATH"] = f"{BUILD / 'apps'}{os.pathsep}{os.environ['PATH']}"
os.environ["PYTHONPATH"] = str(BUILD / "python")
os.environ.setdefault("SMPM_THREADS", "2")

breathe_projects = {"sparsempm": str(BUILD / "docs" / "doxygen" / "xml")}
breathe_default_project = "sparsempm"
breathe_default_members = ("members",)

autodoc_member_order = "bysource"
autodoc_typehints = "none"


def plain_docstring(app, what, name, obj, options, lines):
    """The module's docstrings are plain text, not reStructuredText: |x| is a norm, * a product.
    The characters reStructuredText reads as markup are escaped, and an indented block after a
    line ending in ':' (code, a formula) is shown as written."""
    special = str.maketrans({"|": r"\|", "*": r"\*", "`": r"\`"})
    out, block_indent = [], None
    for i, line in enumerate(lines):
        indent = len(line) - len(line.lstrip())
        if block_indent is not None and (not line.strip() or indent >= block_indent):
            out.append(line)
            continue
        block_indent = None
        text = re.sub(r"(\w)_(?=\W|$)", r"\1\\_", line.translate(special))
        nxt = next((l for l in lines[i + 1:] if l.strip()), "")
        if line.rstrip().endswith(":") and len(nxt) - len(nxt.lstrip()) > indent:
            text = text.rstrip() + ":"
            block_indent = len(nxt) - len(nxt.lstrip())
        out.append(text)
    lines[:] = out


class OneNamespaceManyHeaders(logging.Filter):
    """Breathe declares a header's namespace on each header's page; the namespaces (those of
    Doxygen's index, nothing else) are one object met on several pages, not a duplicate."""

    def __init__(self, namespaces):
        super().__init__()
        self.declarations = {f"'.. cpp:type:: {n}'." for n in namespaces}

    def filter(self, record):
        text = record.getMessage()
        return not (text.startswith("Duplicate C++ declaration") and
                    text.splitlines()[-1].split("Declaration is ")[-1] in self.declarations)


def doxygen_namespaces():
    index = ElementTree.parse(BUILD / "docs" / "doxygen" / "xml" / "index.xml").getroot()
    names = {c.findtext("name") for c in index.iter("compound") if c.get("kind") == "namespace"}
    return names | {n.split("::")[-1] for n in names}


def setup(app):
    app.connect("autodoc-process-docstring", plain_docstring)
    logging.getLogger("sphinx.sphinx.domains.cpp").addFilter(
        OneNamespaceManyHeaders(doxygen_namespaces()))
