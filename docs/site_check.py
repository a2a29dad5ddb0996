"""Open every page of a built site in headless Chromium and fail on what a reader would meet.

Usage: ``python docs/site_check.py BUILD_DIR [--screens DIR] [--chromium PATH]``
(``make site-check``).  Each HTML page of BUILD_DIR is loaded from disk with every
request that leaves the build refused and recorded; after MathJax has finished, the
page fails on

- maths left untypeset (a ``.math`` element without MathJax output, a MathJax error,
  or raw ``\\(`` / ``$$`` delimiters in the text),
- any request, or any ``src``/``href`` of a script, style sheet, image or frame, that
  is not a file of the build,
- a broken image or a link to a missing file or anchor,
- a Python error in an output (a traceback, or an error or warning on stderr),
- a glue placeholder (``{glue:...}`` left in the text, or a glued ``nan``),
- a Python repr where a value belongs (``<function <lambda>>``, ``<factory>``,
  ``object at 0x...``: in an API signature, a data value or an output),
- a table headed by pandas row numbers (0, 1, 2, ...), or with a "nan" or "-0" cell,
- horizontal overflow (the page, or any element of the content, wider than its box).

A full-page screenshot of each page goes to the screens directory.  Exit status 1
lists every failure, page by page.
"""

from __future__ import annotations

import argparse
import shutil
import sys
from pathlib import Path
from urllib.parse import unquote, urlparse

VIEWPORT = {"width": 1280, "height": 900}

# Run in the page after MathJax has typeset it; returns the page's problems.
PROBE = r"""
() => {
  const out = [];
  const main = document.querySelector('div.body') || document.body;
  const text = (el) => el.innerText || '';
  // maths
  for (const el of document.querySelectorAll('.math')) {
    if (!el.querySelector('mjx-container') && !el.closest('mjx-container'))
      out.push(['maths', 'untypeset: ' + text(el).slice(0, 60)]);
  }
  for (const el of document.querySelectorAll('mjx-merror'))
    out.push(['maths', 'MathJax error: ' + (el.getAttribute('data-mjx-error') || text(el))]);
  const walker = document.createTreeWalker(main, NodeFilter.SHOW_TEXT);
  for (let n = walker.nextNode(); n; n = walker.nextNode()) {
    if (n.parentElement.closest('pre, code, script, style, mjx-container, textarea')) continue;
    const s = n.textContent;
    if (/\\\(|\\\[|\$\$/.test(s)) out.push(['maths', 'raw delimiters: ' + s.trim().slice(0, 60)]);
    if (/\{glue:|glue:text|glue:md/.test(s)) out.push(['glue', 'placeholder: ' + s.trim().slice(0, 60)]);
  }
  // resources that are not files of the build
  const attrs = [['script', 'src'], ['link', 'href'], ['img', 'src'], ['iframe', 'src'],
                 ['source', 'src'], ['video', 'src'], ['audio', 'src'], ['object', 'data']];
  for (const [tag, a] of attrs)
    for (const el of document.querySelectorAll(tag + '[' + a + ']')) {
      const u = el.getAttribute(a);
      if (/^(https?:)?\/\//i.test(u)) out.push(['network', tag + ' ' + a + '=' + u]);
    }
  for (const el of document.querySelectorAll('style'))
    for (const m of el.textContent.matchAll(/url\(\s*['"]?((?:https?:)?\/\/[^'")]+)/gi))
      out.push(['network', 'style url ' + m[1]]);
  // images
  for (const img of document.querySelectorAll('img')) {
    if (!img.complete || img.naturalWidth === 0)
      out.push(['image', 'broken: ' + img.getAttribute('src')]);
    else {
      const alt = img.getAttribute('alt') || '';
      if (!alt || /\.(png|svg|jpe?g|gif)$/i.test(alt) || alt.startsWith('data:'))
        out.push(['image', 'no alt text: ' + img.getAttribute('src').slice(0, 60)]);
    }
  }
  // Python errors in outputs
  for (const el of document.querySelectorAll('.output.traceback, .output.error'))
    out.push(['python', 'traceback: ' + text(el).slice(0, 120)]);
  for (const el of document.querySelectorAll('.output.stderr')) {
    const s = text(el);
    if (/Error|Warning|Traceback/.test(s)) out.push(['python', 'stderr: ' + s.slice(0, 120)]);
  }
  for (const el of document.querySelectorAll('.cell_output, .output'))
    if (/Traceback \(most recent call last\)/.test(text(el)))
      out.push(['python', 'traceback in output: ' + text(el).slice(0, 120)]);
  // Python reprs where a reader expects a value (API signatures, data, outputs)
  const reprs = new Set();
  for (const el of main.querySelectorAll('dt, dd > p, .cell_output, td, li, p')) {
    if (el.closest('.cell_input, div.highlight')) continue;
    const m = text(el).match(/<(?:function|lambda|factory|bound method)\b[^>]*>+|\bobject at 0x[0-9a-f]+/);
    if (m) reprs.add(m[0]);
  }
  for (const r of reprs) out.push(['repr', 'Python repr in the text: ' + r.slice(0, 60)]);
  // tables: pandas row numbers (0, 1, 2, ... heading the rows) and "nan" cells
  for (const tb of main.querySelectorAll('table')) {
    const heads = Array.from(tb.querySelectorAll('tbody tr > th:first-child'))
      .map((h) => text(h).trim());
    if (heads.length > 1 && heads.every((h, i) => h === String(i)))
      out.push(['table', 'row numbers heading a table: ' + text(tb).trim().slice(0, 50)]);
    const cells = Array.from(tb.querySelectorAll('td')).map((td) => text(td).trim());
    if (cells.some((c) => /^[-+]?nan$/i.test(c)))
      out.push(['table', 'nan in a table: ' + text(tb).trim().slice(0, 50)]);
    if (cells.some((c) => /^[-\u2212]0(\.0*)?(\s*%)?$/.test(c)))
      out.push(['table', '"-0" in a table: ' + text(tb).trim().slice(0, 50)]);
  }
  // glued values that came out as nan
  for (const el of document.querySelectorAll('.pasted-text, .pasted-inline'))
    if (/^\s*[-+]?nan\s*$/i.test(text(el))) out.push(['glue', 'glued nan']);
  // horizontal overflow (MathJax's assistive MathML is clipped, invisible: not measured)
  const hide = document.createElement('style');
  hide.textContent = 'mjx-assistive-mml { display: none !important; }';
  document.head.appendChild(hide);
  const doc = document.documentElement;
  if (doc.scrollWidth > doc.clientWidth + 1)
    out.push(['overflow', 'page ' + doc.scrollWidth + ' px wide in ' + doc.clientWidth]);
  for (const el of main.querySelectorAll('*')) {
    if (el.closest('mjx-container')) continue;
    const over = el.scrollWidth - el.clientWidth;
    if (el.clientWidth > 0 && over > 1) {
      const st = getComputedStyle(el);
      if (st.overflowX === 'hidden' && !['PRE', 'TABLE', 'DIV'].includes(el.tagName)) continue;
      const what = el.tagName.toLowerCase() + (el.className ? '.' + String(el.className).split(' ')[0] : '');
      out.push(['overflow', what + ' by ' + over + ' px: ' + text(el).trim().slice(0, 50)]);
    }
  }
  hide.remove();
  const anchors = Array.from(document.querySelectorAll('[id]')).map((e) => e.id);
  const links = Array.from(document.querySelectorAll('a[href]')).map((a) => a.getAttribute('href'));
  return {problems: out, anchors: anchors, links: links};
}
"""


