"""Open every page of a built site in headless Chromium and fail on what a reader would meet.

Usage: ``python docs/site_check.py BUILD_DIR [--screens DIR] [--chromium PATH] [--budgets]``
(``make site-check``).  With ``--budgets`` only the word budgets are checked, without a
browser: a table of pages, narrative words and the share of long sentences, and exit
status 1 when a budget is broken (``docs/site_budget.py``).  Otherwise each HTML page of BUILD_DIR is loaded from disk with every
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
- horizontal overflow (the page, or any element of the content, wider than its box),
- an unformatted number in the text or a table (``0.200000``, ``12.800000``: three or
  more trailing zeros after the point, or a zero written as ``0.000``),
- a table with a pandas index row in its header (the index name on a row of its own),
- a built-in docstring on an API page (a constant documented by its type: "Convert a
  string or number to a floating point number", "Built-in immutable sequence"),
- a footer without the version of the package,
- a figure scaled so far down to fit the column that its smallest text (9 pt at 150 dpi,
  ``plotting.save``) reads under 9 pt,

and, across pages, on one glue key shown with two values on two pages (the glued values
the build keeps in ``_glue/``, see ``docs/conf.py``), and on a broken word budget
(``docs/site_budget.py``: narrative words per page and in total, long sentences).

A full-page screenshot of each page goes to the screens directory.  Exit status 1
lists every failure, page by page.
"""

from __future__ import annotations

import argparse
import shutil
import sys
from pathlib import Path
from urllib.parse import unquote, urlparse

import site_budget  # docs/, this script's folder
import site_selftest

VIEWPORT = {"width": 1280, "height": 900}

#: the first line of the docstrings of Python's own types, which autodoc shows for a
#: constant without a ``#:`` comment
BUILTIN_DOCS = sorted(
    {
        t.__doc__.strip().splitlines()[0].strip()
        for t in (float, int, str, tuple, list, dict, set, frozenset, bool, complex, bytes)
    }
    | {"Built-in immutable sequence.", "Convert a string or number to a floating point number"}
)
#: a figure is saved at 150 dpi with no text under 9 pt (``dyntorsion.app.plotting``); shown
#: at a CSS px per image px of less than 96/150 its smallest text reads under 9 pt
MIN_SCALE = 96 / 150

