"""``--quiet`` of reorder and forecast: what its help says, what it keeps off stdout (round 38).

References: argparse's help text (what the option needs, as fix56-c's helper words it for
each command) and the output streams captured by pytest's ``capsys`` (``--quiet`` prints
nothing on stdout on success, as ``convert`` / ``synth``: fix56-c); the JSON file
``--out`` writes, read back with ``json.load``. Each test names the plant of
docs/MUTATION.md's round 38 it fails with.
"""

import json

import pytest

from modalinfo.cli import main

from .conftest import write_small_log


@pytest.mark.parametrize(("command", "needs"), [("reorder", "--out FILE.json"),
                                                ("forecast", "--out DIR")])
def test_quiet_help_names_the_output_it_needs(capsys, command, needs):
    """R38-SH2: the help says which output --quiet needs."""
    with pytest.raises(SystemExit):
        main([command, "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert f"needs {needs}, where the results go" in text


def test_reorder_quiet_keeps_the_stability_summary_off_stdout(tmp_path, capsys):
    """R38-RO4: with --stability the summary is not printed under --quiet."""
    log = write_small_log(tmp_path / "s.npz", 300)
    loud, silent = tmp_path / "loud.json", tmp_path / "silent.json"
    base = ["reorder", str(log), "--method", "variance", "--resamples", "0",
            "--pupil-pixels", "16", "--stability", "100"]
    assert main([*base, "--out", str(loud)]) == 0
    assert "ordering written" in capsys.readouterr().out  # the loud run prints
    assert main([*base, "--out", str(silent), "--quiet"]) == 0
    assert capsys.readouterr().out == ""
    first = json.loads(loud.read_text(encoding="utf-8"))
    second = json.loads(silent.read_text(encoding="utf-8"))
    assert first["labels"] == second["labels"]
