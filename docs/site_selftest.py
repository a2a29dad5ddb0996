"""The self-test of ``docs/site_check.py``: a page with one defect of each kind the check
knows, and the assertion that every one is caught (``site_check.py --self-test``)."""

from __future__ import annotations

import sys
from pathlib import Path

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
<p>a rate of 12.800000 rad/(m s), an energy defect of 0.000 and
<span class="pasted-text">1.4e-16</span> J; in prose as code, 1e-8 N is allowed</p>
<table><thead><tr><th></th><th>t_c</th></tr><tr><th>seed</th><th></th></tr></thead>
<tbody><tr><th>1e-8</th><td>14.70</td></tr></tbody></table>
<dl class="py data"><dt>m_cri</dt><dd><p>Convert a string or number to a floating point number, if possible.</p></dd></dl>
<img src="wide.png" alt="a figure squeezed to a quarter" style="width: 100px">
</div><div class="footer">&copy;. | Powered by Sphinx</div></body></html>"""
#: what the self-test plants in BAD_PAGE: (kind, part of the message) each must be caught
PLANTED = (
    ("maths", "raw delimiters"),
    ("maths", "untypeset"),
    ("network", "cdn.example.org"),
    ("glue", "placeholder"),
    ("glue", "glue key 'x' differs"),
    ("image", "broken"),
    ("image", "no alt text"),
    ("link", "missing file"),
    ("link", "missing anchor"),
    ("python", "stderr"),
    ("overflow", "pre"),
    ("repr", "<function"),
    ("table", "row numbers"),
    ("table", "nan in a table"),
    ("table", "pandas index row"),
    ("number", "12.800000"),
    ("number", "0.000"),
    ("number", "1.4e-16"),
    ("apidoc", "Convert a string or number"),
    ("footer", 'no "version'),
    ("small-text", "wide.png"),
)
OK_SVG = '<svg xmlns="http://www.w3.org/2000/svg" width="10" height="10"></svg>'


def _png(width: int, height: int) -> bytes:
    """A blank grey PNG image of ``width`` x ``height`` pixels."""
    import struct
    import zlib

    def chunk(kind: bytes, data: bytes) -> bytes:
        body = kind + data
        return struct.pack(">I", len(data)) + body + struct.pack(">I", zlib.crc32(body))

    rows = b"".join(b"\0" + b"\x80" * width for _ in range(height))
    head = struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0)
    return (
        b"\x89PNG\r\n\x1a\n"
        + chunk(b"IHDR", head)
        + chunk(b"IDAT", zlib.compress(rows))
        + (chunk(b"IEND", b""))
    )


def self_test(chromium: str, tmp: Path) -> None:
    """Run the check on :data:`BAD_PAGE` (and a second page that glues one key to another
    value); exit non-zero if a planted defect (:data:`PLANTED`) goes unnoticed."""
    import json

    site = tmp / "site"
    (site / "_glue").mkdir(parents=True, exist_ok=True)
    (site / "index.html").write_text(BAD_PAGE)
    (site / "other.html").write_text("<html><body><div class='body'>ok</div></body></html>")
    (site / "ok.svg").write_text(OK_SVG)
    (site / "wide.png").write_bytes(_png(400, 40))
    for page, value in (("index", "'20.78'"), ("other", "'20.79'")):
        glued = {"x": {"data": {"text/plain": value}}, "same": {"data": {"text/plain": "'1'"}}}
        (site / "_glue" / f"{page}.glue.json").write_text(json.dumps(glued))
    from site_check import check  # docs/, beside this module

    found = check(site, tmp / "screens", chromium, version="0.0.0")["index.html"]
    missed = [(kind, what) for kind, what in PLANTED
              if not any(k == kind and what in w for k, w in found)]  # fmt: skip
    if missed:
        sys.exit(f"site-check self-test: planted defects not caught: {missed}; found: {found}")
    if any("'same'" in w for _, w in found):
        sys.exit("site-check self-test: a glue key with one value on two pages was flagged")
    print(f"site-check self-test: all {len(PLANTED)} planted defects caught")
