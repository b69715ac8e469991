"""Command-line tests of the shared ``--outliers warn|clip|drop|raise`` policy and ``info``'s
quality line, and of the batch analyses applying it.

References: a Gaussian log with a planted glitched frame (every mode + 100 sigma) and a
planted stuck run at known frames; the dispatcher contract (one line on stderr, exit 2
for a refusal, no traceback); clipped values checked against NumPy / SciPy's median and
normal-scaled MAD (a white mode's prediction from its past is its mean); dropped frames
against the planted indices.
"""

from __future__ import annotations

import argparse

import numpy as np
import pytest
from scipy import stats

from modalinfo.batch.analyses import resolve_params, run_log_task
from modalinfo.cli import build_parser, main
from modalinfo.cli.shared import OUTLIER_CHOICES
from modalinfo.io import load, save
from modalinfo.telemetry import OUTLIER_POLICIES, ModalLog

GLITCH = 1234
STUCK = (300, 10, 4)  # first frame, length, column


@pytest.fixture(scope="module")
def files(tmp_path_factory):
    d = tmp_path_factory.mktemp("outliers")
    rng = np.random.default_rng(11)
    clean = rng.standard_normal((4000, 6)) * 0.1
    x = clean.copy()
    x[GLITCH] += 10.0  # 100 sigma
    i, n, j = STUCK
    x[i:i + n, j] = x[i, j]
    glitch = save(ModalLog(x, rate=1000.0, wavelength=5e-7), d / "glitch.npz")
    ok = save(ModalLog(clean, rate=1000.0, wavelength=5e-7), d / "clean.npz")
    return {"glitch": glitch, "clean": ok, "x": x, "dir": d}


