"""Figure 7 (solar correlating sensing): its rows, its JSON, its refusals.

References, from outside the module under test:
- the rows of the comparison table are recomputed here from the JSON file the figure
  wrote (each number read from the file and formatted by the test), so the table is
  shown to quote the run's numbers and not typed text;
- table1's numbers in the JSON are recomputed from the table1 runs with numpy (mean SR
  peak over the frames from the no-prediction run's closure, Figure 2's definition; the
  corrected-FoV diameter of each run) and the solar ones from the solar runs the same way;
- physics: with fewer photons (``signal``) or a lower granulation contrast the
  correlation noise grows (Michau et al. 1992: variance ~ 1 / (photons contrast^2)), so
  the sensitivity rows' noise term must grow, never shrink;
- the no-overwrite rule of every figure: existing outputs are refused (exit 2, one line)
  before any computation and left as they were.

The fixture runs a reduced Figure 7 (table1 and table1-solar shrunk to 32 pupil pixels,
8 subapertures and a 3x3 grid, 0.1 s, no prediction, linear and the oracle, two
sensitivity knobs); ``--quick`` through ``python -m paper_figures --only 7`` is
the slow test (``test_main_quick`` runs it in the default tier with every figure).
"""

import json
import math

import numpy as np
import pytest

from paper_figures import closedloop_runs, fig7_solar
from paper_figures.__main__ import main
from paper_figures.closedloop_runs import LABELS

PREDICTORS = ("none", "linear", "oracle")
VALUES = {"signal": (150.0,), "contrast": (0.03,)}


def _small(name):
    """A preset shrunk for speed (32 pupil pixels, 8 subapertures, few modes, 3x3 grid)."""
    import dataclasses

    from closedloop import presets
    from closedloop.config import FieldConfig

    cfg = presets.get(name)
    return cfg.replace(
        telescope=dataclasses.replace(cfg.telescope, n_pixels=32),
        dms=tuple(dataclasses.replace(d, n_modes=m) for d, m in zip(cfg.dms, (20, 9),
                                                                   strict=True)),
        wfss=tuple(dataclasses.replace(w, n_subapertures=8, field_samples=2)
                   for w in cfg.wfss),
        field=FieldConfig(size=cfg.field.size, n_points=3))


@pytest.fixture(scope="module")
def made(tmp_path_factory):
    out = tmp_path_factory.mktemp("fig7")
    runs = closedloop_runs.compute(config=_small("table1"), quick=True, duration=0.1,
                                   names=PREDICTORS, log=lambda s: None)
    fig7 = fig7_solar.compute(runs, config=_small("table1-solar"), predictors=PREDICTORS,
                              sensitivity_predictors=("none",), sensitivity_values=VALUES,
                              log=lambda s: None)
    paths = fig7_solar.plot(fig7, out)
    return out, runs, fig7, paths


@pytest.fixture(scope="module")
def numbers(made):
    out = made[0]
    # strict JSON: no NaN or Infinity tokens
    text = (out / fig7_solar.JSON_NAME).read_text()
    return json.loads(text, parse_constant=lambda c: pytest.fail(f"non-JSON constant {c}"))


def _row(rows, quantity):
    found = [r for r in rows if r[0] == quantity]
    assert len(found) == 1, quantity
    return found[0]


def test_files_written(made):
    out, _, _, paths = made
    assert [p.name for p in paths] == [fig7_solar.FIGURE_NAME, fig7_solar.PDF_NAME,
                                       fig7_solar.JSON_NAME]
    assert (out / fig7_solar.FIGURE_NAME).stat().st_size > 10_000


