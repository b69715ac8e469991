"""``closedloop sweep``: a bad grid or a folder in use is refused before any run; the
documented grid format is the one the code reads; ``export`` and ``info`` say what an
AOT file holds.

References: the grid rules as documented in ``closedloop/sweep.py`` (each refusal is
one line, exit 2, and no output folder is created); the grid format printed by
``--help`` (and copied in the README) is parsed by ``tomllib`` and run through
``sweep_specs``, whose spec count must be overrides x seeds x predictors as the format
says; the lock's holder is a live subprocess we start; the loops an export announces
are read back from the written file with ``aotpy`` (independently of the export code).
"""

from __future__ import annotations

import json
import socket
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

pytest.importorskip("distributed")

from closedloop.cli import main  # noqa: E402
from closedloop.config import save_config  # noqa: E402
from closedloop.sweep import GRID_HELP, load_grid, sweep_specs  # noqa: E402

from .conftest import small  # noqa: E402


def _example() -> str:
    """The TOML example of GRID_HELP, unindented."""
    import textwrap

    return textwrap.dedent(GRID_HELP.split("\n\n", 1)[1].split("\n\nRuns =", 1)[0])


def test_help_shows_a_grid_format_that_the_code_reads(tmp_path, capsys):
    with pytest.raises(SystemExit):
        main(["sweep", "--help"])
    out = capsys.readouterr().out
    for key in ("preset", "config", "duration", "seeds", "predictors", "budget_every",
                "[[overrides]]"):
        assert key in out
    text = _example()
    parsed = tomllib.loads(text)  # valid TOML as printed
    (tmp_path / "grid.toml").write_text(text)
    specs = sweep_specs(load_grid(tmp_path / "grid.toml"))
    n = len(parsed["overrides"]) * len(parsed["seeds"]) * len(parsed["predictors"])
    assert len(specs) == n == 8
    assert {s.labels["override"] for s in specs} == {"gain 0.3", "upper at 15 km"}
    readme = (Path(__file__).resolve().parents[2] / "README.md").read_text()
    assert text.strip() in readme  # the README shows the same format


@pytest.mark.parametrize("grid, needle", [
    ("seeds = [0, -1]", "grid `seeds` must be a non-empty list of ints >= 0"),
    ("seeds = []", "grid `seeds` must be a non-empty list"),
    ("predictors = []", "grid `predictors` must be a non-empty list"),
    ("predictors = ['none', 'tarot']", "'tarot' is not one of"),
    ("duration = -0.1", "grid `duration` must be > 0.0; got -0.1"),
    ("duration = nan", "grid `duration` must be finite; got nan"),
    ("duration = 'long'", "grid `duration` must be a real number; got 'long'"),
    ("budget_every = 0", "grid `budget_every` must be an int >= 1"),
    ("budget_every = 2.5", "grid `budget_every` must be an int >= 1"),
    ("[[overrides]]\n'loop.gian' = 0.2", "unknown key `loop.gian`"),
    ("[[overrides]]\n'dms.7.altitude' = 1.0", "unknown key `dms.7.altitude`"),
    ("[[overrides]]\nname = 'x'\n[[overrides]]\nname = 'x'\n'loop.gain' = 0.2",
     "the name 'x' is used twice"),
    ("overrides = {'loop.gain' = 0.2}", "grid `overrides` must be an array of tables"),
])
def test_bad_grids_are_refused_before_any_run(tmp_path, capsys, grid, needle):
    (tmp_path / "g.toml").write_text(grid + "\n")
    out = tmp_path / "out"
    assert main(["sweep", str(tmp_path / "g.toml"), "--out", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err, err
    assert not out.exists()


@pytest.mark.parametrize("argv, needle", [
    (["--memory-limit", "64MB"], "--memory-limit must be at least 384.00 MiB"),
    (["--workers", "0"], "--workers must be >= 1"),
    (["--worker-wait", "0"], "--worker-wait must be a number of seconds > 0"),
])
def test_bad_cluster_options_are_refused(tmp_path, capsys, argv, needle):
    (tmp_path / "g.toml").write_text("duration = 0.01\n")
    assert main(["sweep", str(tmp_path / "g.toml"), "--out", str(tmp_path / "o"),
                 *argv]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err, err
    assert not (tmp_path / "o").exists()


def test_a_folder_in_use_is_refused(tmp_path, capsys):
    save_config(small(), tmp_path / "small.toml")
    (tmp_path / "g.toml").write_text('config = "small.toml"\nduration = 0.01\n')
    out = tmp_path / "out"
    out.mkdir()
    # alive until killed (it waits on its stdin), not for a time the test might outlast
    holder = subprocess.Popen([sys.executable, "-c", "import sys; sys.stdin.read()"],
                              stdin=subprocess.PIPE)
    try:
        (out / ".lock").write_text(json.dumps({"pid": holder.pid,
                                               "host": socket.gethostname(),
                                               "command": "closedloop sweep"}))
        assert main(["sweep", str(tmp_path / "g.toml"), "--out", str(out)]) == 2
    finally:
        holder.kill()
        holder.wait(timeout=60)
        holder.stdin.close()
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "is in use by closedloop sweep" in err
    assert f"pid {holder.pid}" in err
    assert sorted(p.name for p in out.iterdir()) == [".lock"]


def test_export_lists_the_loops_of_the_file_and_info_names_pol_data(tmp_path, capsys):
    import aotpy

    from closedloop import simulate
    from modalinfo.cli import main as modalinfo_main

    run = simulate(small(), 0.005, seed=0, progress=False)
    run.save(tmp_path / "run.h5")
    assert main(["export", str(tmp_path / "run.h5"), str(tmp_path / "run.fits")]) == 0
    out = capsys.readouterr().out
    loops = [lp.uid for lp in aotpy.AOSystem.read_from_file(
        str(tmp_path / "run.fits")).loops]
    assert len(loops) > 2 * len(run.config.dms)  # residual, POL and reconstructor blocks
    assert f"{len(loops)} loops: " in out
    assert all(uid in out for uid in loops)
    assert modalinfo_main(["info", str(tmp_path / "run.fits"), "--loop", "dm0.pol"]) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("loop "))
    assert "pseudo-open-loop" in line and "not the loop's residual" in line
    assert modalinfo_main(["info", str(tmp_path / "run.fits"), "--loop", "dm0"]) == 0
    line = next(ln for ln in capsys.readouterr().out.splitlines() if ln.startswith("loop "))
    assert "pseudo-open-loop" not in line and "residual" in line


def test_a_grid_point_needing_more_memory_than_the_machine_is_refused(tmp_path, capsys):
    pytest.importorskip("closedloop.resources")  # the simulator's memory estimate
    (tmp_path / "g.toml").write_text('preset = "table1"\nduration = 0.01\n'
                                     '[[overrides]]\nname = "huge"\n'
                                     '"telescope.n_pixels" = 30000\n')
    assert main(["sweep", str(tmp_path / "g.toml"), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "grid override 'huge'" in err
    assert not (tmp_path / "o").exists()
