"""Fixes 41-c (issue 27): no road filters or records the process's warnings any more.

Fixes 40-c left blocks ``warnings.catch_warnings()`` + ``simplefilter`` /
``filterwarnings`` (``modalinfo reorder``, ``fitting-error``, the batch's ordering,
forecast and load tasks, ``closedloop info``'s loader, the CMI interval's replicates,
the solar study's timing, Figures 1 and 5, ``paper_figures``' matplotlibrc check).
``catch_warnings`` swaps Python's one process-wide filter list and ``showwarning``
(Python's documented rule before 3.14), so while one thread was inside, every other
thread's warnings of the filtered category were dropped, or went into the first
thread's record (and were shown as its notes). Now each is a scope of its own thread
(``modalinfo.common.quiet.quiet(category, message=...)`` / ``recording(...)``).

References: Python's warnings machinery itself (under the filter ``"always"`` each
call's warning reaches ``warnings.showwarning`` once, in the thread that raised it). No
timing: thread B warns while thread A is held inside the road's block by two events
(A's library call waits there), so the old filter was installed at that moment on
every run; each road test fails before (B's warnings of the category: 0 shown).
"""

from __future__ import annotations

import ast
import functools
import sys
import threading
import types
import warnings
from pathlib import Path

import numpy as np
import pytest

from modalinfo.common import quiet
from modalinfo.telemetry import ModalLog

from ..cli.conftest import exit_code, write_small_log
from ..information.test_quiet_quarters_round40 import _shown_by_thread


class _StopError(Exception):
    """Ends thread A's road once thread B has warned (what follows is not the test's)."""


def _race(monkeypatch, owner, name, road, b_warns, *, stop=False, own=None, call=1):
    """Run ``road()`` in thread A, held in ``owner.name`` (its ``call``-th call), while
    thread B raises ``b_warns`` ((message, category) through the package's ``warn``)
    and one plain ``warnings.warn``. Return (B's shown (category, message)s, A's shown
    messages, road's value). ``own``: a package warning A's held call raises first.
    """
    real = getattr(owner, name)
    inside, done = threading.Event(), threading.Event()
    calls = []

    def held(*args, **kwargs):
        calls.append(1)
        if len(calls) == call:
            if own is not None:
                quiet.warn(own[0], own[1], stacklevel=2)
            inside.set()
            done.wait(60)
            if stop:
                raise _StopError
        return real(*args, **kwargs)

    monkeypatch.setattr(owner, name, held)
    result, errors = [], []

    def a():
        try:
            result.append(road())
        except _StopError:
            result.append(None)
        except BaseException as exc:  # noqa: BLE001 - reported by the test
            errors.append(exc)
        finally:
            inside.set()  # a road that never reached the call: B does not wait forever

    def b():
        inside.wait(60)
        try:
            for message, category in b_warns:
                quiet.warn(message, category, stacklevel=1)
            warnings.warn("B's own note", UserWarning, stacklevel=1)
        finally:
            done.set()

    before = list(warnings.filters)
    threads = [threading.Thread(target=f, name=n) for f, n in ((a, "A"), (b, "B"))]
    with _shown_by_thread() as shown:  # "always", each warning noted with its thread
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(300)
    assert not errors, errors
    assert calls, f"{name} was not called"
    assert list(warnings.filters) == before
    got_b = [(c, m) for t, c, m in shown if t == "B"]
    got_a = [m for t, _, m in shown if t == "A"]
    return got_b, got_a, result[0]


def _all_shown(got_b, b_warns):
    assert sorted(m for _, m in got_b) == sorted([m for m, _ in b_warns] + ["B's own note"])


# ------------------------------------------------------------------- the CLI commands
def _ordering_warnings():
    from modalinfo.ordering.compare import KLGeometryWarning
    from modalinfo.ordering.cost import OrderingCostWarning
    from modalinfo.ordering.fitting_error import PupilSamplingWarning

    return OrderingCostWarning, KLGeometryWarning, PupilSamplingWarning


