"""Every exception rcb4hv raises lives under rcb4hv.errors (and is imported from there); the
CLI prints each as one line."""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import subprocess
import sys

import pytest

import rcb4hv
from rcb4hv import errors
from rcb4hv.cli._util import error_line, handle_errors


def _modules() -> list[str]:
    names = []
    for info in pkgutil.walk_packages(rcb4hv.__path__, "rcb4hv."):
        names.append(info.name)
    return names


def test_every_exception_class_is_defined_in_rcb4hv_errors() -> None:
    strays = []
    for name in _modules():
        try:
            module = importlib.import_module(name)
        except ImportError:  # an optional extra (plot) that is not installed
            continue
        for attr, obj in vars(module).items():
            if (
                inspect.isclass(obj)
                and issubclass(obj, BaseException)
                and obj.__module__.startswith("rcb4hv")
                and obj.__module__ != "rcb4hv.errors"
                and not attr.startswith("_")
            ):
                strays.append(f"{name}.{attr}")
    assert strays == []


def test_every_public_error_is_an_rcb4_error() -> None:
    for name in errors.__all__:
        cls = getattr(errors, name)
        assert issubclass(cls, errors.Rcb4Error), name


@pytest.mark.parametrize(
    ("path", "name"),
    [
        ("rcb4hv.asm", "AsmError"),
        ("rcb4hv.client", "CommandNotAllowedError"),
        ("rcb4hv.client", "VerifyError"),
        ("rcb4hv.hth4", "Hth4FormatError"),
        ("rcb4hv.emulator.events", "CommandError"),
        ("rcb4hv.rom", "Motion"),
        ("rcb4hv.rom.image", "ServoConfig"),
    ],
)
def test_old_aliases_are_gone(path: str, name: str) -> None:
    """Each error is imported from rcb4hv.errors, each class by its one name (the aliases
    left from renames were dropped; the changelog lists them)."""
    assert not hasattr(importlib.import_module(path), name)


def test_modules_do_not_re_export_errors() -> None:
    """No module but rcb4hv.errors lists an error class in its ``__all__``."""
    listed = []
    for name in _modules():
        try:
            module = importlib.import_module(name)
        except ImportError:  # an optional extra (plot) that is not installed
            continue
        for attr in getattr(module, "__all__", ()):
            obj = getattr(module, attr, None)
            if inspect.isclass(obj) and issubclass(obj, BaseException) and name != "rcb4hv.errors":
                listed.append(f"{name}.{attr}")
    assert listed == []


def test_builtin_bases_are_kept() -> None:
    assert issubclass(errors.AsmError, ValueError)
    assert issubclass(errors.Hth4FormatError, ValueError)
    assert issubclass(errors.CommandNotAllowedError, PermissionError)
    assert issubclass(errors.VerifyError, errors.ProtocolError)
    e = errors.AsmError("bad", 3, 7)
    assert (str(e), e.line, e.column) == ("line 3, column 7: bad", 3, 7)


def test_cli_prints_one_line_for_a_simulation_error(capsys: pytest.CaptureFixture[str]) -> None:
    @handle_errors
    def command() -> None:
        raise errors.SimulationError("board refused MOVE RAM[0000h] <- #00 00")

    with pytest.raises(SystemExit) as exc:
        command()
    assert exc.value.code == 1
    err = capsys.readouterr().err
    assert err == "error: board refused MOVE RAM[0000h] <- #00 00 (SimulationError)\n"
    assert error_line(errors.NakError("")) == "error: NakError"


def test_main_turns_an_unhandled_rcb4_error_into_one_line() -> None:
    # a command module without @handle_errors: main() still prints one line, no traceback
    code = (
        "import click, sys\n"
        "from rcb4hv.cli import main\n"
        "from rcb4hv.errors import SimulationError\n"
        "@main.cli.command('boom')\n"
        "def boom():\n"
        "    raise SimulationError('image does not boot')\n"
        "sys.argv = ['rcb4hv', 'boom']\n"
        "main.main()\n"
    )
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert r.returncode == 1
    assert r.stderr == "error: image does not boot (SimulationError)\n"
    assert "Traceback" not in r.stderr