def chromium_path(explicit: str | None) -> str:
    for name in (explicit, "chromium", "chromium-browser", "google-chrome"):
        if name and (found := shutil.which(name) or (Path(name).is_file() and name)):
            return str(found)
    sys.exit("site-check: no Chromium found (Debian: apt-get install chromium)")


def check(build: Path, screens: Path, chromium: str) -> dict[str, list[tuple[str, str]]]:
    try:
        from playwright.sync_api import sync_playwright
    except ImportError:
        sys.exit("site-check needs playwright: pip install 'dyntorsion[site]' (or make site-check)")

    pages = sorted(p for p in build.rglob("*.html") if "_static" not in p.parts)
    pages = [p for p in pages if p.name not in ("genindex.html", "search.html")] + [
        p for p in pages if p.name in ("genindex.html", "search.html")
    ]
    screens.mkdir(parents=True, exist_ok=True)
    root = build.resolve()
    found: dict[str, list[tuple[str, str]]] = {}
    anchors: dict[Path, set[str]] = {}
    links: dict[Path, list[str]] = {}
    with sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=chromium, args=["--no-sandbox"])
        context = browser.new_context(viewport=VIEWPORT)
        for page_path in pages:
            rel = page_path.relative_to(build).as_posix()
            problems: list[tuple[str, str]] = []
            page = context.new_page()

            def route(r, _request, problems=problems):
                u = urlparse(r.request.url)
                if u.scheme in ("file", "data", "blob", "about"):
                    if u.scheme == "file":
                        target = Path(unquote(u.path)).resolve()
                        if root not in (target, *target.parents):
                            problems.append(("network", f"outside the build: {u.path}"))
                            return r.abort()
                    return r.continue_()
                problems.append(("network", f"request to {r.request.url[:100]}"))
                return r.abort()

            page.route("**/*", route)
            page.on("pageerror", lambda e, problems=problems: problems.append(("js", str(e))))
            page.goto(page_path.resolve().as_uri(), wait_until="load")
            page.evaluate(
                "async () => { if (window.MathJax && MathJax.startup && MathJax.startup.promise)"
                " await MathJax.startup.promise; }"
            )
            page.wait_for_timeout(100)
            result = page.evaluate(PROBE)
            problems += [tuple(p) for p in result["problems"]]
            anchors[page_path.resolve()] = set(result["anchors"])
            links[page_path.resolve()] = result["links"]
            page.screenshot(
                path=str(screens / (rel.replace("/", "__")[:-5] + ".png")), full_page=True
            )
            page.close()
            found[rel] = problems
        browser.close()
    for page_path, hrefs in links.items():
        rel = page_path.relative_to(root).as_posix()
        for href in hrefs:
            u = urlparse(href)
            if u.scheme or href.startswith("//"):
                continue  # a link out is a reader's choice, not a request; mailto: etc.
            target = (page_path.parent / unquote(u.path)).resolve() if u.path else page_path
            if not target.exists():
                found[rel].append(("link", f"missing file: {href}"))
            elif u.fragment and target.suffix == ".html":
                ids = anchors.get(target)
                if ids is not None and u.fragment not in ids:
                    found[rel].append(("link", f"missing anchor: {href}"))
    return found


