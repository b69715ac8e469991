"""A sweep grid's ``config`` ending in ``.TOML`` is accepted as ``.toml`` (review29).

Round 29 L3 (closedloop/sweep.py:128, round 46 PART b F76): the refusal "grid `config`
must name a .toml or .json file" compares the suffix in any case. Planted as written, it
passed every test, whose configs were lower-case. References, outside the package: the
refusal's own words (".toml or .json", no case), the file the grid names written here by
``closedloop.config.save_config`` and re-read by ``tomllib``; ``os.path`` for the path.
"""

import os
import tomllib

import pytest

from closedloop import presets
from closedloop.config import save_config
from closedloop.sweep import load_grid


def test_an_upper_case_config_suffix_is_accepted(tmp_path):
    config = save_config(presets.get("kaos"), tmp_path / "K.TOML")
    assert tomllib.loads(config.read_text(encoding="utf-8"))
    grid = tmp_path / "grid.toml"
    grid.write_text('config = "K.TOML"\nduration = 0.02\nseeds = [0]\n', encoding="utf-8")
    assert load_grid(grid)["config"] == os.path.abspath(tmp_path / "K.TOML")


def test_another_suffix_is_still_refused(tmp_path):
    grid = tmp_path / "grid.toml"
    grid.write_text('config = "k.yaml"\nduration = 0.02\nseeds = [0]\n', encoding="utf-8")
    with pytest.raises(ValueError, match=r"grid `config` must name a \.toml or \.json file"):
        load_grid(grid)
