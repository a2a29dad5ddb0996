"""``dyntorsion info``: what this installation is and where it keeps its records."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from .. import __version__

__all__ = ["info"]


def info(args: argparse.Namespace) -> int:
    """What this installation is and where it keeps its records."""
    import platform

    import numba

    from .. import __file__ as package_file
    from ..store.environment import numerical_environment
    from ..store.location import store_origin

    store, why = store_origin()
    env = numerical_environment()
    kernels = ", ".join(f"{k} ({lib})" for lib, k in env["blas_kernels"].items()) or "not OpenBLAS"
    rows = {
        "dyntorsion": __version__,
        "package": str(Path(package_file).parent),
        "store": f"{store} ({why})",
        "numba cache": os.environ.get("NUMBA_CACHE_DIR")
        or "beside the package's modules (__pycache__)",
        "python": f"{platform.python_version()} ({sys.executable})",
        "numba": numba.__version__,
        "numpy, scipy": f"{env['numpy']}, {env['scipy']}",
        # the runs past contact depend on these in the last bit (dyntorsion.store.environment)
        "openblas kernels": kernels,
        "numpy loops": " ".join(env["numpy_simd"]) or "baseline only",
    }
    width = max(map(len, rows))
    for key, val in rows.items():
        print(f"{key:<{width}}  {val}")
    return 0
