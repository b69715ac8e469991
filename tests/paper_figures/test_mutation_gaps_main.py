"""``python -m paper_figures``: help texts, SIGTERM and failure messages (mutation gaps).

Gaps found by mutation testing (docs/MUTATION.md, "paper_figures/__main__.py"): the help
texts of ``--overwrite``, ``--quick`` and ``--duration`` were free to change, and so were
the SIGTERM handling (installed only from the main thread, the caller's handler restored)
and the one-line message of a failure while computing. References: the module
docstring's contract for each option (``--overwrite`` replaces files already there;
``--quick`` is a smoke run on reduced settings, numbers not the paper's: Figures 2-4, 6,
7 and 8 on reduced closed-loop settings, Figure 5 on its first 5 modes; ``--duration`` is
the simulated time of the closed-loop runs of Figures 2-4 and 7 in seconds, 0.5 s by
default and 0.2 s with ``--quick``) and the defaults
``closedloop_runs.DEFAULT_DURATION`` / ``QUICK_DURATION``, written out here word for word;
``main``'s docstring for the exit statuses; Python's ``signal`` contract; a log's rate
given by ``--rate`` (the CLI's input hints) seen by the figure; a folder named as an
output refused before any work (``_run_locked``'s docstring).
``_run`` or the figure modules are stand-ins: no figure is made, ~1 s.
"""

from __future__ import annotations

import pytest

from paper_figures import closedloop_runs
from paper_figures.__main__ import main

# the stand-in figure modules of the report tests (a fixture) and their log writer
from .test_main_report_text import _save, figs  # noqa: F401


def test_help_of_overwrite_quick_and_duration(capsys, monkeypatch):
    monkeypatch.setenv("COLUMNS", "400")  # one line per option: no hyphen split by wrapping
    with pytest.raises(SystemExit) as exc:
        main(["--help"])
    assert exc.value.code == 0
    text = " ".join(capsys.readouterr().out.split())
    assert (closedloop_runs.DEFAULT_DURATION, closedloop_runs.QUICK_DURATION) == (0.5, 0.2)
    for option in (
            "--overwrite replace figures and report already in the output directory",
            "--quick a smoke run, numbers not the paper's: reduced closed-loop settings for "
            "Figures 2-4, 6, 7 and 8, Figure 5's evaluation on the first 5 modes",
            "--duration DURATION simulated time of the closed-loop runs of Figures 2-4 and 7 "
            "[s] (default 0.5, quick 0.2)"):
        assert option in text


# ---------------------------------------------------------------------------------------
# SIGTERM and the failure messages (survivors of the 2026-11-28 18:28 run). Reference:
# ``main``'s docstring (exit 130 for Ctrl-C, 143 for SIGTERM, 1 for a failure while
# computing or writing, one line naming the error) and the signal module's contract (a
# handler can be set only from the main thread; a caller's handler is restored when
# ``main`` returns).

def test_sigterm_interrupts_like_ctrl_c_and_the_callers_handler_comes_back(
        monkeypatch, capsys, tmp_path):
    import signal

    from paper_figures import __main__ as pf

    def mine(signum, frame):  # a caller's own handler
        raise AssertionError("the caller's handler ran during main")

    seen = []

    def run(args):
        handler = signal.getsignal(signal.SIGTERM)
        seen.append(handler)
        handler(signal.SIGTERM, None)  # what `kill` does while the figures are made

    previous = signal.signal(signal.SIGTERM, mine)
    try:
        monkeypatch.setattr(pf, "_run", run)
        out = tmp_path / "o"
        assert main(["--out", str(out)]) == 143  # 128 + SIGTERM (adversarial round 4, x18)
        assert seen == [pf._terminated]
        assert capsys.readouterr().err == (f"python -m paper_figures: terminated; '{out}' is as "
                                           "it was\n")
        assert signal.getsignal(signal.SIGTERM) is mine
    finally:
        signal.signal(signal.SIGTERM, previous)


