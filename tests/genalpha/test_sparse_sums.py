"""The residual's sums skip the exact zeros of P, Q (and the step's fixed part those of
M, K): genalpha.discrete.Pattern.  Skipping them must change no bit, so the results
are compared with the dense sums (a pattern holding every column) for equality, not
closeness, on the rod's matrices and on random sparse M, K, with both quadratures."""

import numpy as np
import pytest

from dyntorsion import Rod
from dyntorsion import genalpha as ga
from dyntorsion.buckling.loading import EQ30
from dyntorsion.genalpha.discrete import (
    EndValues,
    Pattern,
    Start,
    StepSource,
    pattern,
    prepare_step,
    residual,
    setup,
)
from dyntorsion.model.cosserat import IDX, Cosserat


def _dense(nf: int) -> Pattern:
    return Pattern(np.tile(np.arange(nf, dtype=np.int64), (nf, 1)), np.full(nf, nf, np.int64))


def test_pattern_lists_the_nonzero_columns_in_order(rng):
    a = rng.normal(size=(7, 7)) * (rng.random((7, 7)) < 0.3)
    b = rng.normal(size=(7, 7)) * (rng.random((7, 7)) < 0.3)
    p = pattern(a, b)
    for rr in range(7):
        want = np.nonzero((a[rr] != 0) | (b[rr] != 0))[0]
        assert p.n[rr] == want.size
        assert np.array_equal(p.cols[rr, : p.n[rr]], want)


def _rod_case(quadrature: str, rng):
    model = Cosserat(Rod())
    system = model.system()
    n, dt = 30, 0.01
    left = ga.Boundary(
        ga.Boundary.fields(system, list(EQ30.left)).rows,
        lambda t: np.outer(10.0 + 1.6 * t, [0, 0, 0, 0, 0, 1.0]),
    )
    right = ga.Boundary.fields(system, list(EQ30.right))
    ys, _ = model.scales()
    y0 = np.zeros((n + 1, 12))
    y0[:, IDX["k3"]] = 10.0
    y0 += 1e-2 * ys * rng.normal(size=y0.shape)
    rate0 = 1e-2 * ys * rng.normal(size=y0.shape)
    scheme = ga.Scheme(quadrature=quadrature, lam_t=-0.5)
    con, w, _ = setup(system, scheme, n, 1.0 / n, dt, left, right, Start(y0, rate0))
    gL, gR = left.at(np.array([dt]))[0], right.at(np.array([dt]))[0]
    return system, con, w, gL, gR, ys


def _random_matrices(con, rng):
    """The rod's constants with other sparse M, K (P, Q and patterns to match)."""
    nf = con.M.shape[0]
    M = rng.normal(size=(nf, nf)) * (rng.random((nf, nf)) < 0.3)
    K = rng.normal(size=(nf, nf)) * (rng.random((nf, nf)) < 0.3)
    co = con.co
    P = co.c_M * (1 - co.a_s) * M + (1 - co.b_t) * co.inv_ds * K
    Q = co.c_M * co.a_s * M - (1 - co.b_t) * co.inv_ds * K
    return con._replace(M=M, K=K, P=P, Q=Q, pq=pattern(P, Q), mk=pattern(M, K))


@pytest.mark.parametrize("matrices", ["rod", "random"])
@pytest.mark.parametrize("quadrature", ["trapezoidal", "midpoint"])
def test_skipping_zeros_changes_no_bit_of_the_residual(quadrature, matrices, rng):
    system, con, w, gL, gR, ys = _rod_case(quadrature, rng)
    if matrices == "random":
        con = _random_matrices(con, rng)
    dense = con._replace(pq=_dense(12), mk=_dense(12))
    assert int(con.pq.n.sum()) < 12 * 12  # sparse: zeros are skipped
    qs = 1e-8 * rng.normal(size=w.y.shape)
    prepare_step(system.F, con, w, StepSource(qs, 0.3, 0.7, qs, qs, False))
    fixed_sparse = w.c.copy()
    prepare_step(system.F, dense, w, StepSource(qs, 0.3, 0.7, qs, qs, False))
    assert np.array_equal(fixed_sparse, w.c)
    y = w.y_old + 1e-3 * ys * rng.normal(size=w.y.shape)
    r_sparse, r_dense = np.zeros_like(w.r), np.zeros_like(w.r)
    res_s = residual(system.F, system.dF, con, EndValues(gL, gR), y, w, r_sparse, True)
    res_d = residual(system.F, system.dF, dense, EndValues(gL, gR), y, w, r_dense, True)
    assert res_s == res_d
    assert np.array_equal(r_sparse, r_dense)


def _short(p: Pattern) -> Pattern:
    return Pattern(p.cols, np.maximum(p.n - 1, 0))


def test_the_sums_read_the_pattern(rng):
    """A pattern missing one nonzero column per row changes the residual and the step's
    fixed part: the sums do visit only the listed columns (so the test above compares two
    different loops)."""
    system, con, w, gL, gR, ys = _rod_case("trapezoidal", rng)
    qs = 1e-8 * rng.normal(size=w.y.shape)
    prepare_step(system.F, con, w, StepSource(qs, 0.3, 0.7, qs, qs, False))
    fixed_full = w.c.copy()
    prepare_step(
        system.F, con._replace(mk=_short(con.mk)), w, StepSource(qs, 0.3, 0.7, qs, qs, False)
    )
    assert not np.array_equal(fixed_full, w.c)
    short = con._replace(pq=_short(con.pq))
    y = w.y_old + 1e-3 * ys * rng.normal(size=w.y.shape)
    r_full, r_short = np.zeros_like(w.r), np.zeros_like(w.r)
    residual(system.F, system.dF, con, EndValues(gL, gR), y, w, r_full, False)
    residual(system.F, system.dF, short, EndValues(gL, gR), y, w, r_short, False)
    assert not np.array_equal(r_full, r_short)
