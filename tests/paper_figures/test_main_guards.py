"""``python -m paper_figures``: every refusal before any work, and all-or-nothing output.

References: the rules as documented in ``paper_figures/__main__.py`` (output folder a
folder, writable, with free space; a log checked against each figure that reads it;
``--log`` and its hints only with a figure that reads a log); the output folder's
listing and file contents before the run, compared byte for byte after a run that
fails part-way (a later figure raising ``OSError``, or Ctrl-C); and, for the
figure-level rules, the data itself (a log of zeros has no varying mode; a 3-mode
log has fewer than Figure 1's 21 modes; Figure 5's fit and forecast windows need
``MIN_FRAMES`` frames). The closed-loop figures are replaced by small stand-ins
in the all-or-nothing tests: what is tested is the orchestration, not the figures.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import save
from modalinfo.telemetry.log import ModalLog
from paper_figures.__main__ import main


def _log(path, n_frames, n_modes, *, zero_mode=None, timestamps=None, seed=1):
    rng = np.random.default_rng(seed)
    x = np.cumsum(rng.normal(size=(n_frames, n_modes)), axis=0) * 0.01
    if zero_mode is not None:
        x[:, zero_mode] = 0.0
    kw = {"timestamps": timestamps} if timestamps is not None else {"rate": 2000.0}
    save(ModalLog(x, modes=list(range(2, 2 + n_modes)), convention="noll", units="rad",
                  wavelength=5e-7, **kw), path)
    return path


def _state(folder):
    """Every file under ``folder`` with its bytes (None when the folder is absent)."""
    if not folder.exists():
        return None
    return {p.relative_to(folder): p.read_bytes() for p in sorted(folder.rglob("*"))
            if p.is_file()}


def _leftovers(parent):
    return [p.name for p in parent.iterdir() if ".partial-" in p.name]


def _refused(capsys, argv, needle):
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and err.startswith("python -m paper_figures: error: "), err
    assert needle in err, err
    return err


# ----------------------------------------------------------------------- refusals
def test_output_locations_are_checked_first(tmp_path, capsys, monkeypatch):
    a_file = tmp_path / "results.txt"
    a_file.write_text("mine")
    _refused(capsys, ["--only", "3", "--out", str(a_file)], "exists and is not a directory")
    _refused(capsys, ["--only", "3", "--out", str(a_file / "deeper" / "out")],
             f"'{a_file}' is not a directory")
    assert a_file.read_text() == "mine"
    import shutil
    from collections import namedtuple

    usage = namedtuple("usage", "total used free")
    monkeypatch.setattr(shutil, "disk_usage", lambda _: usage(10**9, 10**9 - 2**19, 2**19))
    _refused(capsys, ["--only", "3", "--out", str(tmp_path / "new")], "has 512.00 kiB free")
    assert not (tmp_path / "new").exists() and _leftovers(tmp_path) == []


def test_log_options_that_would_be_ignored_are_refused(tmp_path, capsys):
    log = _log(tmp_path / "mine.npz", 200, 25)
    _refused(capsys, ["--only", "3,4", "--log", str(log), "--out", str(tmp_path / "o")],
             "--log is read by Figures 1 and 5 only; --only 3,4 makes neither")
    _refused(capsys, ["--only", "1", "--in-units", "nm", "--out", str(tmp_path / "o")],
             "--in-units describes a user's log and needs --log")
    _refused(capsys, ["--only", "5", "--log", str(tmp_path), "--out", str(tmp_path / "o")],
             "is a folder, not a log file")
    import os

    os.mkfifo(tmp_path / "pipe.npz")  # round 5, g04: was "log file ... does not exist"
    _refused(capsys, ["--only", "1", "--log", str(tmp_path / "pipe.npz"), "--out",
                      str(tmp_path / "o")], "is not a regular file (a FIFO or a device)")
    assert not (tmp_path / "o").exists()


def test_run_options_no_chosen_figure_reads_are_refused(tmp_path, capsys):
    # Figures 1 and 5 read a log, not the simulator: --duration and --seed were ignored
    # silently (audit 9-files g01); Figure 6 is simulated, so --seed reaches it
    _refused(capsys, ["--only", "1", "--duration", "1e-300", "--out", str(tmp_path / "o")],
             "--duration sets the closed-loop runs (Figures 2, 3, 4, 7); --only 1 makes none")
    _refused(capsys, ["--only", "6", "--duration", "0.1", "--out", str(tmp_path / "o")],
             "--only 6 makes none of them")
    _refused(capsys, ["--only", "1,5", "--seed", "0", "--out", str(tmp_path / "o")],
             "--seed sets the simulated figures (2, 3, 4, 6, 7, 8); --only 1,5 makes none")
    assert not (tmp_path / "o").exists()


def test_an_empty_out_name_is_refused_not_read_as_the_current_folder(tmp_path, capsys,
                                                                     monkeypatch):
    # `--out "$OUT"` with OUT unset wrote the report into the current folder (audit 9, g06)
    monkeypatch.chdir(tmp_path)
    with pytest.raises(SystemExit) as exc:
        main(["--only", "1", "--out", ""])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--out: must name a folder; got an empty name" in err
    assert list(tmp_path.iterdir()) == []


@pytest.mark.parametrize("frames, modes, zero_mode, only, needle", [
    (150, 3, None, "1", "Figure 1 on --log: the log must hold at least 21 modes"),
    (60, 25, None, "1", "Figure 1 on --log: the log must hold at least 100 frames"),
    (150, 25, 7, "1", "1 mode(s) do not vary, the first Z9"),
    (7100, 2, 0, "5", "Figure 5 on --log: the log must have modes that vary"),
    # Figure 5 comes after Figure 1: its refusal still comes before Figure 1's work
    (400, 25, None, "1,5", "Figure 5 on --log: the log must hold at least 7041 frames"),
])
def test_a_log_a_figure_cannot_use_is_refused_before_any_work(tmp_path, capsys, frames,
                                                              modes, zero_mode, only,
                                                              needle):
    log = _log(tmp_path / "mine.npz", frames, modes, zero_mode=zero_mode)
    out = tmp_path / "o"
    err = _refused(capsys, ["--only", only, "--log", str(log), "--out", str(out)], needle)
    assert "Traceback" not in err
    assert not out.exists() and _leftovers(tmp_path) == []


def test_all_zero_log_is_refused_by_figure1_itself():
    from paper_figures import fig1_fitting_error as fig1

    zero = ModalLog(np.zeros((500, 27)), rate=1000.0, modes=list(range(2, 29)),
                    convention="noll", units="rad", wavelength=5e-7)
    with pytest.raises(ValueError, match="every mode is constant"):
        fig1.compute(zero)


def test_gapped_log_points_to_split_gaps_which_is_accepted(tmp_path, capsys):
    t = np.arange(300) / 1000.0
    t[150:] += 0.5  # a 0.5 s hole
    log = _log(tmp_path / "gaps.npz", 300, 25, timestamps=t)
    err = _refused(capsys, ["--only", "1", "--log", str(log), "--out", str(tmp_path / "o")],
                   "pass --split-gaps")
    assert "gap" in err
    # the option the message names exists: the longest segment (150 frames) is then
    # analysed, and here refused by Figure 5's frame rule, not by the parser
    _refused(capsys, ["--only", "5", "--log", str(log), "--split-gaps", "--out",
                      str(tmp_path / "o")], "at least 7041 frames; got 150")
    assert not (tmp_path / "o").exists()


# ----------------------------------------------------------------------- all or nothing
class _Stand:
    """A stand-in for a closed-loop figure module: writes its PNG, or fails."""

    NEEDS_RUNS = True

    def __init__(self, module, fail=None):
        self.FIGURE_NAME = module.FIGURE_NAME
        self.PDF_NAME = module.PDF_NAME
        self.fail = fail
        self.label = module.FIGURE_NAME.split("_")[0]

    def compute(self, runs):
        return self.label

    def plot(self, result, out_dir):
        if self.fail is not None:
            raise self.fail
        (out_dir / self.FIGURE_NAME).write_bytes(b"new " + result.encode())
        (out_dir / self.PDF_NAME).write_bytes(b"new pdf")

    def report(self, result):
        return f"## {result}\n\n![x]({self.FIGURE_NAME})\n"

    def table_rows(self, result):
        return []


@pytest.fixture
def stand_ins(monkeypatch):
    """Figures 2-4 as stand-ins (Figure 4's behaviour set by the test)."""
    import importlib

    from paper_figures import closedloop_runs

    monkeypatch.setattr(closedloop_runs, "compute", lambda **kw: "runs")
    monkeypatch.setattr(closedloop_runs, "report_section", lambda runs, t: "## runs\n")
    real_import = importlib.import_module
    modules = {name: _Stand(real_import(f"paper_figures.{name}"))
               for name in ("fig2_sr_peak", "fig3_sr_spectrum", "fig4_sr_maps")}

    def fake_import(name, *args):
        short = name.rpartition(".")[2]
        return modules[short] if short in modules else real_import(name, *args)

    monkeypatch.setattr("paper_figures.__main__.importlib.import_module", fake_import)
    return modules


@pytest.mark.parametrize("failure, code", [(OSError(28, "No space left on device"), 1),
                                           (KeyboardInterrupt(), 130)])
def test_a_later_figure_failing_leaves_the_output_folder_as_it_was(tmp_path, capsys,
                                                                  stand_ins, failure, code):
    out = tmp_path / "out"
    out.mkdir()
    (out / "fig2_sr_peak.png").write_bytes(b"previous figure 2")
    (out / "notes.md").write_text("the user's own file")
    before = _state(out)
    stand_ins["fig4_sr_maps"].fail = failure
    assert main(["--only", "2,3,4", "--out", str(out), "--overwrite"]) == code
    err = capsys.readouterr().err
    assert "Traceback" not in err and "as it was" in err
    assert _state(out) == before  # figures 2 and 3 were made, then discarded
    assert _leftovers(tmp_path) == []
    # a new folder is not created by a failed run, nor its missing parents
    assert main(["--only", "2,3,4", "--out", str(tmp_path / "fresh" / "a" / "b")]) == code
    assert not (tmp_path / "fresh").exists() and _leftovers(tmp_path) == []


def test_a_finished_run_moves_every_file_into_place(tmp_path, capsys, stand_ins):
    out = tmp_path / "out"
    out.mkdir()
    (out / "fig2_sr_peak.png").write_bytes(b"previous figure 2")
    (out / "notes.md").write_text("the user's own file")
    assert main(["--only", "2,3,4", "--out", str(out), "--overwrite"]) == 0
    after = _state(out)
    assert after[out.joinpath("fig2_sr_peak.png").relative_to(out)] == b"new fig2"
    assert (out / "notes.md").read_text() == "the user's own file"
    names = {p.name for p in out.iterdir()}
    assert names == {"notes.md", "report.md", "report.html", "fig2_sr_peak.png",
                     "fig2_sr_peak.pdf", "fig3_sr_spectrum.png", "fig3_sr_spectrum.pdf",
                     "fig4_sr_maps.png", "fig4_sr_maps.pdf"}
    assert "## fig3" in (out / "report.md").read_text()
    assert _leftovers(tmp_path) == []
    # into a new nested folder: created at the end, with its parents
    nested = tmp_path / "a" / "b"
    assert main(["--only", "2", "--out", str(nested)]) == 0
    assert (nested / "fig2_sr_peak.png").read_bytes() == b"new fig2"


def test_a_run_the_simulator_refuses_is_one_line_and_writes_nothing(tmp_path, capsys,
                                                                   stand_ins, monkeypatch):
    from paper_figures import closedloop_runs

    def refuse(**kw):
        raise ValueError("`duration` needs 9.1 TB; 12 GB is available.")

    monkeypatch.setattr(closedloop_runs, "compute", refuse)
    out = tmp_path / "out"
    err = _refused(capsys, ["--only", "2", "--duration", "1e9", "--out", str(out)],
                   "closed-loop runs of Figures 2-4: `duration` needs 9.1 TB")
    assert "Traceback" not in err and not out.exists() and _leftovers(tmp_path) == []


def test_a_folder_where_an_output_file_goes_is_refused(tmp_path, capsys):
    out = tmp_path / "out"
    (out / "report.md").mkdir(parents=True)
    (out / "report.md" / "draft.txt").write_text("mine")
    before = _state(out)
    _refused(capsys, ["--only", "3", "--out", str(out), "--overwrite"],
             "report.md' is a folder; the run writes a file of that name")
    assert _state(out) == before


def test_a_second_run_into_a_folder_in_use_is_refused(tmp_path, capsys, stand_ins):
    # the second run starts while the first is drawing Figure 4: it must refuse in one
    # line (exit 2) and not replace the first run's files, even with --overwrite
    out = tmp_path / "out"
    second = {}
    fig4 = stand_ins["fig4_sr_maps"]
    real_plot = fig4.plot

    def plot_and_start_another(result, out_dir):
        second["code"] = main(["--only", "2", "--out", str(out), "--overwrite"])
        second["err"] = capsys.readouterr().err
        real_plot(result, out_dir)

    fig4.plot = plot_and_start_another
    assert main(["--only", "2,3,4", "--out", str(out)]) == 0
    assert second["code"] == 2
    err = second["err"]
    assert err.count("\n") == 1 and "is in use by paper_figures" in err, err
    assert (out / "fig2_sr_peak.png").read_bytes() == b"new fig2"
    assert not (out / ".lock").exists() and _leftovers(tmp_path) == []
    assert not list(out.rglob("*.partial-*"))


def test_a_lock_of_a_live_process_refuses_and_a_dead_ones_is_taken_over(tmp_path, capsys,
                                                                        stand_ins):
    import subprocess
    import sys

    out = tmp_path / "out"
    out.mkdir()
    with subprocess.Popen(
            [sys.executable, "-c", "import sys; from modalinfo.common.folders import OutputLock;"
             f" OutputLock({str(out)!r}, 'paper_figures').acquire(); print('held', flush=True);"
             " sys.stdin.read()"],
            stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True) as holder:
        try:
            assert holder.stdout.readline().strip() == "held"
            _refused(capsys, ["--only", "2", "--out", str(out)],
                     f"--out output directory '{out}' is in use by paper_figures (pid "
                     f"{holder.pid}")
            assert not (out / "fig2_sr_peak.png").exists()
        finally:
            holder.kill()
    # the holder died without releasing: its lock is stale and taken over
    assert (out / ".lock").exists()
    assert main(["--only", "2", "--out", str(out)]) == 0
    assert (out / "fig2_sr_peak.png").read_bytes() == b"new fig2"
    assert not (out / ".lock").exists()


@pytest.mark.parametrize(("argv", "needle"), [
    (["--only", "2", "--seed", str(2**70)], "--seed must be an int in [0, 2**63 - 1]"),
    # 1e308 s is an infinite frame count: an OverflowError traceback before the fix
    (["--only", "2", "--duration", "1e308"], "`duration` must be at most 1e+15 frames"),
])
def test_seeds_and_durations_the_runs_cannot_hold_are_refused(tmp_path, capsys, argv, needle):
    out = tmp_path / "out"
    err = _refused(capsys, argv + ["--out", str(out)], needle)
    assert "Traceback" not in err and not out.exists() and _leftovers(tmp_path) == []


def test_the_partial_folder_of_a_killed_run_is_removed_by_the_next(tmp_path, capsys,
                                                                   stand_ins):
    # issue 27 leftovers: a run killed by SIGKILL (no handler runs) left its staging
    # folder '<out>/.out.partial-*' for good. Reference: POSIX (SIGKILL cannot be caught)
    # and the process table (os.kill(pid, 0)); the next run holding the lock removes the
    # folder of the dead pid only, and leaves a live process's and unnamed ones alone
    import os
    import signal
    import subprocess
    import sys

    out = tmp_path / "out"
    code = ("import sys; from pathlib import Path; "
            "from paper_figures._common import locked_output, staged_output\n"
            f"with locked_output(Path({str(out)!r})), staged_output(Path({str(out)!r})) as s:\n"
            "    (s / 'fig2_sr_peak.png').write_bytes(b'half')\n"
            "    print(s.name, flush=True); sys.stdin.read()\n")
    with subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE,
                          stdout=subprocess.PIPE, text=True) as run:
        try:
            stage = run.stdout.readline().strip()
        finally:
            run.send_signal(signal.SIGKILL)
        run.wait()
    assert run.returncode == -signal.SIGKILL
    assert stage.startswith(f".out.partial-{run.pid}-") and (out / stage).is_dir()
    live = out / f".out.partial-{os.getppid()}-x"  # a live process (pytest's parent)
    unnamed = out / ".out.partial-abc123"  # no pid recorded: not ours to judge, named
    for keep in (live, unnamed):
        keep.mkdir()
    (out / "notes.txt").write_text("mine")
    assert main(["--only", "2", "--out", str(out)]) == 0
    said = [line for line in capsys.readouterr().err.splitlines() if "staging" in line]
    assert said[0] == (f"python -m paper_figures: removed 1 staging item(s) of runs that ended "
                       f"without cleaning up (killed) in '{out}': {stage}")
    assert said[1].startswith(f"python -m paper_figures: note: 1 staging item(s) in '{out}' "
                              "were left by")
    assert said[1].endswith(f"remove them: rm -r '{unnamed}'") and len(said) == 2
    assert not (out / stage).exists() and live.is_dir() and unnamed.is_dir()
    assert (out / "notes.txt").read_text() == "mine"
    assert (out / "fig2_sr_peak.png").read_bytes() == b"new fig2"
