"""closedloop.studies.sensitivity: the variations, the rows, the table and the command.

Gaps found by mutation testing (docs/MUTATION.md, "closedloop/studies/sensitivity.py").
No closed loop is run: ``simulate`` is replaced by a recorder returning
:class:`~closedloop.result.SimulationResult` objects whose residual variances and budget
are written in the test (``test_loop.py::test_sensitivity_rows`` runs the real loop).
References, from outside the code under test:

- the variations' labels read as numbers ("5 km" -> 5000 m on the upper layer, its DM
  and its WFS; ``"40\\", 10\\""`` -> the ground and upper WFS fields; ...), checked as the
  only differences between the changed config's and table1's ``to_dict()``;
- the rows by hand from the variances set in the test: SR = exp(-variance) (Marechal),
  its peak over directions averaged from the run's ``closure_index`` on, the field mean;
  the science-wavelength rows rescale the variance by ``(lambda0 / lambda)^2`` (phase
  variance ~ lambda^-2), their corrected field is that of a run built here with the
  rescaled variance; the budget terms of the direction nearest the axis, rescaled too;
- the documented defaults (table1, 0.3 s, seed 0, a budget every 5 frames, the
  wavelengths 500 and 800 nm) and the Markdown table / command output written out.
"""

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from closedloop import presets
from closedloop.config import FieldConfig
from closedloop.result import SimulationResult
from closedloop.studies import sensitivity as sens


def _flat(d, prefix=()):
    if isinstance(d, dict):
        out = {}
        for k, v in d.items():
            out.update(_flat(v, (*prefix, k)))
        return out
    if isinstance(d, list | tuple):
        out = {}
        for i, v in enumerate(d):
            out.update(_flat(v, (*prefix, i)))
        return out
    return {prefix: d}


def _diff(a, b):
    fa, fb = _flat(a.to_dict()), _flat(b.to_dict())
    assert fa.keys() == fb.keys()
    return {k: fb[k] for k in fa if fa[k] != fb[k]}


EXPECTED = [
    ("upper-layer altitude", "5 km", {("layers", 1, "altitude"): 5000.0,
                                      ("dms", 1, "altitude"): 5000.0,
                                      ("wfss", 1, "altitude"): 5000.0}),
    ("upper-layer altitude", "15 km", {("layers", 1, "altitude"): 15000.0,
                                       ("dms", 1, "altitude"): 15000.0,
                                       ("wfss", 1, "altitude"): 15000.0}),
    ("WFS fields (ground, upper)", "40\", 10\"", {("wfss", 0, "field_of_view"): 40.0,
                                                 ("wfss", 1, "field_of_view"): 10.0}),
    ("WFS fields (ground, upper)", "90\", 30\"", {("wfss", 0, "field_of_view"): 90.0,
                                                 ("wfss", 1, "field_of_view"): 30.0}),
    ("modes per DM (ground, upper)", "65, 35", {("dms", 0, "n_modes"): 65,
                                                ("dms", 1, "n_modes"): 35}),
    ("modes per DM (ground, upper)", "189, 90", {("dms", 0, "n_modes"): 189,
                                                 ("dms", 1, "n_modes"): 90}),
    ("reconstructor model error", "0.1", {("loop", "model_error"): 0.1}),
    ("reconstructor model error", "1.0", {("loop", "model_error"): 1.0}),
]


def test_variations_change_what_their_labels_say_and_nothing_else():
    base = presets.get("table1")
    assert [(p, v) for p, v, _ in sens.VARIATIONS] == [(p, v) for p, v, _ in EXPECTED]
    for (_, _, change), (p, v, want) in zip(sens.VARIATIONS, EXPECTED, strict=True):
        got = _diff(base, change(base))
        assert got == want, (p, v)
        for key, value in want.items():
            assert type(got[key]) is type(value), (p, v, key)


# ------------------------------------------------------------------ rows, on set runs
FIELD = FieldConfig(size=60.0, n_points=3)


