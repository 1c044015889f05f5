"""Upload a project image to the emulator (in process, TCP, pty) and dump it back."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.client import Robot
from rcb4hv.emulator import Board, EmulatorConfig, PtyServer, RealClock, TcpServer, emulator_url
from rcb4hv.project.upload import PAGE_SIZE, changed_pages, upload_image
from rcb4hv.protocol import Move, Rom, decode_command
from rcb4hv.rom import default_image, layout


def _board() -> Board:
    return Board(EmulatorConfig(min_reply_latency_s=0.0), clock=RealClock())


class _RomWriteCounter:
    """Counts the MOVE-to-ROM frames a board receives (wraps ``feed``)."""

    def __init__(self, board: Board) -> None:
        self.addresses: list[int] = []
        inner = board.feed

        def feed(data: bytes | bytearray) -> bytes:
            data = bytes(data)
            if len(data) >= 3 and data[0] == len(data):
                try:
                    cmd = decode_command(data)
                except ValueError:
                    cmd = None
                if isinstance(cmd, Move) and isinstance(cmd.dst, Rom):
                    self.addresses.append(cmd.dst.address)
            return inner(data)

        board.feed = feed  # type: ignore[method-assign]


def test_upload_and_dump_in_process(kxr_image: bytes) -> None:
    board = _board()
    with Robot.open(emulator_url(board) + "&latency=0") as robot:
        res = upload_image(robot, kxr_image)
        assert (res.pages_total, res.pages_written) == (2048, 2048)
        assert robot.read_rom(0, layout.ROM_SIZE) == kxr_image
    assert bytes(board.rom) == kxr_image
    # restarted from 000000h: the new image boots (servo blocks of the project appear)
    assert board.system_register & 0x0002


def test_only_changed_writes_only_differing_pages(kxr_image: bytes) -> None:
    board = _board()
    old = default_image()
    assert bytes(board.rom) == old
    expected = changed_pages(old, kxr_image)
    assert 0 < len(expected) < 2048
    counter = _RomWriteCounter(board)
    with Robot.open(emulator_url(board) + "&latency=0") as robot:
        res = upload_image(robot, kxr_image, only_changed=True, restart=False)
        assert res.pages_written == len(expected) and res.bytes_read == layout.ROM_SIZE
        assert robot.read_rom(0, layout.ROM_SIZE) == kxr_image
        # every written chunk lies in a changed page; every changed page was written
        pages = {a - a % PAGE_SIZE for a in counter.addresses}
        assert pages == set(expected)
        assert len(counter.addresses) == 2 * len(expected)  # 64-byte chunks
        counter.addresses.clear()
        again = upload_image(robot, kxr_image, only_changed=True, restart=False)
        assert again.pages_written == 0 and counter.addresses == []
    assert not board.system_register & 0x0002  # restart=False leaves the program stopped


def test_upload_over_tcp_and_pty(kxr_image: bytes) -> None:
    board = _board()
    with TcpServer(board, "127.0.0.1", 0) as srv:
        host, port = srv.address
        with Robot.open(f"socket://{host}:{port}") as robot:
            res = upload_image(robot, kxr_image)
            assert res.pages_written == 2048
            assert robot.read_rom(0, layout.ROM_SIZE) == kxr_image
    board = _board()
    with PtyServer(board) as pty, Robot.open(pty.path) as robot:
        res = upload_image(robot, kxr_image, only_changed=True)
        assert res.pages_written == len(changed_pages(default_image(), kxr_image))
        assert robot.read_rom(0, layout.ROM_SIZE) == kxr_image


def test_cli_build_upload_dump(kxr_project_path: Path, kxr_image: bytes, tmp_path: Path) -> None:
    runner = CliRunner()
    out = tmp_path / "built.bin"
    r = runner.invoke(cli, ["project", "build", str(kxr_project_path), "-o", str(out)])
    assert r.exit_code == 0, r.output
    assert out.read_bytes() == kxr_image
    rom = tmp_path / "board.bin"
    url = f"rcb4emu://?rom={rom}&latency=0"
    r = runner.invoke(
        cli, ["project", "upload", str(kxr_project_path), "--port", url, "--no-progress"]
    )
    assert r.exit_code == 0, r.output
    assert "2048 of 2048 pages" in r.output
    r = runner.invoke(
        cli,
        [
            "project",
            "upload",
            str(kxr_project_path),
            "--port",
            url,
            "--only-changed",
            "--no-progress",
        ],
    )
    assert r.exit_code == 0, r.output
    assert "wrote and verified 0 of 2048 pages" in r.output
    dump = tmp_path / "dump.bin"
    # explicit --start/--size: their int defaults trip parse_int (reported to the lead)
    r = runner.invoke(
        cli,
        [
            "rom",
            "dump",
            "--port",
            url,
            "-o",
            str(dump),
            "--no-progress",
            "--start",
            "0",
            "--size",
            "0x40000",
        ],
    )
    assert r.exit_code == 0, r.output
    assert dump.read_bytes() == kxr_image


def test_cli_info_and_image(kxr_project_path: Path, tmp_path: Path) -> None:
    runner = CliRunner()
    r = runner.invoke(cli, ["project", "info", str(kxr_project_path), "--json"])
    assert r.exit_code == 0, r.output
    data = json.loads(r.output)
    assert len(data["motions"]) == 65 and len(data["servos"]) == 18
    walk = next(m for m in data["motions"] if m["slot"] == 9)
    assert walk["button_names"] == "UP" and walk["address"] == "04B80"
    r = runner.invoke(cli, ["project", "info", str(kxr_project_path)])
    assert r.exit_code == 0 and "startup" in r.output and "priority 0" in r.output
    img = tmp_path / "i.bin"
    runner.invoke(cli, ["project", "build", str(kxr_project_path), "-o", str(img)])
    r = runner.invoke(cli, ["project", "image", str(img), "--json"])
    assert r.exit_code == 0, r.output
    data = json.loads(r.output)
    assert data["system_register"] == "821B" and len(data["motions"]) == 65
    assert data["startup_motion"] == "13B80"


@pytest.mark.parametrize("bad", [b"", b"\x00" * 100])
def test_upload_refuses_wrong_sizes(bad: bytes) -> None:
    with pytest.raises(ValueError, match="ROM image"):
        upload_image(None, bad)  # type: ignore[arg-type]


def test_an_interrupted_upload_says_how_to_finish(
    kxr_project_path: Path, tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Ctrl-C in the middle of an upload says the ROM is partly written and how to write the
    rest (it printed only "Aborted!")."""
    from rcb4hv.project import upload as upload_module

    def interrupted(robot: Robot, image: bytes, **kwargs: object) -> None:
        robot.write_rom(0, image[:PAGE_SIZE])  # one page, then the user presses Ctrl-C
        raise KeyboardInterrupt

    monkeypatch.setattr(upload_module, "upload_image", interrupted)
    url = f"rcb4emu://?rom={tmp_path / 'board.bin'}&latency=0"
    r = CliRunner().invoke(
        cli, ["project", "upload", str(kxr_project_path), "--port", url, "--no-progress"]
    )
    assert r.exit_code == 130, r.output
    assert "partly written" in r.output and "--only-changed" in r.output
