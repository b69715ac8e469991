"""closedloop commands given another program's file say what it is.

Round 46 PART b (hidden adversary, the command lines): `closedloop info` / `export` given
a modalinfo log, a config or the run's own AOT export said "not an HDF5 closedloop result
(Unable to synchronously open file (file signature not found))" (F37, F38, F40, F43, F74,
F78); a sweep grid given as `--config` was "unknown key `duration` in the config" (G04,
G05); a config given as the grid "unknown key `dms`" (F75); a grid's `config = "run.h5"`
"`path` must end in .toml or .json" - no grid key is `path` (F76). Reference: what each
file is, by the program that writes it (modalinfo.io.save, closedloop's save_config).
"""

from __future__ import annotations

import numpy as np
import pytest

from closedloop import presets
from closedloop.config import load_config, save_config
from closedloop.result import SimulationResult
from closedloop.sweep import load_grid
from modalinfo.io import save
from modalinfo.telemetry import ModalLog


def _log():
    rng = np.random.default_rng(0)
    return ModalLog(rng.standard_normal((200, 5)), rate=1000.0, modes=range(2, 7))


@pytest.mark.parametrize("name, fmt, what", [
    ("log.npz", "npz", "an NPZ file, a telemetry log?"),
    ("log.h5", "hdf5", "an HDF5 file, a telemetry log?"),
    ("log.fits", "aot", "an AOT file"),
])
def test_result_load_names_a_log(tmp_path, name, fmt, what):
    path = tmp_path / name
    save(_log(), path, fmt=fmt)
    with pytest.raises(ValueError) as info:
        SimulationResult.load(path)
    message = str(info.value)
    assert "closedloop result" in message and f"it is {what}" in message
    assert "Unable to synchronously open" not in message


def test_result_load_names_a_config(tmp_path):
    path = save_config(presets.get("kaos"), tmp_path / "k.toml")
    with pytest.raises(ValueError, match="it is a closedloop config"):
        SimulationResult.load(path)


def test_grid_as_config_named(tmp_path):
    path = tmp_path / "g.toml"
    path.write_text('preset = "kaos"\nduration = 0.02\nseeds = [0]\n', encoding="utf-8")
    with pytest.raises(ValueError, match="is a closedloop sweep grid, for `closedloop "
                                         "sweep GRID`, not a closedloop config"):
        load_config(path)


def test_config_as_grid_named(tmp_path):
    path = save_config(presets.get("kaos"), tmp_path / "k.toml")
    with pytest.raises(ValueError, match=r'is a closedloop config, not a sweep grid: name '
                                         r'it in a grid file, config = "k.toml"'):
        load_grid(path)


@pytest.mark.parametrize("value", ['"run.h5"', "5"])
def test_grid_config_of_another_kind_names_the_key(tmp_path, value):
    path = tmp_path / "g.toml"
    path.write_text(f"config = {value}\nduration = 0.02\n", encoding="utf-8")
    with pytest.raises(ValueError, match="grid `config` must name a .toml or .json file"):
        load_grid(path)
