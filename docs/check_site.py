#!/usr/bin/python3
# SPDX-License-Identifier: BSD-3-Clause
"""Checks a built site: every internal link, anchor and image, then every page in a browser.

    docs/check_site.py build/docs/html [--screenshots DIR]

1. Links: each href and src of each page that stays on the site (no scheme) names a file that
   exists, and its #fragment an id of that file.
2. A browser: each page opens in headless Chromium (Debian's chromium and chromium-driver,
   through Selenium); a message at the console of level SEVERE (a script error, a resource that
   failed to load) or an image that did not decode (naturalWidth 0) fails the check.
3. Screenshots of the getting-started page and of a study page go to DIR (to be looked at).
Prints the pages, links and images checked; exits 1 naming each failure.
"""

import argparse
import html.parser
import pathlib
import sys
import urllib.parse

SCREENSHOTS = {"getting-started.html": "getting-started.png",
               "studies/shocks.html": "study-shocks.png"}


class Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.ids, self.refs = set(), []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        for key in ("id", "name"):
            if a.get(key):
                self.ids.add(a[key])
        for key in ("href", "src"):
            if a.get(key) is not None and not (tag == "a" and key == "src"):
                self.refs.append((tag, a[key]))


def parse(path):
    p = Page()
    p.feed(path.read_text(encoding="utf-8"))
    return p


def check_links(root):
    pages = sorted(root.rglob("*.html"))
    parsed = {p: parse(p) for p in pages}
    failures, links = [], 0
    for page, p in parsed.items():
        for tag, ref in p.refs:
            url = urllib.parse.urlsplit(ref)
            if url.scheme or ref.startswith("//"):
                continue  # another site: not checked offline
            links += 1
            target = (page.parent / urllib.parse.unquote(url.path)).resolve() if url.path else page
            where = f"{page.relative_to(root)}: {tag} {ref}"
            if root not in target.parents and target != root:
                failures.append(f"{where}: leaves the site ({target})")
                continue
            if not target.exists():
                failures.append(f"{where}: no file {target}")
                continue
            if url.fragment and target.suffix == ".html":
                ids = parsed[target].ids if target in parsed else parse(target).ids
                if urllib.parse.unquote(url.fragment) not in ids:
                    failures.append(f"{where}: no anchor #{url.fragment}")
    return pages, links, failures


def check_browser(root, pages, shots):
    from selenium import webdriver
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    for a in ("--headless=new", "--no-sandbox", "--disable-gpu", "--window-size=1280,1600",
              "--allow-file-access-from-files"):
        options.add_argument(a)
    options.set_capability("goog:loggingPrefs", {"browser": "ALL"})
    driver = webdriver.Chrome(service=Service("/usr/bin/chromedriver"), options=options)
    failures, images = [], 0
    try:
        for page in pages:
            rel = page.relative_to(root).as_posix()
            driver.get(page.as_uri())
            for entry in driver.get_log("browser"):
                if entry["level"] == "SEVERE":
                    failures.append(f"{rel}: console: {entry['message']}")
            broken = driver.execute_script(
                "return Array.from(document.images).filter(i => !(i.complete && "
                "i.naturalWidth > 0)).map(i => i.getAttribute('src'))")
            images += driver.execute_script("return document.images.length")
            failures += [f"{rel}: image did not load: {src}" for src in broken]
            if shots and rel in SCREENSHOTS:
                shots.mkdir(parents=True, exist_ok=True)
                driver.save_screenshot(str(shots / SCREENSHOTS[rel]))
                print(f"check_site: screenshot of {rel} in {shots / SCREENSHOTS[rel]}")
    finally:
        driver.quit()
    return images, failures


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("html", type=pathlib.Path, help="the built site (build/docs/html)")
    ap.add_argument("--screenshots", type=pathlib.Path, help="where the screenshots go")
    a = ap.parse_args()
    root = a.html.resolve()
    if not (root / "index.html").exists():
        sys.exit(f"check_site: no index.html in {root}")
    pages, links, failures = check_links(root)
    missing = [name for name in SCREENSHOTS if not (root / name).exists()]
    failures += [f"no page {name} to photograph" for name in missing]
    images, browser_failures = check_browser(root, pages, a.screenshots)
    failures += browser_failures
    print(f"check_site: {len(pages)} pages, {links} internal links and sources, {images} images "
          f"in Chromium")
    for f in failures:
        print(f"check_site: {f}")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
