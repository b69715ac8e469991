"""``python -m paper_figures``: refuses to replace outputs unasked; makes every figure.

Reference: the project's rule that no tool overwrites a user's file unasked, and the
report contract of ``paper_figures/__init__.py`` (one section per figure).
The ``--log`` tests check the input hints against the generator's own log
(``modalinfo.telemetry.synthetic.kaos_like``) written to CSV in nm.
"""

import hashlib
import re

import numpy as np
import pytest

from paper_figures.__main__ import DEFAULT_LOG, main


def test_shipped_log_exists():
    assert DEFAULT_LOG.is_file()


@pytest.mark.parametrize("name", ["report.md", "fig1_fitting_error.png", "fig1_fitting_error.pdf",
                                  "fig5_forecast.json", "fig5_forecast.pdf"])
def test_refuses_existing_outputs(tmp_path, capsys, name):
    (tmp_path / name).write_text("mine")
    assert main(["--out", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and name in err and "--overwrite" in err
    assert (tmp_path / name).read_text() == "mine"


def test_missing_log(tmp_path, capsys):
    assert main(["--out", str(tmp_path), "--log", str(tmp_path / "nope.npz")]) == 2
    assert "does not exist" in capsys.readouterr().err


def _csv(path, frames, modes=27, seed=0):
    from modalinfo.telemetry.synthetic import kaos_like

    log = kaos_like(n_frames=frames, seed=seed, modes=list(range(2, 2 + modes)))
    nm = log.to_units("nm")
    np.savetxt(path, np.asarray(nm.coeffs), delimiter=",")
    return log


def test_user_log_with_the_cli_input_hints(tmp_path, capsys):
    log = _csv(tmp_path / "mine.csv", 400)
    assert main(["--out", str(tmp_path / "o"), "--only", "1", "--log",
                 str(tmp_path / "mine.csv"), "--rate", "2000", "--in-units", "nm",
                 "--wavelength", "5e-7", "--in-modes", "2-28", "--in-convention", "noll"]) == 0
    # every hint given: nothing assumed but the outer scale a CSV cannot carry (the
    # generator's is 20 m; Figure 1's theoretical K-L then assumes an infinite one, said
    # since left24-status as fitting-error says it)
    assert capsys.readouterr().err == (
        "python -m paper_figures: note: 'mine.csv' records no outer scale: the theoretical K-L "
        "assumes Kolmogorov turbulence (infinite outer scale): Figure 1\n")
    report = (tmp_path / "o" / "report.md").read_text()
    # named with its SHA-256 (left27-geometry; reference: hashlib of the file's bytes)
    sha = hashlib.sha256((tmp_path / "mine.csv").read_bytes()).hexdigest()
    assert "mine.csv" in report and f"(user log; SHA-256 {sha})" in report
    # the hints were applied: the log read back in waves is the generator's
    waves = np.asarray(log.to_units("waves").coeffs)
    total = float(np.median(np.sum(waves ** 2, axis=1)))
    quoted = float(re.search(r"on the typical frame totals ([0-9.e-]+) waves\^2",
                             report).group(1))
    assert quoted == pytest.approx(total, rel=0.15)


def test_user_log_errors_are_one_line(tmp_path, capsys):
    _csv(tmp_path / "short.csv", 300, modes=5)
    # a rate outside 1 mHz - 1 MHz is refused by the option's parser (exit 2, one line)
    with pytest.raises(SystemExit) as exc:
        main(["--out", str(tmp_path / "a"), "--only", "5", "--log",
              str(tmp_path / "short.csv"), "--rate", "-3"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--rate" in err and "hertz" in err
    assert main(["--out", str(tmp_path / "b"), "--only", "5", "--log",
                 str(tmp_path / "short.csv"), "--rate", "1000"]) == 2
    err = capsys.readouterr().err
    assert err.strip().splitlines()[-1].startswith("python -m paper_figures: error: Figure 5")
    assert "7041 frames" in err


def test_user_log_without_a_rate_counts_in_frames(tmp_path):
    _csv(tmp_path / "norate.csv", 7100, modes=3)
    assert main(["--out", str(tmp_path / "o"), "--only", "5", "--log",
                 str(tmp_path / "norate.csv"), "--in-units", "nm", "--wavelength", "5e-7"]) == 0
    report = (tmp_path / "o" / "report.md").read_text()
    assert "at an unknown rate" in report
    row = [line for line in report.splitlines() if "forecast horizon" in line][0]
    assert " frames" in row and " ms (" not in row.split("|")[4]


# ---------------------------------------------------------------------------------------
# Audit 10-env: SIGHUP (a closed terminal) and SIGUSR1 killed a run by their default
# action, leaving '<out>/.lock' and the half-made '.<out>.partial-*' folder. Reference:
# POSIX (both end the process by default) and the shell's convention, exit 128 + n
# (129, 138); the caller's handler is back after `main`.
@pytest.mark.parametrize("signame, code", [("SIGHUP", 129), ("SIGUSR1", 138)])
def test_hangup_and_usr1_clean_up_as_sigterm(monkeypatch, capsys, tmp_path, signame, code):
    import signal

    from paper_figures import __main__ as pf

    signum = getattr(signal, signame)

    def run(args):
        signal.getsignal(signum)(signum, None)  # what the signal does while figures are made

    monkeypatch.setattr(pf, "_run", run)
    before = signal.getsignal(signum)
    out = tmp_path / "o"
    assert pf.main(["--out", str(out)]) == code
    assert capsys.readouterr().err == f"python -m paper_figures: terminated; '{out}' is as it was\n"
    assert signal.getsignal(signum) is before
