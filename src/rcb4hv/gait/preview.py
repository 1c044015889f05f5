"""ZMP preview control of the linear inverted pendulum (Kajita et al., ICRA 2003).

The centre of mass moves on a plane at height ``zc`` above the floor (the cart-table
model): each horizontal axis is a triple integrator of the CoM jerk ``u``, state
``x = (c, c', c'')``, and the zero moment point is ``p = c - zc / g * c''``. The controller
minimises ``sum Q (p - p_ref)^2 + R u^2`` with the reference known ``preview`` seconds ahead:

    u(k) = -K x(k) + sum_{j=1..N} f(j) p_ref(k + j)

``K`` from the discrete algebraic Riccati equation (solved here by iteration: NumPy only,
no SciPy), ``f(j) = (R + B'PB)^-1 B' (A - BK)'^(j-1) C' Q`` (Kajita 2003, eq. 13-14).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rcb4hv.robot.balance import GRAVITY

__all__ = ["Q_WEIGHT", "R_WEIGHT", "PreviewController", "solve_dare"]

Q_WEIGHT = 1.0
"""Weight of the ZMP error (1/m^2): Kajita 2003's choice."""
R_WEIGHT = 1e-6
"""Weight of the jerk (s^6/m^2): Kajita 2003's choice (Q/R = 10^6)."""

Array = NDArray[np.float64]


def solve_dare(
    a: Array, b: Array, q: Array, r: float, *, tol: float = 1e-12, max_iter: int = 100_000
) -> Array:
    """The stabilising solution P of ``P = A'PA - A'PB (R + B'PB)^-1 B'PA + Q`` by the
    structure-preserving doubling algorithm (quadratic convergence; a few dozen steps)."""
    n = a.shape[0]
    ak = a.copy()
    gk = b @ b.T / r
    hk = q.copy()
    eye = np.eye(n)
    for _ in range(max_iter):
        w = np.linalg.inv(eye + gk @ hk)
        a1 = ak @ w @ ak
        g1 = gk + ak @ w @ gk @ ak.T
        h1 = hk + ak.T @ hk @ w @ ak
        done = np.max(np.abs(h1 - hk)) <= tol * max(1.0, float(np.max(np.abs(h1))))
        ak, gk, hk = a1, g1, h1
        if done:
            return np.asarray(hk, dtype=np.float64)
    raise ArithmeticError("the Riccati iteration did not converge")


@dataclass(frozen=True)
class PreviewController:
    """The preview controller of one CoM height and sampling period."""

    dt: float
    zc: float
    preview: float = 1.6
    q: float = Q_WEIGHT
    r: float = R_WEIGHT

    @property
    def matrices(self) -> tuple[Array, Array, Array]:
        dt = self.dt
        a = np.array([[1.0, dt, dt * dt / 2.0], [0.0, 1.0, dt], [0.0, 0.0, 1.0]])
        b = np.array([[dt**3 / 6.0], [dt * dt / 2.0], [dt]])
        c = np.array([[1.0, 0.0, -self.zc / GRAVITY]])
        return a, b, c

    def gains(self) -> tuple[Array, Array]:
        """The state feedback ``K`` (1x3) and the preview gains ``f`` (N)."""
        a, b, c = self.matrices
        p = solve_dare(a, b, c.T @ c * self.q, self.r)
        s = float(self.r + (b.T @ p @ b)[0, 0])
        k = (b.T @ p @ a) / s
        ac = a - b @ k
        n = max(1, round(self.preview / self.dt))
        f = np.empty(n)
        x = c.T * self.q
        for j in range(n):
            f[j] = float((b.T @ x)[0, 0]) / s
            x = ac.T @ x
        return k, f

    def track(self, zmp_ref: Array, x0: Array | None = None) -> tuple[Array, Array]:
        """The CoM positions and the ZMP the model makes, for a reference ZMP per sample
        (shape (T,) or (T, 2) for x and y); beyond its end the reference holds its last
        value. Starts at rest over the first reference unless ``x0`` (3, or 3x2) is given."""
        ref = np.asarray(zmp_ref, dtype=np.float64)
        flat = ref.ndim == 1
        ref2 = ref.reshape(len(ref), -1)
        a, b, c = self.matrices
        k, f = self.gains()
        n = len(f)
        padded = np.concatenate([ref2, np.repeat(ref2[-1:], n + 1, axis=0)])
        x = np.zeros((3, ref2.shape[1]))
        x[0] = ref2[0]
        if x0 is not None:
            x = np.asarray(x0, dtype=np.float64).reshape(3, -1).copy()
        com = np.empty_like(ref2)
        zmp = np.empty_like(ref2)
        for i in range(len(ref2)):
            com[i] = x[0]
            zmp[i] = (c @ x)[0]
            u = -(k @ x)[0] + f @ padded[i + 1 : i + 1 + n]
            x = a @ x + b @ u[None, :]
        if flat:
            return com[:, 0], zmp[:, 0]
        return com, zmp
