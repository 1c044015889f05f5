"""The CLI's tables line up in a terminal with Japanese names (two columns a character)."""

from __future__ import annotations

import pytest

from rcb4hv.cli._util import display_width, print_table


def test_display_width_counts_wide_characters_twice() -> None:
    assert display_width("knee") == 4
    assert display_width("右膝") == 4
    assert display_width("右肩（ピッチ）") == 14  # full-width parentheses are wide too
    assert display_width("ｶﾀｶﾅ") == 4  # half-width katakana are narrow


def test_columns_after_a_japanese_name_line_up(capsys: pytest.CaptureFixture[str]) -> None:
    print_table(["index", "servo name", "joint"], [[2, "右肩（ピッチ）", "a"], [12, "knee", "b"]])
    lines = capsys.readouterr().out.splitlines()
    starts = {display_width(line[: line.index(j)]) for line, j in zip(lines[2:], "ab", strict=True)}
    assert len(starts) == 1  # the third column starts in the same terminal column
    assert lines[2].startswith("    2  右肩") and lines[3].startswith("   12  knee")
