r"""A config given as a sweep grid: the hint's ``config = "..."`` line is valid TOML (fix49-c).

Round 46 PART b, F75 made ``load_grid`` say "name it in a grid file, config = "NAME"",
the name pasted raw between quotes: a name holding ``"``, a backslash, a newline or an
ANSI escape gave a line TOML refuses or reads as another name (stop 55's note, item
2). Reference: ``tomllib`` (the standard library's TOML reader) reads the pasted line
back to the file's name, and a grid file holding it names the config.
"""

from __future__ import annotations

import os
import re
import tomllib

import pytest

from closedloop import presets
from closedloop.config import save_config
from closedloop.sweep import load_grid

NAMES = ['q"uote.toml', "back\\slash.toml", "new\nline\tt\x1b[1m\u2028.toml", "k.toml"]


def _hint_line(path) -> str:
    with pytest.raises(ValueError, match="is a closedloop config, not a sweep grid") as err:
        load_grid(path)
    message = str(err.value)
    assert len(message.splitlines()) == 1 and message.isprintable(), message
    (line,) = re.findall(r"grid file, (config = .*) \(`closedloop sweep --help`", message)
    return line


@pytest.mark.parametrize("name", NAMES)
def test_the_hint_line_reads_back_as_the_name(tmp_path, name):
    path = save_config(presets.get("kaos"), tmp_path / name)
    line = _hint_line(path)
    assert tomllib.loads(line) == {"config": name}
    grid = tmp_path / "grid.toml"
    grid.write_text(line + "\n", encoding="utf-8")
    assert load_grid(grid)["config"] == os.path.abspath(path)


def test_a_name_that_is_not_utf8_is_said(tmp_path):
    name = os.fsdecode(b"k\xe9.toml")
    path = save_config(presets.get("kaos"), tmp_path / name)
    with pytest.raises(ValueError, match=r"not a sweep grid: name it in a grid file, config = "
                                         r"<this file's name>, once renamed: its name "
                                         r"'k\\xe9.toml' is not UTF-8"):
        load_grid(path)
