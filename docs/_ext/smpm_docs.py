# SPDX-License-Identifier: BSD-3-Clause
"""The site's one directive of its own: a study figure drawn by the site's build.

    ```{short-case} fig4
    ```

shows the command that drew analysis/fig4.py's short case (the figure test's, tests/python/
figure_cases.py) when the site was built, and the figures it wrote (docs/short_cases.py puts
them in generated/figures/ with a manifest). A name without a drawing is an error.
"""

import json
import pathlib

from docutils import nodes
from sphinx.errors import ExtensionError
from sphinx.util.docutils import SphinxDirective


class ShortCase(SphinxDirective):
    required_arguments = 1

    def run(self):
        name = self.arguments[0]
        root = pathlib.Path(self.env.srcdir) / "generated" / "figures"
        manifest = json.loads((root / "manifest.json").read_text())
        if name not in manifest:
            raise ExtensionError(f"short-case {name}: no such case in {root / 'manifest.json'}")
        case = manifest[name]
        note = nodes.admonition(classes=["short-case"])
        note += nodes.title(text=f"Drawn by this site's build: analysis/{name}.py on a short case")
        para = nodes.paragraph(text=f"The case of the figure test (tests/python/figure_cases.py), "
                                    f"{case['seconds']} s on one thread: ")
        note += para
        note += nodes.literal_block(case["command"], case["command"], language="sh")
        for png in case["pngs"]:
            note += nodes.image(uri=f"/generated/figures/{png}",
                                alt=f"analysis/{name}.py on its short case")
        return [note]


def setup(app):
    app.add_directive("short-case", ShortCase)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
