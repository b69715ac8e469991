"""The ``closedloop`` command from the user's side: exit codes, one-line errors, files
untouched, and numbers equal to the library's (reference: the library call itself)."""

import subprocess
import sys

import numpy as np
import pytest

from closedloop import SimulationResult, simulate
from closedloop.cli import main
from closedloop.config import save_config

from .conftest import small


@pytest.fixture(scope="module")
def config_file(tmp_path_factory):
    path = tmp_path_factory.mktemp("cfg") / "small.toml"
    save_config(small(), path)
    return path


def test_run_writes_the_same_result_as_the_library(config_file, tmp_path, capsys):
    out = tmp_path / "run.h5"
    code = main(["run", "--config", str(config_file), "--duration", "0.05", "--seed", "3",
                 "--out", str(out), "--quiet"])
    assert code == 0
    line = capsys.readouterr().out.strip()
    assert line.startswith("none: SR peak") and "steps/s" in line
    saved = SimulationResult.load(out)
    direct = simulate(small(), 0.05, seed=3, progress=False)
    np.testing.assert_array_equal(saved.residual_variance, direct.residual_variance)
    assert f"{direct.summary()['strehl_peak_mean']:.3f}" in line
    # no overwrite unasked, checked before any work; the file is untouched
    before = out.read_bytes()
    code = main(["run", "--config", str(config_file), "--duration", "0.05", "--out", str(out)])
    assert code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--overwrite" in err
    assert out.read_bytes() == before


def test_info_and_config(config_file, tmp_path, capsys):
    out = tmp_path / "r.h5"
    simulate(small(), 0.03, seed=1, progress=False).save(out)
    assert main(["info", str(out)]) == 0
    text = capsys.readouterr().out
    assert "seed 1" in text and "log dm0.pol: 30 x 35" in text
    assert main(["config", "--preset", "table1"]) == 0
    toml = capsys.readouterr().out
    assert "d_over_r0 = 26.0" in toml
    target = tmp_path / "t1.toml"
    assert main(["config", "--preset", "table1", "--out", str(target)]) == 0
    assert main(["config", "--preset", "table1", "--out", str(target)]) == 2
    assert "exists" in capsys.readouterr().err


@pytest.mark.parametrize("argv,needle", [
    (["run", "--predictor", "kalman"], "--predictor must be one of"),
    (["run", "--duration", "-1", "--quiet"], "--duration must be > 0"),
    (["run", "--out", "x.txt"], "--out 'x.txt': unsupported extension '.txt'; use .h5"),
    (["compare", "--predictors", "none,foo"], "--predictors must be"),
    (["info", "missing.h5"], "does not exist"),
    (["info", "."], "is a directory, not a saved run"),
    (["run", "--config", "nope.toml"], "does not exist"),
])
def test_errors_are_one_line_exit_2(argv, needle, capsys):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err and "Traceback" not in err


def test_bad_config_value_names_its_key(tmp_path, capsys):
    path = tmp_path / "bad.toml"
    text = "[loop]\ngain = -1.0\n"
    path.write_text(text)
    assert main(["run", "--config", str(path)]) == 2
    err = capsys.readouterr().err
    assert "loop.gain" in err


def test_compare_table(config_file, capsys):
    code = main(["compare", "--config", str(config_file), "--duration", "0.06",
                 "--predictors", "none,persistence,oracle", "--quiet"])
    assert code == 0
    lines = capsys.readouterr().out.strip().splitlines()
    # a last line "note: SR = exp(-sigma^2) (Marechal) is below 0.3 ..." when one SR peak is
    rows = {ln.split()[0]: ln.split() for ln in lines[2:] if not ln.startswith("note: ")}
    assert set(rows) == {"none", "persistence", "oracle"}
    lowest = min(float(r[1]) for r in rows.values())  # printed to 3 decimals
    noted = lines[-1].startswith("note: SR = exp(-sigma^2) (Marechal)")
    assert lowest <= 0.3 if noted else lowest >= 0.3
    assert rows["none"][1:4] == rows["persistence"][1:4]  # same run, bit for bit


def test_console_entry_point_module():
    proc = subprocess.run([sys.executable, "-m", "closedloop", "run", "--predictor", "x"],
                          capture_output=True, text=True)
    assert proc.returncode == 2 and proc.stderr.count("\n") == 1
