# SPDX-License-Identifier: GPL-3.0-or-later
"""Opens pages of the built documentation site in headless Chromium: each must render with its
stylesheets and every image loaded, and a screenshot of each is written.

usage: /usr/bin/python3 tools/docs/browser_check.py SITE_DIR OUT_DIR [PAGE[=NAME][:MIN_IMAGES] ...]

Default pages: the home page, the MeshLab filters page and the results page (index.html=home:2,
meshlab.html=meshlab:4, results.html=results:8), plus the filter reference without a screenshot
(reference/filters.html=-:0; NAME "-": no screenshot).
The site is served on 127.0.0.1 from this process (the machine's network may be closed); Debian's
`chromium` runs headless, sandbox off, without GPU, background networking, component updates or
sync, each launch with a new profile folder. One launch loads a small checking page that opens each
PAGE in turn in a same-origin frame and reports, from the rendered document, its title, the
stylesheets applied, MkDocs-material's header, and every <img> with whether it loaded (complete and
of non-zero size); then one launch per page takes a 1280 x 1000 screenshot into OUT_DIR/NAME.png,
which must not be blank. `tools/docs/browser_check.py build/site docs/preview` refreshes the site's
preview pictures kept in docs/preview/.
"""
import functools
import http.server
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time

CHROMIUM = ["chromium", "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
            "--disable-background-networking", "--disable-component-update", "--disable-sync",
            "--disable-default-apps", "--disable-extensions", "--mute-audio", "--hide-scrollbars"]
DEFAULT_PAGES = ["index.html=home:2", "meshlab.html=meshlab:4", "results.html=results:8",
                 "reference/filters.html=-:0"]

CHECK_HTML = """<!doctype html><html><head><meta charset="utf-8"><title>check</title></head><body>
<iframe id="f" style="width:1280px;height:1000px"></iframe>
<script>
const pages = new URLSearchParams(location.search).get('pages').split(',');
const f = document.getElementById('f');
const results = {};
function report(page) {
  const d = f.contentDocument;
  const imgs = Array.from(d.images);
  results[page] = {
    title: d.title,
    h1: (d.querySelector('h1') || {textContent: ''}).textContent.replace('\\u00b6', '').trim(),
    stylesheets: d.styleSheets.length,
    header: !!d.querySelector('header.md-header'),
    images: imgs.map(i => ({src: i.getAttribute('src'), ok: i.complete && i.naturalWidth > 0})),
    tables: d.querySelectorAll('table').length
  };
}
function next(k) {
  if (k == pages.length) { document.body.setAttribute('data-result', JSON.stringify(results)); return; }
  f.onload = () => setTimeout(() => { report(pages[k]); next(k + 1); }, 300);
  f.src = 'site/' + pages[k];
}
next(0);
</script></body></html>
"""


class Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


def serve(root):
    handler = functools.partial(Quiet, directory=root)
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    threading.Thread(target=server.serve_forever, daemon=True).start()
    return server


def chromium(args, timeout=60):
    profile = tempfile.mkdtemp(prefix="canonform-chromium-")
    try:
        return subprocess.run(CHROMIUM + [f"--user-data-dir={profile}"] + args, capture_output=True, text=True,
                              timeout=timeout)
    finally:
        shutil.rmtree(profile, ignore_errors=True)


def not_blank(png):
    """The screenshot has more than a few colours (matplotlib reads PNG; Debian's python3-matplotlib)."""
    import matplotlib.image
    import numpy
    a = matplotlib.image.imread(png)
    colours = numpy.unique((a[:, :, :3] * 255).astype(numpy.uint8).reshape(-1, 3), axis=0)
    return a.shape[1] == 1280 and len(colours) > 50, f"{a.shape[1]}x{a.shape[0]}, {len(colours)} colours"


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    site, out = os.path.realpath(sys.argv[1]), os.path.realpath(sys.argv[2])
    pages = sys.argv[3:] or DEFAULT_PAGES
    os.makedirs(out, exist_ok=True)
    root = tempfile.mkdtemp(prefix="canonform-site-")
    os.symlink(site, os.path.join(root, "site"))
    with open(os.path.join(root, "check.html"), "w") as f:
        f.write(CHECK_HTML)
    server = serve(root)
    base = f"http://127.0.0.1:{server.server_address[1]}"
    failures = 0
    t0 = time.time()
    try:
        specs = []
        for spec in pages:
            m = re.match(r"([^=:]+)(?:=([^:]+))?(?::(\d+))?$", spec)
            page = m.group(1)
            specs.append((page, m.group(2) or os.path.splitext(os.path.basename(page))[0], int(m.group(3) or 0)))
        missing = [p for p, _, _ in specs if not os.path.isfile(os.path.join(site, p))]
        for p in missing:
            print(f"  FAIL {p}: not in the site")
        failures += len(missing)
        specs = [s for s in specs if s[0] not in missing]
        r = chromium(["--virtual-time-budget=30000", "--dump-dom",
                      f"{base}/check.html?pages={','.join(p for p, _, _ in specs)}"], timeout=120)
        found = re.search(r'data-result="([^"]*)"', r.stdout)
        if not found:
            print(f"  FAIL Chromium reported nothing (exit {r.returncode}): {r.stderr.strip()[-300:]}")
            sys.exit(1)
        results = json.loads(found.group(1).replace("&quot;", '"').replace("&lt;", "<").replace("&gt;", ">")
                             .replace("&amp;", "&"))
        for page, name, min_images in specs:
            res = results.get(page)
            if res is None:
                print(f"  FAIL {page}: not reported")
                failures += 1
                continue
            broken = [i["src"] for i in res["images"] if not i["ok"]]
            problems = []
            if not res["title"] or not res["h1"]:
                problems.append("no title or heading")
            if res["stylesheets"] < 1 or not res["header"]:
                problems.append("the theme's stylesheets or header did not load")
            if broken:
                problems.append("images not loaded: " + ", ".join(broken))
            if len(res["images"]) < min_images:
                problems.append(f"{len(res['images'])} images, expected at least {min_images}")
            shot_info = "no screenshot"
            if name != "-":
                shot = os.path.join(out, name + ".png")
                tmp = shot + ".tmp.png"
                s = chromium(["--window-size=1280,1000", f"--screenshot={tmp}", f"{base}/site/{page}"])
                if not os.path.isfile(tmp):
                    problems.append(f"no screenshot (exit {s.returncode})")
                else:
                    ok, shot_info = not_blank(tmp)
                    if not ok:
                        problems.append(f"blank screenshot ({shot_info})")
                    os.replace(tmp, shot)
                    shot_info = f"screenshot {shot} ({shot_info})"
            status = "FAIL" if problems else "ok  "
            print(f"  {status} {page}: '{res['h1']}', {res['stylesheets']} stylesheets, "
                  f"{len(res['images']) - len(broken)}/{len(res['images'])} images loaded, {res['tables']} tables; "
                  f"{shot_info}" + "".join(f"\n       {p}" for p in problems))
            failures += bool(problems)
    finally:
        server.shutdown()
        shutil.rmtree(root, ignore_errors=True)
    print(f"browser_check: {len(pages)} pages, {failures} failed, {time.time() - t0:.1f} s")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
