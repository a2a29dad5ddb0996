"""Word budgets of the built site: narrative words per page and in total, long sentences.

The rule (``DESIGN.md``, "Writing"): the narrative prose of the site -- every page but the
API reference pages and the changelog -- is at most :data:`TOTAL_WORDS` words, no page more
than :data:`PAGE_WORDS`, and on every page at most :data:`LONG_SHARE` of the sentences run
over :data:`LONG_WORDS` words.  Words are counted on the built HTML, in the page's main
content, leaving out ``pre``, ``code``, tables, maths, notebook cell outputs and inputs,
API entries a page embeds (autodoc), navigation and the ``¶`` anchors.  Only the standard library is used, so the count runs
without a browser: ``python docs/site_check.py BUILD --budgets`` prints the table and exits
non-zero when a budget is broken.
"""

from __future__ import annotations

import re
from dataclasses import dataclass
from fnmatch import fnmatch
from html.parser import HTMLParser
from pathlib import Path

#: narrative words of the whole site, at most
TOTAL_WORDS = 20_000
#: narrative words of one page, at most
PAGE_WORDS = 2_500
#: a sentence of more than this many words is long ...
LONG_WORDS = 50
#: ... and at most this share of a page's sentences may be long
LONG_SHARE = 0.05
#: pages that are not narrative (paths relative to the build, shell patterns)
NOT_NARRATIVE = (
    "api_*.html",
    "changelog.html",
    "genindex.html",
    "py-modindex.html",
    "search.html",
    "_modules/*",
    "_static/*",
)
#: the element whose text is the page's main content (alabaster, pydata/sphinx-book-theme)
MAIN = (("div", "body"), ("article", "bd-article"))
#: elements whose text is not narrative: (tag, class or None for any element of the tag)
SKIP = (
    ("pre", None),
    ("code", None),
    ("table", None),
    ("script", None),
    ("style", None),
    ("nav", None),
    ("math", None),
    ("mjx-container", None),
    ("dl", "py"),
    (None, "math"),
    (None, "cell_output"),
    (None, "cell_input"),
    (None, "output"),
    (None, "highlight"),
    (None, "headerlink"),
    (None, "toctree-wrapper"),
    (None, "prev-next-area"),
)
#: elements that end a sentence's text (a heading or list item never runs on into the next)
BLOCKS = {
    "p", "li", "dt", "dd", "h1", "h2", "h3", "h4", "h5", "h6", "figcaption",
    "caption", "div", "section", "blockquote", "br", "td", "th", "summary",
}  # fmt: skip
VOID = {"br", "img", "hr", "input", "meta", "link", "wbr", "source", "col", "area", "embed"}
#: what stands for left-out code or maths in the text: no word, but a sentence may start
HOLE = "\ue000"
#: a word holds a letter or a digit ("—" and "·" are not words)
WORD = re.compile(r"\S*[^\W_]\S*")
#: a sentence ends at . ! ? followed by space and a capital, digit, bracket or quote;
#: abbreviations (e.g., Fig.) split too early, which only makes sentences shorter
SENTENCE_END = re.compile(r"(?<=[.!?])[\"'”’)]*\s+(?=[A-Z0-9(\[“\"'*\ue000])")
ABBREVIATIONS = re.compile(r"\b(?:e\.g|i\.e|Fig|Figs|Eq|eq|eqs|cf|vs|al|approx|Sec|ref)\.$")


class _Text(HTMLParser):
    """Collect the narrative text blocks of a page's main content."""

    def __init__(self) -> None:
        super().__init__(convert_charrefs=True)
        self.stack: list[tuple[str, bool, bool]] = []  # (tag, in main, skipped)
        self.blocks: list[str] = []
        self.current: list[str] = []
        self.found_main = False

    def _flush(self) -> None:
        text = " ".join("".join(self.current).split())
        if text:
            self.blocks.append(text)
        self.current = []

    def handle_starttag(self, tag, attrs):
        classes = (dict(attrs).get("class") or "").split()
        in_main, skipped = self.stack[-1][1:] if self.stack else (False, False)
        if not in_main and any(tag == t and c in classes for t, c in MAIN):
            in_main = self.found_main = True
        if not skipped and any(
            (t is None or t == tag) and (c is None or c in classes) for t, c in SKIP
        ):
            skipped = True
            if in_main:  # a sentence may begin with code or maths: keep its place
                self.current.append(HOLE)
        if in_main and not skipped and tag in BLOCKS:
            self._flush()
        if tag not in VOID:
            self.stack.append((tag, in_main, skipped))

    def handle_endtag(self, tag):
        if tag in VOID:
            return
        while self.stack:  # close what was left open, as browsers do
            open_tag, in_main, skipped = self.stack.pop()
            if in_main and not skipped and open_tag in BLOCKS:
                self._flush()
            if open_tag == tag:
                break

    def handle_data(self, data):
        if self.stack and self.stack[-1][1] and not self.stack[-1][2]:
            self.current.append(data)

    def close(self):
        super().close()
        self._flush()


def sentences(block: str) -> list[str]:
    """Split one block of text into sentences (see :data:`SENTENCE_END`)."""
    parts, start = [], 0
    for m in SENTENCE_END.finditer(block):
        if ABBREVIATIONS.search(block[start : m.start()]):
            continue
        parts.append(block[start : m.start()])
        start = m.end()
    parts.append(block[start:])
    return [p for p in parts if WORD.search(p)]


@dataclass(frozen=True)
class PageCount:
    """The narrative count of one page."""

    page: str
    words: int
    sentences: int
    long: int
    longest: int
    #: the sentences over :data:`LONG_WORDS` words, for the writer to mend
    long_sentences: tuple[str, ...] = ()

    @property
    def long_share(self) -> float:
        return self.long / self.sentences if self.sentences else 0.0