def _grid(cfg):
    """The science directions (row-major, y rows) and one frame's variance per direction:
    ``0.2 + 0.7 (r / half-field)^2`` rad^2 (3 x 3 over 60": centre 0.2, edges 0.9,
    corners 1.6)."""
    half = cfg.field.size / 2
    v = np.linspace(-half, half, cfg.field.n_points)
    yy, xx = np.meshgrid(v, v, indexing="ij")
    return (np.column_stack([xx.ravel(), yy.ravel()]),
            0.2 + 0.7 * ((xx ** 2 + yy ** 2) / half ** 2).ravel())


def _variance(pattern, k):
    """12 frames: 3 unclosed (8 rad^2), then the pattern scaled by 1 + 0.1 k, wobbling."""
    wobble = 1.0 + 0.02 * np.array([0, 1, -1, 0, 1, -1, 0, 1, -1])
    v = np.outer(wobble, pattern * (1.0 + 0.1 * k))
    return np.vstack([np.full((3, pattern.size), 8.0), v])


def _budget(k):
    # the direction nearest the axis is the third (0.2" off axis), not the first or last;
    # each term has its own value there
    directions = np.array([[-30.0, -30.0], [10.0, 0.0], [0.0, -0.2], [5.0, 5.0]])
    terms = {t: np.array([7.0, 7.0, 0.01 * (i + 1) + k, 7.0]) for i, t in
             enumerate(("fitting", "aliasing", "temporal", "noise", "measured"))}
    return SimpleNamespace(directions=directions, **terms)


def _run(cfg, k, budget=True):
    directions, pattern = _grid(cfg)
    variance = _variance(pattern, k)
    return SimulationResult(config=cfg, seed=0, predictor="none",
                            times=np.arange(1, variance.shape[0] + 1) * cfg.loop.time_step,
                            directions=directions, residual_variance=variance,
                            budget=_budget(k) if budget else None)


@pytest.fixture
def recorder(monkeypatch):
    calls = []

    def simulate(cfg, duration, *, seed, progress, budget_every):
        calls.append(dict(cfg=cfg, duration=duration, seed=seed, progress=progress,
                          budget_every=budget_every))
        return _run(cfg, len(calls) - 1, budget=budget_every is not None)

    monkeypatch.setattr(sens, "simulate", simulate)
    return calls


def _by_hand(run, scale):
    start = run.closure_index
    sr = np.exp(-run.residual_variance[start:] * scale)
    return sr.max(axis=1).mean(), sr.mean()


def test_rows_by_hand(recorder):
    base = presets.get("table1").replace(field=FIELD)

    def smaller(c):
        return c.replace(wavelength=700e-9)

    rows = sens.sensitivity(base, duration=0.012, seed=3, budget_every=2,
                            variations=[("science band", "700 nm", smaller)], progress=True)
    assert [c["cfg"] for c in recorder] == [base, smaller(base)]
    assert all((c["duration"], c["seed"], c["progress"], c["budget_every"])
               == (0.012, 3, True, 2) for c in recorder)
    assert [(r["parameter"], r["value"]) for r in rows] == [
        ("(table1 defaults)", ""), ("science wavelength", "500 nm"),
        ("science wavelength", "800 nm"), ("science band", "700 nm")]
    ref, var = _run(base, 0), _run(smaller(base), 1)
    assert ref.closure_index == 3  # the three unclosed frames
    for row, run, scale in ((rows[0], ref, 1.0), (rows[1], ref, (630 / 500) ** 2),
                            (rows[2], ref, (630 / 800) ** 2), (rows[3], var, 1.0)):
        peak, mean = _by_hand(run, scale)
        assert row["strehl_peak"] == pytest.approx(peak, rel=1e-12)
        assert row["strehl_field"] == pytest.approx(mean, rel=1e-12)
        scaled = dataclasses.replace(run, residual_variance=run.residual_variance * scale)
        assert row["fov_arcmin"] == pytest.approx(scaled.corrected_fov_diameter(0.3),
                                                  rel=1e-12)
        k = 1 if run is var else 0
        for i, t in enumerate(("fitting", "aliasing", "temporal", "noise", "measured")):
            assert row[t] == pytest.approx((0.01 * (i + 1) + k) * scale, rel=1e-12)
        assert set(row) == {"parameter", "value", "strehl_peak", "strehl_field",
                            "fov_arcmin", "fitting", "aliasing", "temporal", "noise",
                            "measured"}
    # the corrected fields differ between the bands (the rescaling is seen by the FoV)
    fovs = [r["fov_arcmin"] for r in rows[:3]]
    assert len(set(fovs)) == 3 and fovs[1] < fovs[0] < fovs[2]


