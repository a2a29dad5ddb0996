"""How the command line answers a fault: one line saying what went wrong, which file or
parameter, and what to do (:func:`describe`), and an exit status by kind."""

from __future__ import annotations

__all__ = ["describe", "EXIT_INPUT", "EXIT_FAILED", "EXIT_BUG", "EXIT_INTERRUPTED"]

#: exit status of a refused input, of a failed computation or unusable store, of a bug
EXIT_INPUT, EXIT_FAILED, EXIT_BUG, EXIT_INTERRUPTED = 2, 1, 3, 130


def describe(err: BaseException) -> tuple[str, int]:
    """One line for a package error (what, which file or parameter, what to do) and the
    exit status."""
    from ..genalpha import ConvergenceError
    from ..store.results import CorruptResultError, StaleResultError
    from ..store.workers import MissingResultError

    lines = [ln.strip() for ln in str(err).splitlines() if ln.strip()]
    text = (
        " ".join(lines)
        if len(lines) < 2
        else f"{lines[0]} ({lines[1]}{', ...' if len(lines) > 3 else ''}); {lines[-1]}"
    )
    if isinstance(err, ValueError | TypeError):
        return text, EXIT_INPUT
    if isinstance(err, StaleResultError | CorruptResultError | MissingResultError):
        return text, EXIT_FAILED
    if isinstance(err, ConvergenceError):
        return f"{text}; refine --dt or change the Newton options", EXIT_FAILED
    if isinstance(err, ConnectionError):
        return text, EXIT_FAILED
    if isinstance(err, OSError):
        where = f" {err.filename}" if err.filename else ""
        what = err.strerror or text
        return (
            f"{what}:{where}; check that the path exists, is writable and the disk has space "
            "(--store or $DYNTORSION_DATA)",
            EXIT_FAILED,
        )
    if isinstance(err, MemoryError):
        return f"out of memory ({text or 'no detail'}); raise --dt or lower --t-end", EXIT_FAILED
    return (
        f"internal error {type(err).__name__}: {text}; rerun with --debug and report it",
        EXIT_BUG,
    )
