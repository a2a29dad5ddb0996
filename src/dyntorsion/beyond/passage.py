"""Compiled integration of the linear slow passage, eq (L2), over the prebuckling state.

The compiled slow passage of eq (L2) (see :mod:`dyntorsion.beyond.linear_stability`).

The coefficients of (L2) depend on time only through the prebuckling state, and
that state is a short sum of separable terms (:class:`~.linear_stability.Prebuckling`)::

    kappa3(s, t) = kappa0 + a t + sum b_n sin(k_n s) sin(k_n c t)
    omega3(s, t) = -a (L - s)   - c sum b_n cos(k_n s) cos(k_n c t)
    omega3_t     =                c^2 sum b_n k_n cos(k_n s) sin(k_n c t)

so every Galerkin integral is a fixed matrix times a function of t::

    K(t) = Kb + (kappa0 + a t) K1 + sum [b_n sin(k_n c t)] Kn
              + sum [c^2 b_n k_n sin(k_n c t)] Gn
    G(t) = a G1 + sum [-c b_n cos(k_n c t)] Gn

with K1 = -i C int phi'' phi', Kn = -i C int phi'' phi' sin(k_n s),
G1 = -i rho J int phi' phi' (-(L - s)), Gn = -i rho J int phi' phi' cos(k_n s).
:func:`tensors` integrates these once; :func:`rk4_steps` runs the classical
Runge-Kutta steps of :meth:`~.linear_stability.LateralModel.passage` over them.
The seed's modal load F = sum_p R_p exp(i theta(s_p, t)) is evaluated at its
points s_p from the series of theta (every quadrature point for a uniform seed,
the point itself for a point seed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np
import scipy.optimize

from .._numba import jit

__all__ = ["Passage", "Tensors", "tensors", "rk4_steps", "run", "u3"]


@dataclass
class Passage:
    """A linear run through the instability: traces and the predicted onset."""

    t: np.ndarray
    u3: np.ndarray
    kappa3: np.ndarray
    amplitude: np.ndarray
    t_ref: float
    kappa3_ref: float
    u_ref: float
    params: dict = field(default_factory=dict)

    @property
    def reached(self) -> bool:
        """Whether ``|u3(L)|`` reached u_ref before the end of the run."""
        return math.isfinite(self.t_ref)


class Tensors(NamedTuple):
    """The time-independent parts of (L2) and of the prebuckling series."""

    Minv: np.ndarray  # (m, m) inverse of the mass matrix Mr
    Kb: np.ndarray  # (m, m) complex, bending stiffness
    K1: np.ndarray  # (m, m) complex, per unit uniform twist
    Kn: np.ndarray  # (terms, m, m) complex, per wave term of kappa3
    G1: np.ndarray  # (m, m) complex, per unit rate of the quasi-static spin
    Gn: np.ndarray  # (terms, m, m) complex, per wave term of omega3 (and omega3_t)
    P: np.ndarray  # (m, m) int phi' phi': u3(L) = -Re(q* P q_t)
    rows: np.ndarray  # (p, m) complex, the seed's modal rows R_p
    cos_seed: np.ndarray  # (p, terms) cos(k_n s_p)
    lever: np.ndarray  # (p,) L - s_p
    k: np.ndarray  # (terms,) wave numbers k_n
    b: np.ndarray  # (terms,) amplitudes b_n (zero without waves)
    a: float
    kappa0: float
    c: float
    spin: bool


def tensors(model, base, seed_rows, seed_points, spin: bool) -> Tensors:
    """:class:`Tensors` of ``model`` (a LateralModel) about ``base`` (a Prebuckling)."""
    r, s = model.rod, model.nodes
    k = base.wave_numbers
    b = -2 * base.a / (r.L * r.c * k**2) if base.waves else np.zeros_like(k)
    sin_s, cos_s = np.sin(np.outer(s, k)), np.cos(np.outer(s, k))
    rhoJ = model.spin_inertia if spin else 0.0
    ddphi, dphi = model.curvatures, model.slopes
    return Tensors(
        Minv=np.linalg.inv(model.mass_matrix),
        Kb=model.bending_stiffness.astype(complex),
        K1=-1j * r.C * model.integral(ddphi, dphi),
        Kn=np.array([-1j * r.C * model.integral(ddphi, dphi, sin_s[:, n]) for n in range(k.size)]),
        G1=-1j * rhoJ * model.integral(dphi, dphi, -(r.L - s)),
        Gn=np.array([-1j * rhoJ * model.integral(dphi, dphi, cos_s[:, n]) for n in range(k.size)]),
        P=model.u3_matrix,
        rows=np.ascontiguousarray(seed_rows, dtype=complex),
        cos_seed=np.cos(np.outer(seed_points, k)),
        lever=r.L - np.asarray(seed_points, dtype=float),
        k=k,
        b=b,
        a=float(base.a),
        kappa0=float(base.kappa0),
        c=float(r.c),
        spin=bool(spin),
    )


@jit
def _coefficients(T, t, F, K, G):
    """F, K and G of (L2) at the time t (into the arrays given)."""
    m = T.Kb.shape[0]
    kappa = T.kappa0 + T.a * t
    for i in range(m):
        for j in range(m):
            K[i, j] = T.Kb[i, j] + kappa * T.K1[i, j]
            G[i, j] = T.a * T.G1[i, j]
    for n in range(T.k.size):
        if T.b[n] == 0.0:
            continue
        wt = T.k[n] * T.c * t
        sn, cn = np.sin(wt), np.cos(wt)
        ck, cw, cg = T.b[n] * sn, T.c * T.c * T.b[n] * T.k[n] * sn, -T.c * T.b[n] * cn
        for i in range(m):
            for j in range(m):
                K[i, j] += ck * T.Kn[n, i, j]
                if T.spin:
                    K[i, j] += cw * T.Gn[n, i, j]
                    G[i, j] += cg * T.Gn[n, i, j]
    for i in range(m):
        F[i] = 0.0
    shift = np.empty(T.k.size)  # theta's wave terms: cos(k_n s) (b_n / k_n) sin(k_n c t)
    for n in range(T.k.size):
        shift[n] = T.b[n] / T.k[n] * np.sin(T.k[n] * T.c * t)
    for p in range(T.rows.shape[0]):
        theta = -kappa * T.lever[p]
        for n in range(T.k.size):
            theta -= T.cos_seed[p, n] * shift[n]
        e = np.exp(1j * theta)
        for i in range(m):
            F[i] += T.rows[p, i] * e


@jit
def _rhs(T, y, F, K, G, force, out):
    """dy/dt of (L2) written as a first-order system in y = (q, q_t)."""
    m = F.size
    for i in range(m):
        acc = F[i]
        for j in range(m):
            acc -= K[i, j] * y[j] + G[i, j] * y[m + j]
        force[i] = acc
    for i in range(m):
        out[i] = y[m + i]
        acc = 0.0j
        for j in range(m):
            acc += T.Minv[i, j] * force[j]
        out[m + i] = acc


@jit
def u3(T, y):
    """The end-shortening speed u3(L) = -Re(q* P q_t)."""
    m = T.P.shape[0]
    acc = 0.0
    for i in range(m):
        pv = 0.0j
        for j in range(m):
            pv += T.P[i, j] * y[m + j]
        acc += (np.conj(y[i]) * pv).real
    return -acc


@jit
def rk4_steps(T, dt, n_steps, every, u_ref, ts, ys, last):
    """Classical Runge-Kutta (order 4) from rest until ``|u3(L)| >= u_ref`` or n_steps.

    Samples every ``every`` steps (and the last) go to ``ts``/``ys``; ``last`` gets
    y and dy/dt before and after the final step.  Returns (samples, status, time):
    status 1 reached u_ref, 0 did not, -1 the state stopped being finite.
    """
    m = T.Kb.shape[0]
    Fs = np.zeros((3, m), dtype=np.complex128)
    Ks = np.zeros((3, m, m), dtype=np.complex128)
    Gs = np.zeros((3, m, m), dtype=np.complex128)
    y = np.zeros(2 * m, dtype=np.complex128)
    k1 = np.zeros(2 * m, dtype=np.complex128)
    k2, k3, k4, tmp = k1.copy(), k1.copy(), k1.copy(), k1.copy()
    ts[0] = 0.0
    ys[0] = y
    nrec = 1
    t = 0.0
    _coefficients(T, t, Fs[2], Ks[2], Gs[2])
    force = np.zeros(m, dtype=np.complex128)
    for n in range(1, n_steps + 1):
        t_new = n * dt
        Fs[0], Ks[0], Gs[0] = Fs[2], Ks[2], Gs[2]  # copies: the arrays' rows
        _coefficients(T, t + dt / 2, Fs[1], Ks[1], Gs[1])
        _coefficients(T, t_new, Fs[2], Ks[2], Gs[2])
        _rhs(T, y, Fs[0], Ks[0], Gs[0], force, k1)
        for i in range(2 * m):
            tmp[i] = y[i] + dt / 2 * k1[i]
        _rhs(T, tmp, Fs[1], Ks[1], Gs[1], force, k2)
        for i in range(2 * m):
            tmp[i] = y[i] + dt / 2 * k2[i]
        _rhs(T, tmp, Fs[1], Ks[1], Gs[1], force, k3)
        for i in range(2 * m):
            tmp[i] = y[i] + dt * k3[i]
        _rhs(T, tmp, Fs[2], Ks[2], Gs[2], force, k4)
        last[0] = y
        last[1] = k1
        finite = True
        for i in range(2 * m):
            y[i] = y[i] + dt / 6 * (k1[i] + 2 * k2[i] + 2 * k3[i] + k4[i])
            finite = finite and np.isfinite(y[i].real) and np.isfinite(y[i].imag)
        if not finite:
            return nrec, -1, t_new
        reached = abs(u3(T, y)) >= u_ref
        if n % every == 0 or reached:
            ts[nrec] = t_new
            ys[nrec] = y
            nrec += 1
        if reached:
            last[2] = y
            _rhs(T, y, Fs[2], Ks[2], Gs[2], force, last[3])
            return nrec, 1, t
        t = t_new
    return nrec, 0, t


def _crossing(model, T, t, dt, last, u_ref) -> float:
    """The time u3(L) reaches u_ref on the cubic Hermite interpolant of u3 over the last
    step [t, t + dt] (order 4, like the steps), from y and dy/dt at both ends."""
    m, P = model.modes, model.u3_matrix

    def u3_rate(y, f):
        q, v, acc = y[:m], y[m:], f[m:]
        return -np.real(np.conj(v) @ (P @ v) + np.conj(q) @ (P @ acc))

    y0, f0, y1, f1 = last
    a0, a1 = u3(T, y0), u3(T, y1)
    sign = np.sign(a1)
    h0, h1 = a0 * sign, a1 * sign
    d0, d1 = u3_rate(y0, f0) * sign * dt, u3_rate(y1, f1) * sign * dt

    def U(x):
        return (
            (2 * x**3 - 3 * x**2 + 1) * h0
            + (x**3 - 2 * x**2 + x) * d0
            + (-2 * x**3 + 3 * x**2) * h1
            + (x**3 - x**2) * d1
            - u_ref
        )

    if U(0.0) >= 0.0:  # u3 changed sign within the step: fall back to a line
        return t + (u_ref - abs(a0)) / (abs(a1) - abs(a0)) * dt
    return t + scipy.optimize.brentq(U, 0.0, 1.0, xtol=1e-14) * dt


def run(model, base, seed, dt: float, n_steps: int, samples: int, u_ref: float) -> Passage:
    """March ``model`` (a LateralModel) about ``base`` (a Prebuckling) from rest with the
    seed ``seed`` for ``n_steps`` steps of ``dt`` or until ``|u3(L)| = u_ref``; about
    ``samples`` samples are kept."""
    m, r = model.modes, model.rod
    T = tensors(model, base, *model.seed_rows(seed), spin=base.spin)
    every = max(1, n_steps // samples)
    ts = np.empty(n_steps // every + 2)
    ys = np.empty((ts.size, 2 * m), dtype=complex)
    last = np.empty((4, 2 * m), dtype=complex)
    nrec, status, t = rk4_steps(T, dt, n_steps, every, float(u_ref), ts, ys, last)
    if status < 0:
        raise RuntimeError(f"the linear passage blew up at t = {t:.6g} s: reduce dt={dt}")
    t_ref = _crossing(model, T, t, dt, last, u_ref) if status == 1 else math.nan
    ts, ys = ts[:nrec], ys[:nrec].T
    return Passage(
        t=ts,
        u3=np.array([u3(T, ys[:, i]) for i in range(ts.size)]),
        kappa3=base.kappa0 + base.a * ts,
        amplitude=np.sqrt(
            np.real(np.sum(np.conj(ys[:m]) * (model.mass_matrix @ ys[:m]), axis=0))
            / (r.mass_per_length * r.L)
        ),
        t_ref=t_ref,
        kappa3_ref=base.kappa0 + base.a * t_ref,
        u_ref=float(u_ref),
        params={
            "a": base.a,
            "kappa0": base.kappa0,
            "seed": {"magnitude": seed.magnitude, "form": seed.form, "location": seed.location},
            "waves": base.waves,
            "spin": base.spin,
            "terms": base.terms,
            "modes": model.modes,
            "quadrature": model.quadrature,
            "rotary_inertia": model.rotary_inertia,
            "gyro": model.gyro,
            "dt": dt,
        },
    )
