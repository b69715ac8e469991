"""Round 24 PART b: the command lines' advice points the right way, and assumptions are said.

References from outside the code:

- the direction of a cost: KSG's time grows with its sample count n (kd-tree queries,
  O(n log n); Kraskov, Stoegbauer & Grassberger 2004), so a refusal for taking too long
  must ask for FEWER samples, never "raise --budget";
- Kolmogorov vs von Karman turbulence (Conan 2000): the theoretical K-L depends on the
  outer scale, which a bare array saved with numpy does not carry, so a command that
  assumes one must say so; a log that records it needs no note.
"""
from __future__ import annotations

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry.log import ModalLog


@pytest.fixture()
def bare(tmp_path):
    """A (2000, 3) array of Z2..Z4 saved by hand: no rate, units, outer scale."""
    path = tmp_path / "bare.npy"
    np.save(path, np.random.default_rng(0).standard_normal((2000, 3)))
    return path


def _run(argv, capsys) -> tuple[int, str]:
    try:
        code = main(argv)
    except SystemExit as exc:
        code = exc.code
    return code, capsys.readouterr().err


def test_ksg_budget_too_large_asks_for_fewer_samples(bare, capsys):
    # 2000 frames x ~3200 pupil pixels > 5e6 samples: n = --budget = 5e6, ~200 s an estimate
    code, err = _run(["reorder", str(bare), "--rate", "1000", "--estimator", "ksg",
                      "--budget", "5000000", "--quiet"], capsys)
    assert code == 2
    assert len(err.strip().splitlines()) == 1
    assert "too many" in err and "smaller --budget" in err
    assert "too few" not in err and "raise --budget" not in err


def test_budget_too_small_still_asks_for_more(bare, capsys):
    code, err = _run(["reorder", str(bare), "--rate", "1000", "--budget", "10", "--quiet"],
                     capsys)
    assert code == 2
    assert "too few" in err and "raise --budget" in err


def test_kl_theory_outer_scale_assumed_is_said(bare, capsys):
    code, err = _run(["fitting-error", str(bare), "--rate", "1000", "--orderings",
                      "kl-theory:variance"], capsys)
    assert code == 0
    assert "no outer scale" in err and "Kolmogorov" in err and "--outer-scale" in err


def test_kl_theory_diameter_assumed_is_said(bare, capsys):
    code, err = _run(["reorder", str(bare), "--rate", "1000", "--basis", "kl-theory",
                      "--method", "variance", "--outer-scale", "20"], capsys)
    assert code == 0
    assert "no pupil diameter" in err and "1 m" in err


def test_recorded_geometry_needs_no_note(tmp_path, capsys):
    coeffs = np.random.default_rng(1).standard_normal((2000, 3))
    log = ModalLog(coeffs, rate=1000.0, modes=[2, 3, 4], units="rad", wavelength=5e-7,
                   metadata={"outer_scale": 20.0, "diameter": 0.7})
    path = tmp_path / "rec.npz"
    save(log, path)
    code, err = _run(["fitting-error", str(path), "--orderings", "kl-theory:variance"],
                     capsys)
    assert code == 0
    assert "outer scale" not in err and "diameter" not in err