def _run(capsys, argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    return code, out, err.splitlines()


def test_every_log_command_has_the_flag():
    assert OUTLIER_CHOICES == OUTLIER_POLICIES
    sub = next(a for a in build_parser()._actions if isinstance(a, argparse._SubParsersAction))
    for name in ("info", "reorder", "fitting-error", "forecast", "select", "convert", "batch"):
        opts = {o for a in sub.choices[name]._actions for o in a.option_strings}
        assert "--outliers" in opts, name
        extra = {"select": ["--target", "Z2"], "batch": ["--out", "d"], "convert": ["y.npz"]}
        # select cleans by default, as select_inputs(outliers="clip") (fix56-b)
        default = "clip" if name == "select" else "warn"
        assert sub.choices[name].parse_args(["x"] + extra.get(name, [])).outliers == default


def test_info_quality_line_and_one_warning(files, capsys):
    code, out, err = _run(capsys, ["info", files["glitch"]])
    assert code == 0
    line = next(ln for ln in out.splitlines() if ln.startswith("quality"))
    assert "11 of 4000 frames flagged" in line  # the glitched frame + 10 stuck frames
    assert f"1 glitched frame(s) with outliers in >= 3 modes ({GLITCH})" in line
    assert "10 stuck value(s)" in line
    assert len(err) == 1 and err[0].startswith("modalinfo info: warning: 'glitch.npz': 11 of")
    assert "--outliers clip" in err[0]


def test_info_clean_log_is_quiet(files, capsys):
    code, out, err = _run(capsys, ["info", files["clean"]])
    assert code == 0 and err == []
    assert "quality     0 of 4000 frames flagged" in out


def test_info_raise_exits_2_with_one_line(files, capsys):
    code, out, err = _run(capsys, ["info", files["glitch"], "--outliers", "raise"])
    assert code == 2 and out == ""
    assert len(err) == 1 and err[0].startswith("modalinfo info: error: --outliers raise: "
                                               "'glitch.npz': 11 of 4000 frames flagged")


def test_info_drop_summarises_kept_frames(files, capsys):
    code, out, err = _run(capsys, ["info", files["glitch"], "--outliers", "drop"])
    assert code == 0 and len(err) == 1 and "dropped 11 of 4000 frames" in err[0]
    assert "--outliers drop: dropped 11 of 4000 frames" in out
    keep = np.ones(4000, dtype=bool)
    keep[GLITCH] = False
    keep[STUCK[0]:STUCK[0] + STUCK[1]] = False
    row = next(ln for ln in out.splitlines() if ln.startswith("Z2 "))
    assert float(row.split()[1]) == pytest.approx(files["x"][keep, 0].mean(), rel=1e-4)


@pytest.mark.parametrize("argv, what", [
    (["forecast", "{g}", "--outliers", "drop"], "forecasting"),
    (["select", "{g}", "--target", "Z2", "--outliers", "drop"], "input selection"),
    (["reorder", "{g}", "--frame", "3", "--outliers", "drop"], "renumbers the frames"),
    (["fitting-error", "{g}", "--frame", "3", "--outliers", "drop"], "renumbers the frames"),
    (["reorder", "{g}", "--outliers", "drop"], "block bootstrap"),  # default --resamples 20
])
def test_drop_refused_where_frames_matter(files, capsys, argv, what):
    argv = [a.format(g=files["glitch"]) for a in argv]
    code, out, err = _run(capsys, argv)
    assert code == 2 and out == ""
    assert len(err) == 1 and "--outliers drop" in err[0] and what in err[0]


def test_forecast_raise_and_clip(files, capsys, tmp_path):
    base = ["forecast", files["glitch"], "--predictors", "linear", "--horizon", "1",
            "--modes", "2-3"]
    code, _, err = _run(capsys, base + ["--outliers", "raise"])
    assert code == 2 and len(err) == 1 and "error: --outliers raise" in err[0]
    code, out, err = _run(capsys, base + ["--outliers", "clip", "--quiet", "--out", tmp_path])
    assert code == 0 and out == ""
    assert len(err) == 1 and "clipped 2 outlier value(s)" in err[0]


def test_convert_clip_writes_clipped_log_with_record(files, capsys):
    dst = files["dir"] / "clipped.npz"
    code, _, err = _run(capsys, ["convert", files["glitch"], dst, "--outliers", "clip"])
    assert code == 0 and len(err) == 1 and "warning" in err[0]
    x = files["x"]
    med = np.median(x, axis=0)
    sig = stats.median_abs_deviation(x, axis=0, scale="normal")
    back = load(dst)
    k = back.metadata["outliers"][-1]["k"]
    assert k == pytest.approx(stats.norm.isf(0.005 / x.size), rel=1e-9)
    # the glitched frame's values replaced by their prediction from the white past, about
    # the median (AR(4) coefficients O(1 / sqrt(T)): within ~0.03 sigma; 0.2 allowed);
    # every other value kept
    changed = back.coeffs != x
    assert changed[GLITCH].all() and changed.sum() == x.shape[1]
    np.testing.assert_array_less(np.abs(back.coeffs[GLITCH] - med), 0.2 * sig)
    assert back.metadata["outliers"][-1]["policy"] == "clip"
    # the clipped file says so in info; its remaining stuck run is still reported
    code, out, _ = _run(capsys, ["info", dst])
    assert "outliers    earlier: clip: clipped 6 outlier value(s)" in out
    assert "quality     10 of 4000 frames flagged: 10 stuck value(s)" in out


def test_batch_task_rows_carry_quality(files):
    payload = {"path": str(files["glitch"]), "fmt": None, "hints": {},
               "analysis": "summary", "params": resolve_params("summary")}
    row = run_log_task(payload)
    assert row["outliers"] == "warn" and row["quality_flagged_frames"] == 11
    assert row["quality_glitched_frames"] == 1 and row["quality_stuck_values"] == 10
    clipped = run_log_task({**payload, "params": resolve_params("summary",
                                                                 {"outliers": "clip"})})
    x = files["x"]
    med = np.median(x, axis=0)
    # the glitched frame replaced by about its median (within 0.2 sigma: see above) moves
    # the rms of 4000 frames by < 1e-5 of it
    y = x.copy()
    y[GLITCH] = med
    rms = np.sqrt(np.mean(y**2, axis=0))
    assert clipped["largest_rms"] == pytest.approx(rms.max(), rel=1e-5)
    assert clipped["quality_action"].startswith("clipped 6 outlier value(s)")
    with pytest.raises(ValueError, match="'raise'"):
        run_log_task({**payload, "params": resolve_params("summary", {"outliers": "raise"})})
    with pytest.raises(ValueError, match="forecast.outliers"):
        resolve_params("forecast", {"outliers": "drop"})


def test_batch_cli_refuses_drop_with_forecast(files, capsys):
    code, out, err = _run(capsys, ["batch", files["glitch"], "--analyses", "forecast",
                                   "--out", files["dir"] / "b", "--outliers", "drop"])
    assert code == 2 and len(err) == 1 and "forecast analysis" in err[0]
    assert not (files["dir"] / "b").exists()


def _first_ranks(out: str, n: int = 10) -> list[str]:
    rows = [ln.split() for ln in out.splitlines()]
    return [r[1] for r in rows if r and r[0].lstrip("~").isdigit() and int(r[0].lstrip("~")) <= n]


def test_reorder_clip_restores_the_order_of_the_clean_log(tmp_path, capsys):
    """Issue 27: one frame of 4000 with Z2 at 100 sigma; ``--outliers clip`` gives the
    clean log's first 10 ranks and the glitch is reported (the shipped closed-loop log)."""
    from pathlib import Path

    data = Path(__file__).resolve().parents[2] / "data" / "kaos_like_closed_loop.npz"
    log = load(data)[:4000]
    y = np.array(log.coeffs)
    y[2000, 0] += 100 * y[:, 0].std()
    clean = save(log, tmp_path / "clean.npz")
    glitch = save(ModalLog(y, rate=log.rate, modes=log.modes, units=log.units,
                           wavelength=log.wavelength), tmp_path / "glitch.npz")
    fast = ["--resamples", "0", "--budget", "50000", "--pupil-pixels", "32"]
    code, out_clean, err = _run(capsys, ["reorder", clean, *fast])
    assert code == 0 and err == []
    code, out_clip, err = _run(capsys, ["reorder", glitch, *fast, "--outliers", "clip"])
    assert code == 0 and len(err) == 1
    assert ("1 of 4000 frames flagged: 1 outlier value(s) in 1 frame(s) (frames 2000; "
            "most: Z2 1)") in err[0]
    assert "clipped 1 outlier value(s)" in err[0]
    assert len(_first_ranks(out_clean)) == 10
    assert _first_ranks(out_clip) == _first_ranks(out_clean)


def test_batch_cli_warns_once_for_flagged_logs(files, tmp_path, capsys):
    """The batch's warn line, from the rows of a run on an in-process Dask cluster
    (the CLI then resumes it: every task done, no cluster needed)."""
    distributed = pytest.importorskip("distributed")
    from modalinfo.batch import analyse_archive

    src = tmp_path / "logs"
    src.mkdir()
    for name in ("glitch.npz", "clean.npz"):
        (src / name).write_bytes(files[name.split(".")[0]].read_bytes())
    out = tmp_path / "out"
    with distributed.Client(processes=False, n_workers=1, threads_per_worker=1,
                            dashboard_address=":0") as client:
        analyse_archive(src, "summary", out, client=client, progress=False, plots=False)
    capsys.readouterr()
    code, _, err = _run(capsys, ["batch", src, "--out", out, "--no-plots", "--quiet"])
    assert code == 0 and len(err) == 1
    assert err[0].startswith("modalinfo batch: warning: 1 log(s) have frames flagged")
    assert "outlier policy applied: summary: warn on 1 log(s) (--outliers clip" in err[0]


def test_paper_figures_log_goes_through_the_policy(files, tmp_path, capsys):
    from paper_figures.__main__ import main as figures

    for policy, what in (("drop", "--outliers drop removes frames"),
                         ("raise", "--outliers raise: 'glitch.npz': 11 of 4000")):
        code = figures(["--log", str(files["glitch"]), "--only", "1", "--out",
                        str(tmp_path / "figs"), "--outliers", policy])
        err = capsys.readouterr().err.splitlines()
        assert code == 2 and len(err) == 1 and what in err[0]
        assert not (tmp_path / "figs").exists()


def test_reorder_drop_without_bootstrap_removes_the_glitch(files, capsys):
    # no --budget: variance uses no MI samples (refused since round 17 PART b)
    fast = ["--resamples", "0", "--pupil-pixels", "16", "--method", "variance"]
    code, out, err = _run(capsys, ["reorder", files["glitch"], *fast, "--outliers", "drop"])
    assert code == 0 and len(err) == 1 and "dropped 11 of 4000 frames" in err[0]
    keep = np.ones(4000, dtype=bool)
    keep[GLITCH] = False
    keep[STUCK[0]:STUCK[0] + STUCK[1]] = False
    ms = np.mean(files["x"][keep] ** 2, axis=0)  # variance order: mean-square coefficient
    labels = [f"Z{j}" for j in range(2, 8)]
    assert _first_ranks(out, 6) == [labels[j] for j in np.argsort(-ms, kind="stable")]
