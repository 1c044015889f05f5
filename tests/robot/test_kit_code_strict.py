"""Kit codes: a typed ``kxr:CODE`` is read strictly (every part, once, in range), a project
title leniently (Kondo's titles wrap and garble the code), with one grammar."""

from __future__ import annotations

from pathlib import Path

import pytest
from click.testing import CliRunner

from rcb4hv.cli.main import cli
from rcb4hv.cli.robot_cmd import KIT_EXAMPLES
from rcb4hv.errors import RobotModelError
from rcb4hv.hth4 import save_project
from rcb4hv.hth4.newproject import new_project
from rcb4hv.robot.builtin import load_robot
from rcb4hv.robot.kit import parse_kit_code

# (typed code, the part the error must name): each was read as another code with exit 0
BAD = [
    ("kxr:L2L9A3", "L9: a humanoid takes L2, L4, L5 or L6"),  # was L2L5A3
    ("kxr:L2L5A9", "A9: a humanoid takes A3, A4, A5, A6 or A7"),  # was L2L5A7
    ("kxr:L2L5A3H9", "H9: a humanoid takes H, H1 or H2"),  # was H2
    ("kxr:L2W9L6A4H2", "W9: a humanoid takes W2 .* or W "),  # was L2L6A4H2W (wide hips)
    ("kxr:L2L5A3X", "X: not a kit option"),
    ("kxr:L2L5A3ZZ", "Z: not a kit option"),
    ("kxr:L6X", "X: not a kit option .*KXR-L6: it takes no options"),
    ("kxr:L4TQ", "Q: not a kit option .*KXR-L4T: it takes H, M"),
    ("kxr:L2L5A3H2GGG", "G: gripper given twice"),
    ("kxr:L2L5A3 H2G", "' H2G' after L2L5A3"),  # was L2L5A3, the rest dropped
    ("kxr:L2L5A3L6", r"L6: legs given twice \(L5, L6\)"),  # was L2L6A3
    ("kxr:L2L5A3NW", r"W: width given twice \(N, W\)"),
    ("kxr:L6A3", "A3: a KXR-L6 takes no axes per arm"),
    ("kxr:L4R2A5", "A5: a KXR-L4R takes A3"),
    ("kxr:L2L5A3T2", "T2: a humanoid takes T1"),
    ("kxr:ZZ9", "not a KXR kit code .*starts with the body"),
    ("kxr:", "not a KXR kit code"),
]


@pytest.mark.parametrize(("text", "part"), BAD)
def test_a_typed_code_is_read_strictly(text: str, part: str) -> None:
    with pytest.raises(RobotModelError, match=part):
        parse_kit_code(text, strict=True)
    with pytest.raises(RobotModelError, match=part):
        load_robot(text)  # robot show / export, --robot, project new


@pytest.mark.parametrize(("text", "part"), BAD[:4] + BAD[9:10])
def test_robot_show_refuses_a_code_it_would_misread(text: str, part: str) -> None:
    out = CliRunner().invoke(cli, ["robot", "show", text])
    assert out.exit_code == 1
    assert "RobotModelError" in out.output and text in out.output


def test_every_listed_kit_and_its_model_name_parse_strictly() -> None:
    names = {code for _, code, _ in KIT_EXAMPLES} | {"kxr:L4R2A3G", "kxr:L4TM", "kxr:L4TH"}
    for text in sorted(names):
        loose, strict = parse_kit_code(text), parse_kit_code(text, strict=True)
        assert strict == loose, text
        model = load_robot(text)
        assert parse_kit_code(model.name, strict=True) is not None  # kxr:L2L6A7H2GW etc.
    assert parse_kit_code("kxr:l2gl6a7h2w", strict=True).width == "wide"  # case is free


@pytest.mark.parametrize(
    ("title", "fields"),
    [
        ("Hello_KXR-L2GH(V1.0)", ("humanoid", "L2GH", None, None, 2, True, False, "standard")),
        ("Hello_KXR-L2W2L6A4h2", ("humanoid", "L2W2L6A4H2", 6, 4, 2, False, True, "standard")),
        ("Hello_KXR-L4T(V1.1)-l4th", ("L4T", "L4T", None, None, None, False, False, "standard")),
        ("KXR-L2GL6A7H2W", ("humanoid", "L2GL6A7H2W", 6, 7, 2, True, False, "wide")),
        ("Hello_kxrl2l2a6h2g", ("humanoid", "L2L2A6H2G", 2, 6, 2, True, False, "standard")),
        ("Hello_kxra6g", ("humanoid", "A6G", 2, 6, None, True, False, "standard")),
        ("KXR-R4LL(V1.2)", ("R4LL", "R4LL", None, None, None, False, False, "standard")),
        ("Hello_kxrl4nh4", ("L4N", "L4NH4", None, None, 4, False, False, "standard")),
        ("Hello_kxrl4tm", ("L4T", "L4TM", None, None, None, False, False, "standard")),
        ("KXR-L2W2L6A6H2N", ("humanoid", "L2W2L6A6H2N", 6, 6, 2, False, True, "narrow")),
        ("Hello_KXR-l4r2a3g", ("L4R", "L4R2A3G", None, 3, None, True, False, "standard")),
    ],
)
def test_titles_stay_lenient(title: str, fields: tuple[object, ...]) -> None:
    code = parse_kit_code(title)
    assert code is not None
    got = (code.family, code.code, code.legs, code.arms, code.head, code.gripper, code.wheels)
    assert (*got, code.width) == fields


def test_the_lenient_reading_keeps_what_it_can() -> None:
    """A title keeps its loose reading (the code up to the first character no option reads,
    the last of a repeated option); the same text typed is an error."""
    loose = parse_kit_code("Hello_KXR-L2L5A3X(V1.0)")
    assert loose is not None and (loose.code, loose.arms, loose.unknown) == ("L2L5A3X", 3, ("X",))
    twice = parse_kit_code("kxr:L2L5A3L6")
    assert twice is not None and twice.legs == 6
    assert parse_kit_code("HAC-KXR") is None and parse_kit_code("Hello_KHR3(V2.3)") is None
    with pytest.raises(RobotModelError, match="not a KXR kit code"):
        parse_kit_code("Hello_KXR-L6(V1.0)", strict=True)  # a title is no typed code


def test_robot_detect_reads_its_robot_option_strictly(tmp_path: Path) -> None:
    path = tmp_path / "l6.h4p"
    save_project(new_project(load_robot("kxr:L6")), path)
    out = CliRunner().invoke(cli, ["robot", "detect", str(path), "--robot", "kxr:L6Q"])
    assert out.exit_code == 1 and "Q: not a kit option" in out.output
    ok = CliRunner().invoke(cli, ["robot", "detect", str(path), "--robot", "kxr:L6"])
    assert ok.exit_code == 0, ok.output
