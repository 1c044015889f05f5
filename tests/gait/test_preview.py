"""The ZMP preview controller: the cart-table model's ZMP follows a stepping reference."""

from __future__ import annotations

import numpy as np
import pytest

from rcb4hv.gait.preview import PreviewController, solve_dare


def test_the_riccati_solution_satisfies_its_equation() -> None:
    pc = PreviewController(0.01, 0.2)
    a, b, c = pc.matrices
    q = c.T @ c
    p = solve_dare(a, b, q, pc.r)
    s = pc.r + (b.T @ p @ b)[0, 0]
    rhs = a.T @ p @ a - (a.T @ p @ b) @ (b.T @ p @ a) / s + q
    assert np.allclose(p, rhs, rtol=1e-8, atol=1e-12)


def test_the_preview_gains_sum_to_the_position_gain() -> None:
    """At rest over a constant reference the jerk is zero: sum(f) = K[0]."""
    k, f = PreviewController(0.01, 0.25).gains()
    assert f.sum() == pytest.approx(k[0, 0], rel=1e-3)


@pytest.mark.parametrize("zc", [0.15, 0.25])
def test_the_zmp_tracks_a_stepping_reference(zc: float) -> None:
    dt = 0.01
    ref = np.concatenate([np.zeros(100), np.full(50, 0.03), np.full(50, -0.03), np.zeros(150)])
    com, zmp = PreviewController(dt, zc).track(ref)
    settled = np.ones(len(ref), dtype=bool)
    for edge in (100, 150, 200):  # a jump cannot be followed: leave 10 samples either side
        settled[edge - 10 : edge + 10] = False
    assert np.max(np.abs(zmp - ref)[settled]) < 0.005
    assert abs(com[-1]) < 1e-3  # back over the origin at the end
    assert np.max(np.abs(com)) < 0.03  # the CoM sways less than the ZMP


def test_two_axes_at_once_are_the_two_single_axes() -> None:
    pc = PreviewController(0.01, 0.2)
    x = np.concatenate([np.zeros(50), np.full(100, 0.02)])
    y = np.concatenate([np.zeros(80), np.full(70, -0.01)])
    both, _ = pc.track(np.stack([x, y], axis=1))
    assert np.allclose(both[:, 0], pc.track(x)[0])
    assert np.allclose(both[:, 1], pc.track(y)[0])
