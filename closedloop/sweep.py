"""Simulation sweeps on Dask's distributed scheduler: config overrides x seeds x predictors.

A grid (TOML) names a base (a preset or a config file), a duration, seeds, predictors
and a list of overrides; every combination is one task of the generic engine of
:mod:`modalinfo.common.tasks`, keyed by the SHA-256 of its resolved config, seed,
predictor, duration and the package version. The engine gives the guarantees: re-running
the same grid resumes (finished runs are skipped), a failed run is an error row and the
rest goes on, a worker killed mid-run is retried without duplicate rows, and each task
runs with a bounded number of threads. Each run writes its result file
``runs/<key>.h5`` (atomic, replaced by a re-run of the same key, never duplicated) and
one row: SR peak and field-mean SR after closure, corrected-FoV diameter, the error
budget's on-axis terms, steps/s.

The grid file's format is :data:`GRID_HELP` (printed by ``closedloop sweep --help``).
"""

from __future__ import annotations

import contextlib
import copy
import os
import re
import tomllib
from pathlib import Path
from typing import Any

import numpy as np

from closedloop import presets
from closedloop.config import SimulationConfig, load_config
from modalinfo.common.files import quoted
from modalinfo.common.validation import check_real
from modalinfo.io.formats import GRID_KEYS, describe_json  # a grid fed to another command

__all__ = ["GRID_HELP", "load_grid", "sweep_specs", "run_one", "sweep"]

#: The grid file's format, as printed by ``closedloop sweep --help`` (and in the README).
GRID_HELP = """grid file (TOML); every key is optional:

    preset = "table1"          # or (not both): config = "my.toml" (relative to the grid file)
    duration = 0.3             # s of simulated time per run (default 0.3)
    seeds = [0, 1]             # atmospheres (default: the base config's seed)
    predictors = ["none", "arma"]   # closedloop predictors (default ["none"])
    budget_every = 5           # optional: error budget every 5 frames

    [[overrides]]              # optional; none = the base alone
    name = "gain 0.3"          # label of the rows (default: the changes)
    "loop.gain" = 0.3          # dotted config key (as in `closedloop config`) = value
    [[overrides]]
    name = "upper at 15 km"
    "layers.1.altitude" = 15000.0
    "dms.1.altitude" = 15000.0
    "wfss.1.altitude" = 15000.0

Runs = overrides x seeds x predictors, one task each; a run's row holds its SR peak,
field-mean SR, corrected-FoV diameter and (with budget_every) the on-axis error budget
(budget_units rad^2 at budget_wavelength_m, the science wavelength).
Outputs in --out: sweep.csv, sweep.parquet, runs/<key>.h5, rows/ (resume state)."""


def _index(part: str) -> int:
    """Return the list index of a dotted key's part: from 0, as `closedloop config` lists them."""
    i = int(part)
    if i < 0:  # Python's "from the end" would change another layer than the key reads
        raise IndexError(f"index {i} is negative; items count from 0")
    return i


def _apply(d: dict, dotted: str, value: Any) -> None:
    node: Any = d
    parts = dotted.split(".")
    for part in parts[:-1]:
        node = node[_index(part)] if isinstance(node, list) else node[part]
    last = parts[-1]
    if isinstance(node, list):
        node[_index(last)] = value
    elif isinstance(node, dict):
        if last not in node:  # a typo would otherwise add a key the config ignores
            from modalinfo.common.validation import did_you_mean

            raise KeyError(f"{last!r} is not among {', '.join(sorted(node))}"
                           + did_you_mean(last, node))
        node[last] = value
    else:
        raise KeyError(f"{'.'.join(parts[:-1])} is a value, not a table")


def override(config: SimulationConfig, changes: dict[str, Any]) -> SimulationConfig:
    """Return ``config`` with dotted-key changes (``"loop.gain"``, ``"layers.1.altitude"``)."""
    d = copy.deepcopy(config.to_dict())
    for key, value in changes.items():
        try:
            _apply(d, key, value)
        except (KeyError, IndexError, ValueError, TypeError) as exc:
            why = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
            raise ValueError(f"unknown key `{key}` ({why}).") from None
    return SimulationConfig.from_dict(d)


