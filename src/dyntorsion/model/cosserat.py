"""The body-frame Cosserat rod of section 2: eq (6) written as eq (7), ::

    M y_t + K y_s + F(y) + q(s, t) = 0,        y = (u, w, k, n)  (12 fields),

with the linear constitutive law m = diag(B1, B2, C) k.  Rows, in order::

    linear momentum   rho A u_t - n_s - k x n + rho A (w x u)            - f = 0
    angular momentum  rho I w_t - K^ k_s - k x (K^ k) - d3 x n + w x (rho I w) = 0
    compatibility     k_t - w_s - k x w                                      = 0
    inextensibility   u_s + k x u - w x d3                                   = 0

(the first three are eq 6 lines 1-3 moved to one side, the last is eq 6 line 4).
``f`` is a distributed external force per unit length in the body frame; it enters
through the engine's source term q = (-f, 0, 0, 0).

Each nonlinear term has a switch (a weight, 1 = on) so that a study can turn a
single mechanism off, e.g. the gyroscopic term ``w x (rho I w)``:

=============  ======================  ======
switch         term                    row
=============  ======================  ======
``wxu``        rho A (w x u)           1
``kxn``        -k x n                  1
``kxm``        -k x (K^ k)             2
``d3xn``       -d3 x n                 2
``gyro``       w x (rho I w)           2
``kxw``        -k x w                  3
``kxu``        k x u                   4
``wxd3``       -w x d3                 4
=============  ======================  ======
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import NamedTuple

import numpy as np

from .._numba import jacobian_kernel, jit, load_kernel
from .rod import Rod
from .system import System

FIELDS = ("u1", "u2", "u3", "w1", "w2", "w3", "k1", "k2", "k3", "n1", "n2", "n3")
IDX = {name: i for i, name in enumerate(FIELDS)}
U, W, KAPPA, N = slice(0, 3), slice(3, 6), slice(6, 9), slice(9, 12)
TERMS = ("wxu", "kxn", "kxm", "d3xn", "gyro", "kxw", "kxu", "wxd3")


class Params(NamedTuple):
    """The rod's coefficients as the compiled kernels read them: rho A, the rotary inertias
    rho I, the stiffnesses B1, B2, C of K^, and the weight of each nonlinear term (the
    switches of the module docstring).  The engine hands the kernels the same numbers as
    a flat vector (:attr:`Cosserat.params`, in this order); :func:`unpack` names them."""

    rhoA: float
    rI1: float
    rI2: float
    rI3: float
    B1: float
    B2: float
    C: float
    wxu: float
    kxn: float
    kxm: float
    d3xn: float
    gyro: float
    kxw: float
    kxu: float
    wxd3: float


@jit
def unpack(p) -> Params:
    """The flat parameter vector as :class:`Params`."""
    return Params(
        p[0], p[1], p[2], p[3], p[4], p[5], p[6], p[7], p[8], p[9], p[10], p[11], p[12], p[13], p[14]
    )  # fmt: skip


@jit
def _cross(a0, a1, a2, b0, b1, b2):
    return a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0


@load_kernel
def load_vector(y, p, out):
    """F(y) of eq (7) for one node (see the module docstring for the rows)."""
    q = unpack(p)
    u0, u1, u2 = y[0], y[1], y[2]
    w0, w1, w2 = y[3], y[4], y[5]
    k0, k1, k2 = y[6], y[7], y[8]
    n0, n1, n2 = y[9], y[10], y[11]
    # linear momentum: -k x n + rho A (w x u)
    a0, a1, a2 = _cross(k0, k1, k2, n0, n1, n2)
    b0, b1, b2 = _cross(w0, w1, w2, u0, u1, u2)
    out[0] = -q.kxn * a0 + q.wxu * q.rhoA * b0
    out[1] = -q.kxn * a1 + q.wxu * q.rhoA * b1
    out[2] = -q.kxn * a2 + q.wxu * q.rhoA * b2
    # angular momentum: -k x (K^ k) - d3 x n + w x (rho I w)
    a0, a1, a2 = _cross(k0, k1, k2, q.B1 * k0, q.B2 * k1, q.C * k2)
    b0, b1, b2 = _cross(w0, w1, w2, q.rI1 * w0, q.rI2 * w1, q.rI3 * w2)
    out[3] = -q.kxm * a0 + q.d3xn * n1 + q.gyro * b0
    out[4] = -q.kxm * a1 - q.d3xn * n0 + q.gyro * b1
    out[5] = -q.kxm * a2 + q.gyro * b2
    # compatibility: -k x w
    a0, a1, a2 = _cross(k0, k1, k2, w0, w1, w2)
    out[6] = -q.kxw * a0
    out[7] = -q.kxw * a1
    out[8] = -q.kxw * a2
    # inextensibility: k x u - w x d3,   w x d3 = (w1, -w0, 0)
    a0, a1, a2 = _cross(k0, k1, k2, u0, u1, u2)
    out[9] = q.kxu * a0 - q.wxd3 * w1
    out[10] = q.kxu * a1 + q.wxd3 * w0
    out[11] = q.kxu * a2


@jit
def _skew_into(J, r0, c0, scale, a0, a1, a2):
    """J[r0:r0+3, c0:c0+3] += scale * [a]x  where [a]x b = a x b."""
    J[r0 + 0, c0 + 1] += -scale * a2
    J[r0 + 0, c0 + 2] += scale * a1
    J[r0 + 1, c0 + 0] += scale * a2
    J[r0 + 1, c0 + 2] += -scale * a0
    J[r0 + 2, c0 + 0] += -scale * a1
    J[r0 + 2, c0 + 1] += scale * a0


@jacobian_kernel
def load_jacobian(y, p, out):
    """dF/dy (12 x 12) of :func:`load_vector`, analytic."""
    q = unpack(p)
    u0, u1, u2 = y[0], y[1], y[2]
    w0, w1, w2 = y[3], y[4], y[5]
    k0, k1, k2 = y[6], y[7], y[8]
    n0, n1, n2 = y[9], y[10], y[11]
    out[:, :] = 0.0
    # row 1: -k x n = n x k  ->  d/dk = [n]x, d/dn = -[k]x ;  w x u -> d/dw = -[u]x, d/du = [w]x
    _skew_into(out, 0, 6, q.kxn, n0, n1, n2)
    _skew_into(out, 0, 9, -q.kxn, k0, k1, k2)
    _skew_into(out, 0, 3, -q.wxu * q.rhoA, u0, u1, u2)
    _skew_into(out, 0, 0, q.wxu * q.rhoA, w0, w1, w2)
    # row 2: -k x (K^k)  ->  d/dk = -[k]x K^ + [K^k]x
    m0, m1, m2 = q.B1 * k0, q.B2 * k1, q.C * k2
    _skew_into(out, 3, 6, q.kxm, m0, m1, m2)
    out[3, 7] += q.kxm * k2 * q.B2
    out[3, 8] += -q.kxm * k1 * q.C
    out[4, 6] += -q.kxm * k2 * q.B1
    out[4, 8] += q.kxm * k0 * q.C
    out[5, 6] += q.kxm * k1 * q.B1
    out[5, 7] += -q.kxm * k0 * q.B2
    #        -d3 x n = (n1, -n0, 0)
    out[3, 10] += q.d3xn
    out[4, 9] += -q.d3xn
    #        w x (rho I w)  ->  d/dw = [w]x rhoI - [rhoI w]x
    h0, h1, h2 = q.rI1 * w0, q.rI2 * w1, q.rI3 * w2
    _skew_into(out, 3, 3, -q.gyro, h0, h1, h2)
    out[3, 4] += -q.gyro * w2 * q.rI2
    out[3, 5] += q.gyro * w1 * q.rI3
    out[4, 3] += q.gyro * w2 * q.rI1
    out[4, 5] += -q.gyro * w0 * q.rI3
    out[5, 3] += -q.gyro * w1 * q.rI1
    out[5, 4] += q.gyro * w0 * q.rI2
    # row 3: -k x w = w x k  ->  d/dk = [w]x, d/dw = -[k]x
    _skew_into(out, 6, 6, q.kxw, w0, w1, w2)
    _skew_into(out, 6, 3, -q.kxw, k0, k1, k2)
    # row 4: k x u -> d/du = [k]x, d/dk = -[u]x ;  -w x d3 = (-w1, w0, 0)
    _skew_into(out, 9, 0, q.kxu, k0, k1, k2)
    _skew_into(out, 9, 6, -q.kxu, u0, u1, u2)
    out[9, 4] += -q.wxd3
    out[10, 3] += q.wxd3


@dataclass(frozen=True)
class Cosserat:
    """The 12-field body-frame Cosserat model of a :class:`~dyntorsion.model.rod.Rod`.

    ``terms`` maps a switch name of the module table to its weight (default 1);
    ``rotary_inertia_scale`` multiplies rho I1 and rho I2 (the bending rotary
    inertia) without touching rho J, so the torsional wave speed is unchanged.
    """

    rod: Rod = field(default_factory=Rod)
    terms: dict[str, float] = field(default_factory=dict)
    rotary_inertia_scale: float = 1.0

    def __post_init__(self) -> None:
        unknown = set(self.terms) - set(TERMS)
        if unknown:
            raise ValueError(f"terms: unknown switch(es) {sorted(unknown)}; allowed: {TERMS}")
        for name, weight in self.terms.items():
            if not (
                isinstance(weight, int | float | np.integer | np.floating) and np.isfinite(weight)
            ):
                raise ValueError(f"terms[{name!r}]={weight!r} must be a finite weight (1 = on)")
        if not (np.isfinite(self.rotary_inertia_scale) and self.rotary_inertia_scale >= 0):
            raise ValueError(
                f"rotary_inertia_scale={self.rotary_inertia_scale!r} must be finite and >= 0"
            )

    @property
    def params(self) -> np.ndarray:
        r = self.rod
        sw = [float(self.terms.get(name, 1.0)) for name in TERMS]
        ri = self.rotary_inertia_scale
        rI1, rI2, rI3 = r.rotary_inertia
        return np.array(Params(r.mass_per_length, ri * rI1, ri * rI2, rI3, r.B1, r.B2, r.C, *sw))

    @property
    def mass_matrix(self) -> np.ndarray:
        q = Params(*self.params)
        M = np.zeros((12, 12))
        M[U, U] = q.rhoA * np.eye(3)
        M[W, W] = np.diag([q.rI1, q.rI2, q.rI3])
        M[KAPPA, KAPPA] = np.eye(3)
        return M

    @property
    def stiffness_matrix(self) -> np.ndarray:
        r = self.rod
        K = np.zeros((12, 12))
        K[U, N] = -np.eye(3)
        K[W, KAPPA] = -np.diag([r.B1, r.B2, r.C])
        K[KAPPA, W] = -np.eye(3)
        K[N, U] = np.eye(3)
        return K

    def scales(self) -> tuple[np.ndarray, np.ndarray]:
        """Characteristic sizes of the fields and of the rows (bending units).

        Length L, force B/L^2, time T0 = L^2 sqrt(rho A / B) (the rod's bending time,
        B the weaker bending stiffness).  Used to scale the Newton system and as the
        absolute floor of the convergence test.
        """
        r = self.rod
        T0 = r.T0
        F0 = r.B / r.L**2
        ys = np.repeat([r.L / T0, 1.0 / T0, 1.0 / r.L, F0], 3)
        rs = np.repeat([F0 / r.L, F0, 1.0 / (r.L * T0), 1.0 / T0], 3)
        return ys, rs

    def system(self) -> System:
        return System.from_model(
            self, names=FIELDS, F=load_vector, dF=load_jacobian, params=self.params
        )

    def energy_density(self, y: np.ndarray) -> np.ndarray:
        """Kinetic + elastic energy per unit length, 1/2 rhoA|u|^2 + 1/2 w.rhoI w + 1/2 k.K^k."""
        q = Params(*self.params)
        y = np.asarray(y)
        return 0.5 * (
            q.rhoA * np.sum(y[..., U] ** 2, axis=-1)
            + np.sum(np.array([q.rI1, q.rI2, q.rI3]) * y[..., W] ** 2, axis=-1)
            + np.sum(np.array([q.B1, q.B2, q.C]) * y[..., KAPPA] ** 2, axis=-1)
        )

    def external_force(self, f_body: np.ndarray) -> np.ndarray:
        """Source q(s) (nodes x 12) for a distributed body-frame force f (nodes x 3) [N/m]."""
        f_body = np.atleast_2d(np.asarray(f_body, dtype=float))
        q = np.zeros((f_body.shape[0], 12))
        q[:, U] = -f_body
        return q
