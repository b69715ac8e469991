"""closedloop.sweep: grids, specs, a worker's row and the sweep's table, without simulations.

Gaps found by mutation testing (docs/MUTATION.md, "closedloop/sweep.py"). The runs are
replaced by a recorder returning runs whose summary and budget are set in the test, so
every number of a row is known by construction. References, from outside the code:

- the grid format as documented (``GRID_HELP``, the module docstring): defaults
  (preset table1, 0.3 s, the base config's seed, predictor "none", no budget), runs =
  overrides x seeds x predictors, the rows' labels, dotted keys into the config's plain
  form (``closedloop config``'s);
- the key: "the SHA-256 of its resolved config, seed, predictor, duration and the
  package version" (module docstring), computed here with ``hashlib`` on the engine's
  canonical JSON;
- a row's on-axis budget: the term at the budget direction nearest (0, 0), picked here by
  hand from directions written in the test;
- the sweep's output: a CSV whose first columns are override, seed, predictor, status,
  read back with the csv module; an in-process Dask cluster (threads) runs the tasks.
"""

from __future__ import annotations

import csv
import hashlib
import math
from types import SimpleNamespace

import numpy as np
import pytest

from closedloop import presets
from closedloop.config import save_config
from closedloop.sweep import _apply, _base, load_grid, override, run_one, sweep, sweep_specs
from modalinfo.batch.engine import canonical_json, package_version


# ------------------------------------------------------------------ override
def test_override_changes_dotted_keys_of_lists_and_tables():
    base = presets.get("table1")
    cfg = override(base, {"loop.gain": 0.3, "layers.1.altitude": 15000.0,
                          "wfss.0.noise": 0.02})
    assert cfg.loop.gain == 0.3 and cfg.layers[1].altitude == 15000.0
    assert cfg.wfss[0].noise == 0.02
    assert cfg.layers[0] == base.layers[0] and cfg.dms == base.dms
    assert base.loop.gain != 0.3 and base.layers[1].altitude != 15000.0  # base unchanged
    assert override(base, {}) == base


def test_apply_sets_a_list_item_and_refuses_what_is_not_there():
    d = {"a": [1, {"b": 2}], "c": 3}
    _apply(d, "a.0", 5)
    _apply(d, "a.1.b", 6)
    assert d == {"a": [5, {"b": 6}], "c": 3}
    with pytest.raises(KeyError) as exc:
        _apply(d, "a.1.x", 1)
    assert exc.value.args[0] == "'x' is not among b"
    with pytest.raises(KeyError) as exc:
        _apply(d, "c.d", 1)
    assert exc.value.args[0] == "c is a value, not a table"


@pytest.mark.parametrize("key, why", [
    ("loop.gian", "'gian' is not among "),
    ("loop.gain.x", "loop.gain is a value, not a table"),
    ("dms.7.altitude", "list index out of range"),
    ("dms.x.altitude", "invalid literal for int() with base 10: 'x'"),
    # Python's "from the end": `layers.-1` changed table1's layer 1 (audit 9)
    ("layers.-1.altitude", "index -1 is negative; items count from 0"),
    ("layers.-1", "index -1 is negative; items count from 0"),
])
def test_override_names_the_key_and_why(key, why):
    with pytest.raises(ValueError) as exc:
        override(presets.get("table1"), {key: 1.0})
    msg = str(exc.value)
    assert msg.startswith(f"unknown key `{key}` ({why}") and msg.endswith(").")
    assert "\n" not in msg


def test_override_lists_the_table_keys_sorted():
    with pytest.raises(ValueError) as exc:
        override(presets.get("table1"), {"loop.gian": 1.0})
    keys = sorted(presets.get("table1").to_dict()["loop"])
    assert str(exc.value) == (f"unknown key `loop.gian` ('gian' is not among {', '.join(keys)}"
                              " (did you mean `gain`?)).")  # the hint: round 13 PART b


# ------------------------------------------------------------------ load_grid and base
def test_load_grid_reads_toml_and_resolves_config_beside_the_grid(tmp_path):
    (tmp_path / "sub").mkdir()
    save_config(presets.get("kaos"), tmp_path / "sub" / "k.toml")
    (tmp_path / "sub" / "g.toml").write_text('config = "k.toml"\nduration = 0.1\n',
                                             encoding="utf-8")
    grid = load_grid(str(tmp_path / "sub" / "g.toml"))
    assert grid == {"config": str((tmp_path / "sub" / "k.toml").resolve()), "duration": 0.1}
    assert _base(grid) == presets.get("kaos")


