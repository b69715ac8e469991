"""Absurd inputs found in issue 27's adversarial round: refused in one line, before work.

References: the rules as documented where they live (``closedloop/config.py`` bounds
with their reasons, ``closedloop/cli.py``, ``closedloop/sweep.py``); the HDF5 integer
range (a seed the result file cannot store, 2**70, ran to the end and was then lost);
float arithmetic (1e308 s / 0.5 ms is infinite); a refusal is one line on stderr with
exit 2 and no simulation started (``simulate`` replaced by a failing stand-in).
"""

from __future__ import annotations

import pytest

import closedloop.simulation
from closedloop import presets
from closedloop.cli import main
from closedloop.config import SimulationConfig, load_config
from closedloop.resources import ResourceError, estimate
from closedloop.sweep import sweep_specs


@pytest.fixture
def no_simulation(monkeypatch):
    def fail(*args, **kwargs):
        raise AssertionError("a simulation started before the refusal")

    monkeypatch.setattr(closedloop.simulation, "simulate", fail)
    monkeypatch.setattr(closedloop.simulation, "LoopModel", fail)


def _one_line(capsys, needle):
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and needle in err and "Traceback" not in err, err
    return err


def _kaos(**top):
    d = presets.get("kaos").to_dict()
    d.update(top)
    return d


def test_a_seed_the_result_cannot_store_is_refused():
    with pytest.raises(ValueError, match=r"`seed` must be an int <= 9223372036854775807"):
        SimulationConfig.from_dict(_kaos(seed=2**70))
    assert SimulationConfig.from_dict(_kaos(seed=2**63 - 1)).seed == 2**63 - 1


@pytest.mark.parametrize("flag", ["--seed", "--train-seed"])
def test_cli_seeds_beyond_int64_are_refused(capsys, no_simulation, flag):
    assert main(["run", "--preset", "kaos", flag, str(2**70), "--duration", "0.03",
                 "--quiet"]) == 2
    _one_line(capsys, f"{flag} must be an int in [0, 2**63 - 1]")


def test_a_duration_of_more_frames_than_a_float_counts_is_refused(capsys, no_simulation):
    for argv in (["run", "--preset", "kaos", "--duration", "1e308", "--quiet"],
                 ["config", "--preset", "kaos", "--estimate", "--duration", "1e308"]):
        assert main(argv) == 2
        _one_line(capsys, "1e+15 frames")
    with pytest.raises(ResourceError, match="at most 1e\\+15 frames"):
        estimate(presets.get("kaos"), 1e308)


def test_a_shack_hartmann_noise_beyond_its_field_is_refused():
    d = _kaos()
    d["wfss"][0]["noise"] = 1e10
    with pytest.raises(ValueError, match=r"`wfss\[0\].noise` must be <= 10 arcsec RMS"):
        SimulationConfig.from_dict(d)


def test_compare_refuses_a_predictor_named_twice(capsys, no_simulation):
    assert main(["compare", "--preset", "kaos", "--predictors", "none,arma,none",
                 "--duration", "0.03", "--quiet"]) == 2
    _one_line(capsys, "--predictors names 'none' twice")


@pytest.mark.parametrize(("grid", "needle"), [
    ({"preset": "kaos", "seeds": [0, 0]}, "grid `seeds` names 0 twice"),
    ({"preset": "kaos", "predictors": ["none", "none"]}, "grid `predictors` names 'none' twice"),
    ({"preset": "nonexistent"}, "grid `preset` must be one of"),
])
def test_sweep_grids_that_would_merge_runs_or_misname_are_refused(grid, needle):
    with pytest.raises(ValueError, match=needle.replace("`", ".").replace("'", ".")):
        sweep_specs(grid)


def test_a_config_file_that_is_not_text_is_named(tmp_path):
    path = tmp_path / "c.toml"
    path.write_bytes(b"\x00\x01\xff garbage")
    with pytest.raises(ValueError, match=r"c.toml': not a TOML text file \(not UTF-8\)"):
        load_config(path)


def test_the_sensitivity_study_refuses_a_bad_duration_in_one_line(capsys):
    # simulate's own check refuses it at the first run, before any set-up
    from closedloop.studies.sensitivity import main as sensitivity_main

    assert sensitivity_main(["--duration", "-1"]) == 2
    _one_line(capsys, "sensitivity: error: `duration` must be > 0")


def test_a_delay_that_is_no_whole_internal_step_is_refused_at_load():
    # 0.333 ms of a 0.5 ms frame is 0.666 frames: no n <= 64 makes it whole
    d = _kaos()
    d["loop"]["delay"] = 0.000333
    with pytest.raises(ValueError, match=r"`loop.delay` must be a multiple of time_step / n"):
        SimulationConfig.from_dict(d)
    d["loop"]["delay"] = 0.0005 / 3  # a third of a frame: 3 internal steps
    assert SimulationConfig.from_dict(d).loop.oversampling == 3


def test_the_memory_of_a_huge_field_grid_is_blamed_on_the_grid():
    # 10001 x 10001 directions: the logs' rows are the directions, not the modes
    d = _kaos()
    d["field"]["n_points"] = 10001
    est = estimate(SimulationConfig.from_dict(d), 0.03)
    assert est.largest == "logs" and est.driver == "field.n_points"
    assert estimate(presets.get("kaos"), 100.0).drivers["logs"] == "duration"
