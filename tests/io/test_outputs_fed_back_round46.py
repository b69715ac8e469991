"""Outputs of the commands fed back as logs are named, not read as a corrupt CSV.

Round 46 PART b (hidden adversary, the command lines): a closedloop config written as
TOML (`closedloop config --out k.toml`) given to `modalinfo info` was "corrupt CSV file
'k.toml': ValueError: could not convert string 'seed' to float64" (F15), a sweep grid the
same, `closedloop sweep`'s sweep.csv "could not convert string 'base'" (F32, F61) and a
row of its rows/ folder "holds JSON (a result or config file?)" (G11).
Reference: what each file is, by the program that writes it (closedloop's own
`save_config` and the header `closedloop sweep` writes), and the refusal the JSON config
already had (round 21 PART b).
"""

from __future__ import annotations

import pytest

from modalinfo.io import LogFormatError, load

_CONFIG_TOML = 'name = "kaos"\nseed = 0\nwavelength = 6.3e-07\n\n[telescope]\ndiameter = 0.7\n'
_GRID_TOML = 'preset = "kaos"\nduration = 0.02\nseeds = [0]\n\n[[overrides]]\nname = "g"\n'
_SWEEP_CSV = ('"override","seed","predictor","status","averaged_from_s","closed"\n'
              '"base",0,"none","ok",0.004,true\n')


@pytest.mark.parametrize("name, text, what", [
    ("k.toml", _CONFIG_TOML, "a closedloop config"),
    ("grid.toml", _GRID_TOML, "a closedloop sweep grid"),
    ("sweep.csv", _SWEEP_CSV, "sweep.csv, the result table of `closedloop sweep`"),
    ("row.json", '{"override": "base", "seed": 0, "predictor": "none", "status": "ok", '
                 '"key": "ab"}', "a result row of `closedloop sweep`"),
])
def test_output_named_not_read_as_csv(tmp_path, name, text, what):
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    with pytest.raises(LogFormatError, match="not a log") as info:
        load(path)
    message = str(info.value)
    assert what in message and "corrupt CSV" not in message and "float64" not in message
    from modalinfo.io.formats import what_file  # closedloop info's words (F37-F43)

    assert what_file(path).startswith(what)


def test_closedloop_config_from_save_config_named(tmp_path):
    """The TOML that `closedloop config --out` writes, byte for byte (its own writer)."""
    closedloop_config = pytest.importorskip("closedloop.config")
    from closedloop import presets

    path = closedloop_config.save_config(presets.get("kaos"), tmp_path / "k.toml")
    with pytest.raises(LogFormatError, match=r"is a closedloop config, from `closedloop "
                                             r"config`, not a log"):
        load(path)


def test_toml_of_another_kind_still_not_a_csv(tmp_path):
    path = tmp_path / "pyproject.toml"
    path.write_text('[project]\nname = "x"\n', encoding="utf-8")
    with pytest.raises(LogFormatError, match=r"is a TOML file \(a config\?\), not a log"):
        load(path)