@pytest.mark.parametrize("owner_name, name, extra, which", [
    ("modalinfo.ordering", "order_modes", [], 0),
    ("modalinfo.ordering.compare", "basis_for_log", ["--basis", "kl-theory"], 1),
    ("modalinfo.ordering", "ordering_stability", ["--stability", "100"], 0),
])
def test_reorder_leaves_other_threads_warnings(monkeypatch, tmp_path, owner_name, name,
                                               extra, which):
    import importlib

    category = _ordering_warnings()[which]
    path = write_small_log(tmp_path / "log.npz", 400)
    argv = ["reorder", path, "--method", "mi_marginal", "--resamples", "0", "--budget",
            "500", "--pupil-pixels", "16", *extra]
    b_warns = [(f"B's {category.__name__} {i}", category) for i in range(3)]
    got_b, got_a, code = _race(monkeypatch, importlib.import_module(owner_name), name,
                               lambda: exit_code(argv), b_warns,
                               own=("A's own", category))
    assert code == 0
    _all_shown(got_b, b_warns)  # before: 0 of the 3 of the category
    assert "A's own" not in got_a  # still silenced in A's own thread


def test_fitting_error_leaves_other_threads_warnings(monkeypatch, tmp_path, capsys):
    import modalinfo.ordering.compare as compare

    path = write_small_log(tmp_path / "log.npz", 400)
    argv = ["fitting-error", path, "--orderings", "zernike:mi_marginal", "--budget", "500",
            "--pupil-pixels", "16"]
    b_warns = [(f"B's {c.__name__}", c) for c in _ordering_warnings()]
    got_b, got_a, code = _race(monkeypatch, compare, "compare_orderings",
                               lambda: exit_code(argv), b_warns,
                               own=("A's own ordering cost", _ordering_warnings()[0]))
    assert code == 0
    # before: B's OrderingCost / KLGeometry dropped, its PupilSampling and plain note
    # taken into A's record (the plain note re-shown by thread A)
    _all_shown(got_b, b_warns)
    assert got_a == [] or all("B's" not in m and "A's own" not in m for m in got_a)
    assert "B's" not in capsys.readouterr().err.replace("B's own note", "")


# ------------------------------------------------------------------------ the batch
def test_batch_ordering_tasks_leave_other_threads_warnings(monkeypatch):
    from modalinfo.batch import analyses

    work = types.SimpleNamespace(run=lambda: 1)

    def road():
        with analyses._no_cost_note():
            return work.run()

    b_warns = [(f"B's {c.__name__}", c) for c in _ordering_warnings()]
    got_b, got_a, value = _race(monkeypatch, work, "run", road, b_warns,
                                own=("A's own K-L", _ordering_warnings()[1]))
    assert value == 1
    _all_shown(got_b, b_warns)
    assert got_a == []


def test_batch_forecast_task_leaves_other_threads_warnings(monkeypatch):
    import modalinfo.forecast as forecast
    from modalinfo._stats import LevelStepWarning
    from modalinfo.batch import analyses

    log = ModalLog(np.random.default_rng(1).standard_normal((300, 2)), rate=1000.0,
                   modes=[2, 3], units="rad")
    params = {"predictors": "linear", "horizon": 2, "train": 0.5, "modes": None}
    b_warns = [("B's level step", LevelStepWarning),
               ("evaluate: no honest Diebold-Mariano test for B", UserWarning),
               ("evaluate: the test frames differ in scale for B", UserWarning)]
    got_b, got_a, _ = _race(monkeypatch, forecast, "evaluate",
                            lambda: analyses._forecast(log, params), b_warns, stop=True,
                            own=("evaluate: no honest Diebold-Mariano test for A",
                                 UserWarning))
    _all_shown(got_b, b_warns)
    assert got_a == []


def test_batch_load_task_leaves_other_threads_warnings(monkeypatch, tmp_path):
    import modalinfo.io as mio
    from modalinfo.batch import analyses
    from modalinfo.io import LayoutWarning

    path = write_small_log(tmp_path / "log.npz", 50)
    b_warns = [("B's layout", LayoutWarning)]
    got_b, got_a, _ = _race(monkeypatch, mio, "load",
                            lambda: analyses.run_log_task({"path": str(path)}), b_warns,
                            stop=True, own=("A's layout", LayoutWarning))
    _all_shown(got_b, b_warns)
    assert got_a == []


