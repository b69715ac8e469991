"""Adversarial round 13, PART b: closedloop's command lines with hand-edited files.

References: the files each test writes (an empty TOML file; a grid naming both a preset
and a config file, two bases where a grid has one) and the documented scope of
``closedloop config``'s options (``--duration`` and the estimate belong together;
``--fmt`` / ``--out`` print the config). Rows of docs/ADVERSARIAL.md "Round 13 PART b".
Each test fails on the code before its fix.
"""

from __future__ import annotations

import pytest

from closedloop.cli import main
from closedloop.sweep import load_grid


def _status(argv) -> int:
    try:
        return main([str(a) for a in argv])
    except SystemExit as exc:
        return exc.code


def test_empty_config_file_is_named_empty(tmp_path, capsys):
    path = tmp_path / "c.toml"
    path.write_text("")
    assert _status(["config", "--config", path, "--estimate"]) == 2
    err = capsys.readouterr().err
    assert "is empty" in err and "layers" not in err


def test_grid_with_preset_and_config_is_refused(tmp_path):
    (tmp_path / "base.toml").write_text("")
    grid = tmp_path / "g.toml"
    grid.write_text('preset = "kaos"\nconfig = "base.toml"\nduration = 0.01\n')
    with pytest.raises(ValueError, match="`preset` or `config`, not both"):
        load_grid(grid)


@pytest.mark.parametrize("argv, needle", [
    (["config", "--duration", "5"], "--duration applies to --estimate"),
    (["config", "--estimate", "--fmt", "json"], "--estimate prints"),
])
def test_config_refuses_options_its_action_ignores(capsys, argv, needle):
    assert _status(argv) == 2
    err = capsys.readouterr().err
    assert needle in err and err.count("\n") == 1


def test_config_estimate_duration_still_works(capsys):
    assert _status(["config", "--estimate", "--duration", "0.5"]) == 0
    assert ", 0.5 s: " in capsys.readouterr().out


@pytest.mark.parametrize("text, needle", [
    ("sed = 0\n", "(did you mean `seed`?)"),  # a letter left out
    ("[loop]\ngian = 0.3\n", "(did you mean `gain`?)"),  # two letters swapped
    ("[feild]\nsize = 1.0\n", "(did you mean `field`?)"),
])
def test_misspelt_config_key_names_the_key_meant(tmp_path, text, needle):
    from closedloop.config import load_config

    path = tmp_path / "c.toml"
    path.write_text(text)
    with pytest.raises(ValueError) as info:
        load_config(path)
    assert needle in str(info.value)


def test_unrelated_key_gets_no_guess(tmp_path):
    from closedloop.config import load_config

    path = tmp_path / "c.toml"
    path.write_text("bogus = 1\n")
    with pytest.raises(ValueError, match="unknown key `bogus`") as info:
        load_config(path)
    assert "did you mean" not in str(info.value)


def test_misspelt_grid_key_names_the_key_meant(tmp_path):
    grid = tmp_path / "g.toml"
    grid.write_text("seed = [0, 1]\n")
    with pytest.raises(ValueError, match=r"\(did you mean `seeds`\?\)"):
        load_grid(grid)
