"""Examples in the README and on the "Install and run" page run, and do what they say."""

import contextlib
import io
import pathlib
import re

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]


def _python_blocks(path: pathlib.Path) -> list[str]:
    return re.findall(r"```python\n(.*?)```", path.read_text(), flags=re.S)


def test_readme_example_prints_what_it_says():
    (block,) = _python_blocks(ROOT / "README.md")
    said = re.search(r"# (\S+ 1/m, c = \S+ m/s)", block).group(1)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(block, "README.md", "exec"), {})  # noqa: S102
    assert out.getvalue().strip() == said


def test_usage_page_examples_run():
    blocks = _python_blocks(ROOT / "docs" / "usage.md")
    assert len(blocks) == 2, "the usage page has an extending and an engine example"
    extend, engine = blocks
    namespace: dict = {}
    exec(compile(extend, "README.md", "exec"), namespace)  # noqa: S102
    rod, run = namespace["rod"], namespace["run"]
    assert rod.B1 != rod.B2 and namespace["critical_twist"](rod) > 10.0
    onset = namespace["detect_onset"](run)
    # the end is held at 20 1/m: the onset twist is read from the run and cannot exceed it
    assert namespace["critical_twist"](rod, tension=5e-6) < onset.kappa3 <= 20.0
    namespace = {}
    exec(compile(engine, "README.md", "exec"), namespace)  # noqa: S102
    run = namespace["run"]
    assert run.t[-1] == 3.0
    # the 1e-8 N/m seed has grown: the free end moves axially
    assert abs(run["u3_end"][-1]) > 1e-4 and np.all(np.isfinite(run["u3_end"]))
