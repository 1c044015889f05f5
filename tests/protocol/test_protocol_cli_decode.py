"""``rcb4hv decode``: readable and JSON output, one-line errors with exit status 1."""

from __future__ import annotations

import json

from click.testing import CliRunner
from hypothesis import given

from rcb4hv import protocol as p
from rcb4hv.cli.main import cli
from rcb4hv.protocol.describe import describe_command
from tests.strategies import commands


def run(*args: str) -> tuple[int, str, str]:
    result = CliRunner().invoke(cli, ["decode", *args])
    return result.exit_code, result.stdout, result.stderr


def test_single_servo_move_is_readable() -> None:
    code, out, _ = run("07", "0F", "02", "1E", "4C", "1D", "9F")
    assert code == 0
    assert "RunSingleServo: ICS 2 to position 7500" in out
    assert "at speed 30" in out


def test_json_output_has_command_and_fields() -> None:
    code, out, _ = run("--json", "0D10010200000 00A4C1D401FF2", "04 10 06 1A")
    assert code == 0
    first, second = (json.loads(line) for line in out.splitlines())
    assert first["command"] == "RunConstFrameServo"
    assert first["speed"] == 10
    assert first["positions"] == [[0, 7500], [9, 8000]]
    assert second["reply"] == "ACK of 10h"


def test_bad_checksum_is_one_line_error() -> None:
    code, out, err = run("07 0F 02 1E 4C 1D 00")
    assert code == 1
    assert "not decoded: bad checksum 00, the sum of the other bytes is 9F" in out
    assert err.count("\n") == 1 and "checksum" in err


def test_decoding_goes_on_after_a_bad_frame() -> None:
    """Captured traffic with one damaged frame: every other frame is still decoded, and
    each bad one is reported with its offset (the decoder stopped at the first before)."""
    good, bad = "07 0F 02 1E 4C 1D 9F", "07 0F 02 1E 4C 1D 9E"
    code, out, err = run(good, bad, "00 01", "03 0D 10", bad)
    assert code == 1
    assert out.count("RunSingleServo") == 1 and "Return" in out
    lines = err.splitlines()
    assert lines == [
        "error: byte 7: 07 0F 02 1E 4C 1D 9E: bad checksum 9E, the sum of the other bytes is 9F",
        "error: byte 14: 2 bytes skipped: no frame starts there (00 01)",
        "error: byte 19: 07 0F 02 1E 4C 1D 9E: bad checksum 9E, the sum of the other bytes is 9F",
    ]
    code, out, _ = run("--json", bad, "03 0D 10")
    first, second = (json.loads(line) for line in out.splitlines())
    assert first["offset"] == 0 and "bad checksum" in str(first["error"])
    assert second["command"] == "Return"


def test_truncated_frame_reports_offset() -> None:
    code, out, err = run("03 0D 10 07 0B 4B")
    assert code == 1
    assert "Return" in out
    assert "byte 3: truncated frame" in err


def test_not_hex() -> None:
    code, _, err = run("zz")
    assert code == 2
    assert "not hex" in err


@given(commands)
def test_every_command_describes_and_serialises(cmd: p.Command) -> None:
    text = describe_command(cmd)
    assert text.startswith(type(cmd).__name__)
    code, out, _ = run("--json", p.encode_command(cmd).hex())
    assert code == 0
    assert json.loads(out)["command"] == type(cmd).__name__


def test_closed_stdout_stops_quietly() -> None:
    """`rcb4hv decode ... | head`: when the reader goes away, no traceback, no error line."""
    import subprocess
    import sys

    frames = ("07 0F 02 1E 4C 1D 9F " * 20000).split()
    proc = subprocess.Popen(
        [sys.executable, "-c", "from rcb4hv.cli.main import main; main()", "decode", *frames],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
    )
    assert proc.stdout is not None and proc.stderr is not None
    assert proc.stdout.read(100)
    proc.stdout.close()
    err = proc.stderr.read().decode()
    proc.stderr.close()
    assert proc.wait(timeout=60) == 1
    assert "Traceback" not in err and "error" not in err