def _toml_config_line(name: str) -> str:
    r"""Return the grid line ``config = "<name>"`` as TOML reads it, to paste into a grid file.

    A TOML basic string (``tomli_w``), so a name holding ``"``, ``\``, a newline or an
    escape reads back as itself with ``tomllib`` (the hint wrote ``config = "{name}"``
    raw; fix49-c); a tab, a C1 control and U+2028 / U+2029, which ``tomli_w`` leaves as
    they are, are written ``\t`` / ``\uXXXX`` to keep the line one printable line. A name
    that is not UTF-8 (an undecodable byte) cannot be written in a TOML file: said so.
    """
    import tomli_w

    line = re.sub("[\t\x80-\x9f\u2028\u2029]",
                  lambda m: "\\t" if m.group() == "\t" else f"\\u{ord(m.group()):04x}",
                  tomli_w.dumps({"config": name}).strip())
    try:
        line.encode("utf-8")
    except UnicodeEncodeError:
        return (f"config = <this file's name>, once renamed: its name {quoted(name)} is not "
                "UTF-8, which a TOML file cannot hold")
    return line


def load_grid(path: str | Path) -> dict:
    """Read and check a grid file (see the module docstring); return it as a dict."""
    path = Path(path)
    if not path.is_file():  # a FIFO "did not exist"
        raise FileNotFoundError(f"grid file {quoted(path)} " + (
            "is not a regular file (a FIFO or a device)" if path.exists() else
            "does not exist"))
    try:
        grid = tomllib.loads(path.read_text(encoding="utf-8"))
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{quoted(path)}: not valid TOML: {exc}") from exc
    unknown = sorted(set(grid) - GRID_KEYS)
    if unknown and (describe_json(grid) or "").startswith("a closedloop config"):
        # a config given as the grid was "unknown key `dms`" (round 46 PART b, F75)
        raise ValueError(f"{quoted(path)} is a closedloop config, not a sweep grid: name it in a "
                         f"grid file, {_toml_config_line(path.name)} (`closedloop sweep --help` "
                         "shows the grid's format)")
    if unknown:
        allowed = ", ".join(sorted(GRID_KEYS))
        from modalinfo.common.validation import did_you_mean

        hint = did_you_mean(unknown[0], GRID_KEYS)
        raise ValueError(f"{quoted(path)}: unknown key `{unknown[0]}`{hint}; allowed: {allowed}")
    if "config" in grid and "preset" in grid:  # one would be ignored (round 13 PART b)
        raise ValueError(f"{quoted(path)}: give `preset` or `config`, not both (the base of every "
                         f"run is one of them); got preset {grid['preset']!r} and config "
                         f"{grid['config']!r}")
    if "config" in grid:
        if (not isinstance(grid["config"], str)
                or Path(grid["config"]).suffix.lower() not in (".toml", ".json")):
            # "`path` must end in .toml or .json": no key of the grid is `path` (round 46
            # PART b, F76)
            raise ValueError(f"{quoted(path)}: grid `config` must name a .toml or .json file (from "
                             f"`closedloop config --out`); got {grid['config']!r}")
        # absolute, but links kept: resolve() turned a config link to a device into its
        # target, refused as "`path` must end in .toml" (round 28 PART b)
        grid["config"] = os.path.abspath(path.parent / grid["config"])
    return grid


def _base(grid: dict) -> SimulationConfig:
    if "config" in grid:
        return load_config(grid["config"])
    try:
        return presets.get(grid.get("preset", "table1"))
    except (ValueError, TypeError) as exc:  # the library names its argument `name`
        raise ValueError(f"grid `preset` {str(exc).split(' ', 1)[1]}") from None


def _check_memory(config: SimulationConfig, duration: float, budget_every: int | None,
                  oracle: bool) -> None:
    """Refuse, before any cluster starts, a run that needs more memory than the machine.

    Uses ``closedloop.resources.check_resources`` when this version of closedloop has
    it (without it, ``simulate``'s own checks make such a run an error row). A run the
    simulator refuses for other reasons (a run too short for its delay) is not refused
    here: it is an error row of the sweep, found in well under a second. An unstable
    gain never gets here: the config itself refuses it (``LoopConfig``).
    """
    try:
        from closedloop.resources import check_resources
    except ImportError:
        return
    check_resources(config, duration, oracle=oracle,
                    budget=budget_every is not None)


