"""The report's table of the two shipped logs, every row recomputed from the logs here.

Reference: a second implementation, in the test, of each statistic of
``paper_figures.logs_compared`` from its definition (coefficients in waves, mean
removed; total variance; Var(Z2) / Var(Z3); share of radial orders >= 5, i.e. Noll
j >= 16; the largest |lag-1 correlation| between two different modes; the mean lag-1
autocorrelation), on the shipped logs read with ``modalinfo.io.load``, checked against
the cells of the Markdown table that ``logs_compared.report`` writes (in its own number
format), row by row and column by column, and the sentences that quote them.
"""

import re
from pathlib import Path

import numpy as np
import pytest

from modalinfo.io import load
from paper_figures import logs_compared

DATA = Path(__file__).resolve().parents[2] / "data"


def _stats(path):
    log = load(path)
    log = log.to_units("waves") if log.units != "waves" else log
    x = np.asarray(log.coeffs, dtype=np.float64)
    x = x - x.mean(axis=0)
    modes = [int(m) for m in log.modes]
    var = x.var(axis=0)
    n = x.shape[0]
    best = 0.0
    lag1 = []
    for i in range(x.shape[1]):
        for j in range(x.shape[1]):
            # correlation of mode i at t with mode j at t + 1 (population normalisation)
            c = np.sum(x[:-1, i] * x[1:, j]) / (n - 1) / np.sqrt(var[i] * var[j])
            if i == j:
                lag1.append(c)
            else:
                best = max(best, abs(c))
    high = [k for k, m in enumerate(modes) if m >= 16]
    return {"total": var.sum(), "tilt": var[modes.index(2)] / var[modes.index(3)],
            "high": var[high].sum() / var.sum(), "cross": best, "lag1": float(np.mean(lag1))}


@pytest.fixture(scope="module")
def logs():
    return load(DATA / "kaos_like_closed_loop.npz"), load(DATA / "kaos_closedloop.npz")


@pytest.fixture(scope="module")
def expected():
    return (_stats(DATA / "kaos_like_closed_loop.npz"), _stats(DATA / "kaos_closedloop.npz"))


@pytest.fixture(scope="module")
def text(logs):
    return logs_compared.report(logs_compared.compute(*logs))


def _table(text):
    rows = {}
    for line in text.splitlines():
        cells = [c.strip() for c in line.strip().strip("|").split("|")]
        if len(cells) == 3 and line.startswith("|") and not cells[0].startswith("-"):
            rows[cells[0]] = (cells[1], cells[2])
    return rows


def test_every_row_of_the_logs_table_is_recomputed(text, expected):
    rows = _table(text)
    a, b = expected
    assert rows["statistic"] == ("spectral log", "simulated log")
    cases = [
        ("total variance [waves^2]", "total", lambda v: f"{v:.3g}"),
        ("Var(Z2) / Var(Z3)", "tilt", lambda v: f"{v:.2f}"),
        ("variance share of radial orders >= 5", "high", lambda v: f"{v:.1%}"),
        ("largest lag-1 cross-correlation between modes", "cross", lambda v: f"{v:.2f}"),
        ("mean lag-1 autocorrelation", "lag1", lambda v: f"{v:.2f}"),
    ]
    assert len(rows) == len(cases) + 1  # no other row
    for quantity, key, fmt in cases:
        assert rows[quantity] == (fmt(a[key]), fmt(b[key])), quantity


def test_the_sentences_quote_the_right_log(text, expected):
    a, b = expected
    # each comparison quotes the simulated value first, then the spectral one
    assert (f"{b['cross']:.2f} against\n{a['cross']:.2f}" in text
            or f"{b['cross']:.2f} against {a['cross']:.2f}" in text)
    lag = re.search(r"autocorrelation ([0-9.-]+) against ([0-9.-]+)\)", text.replace("\n", " "))
    assert lag and lag.groups() == (f"{b['lag1']:.2f}", f"{a['lag1']:.2f}")
    assert ("smoother" if b["lag1"] > a["lag1"] else "rougher") in text
    coupling = "stronger" if b["cross"] > a["cross"] else "not stronger"
    assert f"between modes is {coupling} in the simulated log" in text.replace("\n", " ")
    more = (b["high"], a["high"]) if b["high"] > a["high"] else (a["high"], b["high"])
    assert f"({more[0]:.1%} against {more[1]:.1%})" in text.replace("\n", " ")


def test_statistics_name_and_order_of_the_logs(logs, expected):
    cmp = logs_compared.compute(*logs)
    assert cmp.spectral.name == "spectral" and cmp.simulated.name == "simulated"
    for stats, ref in ((cmp.spectral, expected[0]), (cmp.simulated, expected[1])):
        assert stats.total == pytest.approx(ref["total"], rel=1e-10)
        assert stats.tilt_ratio == pytest.approx(ref["tilt"], rel=1e-10)
        assert stats.high_order_share == pytest.approx(ref["high"], rel=1e-10)
        assert stats.lagged_cross == pytest.approx(ref["cross"], rel=1e-10)
        assert stats.lag1 == pytest.approx(ref["lag1"], rel=1e-10)


def test_figure5_best_predictor_and_accurate_horizon_by_definition():
    # the definitions the report states, on an evaluation where every choice differs:
    # best at h = 1 is the largest whole-wavefront gain in the first horizon's column;
    # the accurate horizon is the last horizon before the gain first drops to <= 1
    from types import SimpleNamespace

    from paper_figures.fig5_forecast import Figure5

    names = ["persistence", "a", "b", "c"]
    gain = np.array([[1.0, 1.0, 1.0, 1.0],
                     [1.3, 1.2, 0.9, 1.5],   # best at h = 1; beats persistence up to h = 2
                     [1.1, 1.4, 1.6, 1.7],   # best at the longer horizons
                     [0.9, 1.1, 1.2, 1.3]])  # loses at h = 1
    ev = SimpleNamespace(names=names, gain_wavefront=gain, horizons=np.array([1, 2, 3, 4]),
                         index=names.index)
    fig = SimpleNamespace(evaluation=ev)
    assert Figure5.best_one_step.fget(fig) == "a"
    assert Figure5.accurate_horizon(fig, "a") == 2
    assert Figure5.accurate_horizon(fig, "b") == 4
    assert Figure5.accurate_horizon(fig, "c") == 0
    assert Figure5.gain(fig, "b", 3) == 1.6
