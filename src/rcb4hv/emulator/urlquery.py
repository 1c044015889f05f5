"""The query of an emulator URL (``rcb4emu://?speed=10&rom=img.bin``, ``icsemu://?ids=0,1``):
one value per setting. A setting given twice (``?speed=10&speed=0.001``) is a mistake the
URL's reader cannot settle (the last one used to win in silence), so it is refused."""

from __future__ import annotations

import urllib.parse

__all__ = ["query_settings"]


def query_settings(query: str) -> dict[str, str]:
    """``{name: value}`` of ``query`` (blank values kept); ValueError naming a setting given
    more than once."""
    settings: dict[str, str] = {}
    for key, value in urllib.parse.parse_qsl(query, keep_blank_values=True):
        if key in settings:
            raise ValueError(
                f"{key} is given twice ({settings[key]!r} and {value!r}): give it once"
            )
        settings[key] = value
    return settings