# Run in the page after MathJax has typeset it (with BUILTIN_DOCS, VERSION, MIN_SCALE
# defined before it); returns the page's problems.
PROBE = r"""
(cfg) => {
  const BUILTIN_DOCS = cfg.docs, VERSION = cfg.version, MIN_SCALE = cfg.min_scale;
  const out = [];
  const main = document.querySelector('article.bd-article') || document.querySelector('div.body')
    || document.querySelector('main#main-content') || document.body;
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
  // unformatted numbers: trailing zeros ("0.200000", "12.800000") or a zero as "0.000"
  const unformatted = /(?:^|[^\w.])(\d+\.\d*000)(?![\d.])|(?:^|[^\w.])([-\u2212]?0\.00+)(?![\d.])/g;
  // e-notation where a computed value is shown (a table cell, a glued value); prose and
  // API signatures may quote code
  const enote = /(?:^|[^\w.])(\d+(?:\.\d+)?e[-+]?\d+)(?![\w.])/g;
  const numbers = new Set();
  const walker2 = document.createTreeWalker(main, NodeFilter.SHOW_TEXT);
  for (let n = walker2.nextNode(); n; n = walker2.nextNode()) {
    if (n.parentElement.closest('pre, code, script, style, mjx-container, textarea, .cell_input, div.highlight, dt.sig')) continue;
    for (const m of n.textContent.matchAll(unformatted))
      numbers.add((m[1] || m[2]) + ' in "' + n.textContent.trim().slice(0, 50) + '"');
    if (n.parentElement.closest('td, th, .pasted-text, .pasted-inline'))
      for (const m of n.textContent.matchAll(enote))
        numbers.add(m[1] + ' in "' + n.textContent.trim().slice(0, 50) + '"');
  }
  for (const x of numbers) out.push(['number', 'unformatted: ' + x]);
  // pandas index rows: a header row holding only the index name(s), the rest empty
  for (const tb of main.querySelectorAll('table')) {
    for (const tr of tb.querySelectorAll('thead tr')) {
      const cells = Array.from(tr.children).map((c) => text(c).trim());
      if (cells.length > 1 && cells[0] !== '' && cells.slice(1).every((c) => c === '')
          && tb.querySelectorAll('thead tr').length > 1)
        out.push(['table', 'pandas index row in the header: ' + cells[0].slice(0, 40)]);
    }
  }
  // built-in docstrings of Python's types on an API entry
  for (const dd of main.querySelectorAll('dl.py > dd, dl.data > dd, dl.attribute > dd')) {
    const s = text(dd);
    for (const doc of BUILTIN_DOCS)
      if (s.includes(doc)) out.push(['apidoc', 'built-in docstring: ' + doc.slice(0, 60)]);
  }
  // the footer names the version
  // (a theme may have several footers: the page's, a previous/next bar)
  const footers = Array.from(document.querySelectorAll('div.footer, footer'));
  if (!footers.some((f) => text(f).includes('version ' + VERSION)))
    out.push(['footer', 'no "version ' + VERSION + '" in the footer: '
      + (footers.length ? footers.map((f) => text(f).trim().slice(0, 30)).join(' | ') : 'none')]);
  // figures scaled below the smallest readable text
  for (const img of main.querySelectorAll('img')) {
    if (!img.complete || img.naturalWidth === 0 || /\.svg$/i.test(img.getAttribute('src') || '')) continue;
    const scale = img.getBoundingClientRect().width / img.naturalWidth;
    if (img.naturalWidth > 200 && scale < MIN_SCALE)
      out.push(['small-text', 'figure shown at ' + Math.round(100 * scale) + ' % of its '
        + img.naturalWidth + ' px: 9 pt text reads as ' + (9 * scale / MIN_SCALE).toFixed(1)
        + ' pt: ' + img.getAttribute('src').slice(0, 60)]);
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


def glue_conflicts(build: Path) -> dict[str, list[tuple[str, str]]]:
    """One glue key with two values on two pages: ``{page: [("glue", what)]}``, from the
    glued values the build keeps (``_glue/<page>.glue.json``, ``docs/conf.py``)."""
    import json

    seen: dict[str, dict[str, str]] = {}
    for f in sorted((build / "_glue").rglob("*.glue.json")):
        page = f.relative_to(build / "_glue").as_posix().removesuffix(".glue.json") + ".html"
        for key, out in json.loads(f.read_text()).items():
            value = out.get("data", {}).get("text/plain")
            if value is not None:
                seen.setdefault(key, {})[page] = value
    found: dict[str, list[tuple[str, str]]] = {}
    for key, pages in seen.items():
        if len(set(pages.values())) > 1:
            shown = ", ".join(f"{v} on {p}" for p, v in pages.items())
            for p in pages:
                found.setdefault(p, []).append(("glue", f"glue key {key!r} differs: {shown}"))
    return found


def check(
    build: Path, screens: Path, chromium: str, version: str | None = None
) -> dict[str, list[tuple[str, str]]]:
    if version is None:
        from dyntorsion import __version__ as version
    probe_cfg = {"docs": BUILTIN_DOCS, "version": version, "min_scale": MIN_SCALE}
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
            result = page.evaluate(PROBE, probe_cfg)
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
    for rel, problems in glue_conflicts(build).items():
        found.setdefault(rel, []).extend(problems)
    return found


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("build", type=Path, help="a built HTML site (sphinx -b html)")
    ap.add_argument("--screens", type=Path, default=Path("docs/_build/screens"))
    ap.add_argument("--chromium", default=None, help="the browser executable")
    ap.add_argument(
        "--self-test", action="store_true", help="first check that a page of defects fails"
    )
    ap.add_argument(
        "--budgets", action="store_true", help="check only the word budgets (no browser)"
    )
    ap.add_argument(
        "--long",
        nargs="*",
        metavar="PAGE",
        help="with --budgets: list the long sentences"
        " of these pages (of every page when none is named)",
    )
    args = ap.parse_args(argv)
    if args.self_test:
        import tempfile

        with tempfile.TemporaryDirectory() as tmp:
            site_budget.self_test(Path(tmp))
            if not args.budgets:
                site_selftest.self_test(chromium_path(args.chromium), Path(tmp))
    if not (args.build / "index.html").is_file():
        sys.exit(f"site-check: build={args.build} has no index.html")
    counts = site_budget.count_site(args.build)
    over = site_budget.problems(counts)
    if args.budgets:
        print(site_budget.table(counts))
        for c in counts if args.long is not None else ():
            if c.long_sentences and (not args.long or c.page in args.long):
                print(
                    f"\n{c.page}:",
                    *(f"  [{len(s.split())}] {s}" for s in c.long_sentences),
                    sep="\n",
                )
        print("\n".join(f"over budget: {p}" for p in over) or "site-check: every budget kept")
        return 1 if over else 0
    found = check(args.build, args.screens, chromium_path(args.chromium))
    for problem in over:
        page, _, what = problem.partition(": ")
        found.setdefault(page if page != "site" else "index.html", []).append(("budget", what))
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