def test_load_grid_messages(tmp_path):
    missing = tmp_path / "none.toml"
    with pytest.raises(FileNotFoundError) as exc:
        load_grid(missing)
    assert str(exc.value) == f"grid file '{missing}' does not exist"
    with pytest.raises(FileNotFoundError):
        load_grid(tmp_path)  # a directory is not a grid file
    bad = tmp_path / "bad.toml"
    bad.write_text("duration = = 1\n")
    with pytest.raises(ValueError) as exc:
        load_grid(bad)
    assert str(exc.value).startswith(f"'{bad}': not valid TOML: ")
    unknown = tmp_path / "u.toml"
    unknown.write_text("zeta = 1\nalpha = 2\n")
    with pytest.raises(ValueError) as exc:
        load_grid(unknown)
    assert str(exc.value) == (f"'{unknown}': unknown key `alpha`; allowed: budget_every, config, "
                              "duration, overrides, predictors, preset, seeds")


def test_base_is_table1_by_default_and_names_a_bad_preset():
    assert _base({}) == presets.get("table1")
    assert _base({"preset": "mcao3"}) == presets.get("mcao3")
    with pytest.raises(ValueError) as exc:
        _base({"preset": "nope"})
    assert str(exc.value).startswith("grid `preset` must be one of table1")
    assert str(exc.value).endswith("; got 'nope'.")
    with pytest.raises(ValueError, match="grid `preset`"):
        _base({"preset": 3})


# ------------------------------------------------------------------ specs
def _key(payload):
    # the documented key, written here: SHA-256 of the version and the resolved run
    text = canonical_json([package_version(), "closedloop-sweep", payload])
    return hashlib.sha256(text.encode()).hexdigest()


@pytest.fixture
def no_memory_check(monkeypatch):
    import closedloop.resources as resources

    calls = []
    monkeypatch.setattr(resources, "check_resources",
                        lambda config, duration, oracle, budget: calls.append(
                            (config.loop.gain, duration, oracle, budget)))
    return calls


def test_specs_defaults(no_memory_check):
    (spec,) = sweep_specs({})
    base = presets.get("table1")
    assert spec.payload == {"config": base.to_dict(), "seed": base.seed, "predictor": "none",
                            "duration": 0.3, "budget_every": None}
    assert spec.labels == {"override": "base", "seed": base.seed, "predictor": "none",
                           "duration": 0.3}
    assert spec.key == _key(spec.payload) and len(spec.key) == 64
    assert no_memory_check == [(base.loop.gain, 0.3, False, False)]


def test_specs_are_overrides_times_seeds_times_predictors(no_memory_check):
    grid = {"preset": "table1", "duration": 1, "seeds": [4, 2],
            "predictors": ["none", "oracle"], "budget_every": 1,
            "overrides": [{"name": "g", "loop.gain": 0.3},
                          {"loop.gain": 0.2, "loop.leak": 0.01}, {}]}
    specs = sweep_specs(grid)
    base = presets.get("table1")
    names = ["g", "loop.gain=0.2, loop.leak=0.01", "base"]
    configs = [override(base, {"loop.gain": 0.3}),
               override(base, {"loop.gain": 0.2, "loop.leak": 0.01}), base]
    want = [(n, s, p) for n in names for s in (4, 2) for p in ("none", "oracle")]
    assert [(s.labels["override"], s.labels["seed"], s.labels["predictor"]) for s in specs] \
        == want
    for s in specs:
        i = names.index(s.labels["override"])
        assert s.payload == {"config": configs[i].to_dict(), "seed": s.labels["seed"],
                             "predictor": s.labels["predictor"], "duration": 1.0,
                             "budget_every": 1}
        assert isinstance(s.payload["duration"], float) and s.labels["duration"] == 1.0
        assert s.key == _key(s.payload)
    assert len({s.key for s in specs}) == 12
    # the memory check: every override, for each predictor (the oracle keeps its maps)
    assert no_memory_check == [(g, 1.0, o, True) for g in (0.3, 0.2, base.loop.gain)
                               for o in (False, True)]


