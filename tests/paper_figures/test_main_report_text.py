"""``python -m paper_figures``: the report's text and table, assembled from known figures.

Gaps found by mutation testing (docs/MUTATION.md, "paper_figures/__main__.py"). Every
figure module is replaced by a stand-in whose sections and table rows are set here, and
the clock by one that advances 1, 2, 3, ... s per reading, so the whole ``report.md`` is
known in advance. Reference: the report contract (``paper_figures/__init__.py`` and
``__main__.py``'s docstrings) written out by hand: a heading, a line naming the Python,
the machine, the package version (``modalinfo.__version__`` and its source fingerprint),
the time and (``--quick``) the smoke-run notice and the input logs; the
comparison table of every figure's rows tagged with its figure (and log); then one
section per figure, each closed by its time, with the shared closed-loop runs' section
before the first figure that draws them and the logs' comparison last. The options a
figure receives (``quick``, ``seed``, ``duration``) are the command line's. The shipped
logs are read for real; the input logs' SHA-256 is ``hashlib``'s of their bytes.
"""

from __future__ import annotations

import hashlib
import platform
from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from modalinfo.io import save
from modalinfo.telemetry.log import ModalLog
from paper_figures import __main__ as pf
from paper_figures.__main__ import DEFAULT_LOG, SIMULATED_LOG, main

TITLES = {f"Figure {i}": t for i, (_, _, t) in enumerate(pf.FIGURES, start=1)}


class _Fig:
    """A figure module: ``kind`` "log" (Figures 1, 5), "runs" (2-4, 7) or "own" (6, 8)."""

    def __init__(self, number, kind, quick_param=False, fail=None):
        self.number, self.kind, self.fail, self.calls = number, kind, fail, []
        self.frames = []  # n_frames of each log computed on
        if kind == "runs":
            self.NEEDS_RUNS = True
        elif kind == "own":
            self.NEEDS_LOG = False
        self.FIGURE_NAME, self.PDF_NAME = f"f{number}.png", f"f{number}.pdf"
        if kind != "log":
            self.JSON_NAME = f"f{number}.json"
        if kind == "log":
            if quick_param:
                self.compute = self._compute_quick
            else:
                self.compute = self._compute_log
        elif kind == "runs":
            self.compute = self._compute_runs
        else:
            self.compute = self._compute_own

    def check_log(self, log):
        self.calls.append(("check", log.n_frames))

    def output_names(self, suffix):
        return [f"f{self.number}{suffix}.png"]

    def _compute_log(self, log, *, source):
        self.frames.append(log.n_frames)
        return self._result(("log", source))

    def _compute_quick(self, log, *, source, quick=False):
        self.frames.append(log.n_frames)
        return self._result(("log", source, quick))

    def _compute_runs(self, runs):
        return self._result(("runs", runs))

    def _compute_own(self, *, quick, seed):
        return self._result(("own", quick, seed))

    def _result(self, call):
        self.calls.append(call)
        if self.fail is not None:
            raise self.fail
        return f"r{self.number}.{len(self.calls)}"

    def plot(self, result, out_dir, *, suffix=""):
        names = self.output_names(suffix) if self.kind == "log" else [self.FIGURE_NAME,
                                                                       self.PDF_NAME,
                                                                       self.JSON_NAME]
        for name in names:
            (out_dir / name).write_bytes(result.encode())

    def report(self, result, *, suffix=""):
        return f"## Figure {self.number}: about {result}\n\nbody {result}{suffix}\n\n\n"

    def table_rows(self, result):
        return [(f"q{self.number}", "paper", f"ours {result}", "why")]