def sweep_specs(grid: dict) -> list:
    """One :class:`modalinfo.common.tasks.keys.TaskSpec` per (override, seed, predictor)."""
    from closedloop.control.predictors import NAMES, LoopPredictor
    from modalinfo.common.tasks.keys import TaskSpec, task_key

    base = _base(grid)
    try:  # validation.check_real (the one copy), its message said of the grid's key
        duration = check_real(grid.get("duration", 0.3), "duration", minimum=0.0,
                              strict_min=True)
    except (TypeError, ValueError) as exc:
        raise type(exc)(f"grid {exc}") from None
    seeds = grid.get("seeds", [base.seed])
    if (not isinstance(seeds, list) or not seeds
            or any(isinstance(x, bool) or not isinstance(x, int) or x < 0 for x in seeds)):
        raise ValueError(f"grid `seeds` must be a non-empty list of ints >= 0; got {seeds!r}")
    if max(seeds) >= 2**63:  # an OverflowError inside a worker before (as `run --seed`)
        raise ValueError(f"grid `seeds` must be ints <= 2**63 - 1 (the seed is stored in "
                         f"the result); got {max(seeds)}")
    if len(set(seeds)) < len(seeds):  # the same run twice would be one row, silently
        twice = next(x for x in seeds if seeds.count(x) > 1)
        raise ValueError(f"grid `seeds` names {twice} twice; give each seed once")
    predictors = grid.get("predictors", ["none"])
    if not isinstance(predictors, list) or not predictors or not all(
            isinstance(p, str) for p in predictors):
        raise ValueError(f"grid `predictors` must be a non-empty list of names from "
                         f"{', '.join(NAMES)}; got {predictors!r}")
    if len(set(predictors)) < len(predictors):
        twice = next(x for x in predictors if predictors.count(x) > 1)
        raise ValueError(f"grid `predictors` names {twice!r} twice; give each once")
    loop_predictors = {}
    for name in predictors:  # the one check of a name (LoopPredictor.from_name)
        try:
            loop_predictors[name] = LoopPredictor.from_name(name)
        except ValueError:
            raise ValueError(f"grid `predictors`: {name!r} is not one of "
                             f"{', '.join(NAMES)}") from None
    overrides = grid.get("overrides", [])
    if not isinstance(overrides, list) or not all(isinstance(o, dict) for o in overrides):
        raise ValueError("grid `overrides` must be an array of tables ([[overrides]] "
                         f"sections); got {overrides!r}")
    overrides = overrides or [{"name": "base"}]
    budget_every = grid.get("budget_every")
    if budget_every is not None and (isinstance(budget_every, bool)
                                     or not isinstance(budget_every, int) or budget_every < 1):
        raise ValueError(f"grid `budget_every` must be an int >= 1 (frames); got "
                         f"{budget_every!r}")
    names = [str(o["name"]) for o in overrides if "name" in o]
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise ValueError(f"grid `overrides`: the name {twice[0]!r} is used twice; rows "
                         "are told apart by name")
    specs = []
    named: dict[str, str] = {}  # config key -> the override that gave it
    for ov in overrides:
        changes = {k: v for k, v in ov.items() if k != "name"}
        name = str(ov.get("name", ", ".join(f"{k}={v}" for k, v in changes.items()) or "base"))
        try:
            config = override(base, changes)
            for predictor in loop_predictors.values():
                _check_memory(config, duration, budget_every, predictor.oracle)
        except (ValueError, TypeError) as exc:
            raise ValueError(f"grid override {name!r}: {exc}") from None
        # two names for one config are one run and one row: the second name vanished from
        # the table without a word (round 11 PART b, R36), as a seed given twice would
        same = named.setdefault(task_key("closedloop-config", config.to_dict()), name)
        if same != name:
            raise ValueError(f"grid `overrides` {same!r} and {name!r} give the same config "
                             "(one run, one row); give each config once")
        for seed in seeds:
            for predictor in predictors:
                payload = {"config": config.to_dict(), "seed": seed, "predictor": predictor,
                           "duration": duration, "budget_every": budget_every}
                key = task_key("closedloop-sweep", payload)
                specs.append(TaskSpec(key=key, payload=payload,
                                      labels={"override": name, "seed": seed,
                                              "predictor": predictor, "duration": duration}))
    return specs


