"""The PyPI ``rcb4`` client (0.1.6), unchanged, against ``rcb4hv emulate --pty``.

``rcb4`` comes from the ``test`` extra (``make test`` installs it); ``rcb4_driver.py`` runs
in a subprocess of this interpreter and prints JSON lines.
"""

from __future__ import annotations

import json
import subprocess
import sys
from importlib.metadata import PackageNotFoundError, version
from pathlib import Path

import pytest

from rcb4hv.rom import DEFAULT_ICS

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
PEER_VERSION = "0.1.6"  # the pin of pyproject.toml's test extra


@pytest.fixture(scope="session")
def rcb4_python() -> Path:
    """This interpreter, which must hold the pinned peer client."""
    try:
        found = version("rcb4")
    except PackageNotFoundError:
        found = None
    assert found == PEER_VERSION, (
        f"the peer client rcb4=={PEER_VERSION} is not installed (found {found}): "
        "pip install -e '.[test]' (make test does it)"
    )
    return Path(sys.executable)


@pytest.mark.slow
def test_pypi_rcb4_client_drives_the_emulator(rcb4_python: Path) -> None:
    emu = subprocess.Popen(
        [sys.executable, "-c", "from rcb4hv.cli.main import main; main()", "emulate", "--pty"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
        cwd=REPO,
    )
    try:
        assert emu.stdout is not None
        kind, path = emu.stdout.readline().split()
        assert kind == "PTY"
        drv = subprocess.run(
            [str(rcb4_python), str(HERE / "rcb4_driver.py"), path],
            capture_output=True,
            text=True,
            timeout=60,
        )
        assert drv.returncode == 0, drv.stderr[-3000:]
        result = json.loads(drv.stdout.strip().splitlines()[-1])
    finally:
        emu.terminate()
        _, err = emu.communicate(timeout=10)
    assert emu.returncode == 0, err
    assert result["open"] is True
    assert result["ids"] == sorted(DEFAULT_ICS)
    assert result["angles"] == pytest.approx([0.0] * len(DEFAULT_ICS), abs=0.01)
    assert result["sent"] == sorted(DEFAULT_ICS)
    # servo_angle_vector(..., 8000): (8000 - 7500) / 29.63 degrees everywhere
    assert result["angles_after_move"] == pytest.approx([16.875] * len(DEFAULT_ICS), abs=0.01)
    assert result["stretch"] is True
    assert result["play"] is True
    # the motion ran: the PC moved into motion 1 and back into the main loop
    assert result["motion_numbers"] == [0, 1] and result["motion_ended"] is True
    # and raised the left arm (ICS 2 to 7500 + 2700 at its peak)
    assert result["peak_ics2_deg"] > 60