@pytest.fixture
def figs(monkeypatch):
    import importlib

    from paper_figures import closedloop_runs, logs_compared

    mods = {"fig1_fitting_error": _Fig(1, "log"), "fig2_sr_peak": _Fig(2, "runs"),
            "fig3_sr_spectrum": _Fig(3, "runs"), "fig4_sr_maps": _Fig(4, "runs"),
            "fig5_forecast": _Fig(5, "log", quick_param=True),
            "fig6_compression": _Fig(6, "own"), "fig7_solar": _Fig(7, "runs"),
            "fig_information_flow": _Fig(8, "own")}
    real_import = importlib.import_module

    def fake_import(name, *args):
        short = name.rpartition(".")[2]
        return mods[short] if short in mods else real_import(name, *args)

    monkeypatch.setattr("paper_figures.__main__.importlib.import_module", fake_import)
    runs_calls, cmp_calls = [], []

    def runs_compute(**kw):
        runs_calls.append(kw)
        return "RUNS"

    monkeypatch.setattr(closedloop_runs, "compute", runs_compute)
    monkeypatch.setattr(closedloop_runs, "report_section",
                        lambda runs, t: f"## runs {runs} in {t:.1f} s\n")

    def cmp_compute(spectral, simulated):
        cmp_calls.append((spectral.n_modes, simulated.n_modes))
        return "CMP"

    def cmp_report(cmp, fig1, fig5):
        cmp_calls.append((cmp, fig1, fig5))
        return "## logs compared\n"

    monkeypatch.setattr(logs_compared, "compute", cmp_compute)
    monkeypatch.setattr(logs_compared, "report", cmp_report)
    ticks = iter(100 + np.cumsum(np.arange(0, 100)))  # 100, 101, 103, 106: steps 1, 2, 3
    monkeypatch.setattr(pf, "time", SimpleNamespace(perf_counter=lambda: float(next(ticks))))
    return SimpleNamespace(mods=mods, runs=runs_calls, cmp=cmp_calls)


def _table(rows):
    return "\n".join(["| figure | quantity | paper | ours | why they differ |",
                      "|---|---|---|---|---|"] + [f"| {f} | {q} | paper | {o} | why |"
                                                  for f, q, o in rows])


def _version() -> str:
    # the version number and 12 hex digits of the source fingerprint (package_version's
    # documented form), read from the installed package
    import modalinfo
    from modalinfo.common.provenance import git_describe, source_sha256
    from modalinfo.common.tasks.keys import source_fingerprint

    # and (round 43 PART b, R04) the git commit and the SHA-256 of the source listing of
    # modalinfo, closedloop and paper_figures, as the figures' records carry them
    git, sha = git_describe(), source_sha256()
    return (f"{modalinfo.__version__}+src.{source_fingerprint()[:12]} (git {git or 'unknown'}, "
            f"source SHA-256 {sha or 'unknown'} of modalinfo, closedloop and paper_figures)")