# ------------------------------------------------------------------- the library
def test_cmi_interval_replicates_leave_other_threads_warnings(monkeypatch):
    from modalinfo.information import BiasRuleWarning, conditional_mutual_information_ci
    from modalinfo.information import conditional_uncertainty as cu

    real = cu._estimator
    owner = types.SimpleNamespace(real=None)
    owner.step = lambda *a: owner.real(*a)

    def estimator(*args, **kwargs):
        owner.real = real(*args, **kwargs)
        return lambda *a: owner.step(*a)

    monkeypatch.setattr(cu, "_estimator", estimator)
    rng = np.random.default_rng(2)
    x, y, z = rng.standard_normal((3, 300))
    b_warns = [("B's bias rule", BiasRuleWarning)]
    # call 1 is the point estimate (outside the block), call 2 the first replicate
    got_b, got_a, ci = _race(monkeypatch, owner, "step",
                             lambda: conditional_mutual_information_ci(
                                 x, y, z, method="gaussian", n_resamples=20, seed=0),
                             b_warns, call=2, own=("A's replicate bias", BiasRuleWarning))
    assert ci is not None
    _all_shown(got_b, b_warns)  # before: dropped
    assert "A's replicate bias" not in got_a  # the replicates' rule still silenced


def test_closedloop_result_loader_leaves_other_threads_warnings(monkeypatch):
    from closedloop import cli
    from closedloop.result import SimulationResult, UncheckedResultWarning

    args = types.SimpleNamespace(result="x.h5", command="info")
    b_warns = [("B's unchecked result", UncheckedResultWarning)]
    got_b, got_a, _ = _race(monkeypatch, SimulationResult, "load",
                            lambda: cli._load_result(args), b_warns, stop=True)
    _all_shown(got_b, b_warns)  # before: taken as A's note, B's plain note re-shown by A
    assert got_a == [] and getattr(args, "_notes", None) is None


def test_solar_timing_leaves_other_threads_warnings(monkeypatch):
    from closedloop.optics import shifts
    from closedloop.studies import solar

    b_warns = [("B's user warning", UserWarning)]
    got_b, got_a, _ = _race(monkeypatch, shifts, "measure_shifts",
                            lambda: solar.correlation_compute_time(2, 16, repeats=1),
                            b_warns, stop=True, own=("A's cfi bias", UserWarning))
    _all_shown(got_b, b_warns)
    assert got_a == []


# -------------------------------------------------------------------------- figures
def test_figure1_leaves_other_threads_warnings(monkeypatch):
    from paper_figures import fig1_fitting_error as fig1

    rng = np.random.default_rng(3)
    log = ModalLog(rng.standard_normal((200, fig1.MIN_MODES)), rate=1000.0,
                   modes=list(range(2, 2 + fig1.MIN_MODES)), units="rad")
    b_warns = [(f"B's {c.__name__}", c) for c in _ordering_warnings()[1:]]
    got_b, got_a, _ = _race(monkeypatch, fig1, "_typical_frame", lambda: fig1.compute(log),
                            b_warns, stop=True, own=("A's pupil", _ordering_warnings()[2]))
    _all_shown(got_b, b_warns)
    assert got_a == []


def test_figure5_leaves_other_threads_warnings(monkeypatch, capsys, cheap_figure5_predictors):
    import modalinfo.forecast as forecast
    from paper_figures import fig5_forecast as fig5

    log = ModalLog(np.random.default_rng(4).standard_normal((fig5.MIN_FRAMES, 2)),
                   rate=1000.0, modes=[2, 3], units="rad")
    b_warns = [("evaluate: no honest Diebold-Mariano test for B", UserWarning),
               ("B's note", UserWarning)]
    got_b, got_a, _ = _race(monkeypatch, forecast, "evaluate",
                            lambda: fig5.compute(log, quick=True), b_warns, stop=True)
    # before: B's warnings taken into A's record (the DM one printed as Figure 5's note)
    _all_shown(got_b, b_warns)
    assert got_a == []
    assert "for B" not in capsys.readouterr().err


