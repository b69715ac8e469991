"""closedloop sweep on a real 2-worker LocalCluster.

References: each row equals a direct single-process run of the same config, seed and
predictor (closedloop.simulate); a failing run is an error row and the rest go on; the
same grid run again submits nothing (the engine's resume, tested in tests/batch).
"""

import pytest

pytest.importorskip("distributed")

from closedloop import simulate  # noqa: E402
from closedloop.cli import main  # noqa: E402
from closedloop.config import save_config  # noqa: E402
from closedloop.sweep import load_grid, override, sweep  # noqa: E402

from .conftest import small  # noqa: E402

GRID = """
config = "small.toml"
duration = 0.05
seeds = [0, 1]
predictors = ["none"]

[[overrides]]
name = "base"

[[overrides]]
name = "gain 0.3"
"loop.gain" = 0.3

[[overrides]]
name = "late"
"loop.delay" = 0.05
"loop.gain" = 0.02
"""


def test_sweep_rows_resume_and_errors(tmp_path, capsys):
    save_config(small(), tmp_path / "small.toml")
    (tmp_path / "grid.toml").write_text(GRID)
    grid = load_grid(tmp_path / "grid.toml")
    rows, report = sweep(grid, tmp_path / "out", n_workers=2, threads_per_worker=1,
                         progress=False)
    assert report.n_specs == 6 and report.n_ok == 4 and report.n_error == 2
    ok = {(r["override"], r["seed"]): r for r in rows if r["status"] == "ok"}
    direct = simulate(override(small(), {"loop.gain": 0.3}), 0.05, seed=1, progress=False)
    assert ok[("gain 0.3", 1)]["strehl_peak_mean"] == direct.summary()["strehl_peak_mean"]
    errors = [r for r in rows if r["status"] == "error"]
    assert {r["override"] for r in errors} == {"late"}  # 50 frames: no command arrives
    assert "must be longer than" in errors[0]["error_message"]
    assert (tmp_path / "out" / "sweep.parquet").is_file()
    # again: nothing to do, no cluster; the 2 error rows make the exit status 1 (what the
    # first run printed, e.g. a worker-wait notice on a loaded machine, is read away first)
    capsys.readouterr()
    assert main(["sweep", str(tmp_path / "grid.toml"), "--out", str(tmp_path / "out"),
                 "--quiet"]) == 1
    captured = capsys.readouterr()
    assert "6 already done, 0 ran" in captured.out
    # the Marechal caveat once, when an SR peak is below 0.3 (where exp(-sigma^2) is no
    # image's Strehl: test_physics checks it against the FFT-PSF only above)
    lowest = min(r["strehl_peak_mean"] for r in rows if r["status"] == "ok")
    notes = [ln for ln in captured.out.splitlines() if ln.startswith("note: SR = exp(")]
    assert len(notes) == (1 if lowest < 0.3 else 0)
    table = tmp_path / "out" / "sweep.csv"
    assert captured.err == f"closedloop sweep: 2 of 6 runs failed; see {table}\n"


def test_a_grid_with_an_unstable_override_is_refused_before_any_run(tmp_path, capsys):
    # loop.gain 9 with table1's half-frame delay: stable only for gain < 2 (servo law)
    save_config(small(), tmp_path / "small.toml")
    (tmp_path / "g.toml").write_text(GRID.replace('"loop.delay" = 0.05\n"loop.gain" = 0.02',
                                                  '"loop.gain" = 9.0'))
    assert main(["sweep", str(tmp_path / "g.toml"), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert "grid override 'late'" in err and "stable for gain < 2.0000" in err, err
    assert not (tmp_path / "o").exists()


def test_bad_grid(tmp_path, capsys):
    (tmp_path / "g.toml").write_text('preset = "table1"\nseed = [1]\n')
    assert main(["sweep", str(tmp_path / "g.toml"), "--out", str(tmp_path / "o")]) == 2
    assert "unknown key `seed`" in capsys.readouterr().err
    with pytest.raises(ValueError, match="unknown key `loop.gian`"):
        override(small(), {"loop.gian": 0.1})


def test_a_fifo_as_grid_file_is_named_not_said_missing(tmp_path):
    import os

    # round 5: `closedloop sweep fifo.toml` said "does not exist"
    os.mkfifo(tmp_path / "grid.toml")
    with pytest.raises(FileNotFoundError, match="is not a regular file"):
        load_grid(tmp_path / "grid.toml")
