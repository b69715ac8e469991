"""Round 28 PART b: a grid's ``config`` that is a link to a device names the grid's file.

Reference: POSIX file types (``os.path.exists`` / ``Path.is_file`` of a link to
``/dev/null`` are True / False: a character device, not a regular file). A grid whose
``config = "cfg.toml"`` is such a link must be refused as "not a regular file" under the
name the user wrote, not as "`path` must end in .toml or .json; got '/dev/null'" (the
link resolved before the check, naming an argument the user never gave).
"""

import os

import pytest

from closedloop.sweep import _base, load_grid


@pytest.mark.skipif(not os.path.exists("/dev/null"), reason="needs /dev/null")
def test_config_link_to_a_device_refused_under_its_own_name(tmp_path):
    (tmp_path / "cfg.toml").symlink_to("/dev/null")
    grid_file = tmp_path / "grid.toml"
    grid_file.write_text('config = "cfg.toml"\nduration = 0.01\n')
    grid = load_grid(grid_file)
    with pytest.raises(FileNotFoundError, match=r"cfg\.toml' is not a regular file"):
        _base(grid)