def test_ctrl_c_while_making_is_interrupted_and_exit_130(monkeypatch, capsys, tmp_path):
    # main's docstring: Ctrl-C exits 130, one line saying "interrupted" (SIGTERM, above, is
    # "terminated" and 143); x_main__mutmut_121, _124, _125 printed another word
    from paper_figures import __main__ as pf

    def run(args):
        raise KeyboardInterrupt

    monkeypatch.setattr(pf, "_run", run)
    out = tmp_path / "o"
    assert main(["--out", str(out)]) == 130
    assert capsys.readouterr().err == (f"python -m paper_figures: interrupted; '{out}' is as "
                                       "it was\n")


def test_main_from_another_thread_sets_no_handler(monkeypatch, tmp_path):
    import signal
    import threading

    from paper_figures import __main__ as pf

    monkeypatch.setattr(pf, "_run", lambda args: 0)
    before = signal.getsignal(signal.SIGTERM)
    result, errors = [], []

    def call():
        try:
            result.append(main(["--out", str(tmp_path / "o")]))
        except BaseException as exc:  # noqa: BLE001 - reported to the test below
            errors.append(exc)

    t = threading.Thread(target=call)
    t.start()
    t.join(600)  # a hang guard only (the call, with _run stubbed, takes milliseconds)
    assert not t.is_alive(), "main hung in a thread"
    assert errors == [] and result == [0]
    assert signal.getsignal(signal.SIGTERM) is before


@pytest.mark.parametrize("exc, what", [
    (OSError(28, "No space left on device"), "OSError: No space left on device"),
    (OSError("the disk said no"), "OSError: the disk said no"),  # no strerror: the text
    (MemoryError("5.0 GB needed"), "MemoryError: 5.0 GB needed"),
    (MemoryError(), "MemoryError: no detail"),
])
def test_failures_while_making_are_one_line_and_exit_1(monkeypatch, capsys, tmp_path, exc,
                                                       what):
    from paper_figures import __main__ as pf

    def run(args):
        raise exc

    monkeypatch.setattr(pf, "_run", run)
    out = tmp_path / "o"
    assert main(["--out", str(out)]) == 1
    assert capsys.readouterr().err == (f"python -m paper_figures: error: "
                                       f"{what}; '{out}' is as it was\n")


def test_the_users_input_hints_reach_the_log(figs, tmp_path):  # noqa: F811
    # a log that records no rate, read with --rate 500: the figures see 500 Hz (the
    # shipped logs are read without hints; the user's with them: `_load_logs`)
    import numpy as np

    fig1 = figs.mods["fig1_fitting_error"]
    compute, seen = fig1.compute, []

    def recording(log, *, source):
        seen.append(log)
        return compute(log, source=source)

    fig1.compute = recording
    path = _save(tmp_path / "norate.npz", np.random.default_rng(3).normal(size=(300, 6)) * 0.01)
    assert main(["--only", "1", "--log", str(path), "--rate", "500",
                 "--out", str(tmp_path / "o")]) == 0
    assert [log.rate for log in seen] == [500.0]


@pytest.mark.parametrize("folder", ["report.md", "f3.png"])
def test_a_folder_named_as_an_output_is_refused_before_any_work(figs, tmp_path, capsys,  # noqa: F811
                                                                folder):
    # `_run_locked`'s docstring: refuse the outputs first, then make the figures; a folder
    # where the run writes a file is refused in one line (exit 2) even with --overwrite,
    # before the shared runs or any figure are computed, and the folder is left as it was
    # (x__run_locked__mutmut_16 dropped the check: the stand-ins then computed Figure 3)
    out = tmp_path / "out"
    (out / folder).mkdir(parents=True)
    (out / folder / "draft.txt").write_text("mine")
    assert main(["--only", "3", "--out", str(out), "--overwrite"]) == 2
    assert capsys.readouterr().err == (
        f"python -m paper_figures: error: "
        f"'{out / folder}' is a folder; the run writes a file of that "
        "name\n")
    assert figs.runs == [] and figs.mods["fig3_sr_spectrum"].calls == []
    assert sorted(p.relative_to(out).as_posix() for p in out.rglob("*")) == [
        folder, f"{folder}/draft.txt"]
