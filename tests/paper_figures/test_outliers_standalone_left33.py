"""The ``--outliers`` policy on every route of Figures 1 and 5, and what a refusal names.

Issue 27, leftovers 33-report items 3 and 4. References, outside the code:
- the option given: ``--outliers clip`` replaces the one value planted here (frame 200,
  the second mode, 5.0 in a log of RMS 0.01) and leaves every other value as written
  (compared with the array saved, numpy); ``warn`` leaves all 400 x 25 values as
  written; the report's **Outliers.** line names the policy given and "1 of 400 frames
  flagged" (the one planted frame);
- ``--outliers drop`` is refused before any figure is computed (nothing in ``--out``),
  naming the analysis that needs the frames' time axis (Figure 1's stability windows,
  Figure 5's predictors: their docstrings), not the program;
- ``--outliers`` other than the default without ``--log`` is refused (the shipped logs
  get no policy: it was ignored silently), before anything is written.
The figures themselves are replaced by recorders (``make``, ``compute``): ~3 s.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from modalinfo.io import save
from modalinfo.telemetry.log import ModalLog
from paper_figures import __main__ as pf
from paper_figures import fig1_fitting_error as fig1
from paper_figures import fig5_forecast as fig5

DROP = ("--outliers drop removes frames, which breaks the time axis {uses}; use --outliers "
        "clip (replace in place) or warn")


@pytest.fixture(scope="module")
def glitch(tmp_path_factory):
    rng = np.random.default_rng(2)
    x = rng.normal(size=(400, 25)) * 0.01
    x[200, 1] = 5.0
    path = tmp_path_factory.mktemp("log") / "glitch.npz"
    save(ModalLog(x, modes=list(range(2, 27)), convention="noll", units="rad",
                  wavelength=5e-7, rate=2000.0), path)
    return path, x


def _recording_make(calls):
    def make(stage, log_path, *, suffix="", prepared=None):
        calls.append((log_path, suffix, prepared))
        (stage / f"fig{suffix}.png").write_text("data")
        return "the report"
    return make


def _run(module, argv, make):
    from paper_figures._common import figure_main

    return figure_main(argv, prog=f"python -m paper_figures.{module.__name__.split('.')[-1]}",
                       description="d", figure_name="fig.png", make=make,
                       output_names=lambda s: [f"fig{s}.png"], time_axis=module.TIME_AXIS_USE)


@pytest.mark.parametrize("policy", ["warn", "clip"])
def test_the_stand_alone_route_applies_the_policy(glitch, tmp_path, capsys, policy):
    path, x = glitch
    calls = []
    argv = ["--log", str(path), "--out", str(tmp_path / "o")]
    argv += ["--outliers", policy] if policy == "clip" else []  # warn: the default
    assert _run(fig5, argv, _recording_make(calls)) == 0
    [(log_path, _, prepared)] = calls
    log, source, said = prepared
    assert log_path == path and source == f"`{path}`"
    expected = x.copy()
    if policy == "clip":
        assert log.coeffs[200, 1] != 5.0 and abs(log.coeffs[200, 1]) < 0.1
        expected[200, 1] = log.coeffs[200, 1]
    np.testing.assert_array_equal(log.coeffs, expected)  # nothing else touched
    assert said.startswith(f"--outliers {policy}: 1 of 400 frames flagged")
    err = capsys.readouterr().err
    assert err.startswith(f"python -m paper_figures.fig5_forecast: warning: "
                          f"'{path.name}': 1 of 400 frames flagged")
    assert err.count("\n") == 1


@pytest.mark.parametrize("module, uses", [
    (fig1, "Figure 1's stability windows need"), (fig5, "Figure 5's predictors need")])
def test_the_stand_alone_route_refuses_drop_naming_the_analysis(glitch, tmp_path, capsys,
                                                                module, uses):
    calls = []
    out = tmp_path / "o"
    argv = ["--log", str(glitch[0]), "--out", str(out), "--outliers", "drop"]
    assert _run(module, argv, _recording_make(calls)) == 2
    prog = f"python -m {module.__name__}"  # as typed, argparse's prefix (fixes 45-c, c08)
    assert capsys.readouterr().err == f"{prog}: error: --log: {DROP.format(uses=uses)}\n"
    assert calls == [] and not out.exists()


@pytest.mark.parametrize("module", [fig1, fig5])
def test_make_states_the_prepared_policy(module, tmp_path, monkeypatch):
    got = []
    monkeypatch.setattr(module, "compute", lambda log, *, source, **kw: got.append(
        (log, source, kw)) or "FIG")
    monkeypatch.setattr(module, "plot", lambda f, out, *, suffix: None)
    monkeypatch.setattr(module, "report", lambda f, *, suffix: "text")
    assert module.make(tmp_path, Path("x.npz"), prepared=("LOG", "`x.npz`", "said")) == "text"
    assert got == [("LOG", "`x.npz`", {"outliers": "said"})]


@pytest.mark.parametrize("only, uses", [
    ("1", "Figure 1's stability windows need"), ("5", "Figure 5's predictors need"),
    ("1,5", "Figure 1's stability windows and Figure 5's predictors need")])
def test_paper_figures_refuses_drop_naming_the_analysis(glitch, tmp_path, capsys, only, uses):
    out = tmp_path / "o"
    argv = ["--only", only, "--log", str(glitch[0]), "--outliers", "drop", "--out", str(out)]
    assert pf.main(argv) == 2
    assert capsys.readouterr().err == (f"python -m paper_figures: error: --log: "
                                       f"{DROP.format(uses=uses)}\n")
    assert not out.exists()


@pytest.mark.parametrize("policy", ["clip", "drop", "raise"])
def test_paper_figures_refuses_a_policy_without_a_log(tmp_path, capsys, policy):
    out = tmp_path / "o"
    assert pf.main(["--only", "1", "--outliers", policy, "--out", str(out)]) == 2
    assert capsys.readouterr().err == (
        f"python -m paper_figures: error: "
        f"--outliers {policy} applies to a user's log and needs --log; "
        "the shipped logs are analysed as they are\n")
    assert not out.exists()
