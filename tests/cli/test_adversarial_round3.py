"""Round 3 of issue 27's adversarial inputs: the ones that failed, fixed at the entry.

The full list of inputs tried (id | input | expected | observed | verdict | fix) is in
docs/ADVERSARIAL.md, section "Round 3, issue 27".

References: the dispatcher's documented contract (one line on stderr naming the
option and the rule, exit 2, no traceback, nothing written or overwritten); the
extension table ``LOG_SUFFIXES`` of the README ("the output format comes from OUT's
extension"); for the glitched log, the ordering of the same log without the glitch
(same seed, same samples), as in tests/ordering/test_glitch_robustness.py.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog

DATA = Path(__file__).resolve().parents[2] / "data"


@pytest.fixture
def small_log(tmp_path):
    rng = np.random.default_rng(0)
    coeffs = np.cumsum(rng.standard_normal((300, 3)), axis=0) * 0.01
    return save(ModalLog(coeffs, rate=2000.0, modes=[2, 3, 4], units="rad"),
                tmp_path / "log.npz")


def _exit_code(argv):
    """``main``'s status, returned or raised (argparse errors raise SystemExit)."""
    try:
        return main([str(a) for a in argv])
    except SystemExit as exc:
        return exc.code


def _one_line(capsys) -> str:
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Traceback" not in err, err
    return err


# ------------------------------------------------------------ --to-fmt vs the extension
@pytest.mark.parametrize("name, fmt", [
    ("out.csv", "npz"), ("out.npz", "csv"), ("out.h5", "fits"), ("out.fits", "hdf5"),
    ("out.hdf5", "aot"), ("out.FIT", "npz"),
])
def test_convert_to_fmt_contradicting_the_extension_is_refused(small_log, tmp_path, capsys,
                                                               name, fmt):
    # Before: `convert --to-fmt npz out.csv` wrote NPZ bytes under a .csv name, exit 0.
    out = tmp_path / name
    assert _exit_code(["convert", small_log, out, "--to-fmt", fmt, "--quiet"]) == 2
    err = _one_line(capsys)
    assert f"--to-fmt {fmt} contradicts OUT" in err, err
    assert not out.exists()


def test_synth_to_fmt_contradicting_the_extension_is_refused(tmp_path, capsys):
    out = tmp_path / "s.csv"
    assert _exit_code(["synth", out, "--frames", "50", "--to-fmt", "npz", "--quiet"]) == 2
    assert "--to-fmt npz contradicts OUT" in _one_line(capsys)
    assert not out.exists()


@pytest.mark.parametrize("name, fmt, kind", [
    ("out.npz", "npz", "npz"), ("out.fits", "aot", "aot"), ("out.fts", "fits", "fits"),
    ("out.dat", "csv", "csv"),
])
def test_to_fmt_agreeing_with_or_naming_the_extension_still_writes(small_log, tmp_path,
                                                                   capsys, name, fmt, kind):
    out = tmp_path / name
    assert _exit_code(["convert", small_log, out, "--to-fmt", fmt, "--quiet"]) == 0
    back = load(out, fmt=kind)
    np.testing.assert_array_equal(back.coeffs, load(small_log).coeffs)


# ------------------------------------------------------------ batch --analyses twice
def test_batch_analyses_named_twice_is_refused_before_any_work(small_log, tmp_path, capsys):
    # Before: `--analyses summary,summary` merged the two silently (exit 0, one row).
    pytest.importorskip("distributed")
    out = tmp_path / "out"
    assert _exit_code(["batch", small_log, "--out", out, "--analyses", "summary,summary",
                       "--quiet"]) == 2
    err = _one_line(capsys)
    assert "names 'summary' twice" in err and "analyses" in err, err
    assert not out.exists()


def test_analyse_archive_refuses_a_repeated_analysis(small_log, tmp_path):
    pytest.importorskip("distributed")
    from modalinfo.batch import analyse_archive

    with pytest.raises(ValueError, match=r"`analyses` names 'ordering' twice"):
        analyse_archive(small_log, ["ordering", "summary", "ordering"], tmp_path / "o")
    assert not (tmp_path / "o").exists()


# ------------------------------------------------------------ one glitched frame
def _ranks(out: str, n: int = 10) -> list[str]:
    rows = [ln.split() for ln in out.splitlines()]
    return [r[1] for r in rows if r and r[0].lstrip("~").isdigit()
            and int(r[0].lstrip("~")) <= n]
