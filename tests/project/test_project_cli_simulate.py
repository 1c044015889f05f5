"""``rcb4hv project simulate``: table, JSON, exit status, hold, plot."""

from __future__ import annotations

import json
from pathlib import Path

from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.protocol import Data, Move, Ram, Return
from rcb4hv.rom import ImageDescription, ImageMotion, ImageServo, build_image


def test_simulate_walk_json_with_hold(kxr_project_path: Path) -> None:
    r = CliRunner().invoke(
        cli,
        [
            "project",
            "simulate",
            str(kxr_project_path),
            "--motion",
            "9",
            "--motion",
            "40",
            "--hold-button",
            "UP",
            "--for",
            "2",
            "--json",
        ],
    )
    assert r.exit_code == 0, r.output
    data = json.loads(r.output)
    assert data["boot"]["status"] == "completed"
    walk, battery = data["motions"]
    assert walk["status"] == "completed" and walk["duration_s"] >= 2.0
    assert battery["status"] == "waiting" and battery["inputs"] == ["buttons"]
    assert data["summary"] == {"completed": 1, "waiting": 1}
    # one vocabulary with --physics: virtual_s (board time, the boot included), no physics
    assert "virtual_seconds" not in data and "physics" not in data
    assert data["virtual_s"] >= data["boot"]["duration_s"] + walk["duration_s"]
    assert walk["start_s"] >= data["boot"]["duration_s"]


def test_simulate_table_and_plot(kxr_project_path: Path, tmp_path: Path) -> None:
    png = tmp_path / "angles.png"
    r = CliRunner().invoke(
        cli, ["project", "simulate", str(kxr_project_path), "--motion", "39", "--plot", str(png)]
    )
    assert r.exit_code == 0, r.output
    assert "completed" in r.output and "1 motions: 1 completed" in r.output
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_simulate_error_exit_status(tmp_path: Path) -> None:
    desc = ImageDescription(
        system_register=0x821B,
        servos=(ImageServo(2),),
        motions=(
            ImageMotion(1, [Move(Ram(0x0005), Data(b"\x00")), Return()]),
            ImageMotion(2, [Return()]),
        ),
    )
    img = tmp_path / "bad.bin"
    img.write_bytes(build_image(desc))
    r = CliRunner().invoke(cli, ["project", "simulate", str(img)])
    assert r.exit_code == 1, r.output
    assert "underflow" in r.output and "RETURN" in r.output and "00B88" in r.output
    assert "1 completed, 1 error" in r.output


def test_simulate_unknown_button(kxr_project_path: Path) -> None:
    r = CliRunner().invoke(
        cli, ["project", "simulate", str(kxr_project_path), "--hold-button", "JUMP"]
    )
    assert r.exit_code == 2 and "unknown button" in r.output
