"""The dashboard's parts without a browser: the access guard, flowchart SVG, the CLI."""

from __future__ import annotations

import asyncio
import json
from pathlib import Path

import httpx
import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.hth4 import load_project, parse_motion_xml
from rcb4hv.project.image import build_project_image
from rcb4hv.project.simulate import Simulator
from rcb4hv.ui.app import parse_bind
from rcb4hv.ui.flowsvg import canvas_svg, motion_graph, motion_svg
from rcb4hv.ui.security import AccessPolicy, GuardMiddleware, new_token


async def _echo(scope: dict, receive: object, send: object) -> None:  # type: ignore[type-arg]
    await send({"type": "http.response.start", "status": 200, "headers": []})  # type: ignore[operator]
    await send({"type": "http.response.body", "body": b"ok"})  # type: ignore[operator]


def _get(policy: AccessPolicy, url: str = "/", **headers: str) -> httpx.Response:
    async def go() -> httpx.Response:
        transport = httpx.ASGITransport(GuardMiddleware(_echo, policy))  # type: ignore[arg-type]
        async with httpx.AsyncClient(transport=transport, base_url="http://127.0.0.1:8765") as c:
            return await c.get(url, headers=headers)

    return asyncio.run(go())


def test_guard_checks_host_and_origin() -> None:
    policy = AccessPolicy(port=8765)
    assert _get(policy).status_code == 200
    assert _get(policy, host="localhost:8765").status_code == 200
    r = _get(policy, host="evil.example:8765")  # DNS rebinding
    assert r.status_code == 403 and "Host" in r.text
    assert _get(policy, origin="http://127.0.0.1:8765").status_code == 200
    r = _get(policy, origin="http://evil.example")
    assert r.status_code == 403 and "Origin" in r.text


def test_guard_needs_the_token_when_remote() -> None:
    token = new_token()
    policy = AccessPolicy(bind_host="0.0.0.0", port=8765, token=token)
    assert _get(policy).status_code == 403
    assert _get(policy, "/?token=wrong").status_code == 403
    r = _get(policy, f"/?token={token}")
    assert r.status_code == 200
    assert (
        f"rcb4hv_token={token}" in r.headers["set-cookie"] and "HttpOnly" in r.headers["set-cookie"]
    )
    assert _get(policy, cookie=f"rcb4hv_token={token}").status_code == 200
    assert _get(policy, **{"x-rcb4hv-token": token}).status_code == 200


def test_guard_refuses_large_bodies() -> None:
    policy = AccessPolicy(port=8765, max_body=100)

    async def go() -> httpx.Response:
        transport = httpx.ASGITransport(GuardMiddleware(_echo, policy))  # type: ignore[arg-type]
        async with httpx.AsyncClient(transport=transport, base_url="http://127.0.0.1:8765") as c:
            return await c.post("/upload", content=b"x" * 101)

    assert asyncio.run(go()).status_code == 413


def test_parse_bind() -> None:
    assert parse_bind("127.0.0.1:0") == ("127.0.0.1", 0)
    assert parse_bind("[::1]:8765") == ("::1", 8765)
    for bad in ("8765", "host:", "h:99999"):
        with pytest.raises(ValueError):
            parse_bind(bad)


def test_cli_ui_refuses_a_remote_bind_without_allow_remote() -> None:
    r = CliRunner().invoke(cli, ["ui", "--bind", "0.0.0.0:0"])
    assert r.exit_code != 0 and "--allow-remote" in r.output
    r = CliRunner().invoke(cli, ["ui", "--bind", "nonsense"])
    assert r.exit_code != 0 and "HOST:PORT" in r.output


def test_motion_graph_follows_jumps(kxr_project_path: Path) -> None:
    m = load_project(kxr_project_path).motion(3)  # a walk loop with a button compare
    nodes, edges = motion_graph(m.frames, m.address)
    assert len(nodes) == len(m.frames)
    kinds = {k for _, _, k in edges}
    assert {"next", "jump", "end"} <= kinds
    assert all(j < len(nodes) for _, j, _ in edges)
    svg = motion_svg(m.frames, m.address)
    assert svg.count('class="node"') == len(nodes) and "edge-jump" in svg


def test_canvas_svg_draws_boxes_and_lines(kxr_dir: Path) -> None:
    chart = parse_motion_xml((kxr_dir / "HAC_KXR_TURN_LEFT.xml").read_bytes())
    svg = canvas_svg(chart)
    assert svg.count('class="node"') == len(chart.activities) == 5
    assert svg.count("<polyline") == len(chart.lines)


def test_cli_add_motion(kxr_project_path: Path, tmp_path: Path) -> None:
    frames = {
        "keyframes": [
            {"time": 0.3, "positions": {"2": 7500, "3": 7500}},
            {"time": 0.6, "positions": {"2": 9000}, "name": "up"},
        ]
    }
    kf = tmp_path / "kf.json"
    kf.write_text(json.dumps(frames))
    out, xml = tmp_path / "out.h4p", tmp_path / "m.xml"
    r = CliRunner().invoke(
        cli,
        [
            "project",
            "add-motion",
            str(kxr_project_path),
            str(kf),
            "--name",
            "cli motion",
            "--button",
            "SQUARE+S2",
            "-o",
            str(out),
            "--flowchart",
            str(xml),
        ],
    )
    assert r.exit_code == 0, r.output
    project = load_project(out)
    m = next(m for m in project.used_motions if m.name == "cli motion")
    assert m.button_data == 0x0100 | 0x0400
    chart = parse_motion_xml(xml.read_bytes())
    assert [a.text for a in chart.activities] == ["Pos1", "up"]
    sim = Simulator(build_project_image(project))
    sim.boot()
    assert sim.play(m.address).status == "completed"
    kf.write_text(json.dumps({"keyframes": [{"time": 0.3}]}))
    r = CliRunner().invoke(
        cli,
        ["project", "add-motion", str(kxr_project_path), str(kf), "--name", "x", "-o", str(out)],
    )
    assert r.exit_code == 1 and "keyframe 1" in r.output


def test_cli_add_motion_refuses_a_button_another_motion_holds(
    kxr_project_path: Path, tmp_path: Path
) -> None:
    """`add-motion --button UP` on the fixture, whose motion 9 starts on UP: the new motion
    was bound too and never played from the remote (the board starts the first). Refused as
    `project bind` refuses it, and nothing is written."""
    kf = tmp_path / "kf.json"
    kf.write_text(json.dumps({"keyframes": [{"time": 0.3, "positions": {"2": 7600}}]}))
    out = tmp_path / "out.h4p"
    args = ["project", "add-motion", str(kxr_project_path), str(kf), "--name", "x", "-o", str(out)]
    r = CliRunner().invoke(cli, [*args, "--button", "UP"])
    assert r.exit_code == 1 and "already starts motion 9" in r.output, r.output
    assert "project bind --force" in r.output and not out.exists()
    kf.write_text("{not json")
    r = CliRunner().invoke(cli, args)
    assert r.exit_code == 1 and f"error: {kf}: not JSON keyframes" in r.output, r.output
