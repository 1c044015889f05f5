"""rcb4hv.robot.servos: the servo figures once, checked against the catalogue figures
(shared/robots/FACTS.md) written out here; and each fact of the servo defined in one module."""

from __future__ import annotations

import ast
import math
from pathlib import Path

import pytest

import rcb4hv
from rcb4hv.ics.servo import COUNTS_PER_S_AT_127
from rcb4hv.robot.servos import (
    DEFAULT_SERVO,
    KRS_2552RHV,
    KRS_3304R2,
    TRAVEL_DEG,
    speed_cap,
    stiffness,
)

SRC = Path(rcb4hv.__file__).resolve().parent


def test_the_catalogue_figures() -> None:
    # 13.9 kgf·cm, 0.13 s/60°; 14.0 kgf·cm, 0.14 s/60° (FACTS.md "Servo figures")
    assert KRS_3304R2.stall_torque == pytest.approx(13.9 * 9.80665 / 100)
    assert KRS_3304R2.no_load_speed == pytest.approx(math.radians(60) / 0.13)
    assert KRS_2552RHV.stall_torque == pytest.approx(14.0 * 9.80665 / 100)
    assert KRS_2552RHV.no_load_speed == pytest.approx(math.radians(60) / 0.14)
    assert DEFAULT_SERVO is KRS_3304R2


def test_the_travel_is_3500_to_11500_around_7500() -> None:
    assert TRAVEL_DEG == pytest.approx(4000 * 270 / 8000) == 135.0


def test_the_emulated_ics_servo_slews_at_the_default_servos_speed() -> None:
    assert pytest.approx(60 / 0.13 * 8000 / 270) == COUNTS_PER_S_AT_127


def test_the_model_at_the_ends_of_the_ics_range() -> None:
    full = KRS_3304R2.stall_torque / math.radians(2.0)  # stretch 127: stall at 2° of error
    assert stiffness(KRS_3304R2, 127) == pytest.approx(full)
    assert stiffness(KRS_3304R2, 0) == stiffness(KRS_3304R2, None) == pytest.approx(full * 60 / 127)
    assert speed_cap(KRS_3304R2, 127) == speed_cap(KRS_3304R2, 128) == KRS_3304R2.no_load_speed
    assert speed_cap(KRS_3304R2, 1) == pytest.approx(KRS_3304R2.no_load_speed / 127)


FACTS = (
    "CENTER",
    "COUNTS_PER_DEGREE",
    "DEFAULT_SERVO",
    "KRS_2552RHV",
    "KRS_3304R2",
    "POSITION_MAX",
    "POSITION_MIN",
    "STRETCH_MAX",
    "TRAVEL_DEG",
)


def test_each_servo_fact_is_defined_in_one_module() -> None:
    """A name of FACTS is assigned in one file only; every other
    module imports it."""
    where: dict[str, list[str]] = {name: [] for name in FACTS}
    for path in sorted(SRC.rglob("*.py")):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            targets = (
                node.targets
                if isinstance(node, ast.Assign)
                else [node.target]
                if isinstance(node, ast.AnnAssign)
                else []
            )
            for t in targets:
                if isinstance(t, ast.Name) and t.id in where:
                    where[t.id].append(str(path.relative_to(SRC)))
    assert {name: len(files) for name, files in where.items()} == dict.fromkeys(FACTS, 1), where