def test_an_override_named_in_the_table_keeps_its_name_as_text(no_memory_check):
    (spec,) = sweep_specs({"overrides": [{"name": 7, "loop.gain": 0.3}]})
    assert spec.labels["override"] == "7"


@pytest.mark.parametrize("grid, message", [
    # validation.check_real's words, said of the grid's key (left26-twins)
    ({"duration": 0}, "grid `duration` must be > 0.0; got 0.0."),
    ({"duration": math.inf}, "grid `duration` must be finite; got inf."),
    ({"seeds": 3}, "grid `seeds` must be a non-empty list of ints >= 0; got 3"),
    ({"seeds": [True]}, "grid `seeds` must be a non-empty list of ints >= 0; got [True]"),
    ({"seeds": [1.0]}, "grid `seeds` must be a non-empty list of ints >= 0; got [1.0]"),
    ({"seeds": [0, 2, 2, 0]}, "grid `seeds` names 0 twice; give each seed once"),
    ({"predictors": "none"}, "grid `predictors` must be a non-empty list of names from "),
    ({"predictors": [1]}, "grid `predictors` must be a non-empty list of names from "),
    ({"predictors": ["none", "arma", "none"]},
     "grid `predictors` names 'none' twice; give each once"),
    ({"predictors": ["tarot"]}, "grid `predictors`: 'tarot' is not one of none, "),
    ({"overrides": [1]}, "grid `overrides` must be an array of tables ([[overrides]] "
                         "sections); got [1]"),
    ({"budget_every": True}, "grid `budget_every` must be an int >= 1 (frames); got True"),
    ({"budget_every": 0}, "grid `budget_every` must be an int >= 1 (frames); got 0"),
    ({"overrides": [{"name": "b"}, {"name": "a"}, {"name": "b"}, {"name": "a"}]},
     "grid `overrides`: the name 'a' is used twice; rows are told apart by name"),
    ({"overrides": [{"name": "x", "loop.gian": 1}]},
     "grid override 'x': unknown key `loop.gian` ("),
    ({"overrides": [{"loop.gain": "high"}]}, "grid override 'loop.gain=high': "),
])
def test_grid_refusals_name_the_key_and_rule(no_memory_check, grid, message):
    with pytest.raises(ValueError) as exc:
        sweep_specs(grid)
    assert str(exc.value).startswith(message), str(exc.value)


@pytest.mark.parametrize("bad", [True, "1"])
def test_a_grid_duration_that_is_no_number_is_a_type_error(no_memory_check, bad):
    # check_real's TypeError (left26-twins); the command line prints it as one line
    with pytest.raises(TypeError) as exc:
        sweep_specs({"duration": bad})
    assert str(exc.value) == f"grid `duration` must be a real number; got {bad!r}."


def test_predictor_message_lists_every_name():
    from closedloop.control.predictors import NAMES

    with pytest.raises(ValueError) as exc:
        sweep_specs({"predictors": []})
    assert str(exc.value) == ("grid `predictors` must be a non-empty list of names from "
                              f"{', '.join(NAMES)}; got []")


def test_boundaries_are_accepted(no_memory_check):
    specs = sweep_specs({"seeds": [0], "budget_every": 1, "duration": 1e-3})
    assert specs[0].payload["seed"] == 0 and specs[0].payload["budget_every"] == 1


def test_memory_refusal_names_the_override(monkeypatch):
    import closedloop.resources as resources

    def refuse(config, duration, oracle, budget):
        raise ValueError("too big")

    monkeypatch.setattr(resources, "check_resources", refuse)
    with pytest.raises(ValueError) as exc:
        sweep_specs({"overrides": [{"name": "huge"}]})
    assert str(exc.value) == "grid override 'huge': too big"


# ------------------------------------------------------------------ a worker's row
class _Run:
    def __init__(self, path_log):
        self.budget = SimpleNamespace(
            directions=np.array([[20.0, 0.0], [0.0, 0.0], [0.0, -20.0]]),
            **{t: np.array([9.0, 0.1 * (i + 1), 7.0]) for i, t in enumerate(
                ("fitting", "aliasing", "temporal", "noise", "measured"))})
        self.saved = path_log

    def summary(self):
        return {"predictor": "x", "seed": 9, "strehl_peak_mean": 0.25, "closed": True}

    def save(self, path, overwrite=False):
        self.saved.append((path, overwrite))
        path.write_bytes(b"run")


