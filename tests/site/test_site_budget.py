"""The site's word budgets (docs/site_budget.py): what counts as narrative, and when a
page or the site is over budget."""

import importlib.util
import sys

import pytest

from dyntorsion.store.location import checkout

ROOT = checkout()
pytestmark = pytest.mark.skipif(ROOT is None, reason="needs a checkout (docs/)")


@pytest.fixture(scope="module")
def budget():
    spec = importlib.util.spec_from_file_location("site_budget", ROOT / "docs" / "site_budget.py")
    module = importlib.util.module_from_spec(spec)
    sys.modules["site_budget"] = module  # its dataclass looks its module up
    spec.loader.exec_module(module)
    return module


def test_the_planted_pages_are_judged(budget, tmp_path):
    budget.self_test(tmp_path)


def test_words_outside_prose_do_not_count(budget):
    html = (
        '<html><body><nav>Menu Home</nav><article class="bd-article"><h1>Fig 8</h1>'
        "<p>The rod buckles at <span class='pasted-text'>14.70</span> s.</p>"
        "<div class='cell_input'><pre>x = 1</pre></div><table><tr><td>a b</td></tr></table>"
        "<div class='math'>\\[a = b\\]</div></article></body></html>"
    )
    c = budget.count_html(html, "fig08.html")
    assert (c.words, c.sentences, c.long) == (8, 2, 0)  # "Fig 8" and the sentence


def test_a_long_sentence_is_named(budget):
    long = "The " + "rod " * budget.LONG_WORDS + "buckles."
    c = budget.count_html(f'<div class="body"><p>{long} It ends.</p></div>', "p.html")
    assert c.long == 1 and c.sentences == 2 and c.long_sentences == (long,)
    assert any("p.html" in p and "sentences" in p for p in budget.problems([c]))


def test_a_page_without_main_content_is_refused(budget):
    with pytest.raises(ValueError, match="page='x.html'"):
        budget.count_html("<html><body><p>no main</p></body></html>", "x.html")


def test_a_sentence_may_begin_with_code(budget):
    c = budget.count_html(
        '<div class="body"><p>It runs at every step. <code>tests/x.py</code> checks it.</p></div>'
    )
    assert (c.words, c.sentences) == (7, 2)
