#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Keeps the Concepts page of the API documentation (docs/concepts.md) true: every function or
class its tables name in the column "Implemented by" is declared in the public header of the
column "Header", and that header exists.

A table row is `| Paper | Equation | Implemented by | Header |`; the names are separated by
commas, a function written `name()`, a class or enum `smpm::Name`, a member function
`smpm::Class::name()`, a nested class `smpm::Class::Name`. A function counts as declared when
the header (without its comments) has the name followed by `(` after a type; a class or enum
when it has `struct`, `class` or `enum class` followed by the name and its body; a member when
its class is declared so and the member is declared in the class's body.

Run by ctest as docs.concepts: check_concepts.py [SOURCE_DIR] (default: this checkout).
Prints every failure and exits with status 1 when there is one.
"""
import pathlib
import re
import sys

INCLUDE_DIRS = [
    "lib/include/sparsempm",
    "lib/exact/include/sparsempm",
    "lib/analysis/include/sparsempm",
    "lib/io/include/sparsempm",
]
# Fewer rows than this means the tables were not parsed (the page is far longer).
MIN_ROWS = 20

IDENT = r"[A-Za-z_]\w*"
KEYWORDS = {"return", "throw", "new", "delete", "else", "do", "case", "co_return", "sizeof"}


def strip_comments(text):
    """The header without its // and /* */ comments (the declarations only)."""
    text = re.sub(r"/\*.*?\*/", " ", text, flags=re.S)
    return re.sub(r"//[^\n]*", "", text)


def declares_function(code, name):
    """Whether `code` declares the function `name`: a type, then the name, then `(`."""
    pattern = r"(?:^|(" + IDENT + r")\s+|[&*>\]]\s*)" + re.escape(name) + r"\s*\("
    for m in re.finditer(pattern, code, flags=re.M):
        if m.group(1) not in KEYWORDS:
            return True
    return False


def class_body(code, name):
    """The body of the struct, class or enum class `name` defined in `code`, or None."""
    m = re.search(r"\b(?:struct|class|enum\s+class|enum\s+struct)\s+" + re.escape(name) +
                  r"\b(?:\s+final)?\s*(?::[^;{]*)?\{", code)
    if not m:
        return None
    depth, start = 1, m.end()
    for i in range(start, len(code)):
        if code[i] == "{":
            depth += 1
        elif code[i] == "}":
            depth -= 1
            if depth == 0:
                return code[start:i]
    return None


def find_header(root, name):
    """The path of the public header `name` ("stages.hpp" or "sparsempm/stages.hpp"): exactly
    one of the include directories must hold it."""
    base = name.split("/")[-1]
    found = [root / d / base for d in INCLUDE_DIRS if (root / d / base).is_file()]
    if len(found) != 1:
        return None, f"header {name} is {'not a public header' if not found else 'ambiguous'}"
    return found[0], None


def parse_rows(page):
    """(line number, names, header) of every table row of the page."""
    rows = []
    for number, line in enumerate(page.splitlines(), 1):
        if not line.startswith("|"):
            continue
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if cells[0] == "Paper" or set("".join(cells)) <= set("-: "):
            continue
        rows.append((number, cells))
    return rows


def check_name(code, name):
    """None when `name` (as the table writes it) is declared in `code`, else why not."""
    bare = name[len("smpm::"):] if name.startswith("smpm::") else name
    function = bare.endswith("()")
    bare = bare[:-2] if function else bare
    parts = bare.split("::")
    if not all(re.fullmatch(IDENT, p) for p in parts) or len(parts) > 2:
        return f"'{name}' is not a name (name(), smpm::Class or smpm::Class::name())"
    if len(parts) == 2:
        body = class_body(code, parts[0])
        if body is None:
            return f"class {parts[0]} of '{name}' is not defined there"
        if function and not declares_function(body, parts[1]):
            return f"member function '{parts[1]}' is not declared in the body of {parts[0]}"
        if not function and class_body(body, parts[1]) is None:
            return f"nested class '{parts[1]}' is not defined in the body of {parts[0]}"
        return None
    if function:
        return None if declares_function(code, bare) else f"function '{bare}' is not declared"
    if class_body(code, bare) is not None or re.search(r"\busing\s+" + bare + r"\s*=", code):
        return None
    return f"class or enum '{bare}' is not defined"


def main():
    root = pathlib.Path(sys.argv[1] if len(sys.argv) > 1 else pathlib.Path(__file__).parents[2])
    page_path = root / "docs" / "concepts.md"
    page = page_path.read_text(encoding="utf-8")
    failures, checked = [], 0
    rows = parse_rows(page)
    if len(rows) < MIN_ROWS:
        failures.append(f"{page_path}: {len(rows)} table rows, expected at least {MIN_ROWS}")
    for number, cells in rows:
        where = f"{page_path}:{number}"
        if len(cells) != 4:
            failures.append(f"{where}: {len(cells)} columns, expected 4 (Paper | Equation | "
                            "Implemented by | Header)")
            continue
        names = [n.strip() for n in cells[2].split(",") if n.strip()]
        header, why = find_header(root, cells[3])
        if not names:
            failures.append(f"{where}: no name in the column Implemented by")
        if why:
            failures.append(f"{where}: {why}")
            continue
        code = strip_comments(header.read_text(encoding="utf-8"))
        for name in names:
            checked += 1
            why = check_name(code, name)
            if why:
                failures.append(f"{where}: {why} in {header.relative_to(root)}")
    for f in failures:
        print(f, file=sys.stderr)
    if failures:
        print(f"check_concepts: {len(failures)} failure(s)", file=sys.stderr)
        return 1
    print(f"check_concepts: {len(rows)} rows, {checked} names, each declared in its header")
    return 0


if __name__ == "__main__":
    sys.exit(main())
