"""Examples in the README run, and do what they say."""

import pathlib
import re

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[1]


def test_readme_example_runs():
    text = (ROOT / "README.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks, "README has no python example"
    extend, engine = blocks[0], blocks[1]
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
