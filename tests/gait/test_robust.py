"""``project robust``: trials draw the documented constants deterministically per seed, the
pool and Ray give the same numbers, a torso leant far forward falls where the upright walk
does not, and the CLI prints the JSON the issue names."""

from __future__ import annotations

import json
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.gait.generate import default_params, walk
from rcb4hv.gait.motion import walk_motion
from rcb4hv.hth4 import save_project
from rcb4hv.hth4.keyframes import add_motion
from rcb4hv.hth4.newproject import new_project
from rcb4hv.project.relocate import project_image
from rcb4hv.project.robust import RANGES, TILT_MAX_DEG, draw, robust, wilson
from rcb4hv.robot.builtin import load_builtin
from rcb4hv.rom.layout import MotionLayout

KXR = load_builtin("kxr-l2")


def _walk_image(lean: float = 0.0) -> tuple[bytes, MotionLayout]:
    params = replace(default_params(KXR, "forward", steps=1), lean=lean)
    motion = walk_motion(KXR, walk(KXR, params), slot=2, name="walk").motion
    return project_image(add_motion(new_project(KXR), motion))


@pytest.fixture(scope="module")
def upright() -> tuple[bytes, MotionLayout]:
    return _walk_image()


def test_the_wilson_interval_matches_its_formula() -> None:
    lo, hi = wilson(0, 10)
    assert lo == 0.0 and hi == pytest.approx(0.2775, abs=1e-4)
    lo, hi = wilson(5, 10)
    assert (lo, hi) == pytest.approx((0.2366, 0.7634), abs=1e-4)


def test_a_draw_stays_in_its_ranges_and_repeats_with_its_seed() -> None:
    seeds = np.random.SeedSequence(7).spawn(20)
    opts = [draw(np.random.default_rng(s)) for s in seeds]
    again = [draw(np.random.default_rng(s)) for s in np.random.SeedSequence(7).spawn(20)]
    assert opts == again
    assert len(set(opts)) == 20
    for o in opts:
        for name, (lo, hi) in RANGES.items():
            assert lo <= getattr(o, name) <= hi
        assert 0.0 <= o.floor_tilt_deg <= TILT_MAX_DEG


def test_one_process_and_a_pool_give_the_same_numbers(upright: tuple[bytes, MotionLayout]) -> None:
    image, layout = upright
    one = robust(image, [2], layout=layout, robot=KXR, trials=2, seed=3, workers=1)
    two = robust(image, [2], layout=layout, robot=KXR, trials=2, seed=3, workers=2)
    assert one == two
    (m,) = one
    assert m["slot"] == 2 and m["trials"] == 2 and m["fall_probability"] == 0.0
    assert m["dx_m"]["median"] > 0.6 * 0.029


def test_ray_gives_the_same_numbers_as_the_pool(upright: tuple[bytes, MotionLayout]) -> None:
    import ray  # the [scale] extra, which `make test` installs

    image, layout = upright
    local = robust(image, [2], layout=layout, robot=KXR, trials=2, seed=5, workers=1)
    ray.init(num_cpus=1, include_dashboard=False, log_to_driver=False)
    try:
        remote = robust(image, [2], layout=layout, robot=KXR, trials=2, seed=5, use_ray=True)
    finally:
        ray.shutdown()
    assert remote == local


def test_a_torso_leant_far_forward_falls_where_the_upright_walk_does_not(
    upright: tuple[bytes, MotionLayout],
) -> None:
    image, layout = upright
    good = robust(image, [2], layout=layout, robot=KXR, trials=3, seed=1, workers=2)
    bad_image, _ = _walk_image(lean=65.0)
    bad = robust(bad_image, [2], layout=layout, robot=KXR, trials=3, seed=1, workers=2)
    assert good[0]["fall_probability"] == 0.0
    assert bad[0]["fall_probability"] == 1.0
    assert good[0]["ci"][1] < 1.0 and bad[0]["ci"][0] > 0.0


def test_the_cli_prints_the_json_of_the_issue(tmp_path: Path) -> None:
    params = default_params(KXR, "forward", steps=1)
    motion = walk_motion(KXR, walk(KXR, params), slot=2, name="walk").motion
    path = tmp_path / "walk.h4p"
    save_project(add_motion(new_project(KXR), motion), path)
    args = ["project", "robust", str(path), "--motion", "2", "--trials", "2", "--json"]
    r = CliRunner().invoke(cli, [*args, "--robot", "kxr-l2", "--workers", "1"])
    assert r.exit_code == 0, r.output
    data = json.loads(r.output)
    (m,) = data["motions"]
    assert m["slot"] == 2 and m["trials"] == 2 and len(m["ci"]) == 2
    assert set(m["dx_m"]) == {"median", "q1", "q3"}


def test_without_ray_the_error_says_which_extra(
    upright: tuple[bytes, MotionLayout], monkeypatch: pytest.MonkeyPatch
) -> None:
    import sys

    from rcb4hv.errors import ScaleError

    monkeypatch.setitem(sys.modules, "ray", None)
    image, layout = upright
    with pytest.raises(ScaleError, match=r"rcb4hv\[scale\]"):
        robust(image, [2], layout=layout, robot=KXR, trials=1, use_ray=True)


def test_an_address_that_answers_nothing_is_a_clear_error() -> None:
    import socket

    from rcb4hv.errors import ScaleError
    from rcb4hv.project.robust_ray import probe

    with socket.socket() as s:  # a port nobody listens on: bound, never listening
        s.bind(("127.0.0.1", 0))
        port = s.getsockname()[1]
        with pytest.raises(ScaleError, match="answers nothing"):
            probe(f"127.0.0.1:{port}")
    with pytest.raises(ScaleError, match="HOST:PORT"):
        probe("nowhere")
    probe(None)
