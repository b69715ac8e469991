"""``--quiet`` of ``fitting-error`` and ``info`` (fix57-d).

Reference: ``--quiet``'s meaning in ``reorder`` / ``forecast`` / ``convert`` / ``synth``
(fix56-c, ``modalinfo.cli.shared.QUIET_HELP``): nothing on stdout on success, refused
before any work without the command's output file. ``fitting-error --quiet`` meant "no
progress bar", printed its whole table, and its help said it "needs --out FILE.json", an
option ``fitting-error`` does not have; it now prints nothing and needs ``--plot PNG``
(the figure: a PNG by its signature bytes). ``info`` writes no file: its report on stdout
is its output, so ``--quiet`` stays "no progress bar" and its help says so; the report
printed with and without it is the same text.
"""

import pytest

from modalinfo.cli import main

from .conftest import write_small_log

FAST = ["--orderings", "zernike:standard,zernike:variance", "--pupil-pixels", "16"]
PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def small(tmp_path_factory):
    return write_small_log(tmp_path_factory.mktemp("q") / "s.npz", 300)


def _help(capsys, command: str) -> str:
    with pytest.raises(SystemExit):
        main([command, "--help"])
    return " ".join(capsys.readouterr().out.split())


def test_fitting_error_quiet_prints_nothing_and_draws(small, tmp_path, capsys):
    assert main(["fitting-error", str(small), *FAST]) == 0
    assert "total variance dPhi(0)" in capsys.readouterr().out  # the loud run prints
    plot = tmp_path / "fe.png"
    assert main(["fitting-error", str(small), *FAST, "--plot", str(plot), "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.out == ""
    assert plot.read_bytes()[:8] == PNG


def test_fitting_error_quiet_without_plot_is_refused_before_the_work(small, capsys,
                                                                      monkeypatch):
    import modalinfo.ordering.compare as compare

    def no_work(*args, **kwargs):
        raise AssertionError("compare_orderings ran")

    monkeypatch.setattr(compare, "compare_orderings", no_work)
    assert main(["fitting-error", str(small), *FAST, "--quiet"]) == 2
    captured = capsys.readouterr()
    assert captured.out == "" and captured.err.count("\n") == 1
    assert "--quiet without --plot" in captured.err and "--plot PNG" in captured.err


def test_fitting_error_quiet_says_its_note_on_stderr(small, tmp_path, capsys):
    plot = tmp_path / "fe.png"
    assert main(["fitting-error", str(small), *FAST, "--target", "1e6", "--plot", str(plot),
                 "--quiet"]) == 0
    captured = capsys.readouterr()
    assert captured.out == ""
    assert "the target 1e+06 waves2 is above the total variance" in captured.err


def test_quiet_help_says_what_it_does(capsys):
    fitting = _help(capsys, "fitting-error")
    assert "--quiet print nothing on success (and no progress bar); needs --plot PNG" in fitting
    assert "--out FILE.json" not in fitting  # an option fitting-error does not have
    reorder = _help(capsys, "reorder")
    assert "needs --out FILE.json" in reorder
    info = _help(capsys, "info")
    assert "--quiet no progress bar only: the report on stdout is the command's output" in info


def test_info_quiet_prints_the_same_report(small, capsys):
    assert main(["info", str(small)]) == 0
    loud = capsys.readouterr().out
    assert main(["info", str(small), "--quiet"]) == 0
    assert capsys.readouterr().out == loud and "Z2" in loud