@pytest.fixture
def fake_runs(monkeypatch):
    import closedloop.training as training

    calls, saved = [], []

    def run_trained(config, predictor, duration, *, seed, progress, budget_every):
        calls.append((config, predictor, duration, seed, progress, budget_every))
        run = _Run(saved)
        if budget_every is None:
            run.budget = None
        return run

    monkeypatch.setattr(training, "run_trained", run_trained)
    return SimpleNamespace(calls=calls, saved=saved)


def test_run_one_row_holds_the_summary_and_the_on_axis_budget(fake_runs, tmp_path):
    cfg = presets.get("table1")
    payload = {"config": cfg.to_dict(), "seed": 3, "predictor": "arma", "duration": 0.02,
               "budget_every": 4, "out_dir": str(tmp_path), "key": "abc"}
    row = run_one(payload)
    assert fake_runs.calls == [(cfg, "arma", 0.02, 3, False, 4)]
    path = tmp_path / "runs" / "abc.h5"
    assert fake_runs.saved == [(path, True)] and path.read_bytes() == b"run"
    # the direction at (0, 0) is the second; predictor and seed are the spec's labels
    assert row == {"strehl_peak_mean": 0.25, "closed": True,
                   "budget_fitting_on_axis": 0.1, "budget_aliasing_on_axis": 0.2,
                   "budget_temporal_on_axis": pytest.approx(0.3),
                   "budget_noise_on_axis": 0.4, "budget_measured_on_axis": 0.5,
                   # the budget's units, the preset's science wavelength (round 49 b W06)
                   "budget_units": "rad^2", "budget_wavelength_m": cfg.wavelength,
                   "result_file": str(path)}


def test_run_one_without_budget_or_output_folder(fake_runs):
    cfg = presets.get("table1")
    row = run_one({"config": cfg.to_dict(), "seed": 1, "predictor": "none", "duration": 0.02})
    assert fake_runs.calls == [(cfg, "none", 0.02, 1, False, None)]
    assert row == {"strehl_peak_mean": 0.25, "closed": True}
    assert fake_runs.saved == []


# ------------------------------------------------------------------ the sweep
@pytest.fixture
def cluster():
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=False,
                                  dashboard_address=":0") as c:
        yield c


def test_sweep_writes_every_row_and_its_table(fake_runs, cluster, tmp_path, no_memory_check):
    grid = {"seeds": [5, 6], "duration": 0.02,
            "overrides": [{"name": "a", "loop.gain": 0.3}, {"name": "b"}]}
    out = tmp_path / "out"
    rows, report = sweep(grid, out, scheduler=cluster.scheduler_address, progress=False)
    specs = sweep_specs(grid)
    assert report.n_specs == 4 and report.n_ok == 4
    assert sorted(r["key"] for r in rows) == sorted(s.key for s in specs)
    assert sorted(c[3] for c in fake_runs.calls) == [5, 5, 6, 6]
    by_key = {r["key"]: r for r in rows}
    for s in specs:
        r = by_key[s.key]
        assert (r["override"], r["seed"], r["predictor"], r["status"]) == (
            s.labels["override"], s.labels["seed"], "none", "ok")
        assert r["result_file"] == str((out / "runs" / f"{s.key}.h5").resolve())
        assert (out / "runs" / f"{s.key}.h5").read_bytes() == b"run"
    with open(out / "sweep.csv", newline="", encoding="utf-8") as fh:
        table = list(csv.reader(fh))
    assert table[0][:4] == ["override", "seed", "predictor", "status"]
    assert len(table) == 5
    assert (out / "sweep.parquet").is_file()

    # a row of another grid in the same folder is not this sweep's; a re-run runs nothing
    from modalinfo.batch.engine import RowStore

    RowStore(out).write("f" * 64, {"status": "ok", "override": "other"})
    fake_runs.calls.clear()
    again, report = sweep(grid, out, scheduler="tcp://127.0.0.1:1", progress=False)
    assert fake_runs.calls == [] and report.n_specs == 4
    assert sorted(r["key"] for r in again) == sorted(by_key)
    with open(out / "sweep.csv", newline="", encoding="utf-8") as fh:
        assert len(list(csv.reader(fh))) == 5
