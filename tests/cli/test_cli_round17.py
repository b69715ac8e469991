"""Round 17 PART b of issue 27: option interactions, live files and exit statuses.

The full list of inputs (id | input | expected | before | after) is in
docs/ADVERSARIAL.md, section "Round 17 PART b, issue 27".

References, all from outside the code under test: argparse's documented ``--version``
contract (the string on stdout, exit status 0; Python's ``argparse`` docs, "action
'version'") and the common brief's one-line refusal rule (exit 2, the option named);
h5py's documented file locking (a file opened for writing by one process cannot be
opened by another: ``BlockingIOError`` errno EAGAIN) for the locked-file message; for
the converted log's units note, the units the converted file itself records.
"""

from __future__ import annotations

import subprocess
import sys

import pytest

from modalinfo.io import load

from .conftest import exit_code


@pytest.fixture
def small_log(make_small_log):
    return make_small_log(300)


def _one_line(capsys) -> str:
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


@pytest.mark.parametrize("module", ["modalinfo", "closedloop", "paper_figures"])
def test_version_prints_to_stdout_and_exits_0(module):
    # Before: "unrecognized arguments: --version", exit 2 (V01-V03)
    done = subprocess.run([sys.executable, "-m", module, "--version"], capture_output=True,
                          text=True, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stderr == ""
    name, version = done.stdout.split()[-2:]
    assert version.startswith("0.1.0+src.") and name in (module, "paper_figures")


def test_forecast_window_without_refits_is_refused(small_log, tmp_path, capsys):
    # Before: --window 50 without --refit-every was recorded and used by nothing (A22)
    assert exit_code(["forecast", small_log, "--predictors", "linear", "--modes", "2",
                      "--window", "50", "--out", tmp_path / "f", "--quiet"]) == 2
    err = _one_line(capsys)
    assert "--window 50" in err and "--refit-every" in err
    assert not (tmp_path / "f").exists()


@pytest.mark.parametrize("basis", ["zernike", "kl-data"])
def test_reorder_outer_scale_on_a_basis_without_one_is_refused(small_log, basis, capsys):
    # Before: --basis zernike --outer-scale 20 ordered the Zernikes, exit 0 (A18)
    assert exit_code(["reorder", small_log, "--basis", basis, "--outer-scale", "20",
                      "--method", "variance"]) == 2
    err = _one_line(capsys)
    assert "--outer-scale" in err and f"--basis {basis}" in err


def test_closedloop_run_overwrite_without_out_is_refused(capsys):
    from closedloop.cli import main

    # Before: the run went ahead and saved nothing (E10)
    try:
        status = main(["run", "--preset", "kaos", "--duration", "0.001", "--overwrite",
                       "--quiet"])
    except SystemExit as exc:
        status = exc.code
    assert status == 2
    err = _one_line(capsys)
    assert "--overwrite" in err and "--out" in err


def test_an_hdf5_log_open_for_writing_elsewhere_is_named_locked_not_corrupt(
        small_log, tmp_path, capsys):
    h5 = tmp_path / "busy.h5"
    assert exit_code(["convert", small_log, h5, "--quiet"]) == 0
    writer = subprocess.Popen(
        [sys.executable, "-c", "import h5py, sys, time; f = h5py.File(sys.argv[1], 'a'); "
         "print('open', flush=True); time.sleep(60)", str(h5)],
        stdout=subprocess.PIPE, text=True)
    try:
        assert writer.stdout.readline().strip() == "open"
        # Before: "corrupt HDF5 file 'busy.h5': BlockingIOError: ..." (L05)
        assert exit_code(["info", h5, "--quiet"]) == 2
        err = _one_line(capsys)
        assert "locked by another process" in err and "corrupt" not in err
    finally:
        writer.kill()
        writer.wait()
        writer.stdout.close()


def test_convert_to_other_units_does_not_keep_the_old_units_note(tmp_path):
    src = tmp_path / "s.npz"
    assert exit_code(["synth", src, "--frames", "50", "--quiet", "--overwrite"]) == 0
    assert "in rad" in load(src).metadata["units_note"]
    out = tmp_path / "w.npz"
    # Before: units waves beside "units_note: coefficients in rad of phase ..." (A32)
    assert exit_code(["convert", src, out, "--units", "waves", "--quiet"]) == 0
    log = load(out)
    assert log.units == "waves"
    assert log.metadata["units_note"].startswith("converted from rad to waves")


@pytest.mark.parametrize("argv", [
    ["run", "--preset", "kaos", "--duration", "0.005", "--train-seed", "3", "--quiet"],
    ["run", "--preset", "kaos", "--duration", "0.005", "--train-seed", "3",
     "--predictor", "oracle", "--quiet"],
    ["compare", "--preset", "kaos", "--duration", "0.005", "--train-seed", "3",
     "--predictors", "none,oracle", "--quiet"],
])
def test_closedloop_train_seed_without_a_trained_predictor_is_refused(argv, capsys):
    from closedloop.cli import main

    # Before: the run went ahead, the seed used by nothing (E09, C06)
    try:
        status = main(argv)
    except SystemExit as exc:
        status = exc.code
    assert status == 2
    err = _one_line(capsys)
    assert "--train-seed 3" in err and "trained" in err


def test_closedloop_config_overwrite_without_out_is_refused(capsys):
    from closedloop.cli import main

    # Before: the config was printed, --overwrite ignored (C03)
    assert main(["config", "--preset", "kaos", "--overwrite"]) == 2
    err = _one_line(capsys)
    assert "--overwrite" in err and "--out" in err


@pytest.mark.parametrize("extra, flag", [
    (["--method", "standard", "--budget", "1000"], "--budget"),
    (["--method", "variance", "--seed", "3"], "--seed"),
])
def test_reorder_mi_options_on_a_method_without_mi_are_refused(small_log, extra, flag, capsys):
    # Before: accepted and used by nothing, exit 0 (A20; order_modes' docstring: the
    # sample budget is "for the MI methods")
    assert exit_code(["reorder", small_log, *extra]) == 2
    err = _one_line(capsys)
    assert flag in err and "drop it" in err


def test_reorder_defaults_still_apply_when_the_mi_options_are_not_given(small_log, capsys):
    # the documented defaults (--budget 200000, --seed 0) are what an MI run reports
    assert exit_code(["reorder", small_log, "--method", "mi_marginal", "--resamples", "0",
                      "--pupil-pixels", "16"]) == 0
    out = capsys.readouterr().out
    assert "seed 0" in out.splitlines()[0]
