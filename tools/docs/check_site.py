# SPDX-License-Identifier: GPL-3.0-or-later
"""Checks a built documentation site: every internal link, anchor and image resolves.

usage: /usr/bin/python3 tools/docs/check_site.py SITE_DIR

MkDocs 1.4's --strict checks links to pages, not anchors; this reads every HTML page of the built
site and checks each relative href and src: the file exists in the site, and a #fragment names an
element id of the target page. External links (with a scheme) are not followed: the site must work
offline. Exit status 1 with one line per problem.
"""
import html.parser
import os
import sys
import urllib.parse


class Page(html.parser.HTMLParser):
    def __init__(self):
        super().__init__(convert_charrefs=True)
        self.ids, self.links, self.images = set(), [], []

    def handle_starttag(self, tag, attrs):
        a = dict(attrs)
        if "id" in a:
            self.ids.add(a["id"])
        if tag == "a" and "name" in a:
            self.ids.add(a["name"])
        if tag == "a" and a.get("href"):
            self.links.append(a["href"])
        if tag in ("img", "script") and a.get("src"):
            self.images.append(a["src"])
        if tag == "link" and a.get("href") and a.get("rel") in ("stylesheet", "icon", "shortcut icon"):
            self.images.append(a["href"])


def main():
    site = os.path.realpath(sys.argv[1])
    pages = {}
    for folder, _, files in os.walk(site):
        for f in files:
            if f.endswith(".html") and f != "404.html":  # 404.html links from the server root
                path = os.path.join(folder, f)
                p = Page()
                with open(path, encoding="utf-8") as fh:
                    p.feed(fh.read())
                pages[os.path.relpath(path, site)] = p
    problems, links, images = [], 0, 0
    for rel, p in sorted(pages.items()):
        base = os.path.dirname(rel)
        for kind, refs in (("link", p.links), ("image", p.images)):
            for ref in refs:
                u = urllib.parse.urlsplit(ref)
                if u.scheme or ref.startswith("//"):
                    continue  # external: not followed (the site works offline)
                target = rel if not u.path else os.path.normpath(os.path.join(base, urllib.parse.unquote(u.path)))
                if kind == "link":
                    links += 1
                else:
                    images += 1
                full = os.path.join(site, target)
                if os.path.isdir(full):
                    target = os.path.join(target, "index.html")
                    full = os.path.join(site, target)
                if not os.path.isfile(full):
                    problems.append(f"{rel}: {kind} '{ref}': {target} is not in the site")
                    continue
                if kind == "link" and u.fragment and target.endswith(".html"):
                    if target not in pages or urllib.parse.unquote(u.fragment) not in pages[target].ids:
                        problems.append(f"{rel}: link '{ref}': {target} has no anchor '#{u.fragment}'")
    for line in problems:
        print("check_site:", line)
    print(f"check_site: {len(pages)} pages, {links} internal links, {images} images, scripts and stylesheets; "
          f"{len(problems)} problems")
    sys.exit(1 if problems else 0)


if __name__ == "__main__":
    main()