def run_one(payload: dict) -> dict:
    """Run one simulation of a sweep (a module-level function, importable by workers)."""
    from closedloop.training import run_trained

    config = SimulationConfig.from_dict(payload["config"])
    result = run_trained(config, payload["predictor"], payload["duration"],
                         seed=payload["seed"], progress=False,
                         budget_every=payload.get("budget_every"))
    row = dict(result.summary())
    row.pop("predictor", None)
    row.pop("seed", None)
    row.pop("strehl_note", None)  # a caveat, not a number: the sweep prints it once
    b = result.budget
    if b is not None:
        k = int(np.argmin(np.hypot(*b.directions.T)))
        for term in ("fitting", "aliasing", "temporal", "noise", "measured"):
            row[f"budget_{term}_on_axis"] = float(getattr(b, term)[k])
        # the table said no unit: rad^2 of phase at the science wavelength, as the run's
        # .h5 states them (``units``, ``wavelength_m``; round 49 PART b, W06)
        row["budget_units"] = "rad^2"
        row["budget_wavelength_m"] = float(config.wavelength)
    out_dir = payload.get("out_dir")
    if out_dir:
        path = Path(out_dir) / "runs" / f"{payload['key']}.h5"
        # never `parents=True`: a worker outliving its interrupted client must not
        # recreate a sweep folder removed meanwhile (Leftovers 16-dask, sweep #11)
        path.parent.mkdir(exist_ok=True)
        result.save(path, overwrite=True)  # same key, same run: replacing never loses data
        row["result_file"] = str(path)
    return row


def _here(row: dict, out_dir: Path) -> dict:
    """Return ``row`` with its ``result_file`` in ``out_dir``'s ``runs/`` (where it lies now).

    A row keeps the absolute path its worker saved to: after the folder was moved,
    renamed or copied and resumed, the table pointed at the old place (a file gone, or
    the original's file for a copy) without a word (adversarial round 20 PART b, S03 /
    S04). The run file is named by the row's key, so its place follows the folder.
    """
    if not row.get("result_file"):
        return row
    return {**row, "result_file": str(out_dir.resolve() / "runs" / Path(row["result_file"]).name)}


def sweep(grid: dict, out_dir: str | Path, *, scheduler: str | None = None,
          n_workers: int | None = None, threads_per_worker: int | None = None,
          memory_limit: str | None = None, progress: bool = True,
          worker_wait: float | None = None):
    """Run a grid; write ``sweep.csv`` / ``sweep.parquet`` and the runs; return the rows.

    Everything is checked before any run: the grid (every override builds a valid
    config), the memory limit, and the output directory (a directory or creatable,
    writable, with free space, not foreign, not in use by another batch or sweep:
    ``<out>/.lock``).

    Returns
    -------
    rows : list of dict
        One row per (override, seed, predictor), ``status`` ``ok``, ``error`` or ``lost``.
    report : modalinfo.common.tasks.runner.EngineReport

    Raises
    ------
    ValueError
        A bad grid, memory limit or output directory; ``OutputInUseError`` (a
        ValueError) when another run holds the directory.
    modalinfo.common.tasks.watch.NoWorkersError
        No worker ran a run for ``worker_wait`` seconds; finished rows are kept.
    """
    from modalinfo.common.folders import check_out_dir, locked_out_dir
    from modalinfo.common.tasks.cluster import check_memory_limit, open_client
    from modalinfo.common.tasks.rows import RowStore, clean_run_staging, write_table
    from modalinfo.common.tasks.runner import run_tasks
    from modalinfo.common.tasks.watch import WORKER_WAIT

    out_dir = Path(out_dir)
    check_out_dir(out_dir)
    specs = sweep_specs(grid)
    check_memory_limit(memory_limit, threads_per_worker or 1)
    for spec in specs:
        spec.payload["out_dir"] = str(out_dir.resolve())
        spec.payload["key"] = spec.key
    with contextlib.ExitStack() as stack:
        stack.enter_context(locked_out_dir(out_dir, "closedloop sweep", also=("runs",)))
        clean_run_staging(out_dir, "sweep", "closedloop sweep", worker_folders=("runs",))
        store = RowStore(out_dir)
        started: list = [None]
        # closed before the table is written, so a Ctrl-C ends the write at once (the
        # client's handler only records it; see modalinfo.batch.archive)
        client_life = stack.enter_context(contextlib.ExitStack())

        def get_client():  # a cluster is started only when some run is left to do
            if started[0] is None:
                started[0] = client_life.enter_context(open_client(
                    scheduler, n_workers=n_workers, threads_per_worker=threads_per_worker,
                    memory_limit=memory_limit))
            return started[0]

        report = run_tasks(specs, run_one, store, get_client, progress=progress,
                           worker_wait=WORKER_WAIT if worker_wait is None else worker_wait,
                           name="closedloop sweep")
        client_life.close()  # the cluster stops; a Ctrl-C recorded meanwhile is raised
        keys = {s.key for s in specs}
        rows = [_here(r, out_dir) for r in store.rows() if r.get("key") in keys]
        write_table(rows, out_dir, "sweep", first=("override", "seed", "predictor", "status"))
    return rows, report
