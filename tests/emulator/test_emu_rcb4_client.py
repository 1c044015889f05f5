"""The PyPI ``rcb4`` client (0.1.6), unchanged, against ``rcb4hv emulate --pty``.

Builds a throwaway venv once per session (``pip install --no-deps rcb4==0.1.6 numpy pyserial``)
and runs ``rcb4_driver.py`` in it; skipped with the reason when the registry is unreachable.
"""

from __future__ import annotations

import json
import subprocess
import sys
import venv
from pathlib import Path

import pytest

from rcb4hv.rom import DEFAULT_ICS

HERE = Path(__file__).resolve().parent
REPO = HERE.parents[1]
NETWORK_HINTS = (
    "NewConnectionError",
    "Failed to establish",
    "Temporary failure in name resolution",
    "Could not find a version",
    "No matching distribution",
    "Network is unreachable",
    "ConnectTimeout",
    "ReadTimeout",
    "ProxyError",
)


@pytest.fixture(scope="session")
def rcb4_python(tmp_path_factory: pytest.TempPathFactory) -> Path:
    root = tmp_path_factory.mktemp("rcb4-venv")
    venv.create(root, with_pip=True)
    py = root / "bin" / "python"
    proc = subprocess.run(
        [
            str(py),
            "-m",
            "pip",
            "install",
            "--quiet",
            "--disable-pip-version-check",
            "--no-deps",
            "rcb4==0.1.6",
            "numpy",
            "pyserial",
        ],
        capture_output=True,
        text=True,
        timeout=100,
    )
    if proc.returncode != 0:
        if any(h in proc.stderr for h in NETWORK_HINTS):
            pytest.skip(f"PyPI unreachable, cannot install rcb4 0.1.6: {proc.stderr[-300:]}")
        pytest.fail(f"pip failed: {proc.stderr[-2000:]}")
    return py


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