# A page with one of each defect; --self-test asserts that every kind is caught.
BAD_PAGE = """<!DOCTYPE html><html><head>
<script src="https://cdn.example.org/mathjax.js"></script>
<style>div.body { width: 400px; }</style></head><body><div class="body">
<p>raw maths: \\(\\kappa_0\\)</p><span class="math">\\(x\\)</span>
<p>a value {glue:text}`x`</p>
<img src="missing.png" alt="a missing image">
<img src="ok.svg">
<dl><dt>PRESETS = {'a': &lt;function &lt;lambda&gt;&gt;}</dt></dl>
<table><tbody><tr><th>0</th><td>1.5</td></tr><tr><th>1</th><td>nan</td></tr></tbody></table>
<a href="nowhere.html">broken link</a> <a href="#no-such-anchor">broken anchor</a>
<div class="cell_output"><div class="output stderr"><pre>ValueError: bad</pre></div></div>
<pre>a line of code far too long for the column it sits in, so that it runs out of its box sideways</pre>
</div></body></html>"""
OK_SVG = '<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"></svg>'
KINDS = {"maths", "network", "glue", "image", "link", "python", "overflow", "repr", "table"}


def self_test(chromium: str, tmp: Path) -> None:
    """Run the check on :data:`BAD_PAGE`; exit non-zero if a kind of defect goes unnoticed."""
    (tmp / "site").mkdir(parents=True, exist_ok=True)
    (tmp / "site" / "index.html").write_text(BAD_PAGE)
    (tmp / "site" / "ok.svg").write_text(OK_SVG)
    found = check(tmp / "site", tmp / "screens", chromium)["index.html"]
    missed = KINDS - {kind for kind, _ in found}
    if missed:
        sys.exit(f"site-check self-test: defects of kind {sorted(missed)} were not caught: {found}")
    print(f"site-check self-test: all {len(KINDS)} kinds of defect caught")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("build", type=Path, help="a built HTML site (sphinx -b html)")
    ap.add_argument("--screens", type=Path, default=Path("docs/_build/screens"))
    ap.add_argument("--chromium", default=None, help="the browser executable")
    ap.add_argument(
        "--self-test", action="store_true", help="first check that a page of defects fails"
    )
    args = ap.parse_args(argv)
    if args.self_test:
        import tempfile

        with tempfile.TemporaryDirectory() as tmp:
            self_test(chromium_path(args.chromium), Path(tmp))
    if not (args.build / "index.html").is_file():
        sys.exit(f"site-check: build={args.build} has no index.html")
    found = check(args.build, args.screens, chromium_path(args.chromium))
    bad = {k: v for k, v in found.items() if v}
    for rel, problems in bad.items():
        print(f"{rel}:")
        for kind, what in problems:
            print(f"  [{kind}] {what}".encode("utf-8", "replace").decode())
    print(
        f"site-check: {len(found)} pages, {len(found) - len(bad)} clean, {len(bad)} with problems;"
        f" screenshots in {args.screens}"
    )
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
