"""The numbers the site states on more than one page: one computation, one rounding.

A number a reader meets on two pages must read the same on both.  Each such fact is
computed here once (the buckling ones from the cached records of ``data/``, the same
records the at-a-glance table reads), formatted once, and glued by every page that
shows it under the key :func:`facts` gives it; ``make site-check`` fails when one glue
key shows two values on two pages.  The onset rule is the default one
(:func:`~dyntorsion.buckling.onset.detect_onset`, the 10-50 % window fit) unless a
key says otherwise.

The rounding rules: a time or a twist to two decimals (:func:`fixed`), a relative
difference to two significant figures, signed, in percent (:func:`percent`).
"""

from __future__ import annotations

import re
from functools import cache

from ..buckling.delay_law import fit_power_law
from ..published import published
from ..studies.presets import SEEDS, cached
from .glance import KAPPA_CRI_FREE_DECIMALS, percent, sci, sig

__all__ = ["RULE_DEFAULT", "facts", "fixed", "percent", "ended", "seed_text"]

#: how the site names the default onset rule where another rule is also shown
RULE_DEFAULT = "default onset rule (straight line through 10–50 % of the first peak)"


def fixed(x: float, decimals: int = 2) -> str:
    """``x`` to ``decimals`` decimals, without a "-0"."""
    out = f"{x:.{decimals}f}"
    return out[1:] if out.startswith("-") and float(out) == 0 else out


def ended(stopped: str, t_last: float | None = None) -> str:
    """How a run ended, in words: ``stopped`` as a run or a record gives it ("t_end",
    "self-contact at t = 22.09 s (...)", "failed: ..."), ``t_last`` its last time [s]
    (read from ``stopped`` when it names one)."""
    said = re.search(r"at t = ([0-9.eE+-]+) s", stopped)
    if t_last is None and said is None:
        raise ValueError(f"stopped={stopped!r} names no time; give t_last")
    t = float(said.group(1)) if t_last is None else t_last
    if stopped.startswith("failed"):
        return f"Newton failure at t = {t:.2f} s"
    if stopped.startswith("self-contact"):
        return f"self-contact at t = {t:.2f} s"
    return f"end of the run, t = {t:.2f} s"


def seed_text(name: str) -> str:
    """A named seed of :data:`~dyntorsion.studies.presets.SEEDS` for prose: ``10⁻¹⁷``."""
    return sci(SEEDS[name].magnitude)


@cache
def facts() -> dict[str, str]:
    """Every fact shown on more than one page, formatted: glue key -> text.

    ``fig{8,9}_{stated,tiny}_{tc,unc,k3,rel,ended}``: the direct runs of Figs 8 and 9
    (records ``fig08-09`` and ``fig08-09-tiny-seed``, standard grid, default onset rule),
    their t_c [s], its window uncertainty [s], kappa3 [1/m], t_c against the paper's (Fig 8)
    or its law's (Fig 9) value, and how the run ended; ``seed_{stated,tiny}`` the seeds
    [N/m]; ``paper_tc8``, ``paper_law9``, ``paper_k38`` the paper's values;
    ``fig10_{stated,tiny}_{b,sigma,b_rel,kcfree}``: the delay law fitted to the Fig 10
    sweeps (kappa_cri fixed at eq (32); ``kcfree`` with it free, [1/m]);
    ``c_rel``, ``T1_rel`` our wave speed and period against the paper's."""
    from ..model.rod import Rod

    pub = {k: v["value"] for k, v in published().items()}
    out = {"seed_stated": seed_text("stated"), "seed_tiny": seed_text("tiny")}
    out |= {
        "paper_tc8": f"{pub['fig8_tc']}",
        "paper_k38": f"{pub['fig8_kappa3']}",
        "paper_law9": fixed(pub["law_fig9"]),
    }
    for seed, preset in (("stated", "fig08-09"), ("tiny", "fig08-09-tiny-seed")):
        rows = cached(preset).set_index("rho")
        for fig, rho, paper in (
            ("fig8", 1500.0, pub["fig8_tc"]),
            ("fig9", 5000.0, pub["law_fig9"]),
        ):
            r = rows.loc[rho]
            key = f"{fig}_{seed}"
            out[f"{key}_tc"] = fixed(r["t_c"])
            out[f"{key}_unc"] = fixed(r["uncertainty_t"])
            out[f"{key}_k3"] = fixed(r["kappa3"])
            out[f"{key}_rel"] = percent(r["t_c"] / paper - 1)
            out[f"{key}_ended"] = ended(str(r["stopped"]))
    rod = Rod.paper()
    for seed, preset in (("stated", "fig10"), ("tiny", "fig10-tiny-seed")):
        t = cached(preset)
        fit = fit_power_law(t["a"], t["kappa3"], rod, n_boot=0)
        free = fit_power_law(t["a"], t["kappa3"], rod, kappa_cri=None, n_boot=0)
        # b and sigma to the paper's digits, as the at-a-glance table gives them
        out[f"fig10_{seed}_b"] = sig(fit.b, published()["b"]["digits"])
        out[f"fig10_{seed}_sigma"] = sig(fit.sigma, published()["sigma"]["digits"])
        out[f"fig10_{seed}_b_rel"] = percent(fit.b / pub["b"] - 1)
        out[f"fig10_{seed}_kcfree"] = fixed(free.kappa_cri, KAPPA_CRI_FREE_DECIMALS)
    out["c_rel"] = percent(rod.c / pub["c"] - 1)
    out["T1_rel"] = percent(rod.T1 / pub["T1"] - 1)
    return out