def test_paper_figures_rc_check_leaves_other_threads_warnings(monkeypatch, tmp_path,
                                                             capsys):
    import modalinfo.common.plotting as plotting
    from paper_figures import __main__ as pf

    monkeypatch.setattr(pf, "_make", lambda *a, **k: None)
    b_warns = [("B's package note", UserWarning)]
    got_b, got_a, code = _race(monkeypatch, plotting, "rc_overrides",
                               lambda: pf.main(["--only", "2", "--out",
                                                str(tmp_path / "out")]),
                               b_warns, own=("A's font note", UserWarning))
    _all_shown(got_b, b_warns)  # before: printed as paper_figures' own warnings
    err = capsys.readouterr().err
    assert "python -m paper_figures: warning: A's font note" in err  # A's, said as before
    assert "python -m paper_figures: warning: B's" not in err
    assert code == 0


# --------------------------------------------------------------- the scopes themselves
def test_scopes_select_by_category_and_text_and_record_the_callers_line():
    from modalinfo.information import BiasRuleWarning

    def library(message, category):
        quiet.warn(message, category, stacklevel=2)

    with warnings.catch_warnings(record=True) as shown:
        warnings.simplefilter("always")
        with quiet.quiet(BiasRuleWarning), quiet.recording(message="keep") as kept:
            here = sys._getframe().f_lineno
            library("dropped", BiasRuleWarning)
            library("keep me", UserWarning)
            library("keep me too", BiasRuleWarning)  # the innermost scope first
            library("shown", UserWarning)
        library("after", BiasRuleWarning)
    assert [str(w.message) for w in shown] == ["shown", "after"]
    assert [str(w.message) for w in kept] == ["keep me", "keep me too"]
    assert [w.category for w in kept] == [UserWarning, BiasRuleWarning]
    assert [type(w.message) for w in kept] == [UserWarning, BiasRuleWarning]  # instances
    assert {w.filename for w in kept} == {__file__}
    assert [w.lineno for w in kept] == [here + 2, here + 3]  # the caller's lines
    assert not quiet.is_quiet()  # a selective scope is not the whole-package quiet()


# ------------------------------------------------------------------------ structure
_PACKAGES = ("modalinfo", "closedloop", "paper_figures")
#: blocks that still change the process's filters, each for another library's warnings
#: (the package's own go through quiet.warn and its thread's scopes), under the lock
FOREIGN = {
    "modalinfo/common/jit.py",  # numba's, at import
    "modalinfo/forecast/nn.py",  # sklearn's ConvergenceWarning
    "modalinfo/information/uncertainty.py",  # scipy's DegenerateDataWarning
    "modalinfo/io/aot.py",  # astropy / h5py readers'
    "modalinfo/io/fits.py",  # astropy's
}


@functools.cache
def _all_calls(root: Path) -> tuple:
    return tuple(_calls(root))


def _calls(root: Path):
    """(file, line, name) of every call of the three packages (``warnings.warn`` named so)."""
    for package in _PACKAGES:
        for path in sorted((root / package).rglob("*.py")):
            rel = path.relative_to(root).as_posix()
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute):
                    owner = node.func.value
                    name = node.func.attr
                    if isinstance(owner, ast.Name) and owner.id == "warnings":
                        name = f"warnings.{name}"
                    yield rel, node.lineno, name
                elif isinstance(node, ast.ImportFrom) and node.module == "warnings":
                    yield rel, node.lineno, "from warnings import"


def test_no_road_swaps_the_process_filters_for_the_packages_own_warnings():
    import modalinfo

    root = Path(modalinfo.__file__).parent.parent
    found = {rel for rel, _, name in _all_calls(root)
             if name in ("warnings.simplefilter", "warnings.filterwarnings",
                         "warnings.catch_warnings")
             and rel != "modalinfo/common/quiet.py"}
    assert found <= FOREIGN, found - FOREIGN  # fails before: 9 more files


def test_every_warning_of_the_three_packages_goes_through_the_one_warn():
    """``warnings.warn`` only in ``quiet.warn``: closedloop and paper_figures too."""
    import modalinfo

    root = Path(modalinfo.__file__).parent.parent
    found = [f"{rel}:{no}" for rel, no, name in _all_calls(root)
             if name in ("warnings.warn", "from warnings import")
             and rel != "modalinfo/common/quiet.py"]
    assert found == []  # fails before: 5 sites in closedloop