def test_rows_recomputed_from_the_json(made, numbers):
    fig7 = made[2]
    rows = fig7_solar.table_rows(fig7)
    sol, t1 = numbers["solar"], numbers["table1"]
    assert sol["config"] == "table1-solar" and t1["config"] == "table1"
    for p in PREDICTORS:
        r = _row(rows, f"SR peak, {LABELS[p]}, table1-solar (extension)")
        assert r[2] == f"{sol['peak_mean'][p]:.3f} (table1 {t1['peak_mean'][p]:.3f})"
        if p != "none":
            ratio = sol["peak_mean"][p] / sol["peak_mean"]["none"]
            assert r[3].startswith(f"x{ratio:.3f} over no prediction")
    for p in ("none",):
        r = _row(rows, f"corrected FoV d, {LABELS[p]}, table1-solar (extension)")
        assert r[2] == f"{sol['fov'][p]:.2f}' (table1 {t1['fov'][p]:.2f}')"
    b = sol["budget"]
    r = _row(rows, "error budget at the best direction, table1-solar (extension)")
    assert r[2] == (f"fitting {b['fitting']:.3f} + aliasing {b['aliasing']:.3f} + temporal "
                    f"{b['temporal']:.3f} + noise {b['noise']:.4f} rad^2 (measured "
                    f"{b['measured']:.3f})")
    for rtc, lat in numbers["latency"].items():
        r = _row(rows, f"correlation latency, {rtc} RTC (extension)")
        assert f"{lat['compute_ms']:.2f} ms of correlation" in r[2]
        if lat["delay_ms"] is not None:
            assert r[2].endswith(f"delay {lat['delay_ms']:.3f} ms")
    # the rows made from the file equal the rows of the figure's own numbers
    assert fig7_solar.table_rows(numbers) == rows


def test_numbers_are_the_runs(made, numbers):
    _, runs, fig7, _ = made
    for key, r in (("table1", runs), ("solar", fig7.solar)):
        start = r.runs["none"].closure_index
        for p in PREDICTORS:
            peak = float(np.mean(r.runs[p].strehl_peak[start:]))
            assert numbers[key]["peak_mean"][p] == pytest.approx(peak, rel=1e-12)
            assert numbers[key]["fov"][p] == pytest.approx(r.runs[p].fov_diameter, rel=1e-12)
    # the solar runs are the same atmosphere, duration and grid as the table1 runs
    assert fig7.solar.seed == runs.seed and fig7.solar.duration == runs.duration
    assert fig7.solar.runs["none"].strehl_map.shape == runs.runs["none"].strehl_map.shape


def test_less_signal_or_contrast_means_more_noise(numbers):
    rows = {(r["knob"], r["value"]): r for r in numbers["sensitivity"]
            if r["predictor"] == "none"}
    base = rows[("base", "")]["noise"]
    assert base > 0
    assert rows[("signal", "150 e-")]["noise"] > base
    assert rows[("contrast", "0.03")]["noise"] > base


def test_report_section(made):
    text = fig7_solar.report(made[2])
    assert text.startswith("## Figure 7: ")
    assert "not in the paper" in text and f"({fig7_solar.FIGURE_NAME})" in text
    assert "| (base) |" in text  # the sensitivity table


@pytest.mark.parametrize("name", [fig7_solar.FIGURE_NAME, fig7_solar.JSON_NAME])
def test_existing_outputs_are_refused_before_any_work(tmp_path, capsys, monkeypatch, name):
    def boom(*a, **k):
        raise AssertionError("computed before refusing")

    monkeypatch.setattr(closedloop_runs, "compute", boom)
    (tmp_path / name).write_text("mine")
    assert main(["--out", str(tmp_path), "--only", "7"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and name in err and "--overwrite" in err
    assert fig7_solar.main(["--out", str(tmp_path)]) == 2
    assert (tmp_path / name).read_text() == "mine"


def test_registered_as_figure_7():
    from paper_figures import FIGURES

    entry = [f for f in FIGURES if f[0] == "fig7_solar"]
    assert entry and entry[0][1] == "Figure 7" and "not in the paper" in entry[0][2]


@pytest.mark.slow
def test_quick_main_makes_figure_7(tmp_path):
    assert main(["--out", str(tmp_path), "--only", "7", "--quick"]) == 0
    report = (tmp_path / "report.md").read_text()
    assert "## Figure 7" in report
    numbers = json.loads((tmp_path / fig7_solar.JSON_NAME).read_text())
    assert numbers["quick"] is True
    assert sorted(numbers["solar"]["peak_mean"]) == sorted(fig7_solar.QUICK_PREDICTORS)
    for p in fig7_solar.QUICK_PREDICTORS:
        v = numbers["solar"]["peak_mean"][p]
        assert math.isfinite(v) and f"{v:.3f}" in report
