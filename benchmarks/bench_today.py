"""Today's speed targets against their floors, written as a dated record for the site.

    python benchmarks/bench_today.py [--quick] [--out data/bench/today.json]

Runs :data:`bench_targets.MEASURE` on this checkout's sources (one subprocess, medians of
repeated runs; no baseline) and writes, beside the measured values, each target's floor
(:func:`bench_targets.targets`), the date and the machine (processor model, cores,
architecture) and the versions that ran it.  The Benchmarks page reads this record: a
time on the site is the one this record carries, with its date and machine.  ``--quick``
measures a quarter of the Fig 10 rates (the floors are scaled to the rates measured).
"""

from __future__ import annotations

import argparse
import datetime as dt
import os
import platform
import sys
from pathlib import Path

from bench_targets import measure, targets
from dyntorsion.studies.contact.records import write
from worktree import ROOT


def processor() -> str:
    """The processor's model name (``/proc/cpuinfo`` where there is one), else the
    platform's own description."""
    info = Path("/proc/cpuinfo")
    if info.is_file():
        for line in info.read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    return platform.processor() or platform.machine()


def machine() -> dict:
    """Where the record was measured: processor, cores, architecture, system, Python."""
    return {
        "processor": processor(),
        "cores": os.cpu_count(),
        "architecture": platform.machine(),
        "system": platform.system(),
        "python": sys.version.split()[0],
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--quick", action="store_true", help="a quarter of the Fig 10 rates")
    p.add_argument("--out", type=Path, default=ROOT / "data" / "bench" / "today.json")
    args = p.parse_args()
    now = measure(ROOT / "src", args.quick)
    from dyntorsion import __version__

    rows = [
        {"target": label.strip(), "key": key, "floor": floor, "value": now[key]}
        for label, key, floor in targets(now)
    ]
    record = {
        "date": dt.datetime.now(dt.UTC).isoformat(timespec="seconds"),
        "machine": machine(),
        "dyntorsion": __version__,
        "quick": args.quick,
        "rows": rows,
        "results": now,
    }
    write(args.out, record, indent=1)
    for r in rows:
        floor = "" if r["floor"] is None else f"{r['floor']:.3f}"
        print(f"{r['target']:58s} {floor:>8s} {r['value']:9.3f}")
    print(f"written: {args.out}")


if __name__ == "__main__":
    main()
