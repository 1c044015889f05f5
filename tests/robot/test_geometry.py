"""rcb4hv.robot.geometry: rotations from quaternions and the corners and lowest point of
shapes, checked against rotations built independently (kinematics' Rodrigues) and against
dense sampling of the shapes' surfaces. (The stance half: tests/ui/test_stance.py.)"""

from __future__ import annotations

import itertools
import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from rcb4hv.robot import Geom
from rcb4hv.robot.builtin import BUILTIN, load_builtin
from rcb4hv.robot.geometry import (
    box_corners,
    geom_lowest_z,
    geom_points,
    half_extents,
    lowest_z,
    pose_transform,
    quaternion_matrix,
    rotation_of,
)
from rcb4hv.robot.kinematics import apply, compose, forward, from_xyz_rpy, rotation_about
from rcb4hv.robot.mjcf import lowest_point

angles = st.floats(-math.pi, math.pi, allow_nan=False)
unit = st.floats(-1.0, 1.0, allow_nan=False)


def _axis_angle_quaternion(axis: tuple[float, float, float], angle: float) -> tuple[float, ...]:
    n = math.sqrt(sum(a * a for a in axis))
    s = math.sin(angle / 2) / n
    return (math.cos(angle / 2), axis[0] * s, axis[1] * s, axis[2] * s)


@given(unit, unit, unit, angles)
def test_the_quaternion_matrix_is_the_rotation_about_its_axis(
    ax: float, ay: float, az: float, angle: float
) -> None:
    if math.sqrt(ax * ax + ay * ay + az * az) < 1e-3:
        return
    w, x, y, z = _axis_angle_quaternion((ax, ay, az), angle)
    got = quaternion_matrix((w, x, y, z))
    want = rotation_of(rotation_about((ax, ay, az), angle))
    for row_got, row_want in zip(got, want, strict=True):
        assert row_got == pytest.approx(row_want, abs=1e-12)


def test_pose_transform_turns_then_moves() -> None:
    q = _axis_angle_quaternion((0.0, 0.0, 1.0), math.pi / 2)  # a quarter turn about z
    t = pose_transform((1.0, 2.0, 3.0), (q[0], q[1], q[2], q[3]))
    assert apply(t, (1.0, 0.0, 0.0)) == pytest.approx((1.0, 3.0, 3.0))
    assert t[3] == (0.0, 0.0, 0.0, 1.0)


def test_half_extents_of_each_shape_kind() -> None:
    assert half_extents(Geom("box", (0.2, 0.4, 0.6))) == (0.1, 0.2, 0.3)
    assert half_extents(Geom("cylinder", (0.05, 0.3, 0.0))) == (0.05, 0.05, 0.15)
    assert half_extents(Geom("sphere", (0.07, 0.0, 0.0))) == (0.07, 0.07, 0.07)


def test_box_corners_of_an_unturned_box() -> None:
    eye = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    corners = box_corners((1.0, 2.0, 3.0), eye, (0.1, 0.2, 0.3))
    assert sorted(corners) == sorted(
        (1.0 + a, 2.0 + b, 3.0 + c) for a in (-0.1, 0.1) for b in (-0.2, 0.2) for c in (-0.3, 0.3)
    )


def _surface_lowest(geom: Geom, link: tuple) -> float:  # type: ignore[type-arg]
    """The lowest z of points sampled densely on the shape's surface (a bound from above)."""
    t = compose(link, from_xyz_rpy(geom.pos, geom.rpy))
    hx, hy, hz = half_extents(geom)
    n = 360
    if geom.shape == "box":
        local = list(itertools.product((-hx, hx), (-hy, hy), (-hz, hz)))
    elif geom.shape == "cylinder":
        local = [
            (hx * math.cos(2 * math.pi * k / n), hx * math.sin(2 * math.pi * k / n), h)
            for k in range(n)
            for h in (-hz, hz)
        ]
    else:
        local = [
            (
                hx * math.sin(math.pi * i / 90) * math.cos(2 * math.pi * k / 90),
                hx * math.sin(math.pi * i / 90) * math.sin(2 * math.pi * k / 90),
                hx * math.cos(math.pi * i / 90),
            )
            for i in range(91)
            for k in range(90)
        ]
    return min(apply(t, p)[2] for p in local)


@given(st.sampled_from(["box", "cylinder", "sphere"]), angles, angles, angles)
def test_lowest_z_is_the_lowest_surface_point(shape: str, r: float, p: float, y: float) -> None:
    geom = Geom(shape, (0.04, 0.1, 0.06), pos=(0.01, -0.02, 0.5), rpy=(r, p, y))  # type: ignore[arg-type]
    link = from_xyz_rpy((0.1, 0.2, 0.3), (0.3, -0.2, 0.1))
    exact = geom_lowest_z(geom, link)
    sampled = _surface_lowest(geom, link)
    assert exact <= sampled + 1e-12
    step = math.radians(1 if shape == "cylinder" else 4)  # the sampling's angular step
    assert sampled - exact < 0.04 * (1 - math.cos(step)) + 1e-12
    # the corners of the bounding box are never above it
    t = compose(link, from_xyz_rpy(geom.pos, geom.rpy))
    centre = (t[0][3], t[1][3], t[2][3])
    corners = box_corners(centre, rotation_of(t), half_extents(geom))
    assert min(c[2] for c in corners) <= exact + 1e-12
    assert lowest_z(geom.shape, centre, rotation_of(t), half_extents(geom)) == exact


@pytest.mark.parametrize("name", sorted(BUILTIN))
def test_the_exported_model_stands_on_its_lowest_shape_point(name: str) -> None:
    model = load_builtin(name)
    frames = forward(model, {})
    points = [
        p for link in model.links for g in link.geoms for p in geom_points(g, frames[link.name])
    ]
    assert lowest_point(model) == pytest.approx(min(p[2] for p in points), abs=1e-9)