def test_rows_without_a_budget_have_no_terms(recorder):
    base = presets.get("table1").replace(field=FIELD)
    rows = sens.sensitivity(base, duration=0.012, budget_every=None, variations=[])
    assert len(rows) == 3
    assert all(set(r) == {"parameter", "value", "strehl_peak", "strehl_field", "fov_arcmin"}
               for r in rows)
    assert [c["budget_every"] for c in recorder] == [None]


def test_documented_defaults(recorder):
    rows = sens.sensitivity()
    table1 = presets.get("table1")
    assert [c["cfg"] for c in recorder] == [table1] + [ch(table1) for _, _, ch in
                                                      sens.VARIATIONS]
    assert all((c["duration"], c["seed"], c["progress"], c["budget_every"])
               == (0.3, 0, None, 5) for c in recorder)
    assert [(r["parameter"], r["value"]) for r in rows[3:]] == [
        (p, v) for p, v, _ in EXPECTED]
    assert [r["value"] for r in rows[:3]] == ["", "500 nm", "800 nm"]


# ------------------------------------------------------------------ the table, the command
ROWS = [
    {"parameter": "(table1 defaults)", "value": "", "strehl_peak": 0.51234,
     "strehl_field": 0.3, "fov_arcmin": 1.23456, "fitting": 0.1, "aliasing": 0.0204,
     "temporal": 0.3, "noise": 0.0005, "measured": 1.2345},
    {"parameter": "modes", "value": "20", "strehl_peak": 0.4, "strehl_field": 0.25,
     "fov_arcmin": float("nan")},
]
TABLE = (
    "| parameter | value | SR peak | SR field mean | FoV d [arcmin] | fitting | aliasing | "
    "temporal | noise | measured (on axis, rad^2) |\n"
    "|---|---|---|---|---|---|---|---|---|---|\n"
    "| (table1 defaults) |  | 0.512 | 0.300 | 1.23 | 0.100 | 0.020 | 0.300 | 0.001 | 1.234 |\n"
    "| modes | 20 | 0.400 | 0.250 | nan |  |  |  |  |  |")


def test_markdown_whole_text():
    assert sens.markdown(ROWS) == TABLE


def test_main_prints_the_table(monkeypatch, capsys):
    calls = []

    def fake(**kw):
        calls.append(kw)
        return ROWS

    monkeypatch.setattr(sens, "sensitivity", fake)
    assert sens.main([]) == 0
    assert calls == [{"duration": 0.3, "seed": 0}]
    out = capsys.readouterr().out
    assert out == ("table1 sensitivity: seed 0, 0.3 s per run, no prediction, one default "
                   "changed at a time\n\n" + TABLE + "\n")
    assert sens.main(["--duration", "0.05", "--seed", "7"]) == 0
    assert calls[-1] == {"duration": 0.05, "seed": 7}
    assert capsys.readouterr().out.startswith("table1 sensitivity: seed 7, 0.05 s per run,")


@pytest.mark.parametrize("exc", [ValueError, TypeError])
def test_main_refuses_in_one_line(monkeypatch, capsys, exc):
    def fake(**kw):
        raise exc("`duration` must be > 0; got -1.\nsecond line")

    monkeypatch.setattr(sens, "sensitivity", fake)
    assert sens.main(["--duration", "-1"]) == 2
    captured = capsys.readouterr()
    assert captured.err == "sensitivity: error: `duration` must be > 0; got -1.\n"
    assert captured.out == ""


def test_main_usage_error_names_the_program(capsys):
    with pytest.raises(SystemExit) as exit_:
        sens.main(["--seed", "x"])
    assert exit_.value.code == 2
    err = capsys.readouterr().err
    assert err.startswith("python -m closedloop.studies.sensitivity: error: ")
    assert err.count("\n") == 1