def _sha(path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


#: the figures that read the logs, named as the head names them: only those made
#: ("Input logs of Figures 1 and 5" after --only 1: leftovers 33-report)
_LOG_FIGURES = {(1,): "Figure 1", (5,): "Figure 5", (1, 5): "Figures 1 and 5"}


def _head(seconds, quick, logs, rows, made=range(1, 9)):
    log_figures = tuple(k for k in sorted(made) if k in (1, 5))
    # a partial run names what it made and what it did not (round 22 PART b, g15)
    partial = ("" if set(made) == set(range(1, 9)) else
               " A partial run (`--only`): made "
               + ", ".join(f"Figure {k}" for k in sorted(made)) + "; not made here: "
               + ", ".join(f"Figure {k}" for k in range(1, 9) if k not in made) + ".")
    line = (f"Python {platform.python_version()}, {platform.machine()}; modalinfo "
            f"{_version()}; made in {seconds} s"
            + (" with `--quick` (a smoke run on reduced settings: numbers not the paper's)"
               if quick else "") + "." + partial
            + (f" Input log{'s' if len(logs) > 1 else ''} of {_LOG_FIGURES[log_figures]}: "
               + ", ".join(logs) + "." if logs else ""))
    return "\n".join([
        "# modalinfo: regenerated figures of Stangalini et al., LOST MCAO simulations\n",
        line + "\n",
        "## The paper's numbers beside ours\n",
        "Every number in the *ours* column is computed by this run (the paper's column "
        "quotes the paper); the last column says why they differ.\n",
        _table(rows) + "\n"])


def test_report_of_log_runs_and_own_figures_written_by_hand(figs, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["--only", "6,1,2,5", "--quick", "--seed", "5", "--duration", "0.1",
                 "--out", str(out)]) == 0
    m = figs.mods
    spectral, simulated = f"`{DEFAULT_LOG}`", f"`{SIMULATED_LOG}`"
    # Figure 1: both shipped logs, no quick option; Figure 5: quick=True
    assert [c for c in m["fig1_fitting_error"].calls if c[0] == "log"] == [
        ("log", spectral), ("log", simulated)]
    assert [c for c in m["fig5_forecast"].calls if c[0] == "log"] == [
        ("log", spectral, True), ("log", simulated, True)]
    assert m["fig2_sr_peak"].calls == [("runs", "RUNS")]
    assert m["fig6_compression"].calls == [("own", True, 5)]
    assert figs.runs == [{"quick": True, "duration": 0.1, "seed": 5}]
    # the clock: total from 0; Figure 1 from 1 to 3, its log pass; runs 6 -> 10, ...
    d1 = "spectral KAOS-like log"
    d2 = "simulated kaos closed-loop log"
    # (each figure's results are numbered by its calls: the two log checks come first)
    rows = [(f"Figure 1 ({d1})", "q1", "ours r1.3"), (f"Figure 1 ({d2})", "q1", "ours r1.4"),
            ("Figure 2", "q2", "ours r2.1"),
            (f"Figure 5 ({d1})", "q5", "ours r5.3"), (f"Figure 5 ({d2})", "q5", "ours r5.4"),
            ("Figure 6", "q6", "ours r6.1")]
    sections = [
        f"## Figure 1 ({d1}): about r1.3\n\nbody r1.3\n\n\n\n"
        f"## Figure 1 ({d2}): about r1.4\n\nbody r1.4_closedloop"
        "\n\n_(Figure 1 made in 2.0 s.)_\n",
        "## runs RUNS in 4.0 s\n",
        "## Figure 2: about r2.1\n\nbody r2.1\n\n_(Figure 2 made in 6.0 s.)_\n",
        f"## Figure 5 ({d1}): about r5.3\n\nbody r5.3\n\n\n\n"
        f"## Figure 5 ({d2}): about r5.4\n\nbody r5.4_closedloop"
        "\n\n_(Figure 5 made in 8.0 s.)_\n",
        "## Figure 6: about r6.1\n\nbody r6.1\n\n_(Figure 6 made in 10.0 s.)_\n",
        "## logs compared\n"]
    expected = "\n".join([_head(66, True, [f"{spectral} ({d1}; SHA-256 {_sha(DEFAULT_LOG)})",
                                             f"{simulated} ({d2}; SHA-256 {_sha(SIMULATED_LOG)})"],
                                rows, made=(1, 2, 5, 6)), *sections])
    assert (out / "report.md").read_text(encoding="utf-8") == expected
    html = (out / "report.html").read_text(encoding="utf-8")
    assert _version() in html and _sha(SIMULATED_LOG) in html and _sha(DEFAULT_LOG) in html
    # the logs compared: the two shipped logs, and Figures 1 and 5's results of each
    assert figs.cmp[1] == ("CMP", {"spectral": "r1.3", "simulated": "r1.4"},
                           {"spectral": "r5.3", "simulated": "r5.4"})
    from modalinfo.io import load

    frames = [load(DEFAULT_LOG).n_frames, load(SIMULATED_LOG).n_frames]
    assert m["fig1_fitting_error"].frames == frames and m["fig5_forecast"].frames == frames
    assert (out / "f1.png").read_bytes() == b"r1.3"  # each log's result drawn
    assert (out / "f1_closedloop.png").read_bytes() == b"r1.4"
    assert (out / "f6.json").read_bytes() == b"r6.1"
    assert sorted(p.name for p in out.iterdir()) == sorted(
        ["report.md", "report.html", "f1.png", "f1_closedloop.png", "f2.png", "f2.pdf",
         "f2.json", "f5.png", "f5_closedloop.png", "f6.png", "f6.pdf", "f6.json"])
    printed = capsys.readouterr().out.splitlines()
    assert printed == [
        f"[paper_figures] Figure 1: {TITLES['Figure 1']} ...",
        "[paper_figures] Figure 1 done in 2.0 s",
        "[paper_figures] closed-loop runs for Figures 2-4 (quick) ...",
        "[paper_figures] closed-loop runs done in 4.0 s",
        f"[paper_figures] Figure 2: {TITLES['Figure 2']} ...",
        "[paper_figures] Figure 2 done in 6.0 s",
        f"[paper_figures] Figure 5: {TITLES['Figure 5']} ...",
        "[paper_figures] Figure 5 done in 8.0 s",
        f"[paper_figures] Figure 6: {TITLES['Figure 6']} ...",
        "[paper_figures] Figure 6 done in 10.0 s",
        f"[paper_figures] report written to {out / 'report.md'} and {out / 'report.html'}"]


def test_runs_are_computed_once_and_without_quick(figs, tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["--only", "3,2,8", "--out", str(out)]) == 0
    assert figs.runs == [{"quick": False, "duration": None, "seed": 0}]
    assert figs.mods["fig2_sr_peak"].calls == [("runs", "RUNS")]
    assert figs.mods["fig3_sr_spectrum"].calls == [("runs", "RUNS")]
    assert figs.mods["fig_information_flow"].calls == [("own", False, 0)]
    assert figs.cmp == []  # no log figure: no comparison of the logs
    rows = [("Figure 2", "q2", "ours r2.1"), ("Figure 3", "q3", "ours r3.1"),
            ("Figure 8", "q8", "ours r8.1")]
    text = (out / "report.md").read_text(encoding="utf-8")
    # 0 -> 45 on the clock; no --quick notice and no input logs in the heading
    assert text.startswith(_head(45, False, [], rows, made=(2, 3, 8)) + "\n## runs RUNS in 2.0 s\n")
    assert "closed-loop runs for Figures 2-4 ..." in capsys.readouterr().out


def _log(path, n_frames=300, n_modes=6):
    rng = np.random.default_rng(1)
    x = rng.normal(size=(n_frames, n_modes)) * 0.01  # white: no outlier note
    save(ModalLog(x, modes=list(range(2, 2 + n_modes)), convention="noll", units="rad",
                  wavelength=5e-7, rate=2000.0), path)
    return path


def test_a_user_log_is_one_section_without_a_log_name(figs, tmp_path):
    log = _log(tmp_path / "mine.npz")
    out = tmp_path / "out"
    assert main(["--only", "1", "--log", str(log), "--out", str(out)]) == 0
    assert figs.mods["fig1_fitting_error"].calls == [("check", 300), ("log", f"`{log}`")]
    text = (out / "report.md").read_text(encoding="utf-8")
    expected = "\n".join([_head(6, False, [f"`{log}` (user log; SHA-256 {_sha(log)})"],
                                [("Figure 1", "q1", "ours r1.2")], made=(1,)),
                          "## Figure 1: about r1.2\n\nbody r1.2\n\n_(Figure 1 made in 2.0 s.)_\n"])
    assert text == expected
    assert figs.cmp == []


def test_the_head_names_only_the_log_figures_made(figs, tmp_path):
    # --only 5 on the shipped logs: "Input logs of Figure 5", not "of Figures 1 and 5"
    out = tmp_path / "out"
    assert main(["--only", "5", "--out", str(out)]) == 0
    head = (out / "report.md").read_text(encoding="utf-8").splitlines()[2]
    assert f" Input logs of Figure 5: `{DEFAULT_LOG}` (spectral KAOS-like log; SHA-256 " \
           f"{_sha(DEFAULT_LOG)})" in head
    assert "Figures 1 and 5" not in head and "Figure 1" not in head.split("not made")[0]


def test_figure_refusals_while_computing_are_one_line(figs, tmp_path, capsys):
    log = _log(tmp_path / "mine.npz")
    figs.mods["fig1_fitting_error"].fail = ValueError("too short\nsecond line")
    assert main(["--only", "1", "--log", str(log), "--out", str(tmp_path / "a")]) == 2
    assert capsys.readouterr().err == ("python -m paper_figures: error: "
                                       "Figure 1 on --log: too short\n")
    # on a shipped log the same error is a bug of the figure, not a refusal
    with pytest.raises(ValueError, match="too short"):
        main(["--only", "1", "--out", str(tmp_path / "b")])
    figs.mods["fig6_compression"].fail = ValueError("needs 9 TB\nmore")
    assert main(["--only", "6", "--out", str(tmp_path / "c")]) == 2
    assert capsys.readouterr().err == "python -m paper_figures: error: Figure 6: needs 9 TB\n"
    figs.mods["fig2_sr_peak"].fail = ValueError("unstable")
    assert main(["--only", "2", "--out", str(tmp_path / "d")]) == 2
    assert capsys.readouterr().err == "python -m paper_figures: error: Figure 2: unstable\n"
    for name in "acd":
        assert not (tmp_path / name).exists()


def test_a_shipped_log_a_figure_refuses_names_the_file(figs, tmp_path, capsys):
    def refuse(log):
        raise ValueError("`log` must hold 99 modes\nmore")

    figs.mods["fig1_fitting_error"].check_log = refuse
    assert main(["--only", "1", "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err == (f"python -m paper_figures: error: Figure 1 on shipped log "
                                       f"'{DEFAULT_LOG}': the log must hold 99 modes\n")
    assert main(["--only", "1", "--log", str(_log(tmp_path / "m.npz")),
                 "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err == ("python -m paper_figures: error: Figure 1 on --log: the log "
                                       "must hold 99 modes\n")


@pytest.mark.parametrize("argv, message", [
    (["--only", "9"], "--only must be a comma list of figure numbers 1,2,3,4,5,6,7,8; got '9'"),
    (["--only", " , "], "--only must be a comma list of figure numbers 1,2,3,4,5,6,7,8; "
                        "got ' , '"),
    (["--only", "1,x"], "--only must be a comma list of figure numbers 1,2,3,4,5,6,7,8; "
                        "got '1,x'"),
    (["--only", "2", "--duration", "0"], "--duration must be a number of seconds > 0; got 0"),
    (["--only", "2", "--duration", "inf"],
     "--duration must be a number of seconds > 0; got inf"),
    (["--only", "2", "--seed", "-1"], "--seed must be an int in [0, 2**63 - 1]; got -1"),
    (["--only", "2", "--seed", str(2**63)],
     f"--seed must be an int in [0, 2**63 - 1]; got {2**63}"),
    (["--only", "2,3", "--log", "x.npz"], "--log is read by Figures 1 and 5 only; --only 2,3 "
                                          "makes neither (add 1 or 5, or drop --log)"),
    (["--only", "1", "--split-gaps"], "--split-gaps describes a user's log and needs --log; "
                                      "the shipped logs record it"),
    (["--only", "1", "--log", "nowhere.npz"], "log file 'nowhere.npz' does not exist"),
])
def test_option_refusals_in_one_line(figs, tmp_path, capsys, monkeypatch, argv, message):
    monkeypatch.chdir(tmp_path)
    assert main([*argv, "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err == f"python -m paper_figures: error: {message}\n"
    assert not (tmp_path / "o").exists()


def test_extreme_seed_is_accepted_and_a_repeated_figure_refused(figs, tmp_path, capsys):
    assert main(["--only", "6,", "--seed", str(2**63 - 1), "--out", str(tmp_path / "o")]) == 0
    assert figs.mods["fig6_compression"].calls == [("own", False, 2**63 - 1)]
    # a figure named twice was merged silently before (adversarial round 3): refused now
    assert main(["--only", "6,6,", "--out", str(tmp_path / "p")]) == 2
    assert "--only names figure 6 twice; give each once" in capsys.readouterr().err
    assert figs.mods["fig6_compression"].calls == [("own", False, 2**63 - 1)]


def test_only_defaults_to_every_figure():
    assert pf._parse_only(None) == [1, 2, 3, 4, 5, 6, 7, 8]
    assert pf._parse_only("8, 1") == [1, 8]
    with pytest.raises(ValueError, match="^--only names figure 1 twice; give each once$"):
        pf._parse_only("8, 1,1")


# ------------------------------------------------------------------ a user's log: notes
def _save(path, x, **kw):
    save(ModalLog(x, modes=list(range(2, 2 + x.shape[1])), convention="noll", units="rad",
                  wavelength=5e-7, **kw), path)
    return path


def test_a_flagged_user_log_gets_one_note_without_the_cli_prefix(figs, tmp_path, capsys):
    x = np.random.default_rng(1).normal(size=(300, 6)) * 0.01
    x[100, 2] = 1.0  # one outlier, 100 sigma: flagged (|x - median| > 4.54 x 1.4826 MAD)
    log = _save(tmp_path / "out.npz", x, rate=2000.0)
    assert main(["--only", "1", "--log", str(log), "--out", str(tmp_path / "o")]) == 0
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert err.startswith("python -m paper_figures: note: 'out.npz': 1 of 300 frames flagged: ")
    assert err.endswith("; used as is (--outliers clip replaces the outliers, drop removes "
                        "the frames, raise refuses the log)\n")
    # dropping frames would break the time axis, so drop is refused, naming the analysis
    # (the stand-in has no TIME_AXIS_USE: its label; the real figures' words in
    # test_outliers_standalone_left33.py), not the program (leftovers 33-report)
    assert main(["--only", "1", "--log", str(log), "--outliers", "drop",
                 "--out", str(tmp_path / "p")]) == 2
    assert capsys.readouterr().err == (
        "python -m paper_figures: error: "
        "--log: --outliers drop removes frames, which breaks the time "
        "axis Figure 1's analyses need; use --outliers clip (replace in place) or warn\n")


def test_a_gapped_user_log_is_refused_for_figures_1_and_5_or_split(figs, tmp_path, capsys):
    t = np.arange(300) / 2000.0
    t[150:] += 0.01
    x = np.random.default_rng(2).normal(size=(300, 6)) * 0.01
    log = _save(tmp_path / "gap.npz", x, timestamps=t)
    assert main(["--only", "1", "--log", str(log), "--out", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.startswith(f"python -m paper_figures: error: "
                          f"--log: '{log}' has 1 timestamp gap(s), ")
    # the chosen figure, with its verb ("Figures 1 and 5 needs" whatever --only chose)
    assert err.endswith("; Figure 1 needs equally spaced frames: pass --split-gaps to "
                        "analyse the longest contiguous segment (frames 0..149)\n")
    assert main(["--only", "1", "--log", str(log), "--split-gaps",
                 "--out", str(tmp_path / "o")]) == 0
    assert capsys.readouterr().err == ("python -m paper_figures: note: --split-gaps: analysed "
                                       "frames 0..149 (150 of 300), the longest of 2 contiguous "
                                       "segments\n")
    assert figs.mods["fig1_fitting_error"].calls[-2] == ("check", 150)


def test_a_clean_user_log_without_a_rate_prints_nothing(figs, tmp_path, capsys):
    x = np.random.default_rng(3).normal(size=(300, 6)) * 0.01
    log = _save(tmp_path / "norate.npz", x)
    assert main(["--only", "1", "--log", str(log), "--out", str(tmp_path / "o")]) == 0
    assert capsys.readouterr().err == ""


def test_a_reader_error_without_text_is_named_by_its_type(figs, tmp_path, capsys,
                                                           monkeypatch):
    import modalinfo.cli.shared as common

    def fail(*a, **k):
        raise ValueError()

    monkeypatch.setattr(common, "load_log_with_hints", fail)
    log = _save(tmp_path / "m.npz", np.random.default_rng(4).normal(size=(300, 6)))
    assert main(["--only", "1", "--log", str(log), "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err == "python -m paper_figures: error: --log: ValueError()\n"

    def fail_text(*a, **k):
        raise OSError("  disk gone \n more")

    monkeypatch.setattr(common, "load_log_with_hints", fail_text)
    assert main(["--only", "1", "--log", str(log), "--out", str(tmp_path / "o")]) == 2
    assert capsys.readouterr().err == ("python -m paper_figures: error: "
                                       "--log: disk gone \n")  # 1st line


def test_only_the_section_heading_names_the_log(figs, tmp_path):
    fig1 = figs.mods["fig1_fitting_error"]
    fig1.report = lambda result, suffix="": (f"## Figure 1: head {result}\n\nquotes "
                                             f"\"## Figure 1: head\"\n")
    assert main(["--only", "1", "--out", str(tmp_path / "o")]) == 0
    text = (tmp_path / "o" / "report.md").read_text(encoding="utf-8")
    assert "## Figure 1 (spectral KAOS-like log): head r1.3\n\nquotes \"## Figure 1: head\"" \
        in text


@pytest.mark.parametrize("name", ["f1.png", "f1_closedloop.png", "f2.png", "f2.pdf", "f2.json",
                                  "f6.png", "f6.pdf", "f6.json", "report.html"])
def test_every_output_of_every_kind_is_protected(figs, tmp_path, capsys, name):
    out = tmp_path / "o"
    out.mkdir()
    (out / name).write_bytes(b"mine")
    assert main(["--only", "1,2,6", "--out", str(out)]) == 2
    assert capsys.readouterr().err == (f"python -m paper_figures: error: "
                                       f"'{out / name}' exists; pass "
                                       "--overwrite to replace it\n")
    assert (out / name).read_bytes() == b"mine" and figs.runs == []


def test_help_names_the_program_its_purpose_and_defaults(capsys):
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    raw = capsys.readouterr().out
    assert raw.startswith("usage: python -m paper_figures ")
    text = " ".join(raw.split())
    # the description is the first line of the module's docstring, and only that
    assert ("] Regenerate every figure of the paper, and write a report with the paper's "
            "numbers beside ours. options: -h, --help") in text
    for option in ("--log LOG modal log for Figures 1 and 5 (default: both shipped KAOS-like "
                   "logs)", "--out OUT output directory (default: out)",
                   "--only ONLY comma-separated figure numbers to make (default: all)",
                   "--seed SEED atmosphere of the closed-loop runs (default 0)"):
        assert option in text


def test_defaults_of_out_and_log(figs, tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    assert main(["--only", "6"]) == 0
    assert (tmp_path / "out" / "report.md").is_file()  # --out defaults to ./out
    assert "Input logs" not in (tmp_path / "out" / "report.md").read_text(encoding="utf-8")