def count_html(html: str, page: str = "") -> PageCount:
    """Count the narrative words and sentences of one built page (the rule: module doc)."""
    parser = _Text()
    parser.feed(html)
    parser.close()
    if not parser.found_main:
        raise ValueError(f"page={page!r}: no main content ({' or '.join(map(str, MAIN))})")
    split = [s for b in parser.blocks for s in sentences(b)]
    lengths = [len(WORD.findall(s)) for s in split]
    return PageCount(
        page=page,
        words=sum(len(WORD.findall(b)) for b in parser.blocks),
        sentences=len(lengths),
        long=sum(n > LONG_WORDS for n in lengths),
        longest=max(lengths, default=0),
        long_sentences=tuple(
            s.replace(HOLE, "[…]") for s, n in zip(split, lengths, strict=True) if n > LONG_WORDS
        ),
    )


def narrative_pages(build: Path) -> list[Path]:
    """The built pages whose prose counts (all HTML pages but :data:`NOT_NARRATIVE`)."""
    pages = sorted(build.rglob("*.html"))
    return [
        p
        for p in pages
        if not any(fnmatch(p.relative_to(build).as_posix(), pat) for pat in NOT_NARRATIVE)
    ]


def count_site(build: Path) -> list[PageCount]:
    """The :class:`PageCount` of every narrative page of a built site."""
    return [
        count_html(p.read_text(encoding="utf-8"), p.relative_to(build).as_posix())
        for p in narrative_pages(build)
    ]


def problems(counts: list[PageCount]) -> list[str]:
    """Every budget a site breaks (empty when it keeps them all)."""
    out = [
        f"{c.page}: {c.words} words, over the page budget of {PAGE_WORDS}"
        for c in counts
        if c.words > PAGE_WORDS
    ]
    out += [
        f"{c.page}: {c.long} of {c.sentences} sentences ({c.long_share:.0%}) over"
        f" {LONG_WORDS} words, more than {LONG_SHARE:.0%} (longest {c.longest})"
        for c in counts
        if c.long_share > LONG_SHARE
    ]
    total = sum(c.words for c in counts)
    if total > TOTAL_WORDS:
        out.append(f"site: {total} narrative words, over the budget of {TOTAL_WORDS}")
    return out


def table(counts: list[PageCount]) -> str:
    """The counts as a plain-text table, pages by words, with the total."""
    rows = [f"{'page':44} {'words':>6} {'sent.':>6} {'>50w':>5} {'share':>6} {'longest':>7}"]
    for c in sorted(counts, key=lambda c: -c.words):
        flag = " *" if c.words > PAGE_WORDS or c.long_share > LONG_SHARE else ""
        rows.append(
            f"{c.page:44} {c.words:6d} {c.sentences:6d} {c.long:5d} {c.long_share:6.1%}"
            f" {c.longest:7d}{flag}"
        )
    rows.append(f"{'total':44} {sum(c.words for c in counts):6d}   (budget {TOTAL_WORDS})")
    return "\n".join(rows)


def _page(body: str) -> str:
    return f'<html><body><nav>menu words</nav><div class="body">{body}</div></body></html>'


def self_test(tmp: Path) -> None:
    """Plant an over-long page, a page of long sentences and a page whose words sit only in
    code, tables, maths and outputs; raise ``AssertionError`` if the count misjudges one."""
    sentence = "The rod twists and the wave runs along it. "  # 9 words
    long_one = "Then " + " ".join(["word"] * (LONG_WORDS + 5)) + ". "
    site = tmp / "budget-site"
    (site / "api_x").mkdir(parents=True, exist_ok=True)
    pages = {
        "long.html": _page("<p>" + sentence * (PAGE_WORDS // 9 + 1) + "</p>"),
        "rambling.html": _page("<p>" + long_one * 2 + sentence * 10 + "</p>"),
        "hidden.html": _page(
            "<h1>Title here</h1><p>One two three.</p><pre>" + "x " * 3000 + "</pre>"
            "<p>Inline <code>a b c</code> and <span class='math'>\\(a b c\\)</span>.</p>"
            "<table><tr><td>" + "y " * 3000 + "</td></tr></table>"
            "<div class='cell_output'>" + "z " * 3000 + "</div>"
            "<dl class='py function'><dt>f()</dt><dd><p>" + "Doc words. " * 500 + "</p></dd></dl>"
        ),
        "api_reference.html": _page("<p>" + sentence * 400 + "</p>"),
    }
    for name, html in pages.items():
        (site / name).write_text(html, encoding="utf-8")
    counts = {c.page: c for c in count_site(site)}
    assert "api_reference.html" not in counts, "an API page was counted"
    assert counts["hidden.html"].words == 7, counts[
        "hidden.html"
    ]  # Title here One two three Inline and
    assert counts["long.html"].words > PAGE_WORDS, counts["long.html"]
    assert counts["rambling.html"].long == 2, counts["rambling.html"]
    found = problems(list(counts.values()))
    for page, what in (("long.html", "page budget"), ("rambling.html", "sentences")):
        assert any(p.startswith(page) and what in p for p in found), (page, found)
    assert not any(p.startswith("hidden.html") for p in found), found
    many = [PageCount(f"p{i}.html", PAGE_WORDS, 10, 0, 20) for i in range(9)]
    assert any(p.startswith("site:") for p in problems(many)), "total budget not enforced"
    assert sentences("See Fig. 8, e.g. the onset. Then 3 more.") == [
        "See Fig. 8, e.g. the onset.",
        "Then 3 more.",
    ]
    print("site-budget self-test: the over-long page, long sentences and hidden words judged")
