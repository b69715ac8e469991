"""Frames swapped in pairs and a block appended twice (adversarial round 34 PART b,
B21-B23 and B38-B39; issue 27, fix34-b).

References, from outside the code: the frames planted (numpy indexing: every pair
``2k, 2k + 1`` written in reverse order, or rows ``a..b`` appended again, so the exact
rows of the copy are known), the lag-1 products of the planted data computed with numpy
(the parity whose products span a swapped pair's two frames has the true lag 1, the
other the true lag 3 = rho^3 for an AR(1): 0.95 vs 0.857), and ``numpy.array_equal`` of
what ``"drop"`` leaves against the log before the copy. Before the fix none of these
was reported (``clean`` True, ``--outliers raise`` accepted both logs).
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import save
from modalinfo.telemetry import ModalLog, apply_outlier_policy, assess_quality


def _ar1(n: int, m: int, rho: float, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.normal(size=(n, m)) * np.sqrt(1 - rho**2)
    x = np.empty((n, m))
    x[0] = rng.normal(size=m)
    for t in range(1, n):
        x[t] = rho * x[t - 1] + e[t]
    return x


def _swapped(x: np.ndarray) -> np.ndarray:
    y = x.copy()
    k = (len(x) // 2) * 2
    y[0:k:2], y[1:k:2] = x[1:k:2], x[0:k:2]
    return y


def _parity_lag1(y: np.ndarray) -> tuple[float, float]:
    """Pooled lag-1 correlation of the products at even and at odd frames (numpy)."""
    z = y - y.mean(axis=0)
    p = (z[:-1] * z[1:]).sum(axis=1) / (z * z).sum(axis=1).mean()
    return float(p[0::2].mean()), float(p[1::2].mean())


def test_every_pair_swapped_is_found_and_raise_refuses():
    x = _ar1(4000, 10, 0.95, 1)
    y = _swapped(x)
    even, odd = _parity_lag1(y)
    assert even == pytest.approx(0.95, abs=0.02) and odd == pytest.approx(0.95**3, abs=0.03)
    report = assess_quality(y)
    assert report.pair_judged and report.pair_order
    r_even, r_odd, p = report.pair_order
    assert r_even > r_odd and p < 1e-10
    assert r_even == pytest.approx(even, abs=0.05) and r_odd == pytest.approx(odd, abs=0.05)
    assert not report.clean and "swapped pairs" in report.describe()
    assert "pair_order" in report.to_dict()
    with pytest.raises(ValueError, match="swapped pairs"):
        apply_outlier_policy(ModalLog(y, rate=1000.0), "raise")


def test_the_log_in_order_is_not_flagged():
    x = _ar1(4000, 10, 0.95, 1)
    even, odd = _parity_lag1(x)
    assert abs(even - odd) < 0.01  # the same lag on both parities (numpy)
    report = assess_quality(x)
    assert report.pair_judged and report.pair_order == () and report.clean
    assert "pair_order" not in report.to_dict()
    assert report.columns()["quality_pair_order"] == ""


def test_the_other_pairing_swapped_is_named():
    x = _ar1(4001, 6, 0.9, 2)
    y = x.copy()
    y[1:], y[0] = _swapped(x[1:]), x[0]  # pairs (2k + 1, 2k + 2) reversed
    r_even, r_odd, _ = assess_quality(y).pair_order
    assert r_odd > r_even


def test_a_block_appended_twice_is_named_with_its_rows():
    x = _ar1(6000, 5, 0.99, 3)
    y = np.vstack([x, x[4000:]])  # the last 2000 frames written again
    report = assess_quality(y)
    assert report.copied_frames.tolist() == list(range(6000, 8000))
    assert report.copied_block == (6000, 8000, 4000)
    small = assess_quality(y, chunk_frames=333)  # blocks not aligned with the copy
    assert small.copied_frames.tolist() == list(range(6000, 8000))
    assert "rows 6000..7999 repeat rows 4000..5999" in report.describe()
    assert report.to_dict()["copied_frames"] == 2000
    assert report.columns()["quality_copied_block"] == "6000-7999 = 4000-5999"
    kept, _ = apply_outlier_policy(ModalLog(y, rate=1000.0), "drop")
    assert np.array_equal(np.asarray(kept.coeffs), x)
    with pytest.raises(ValueError, match="block written twice"):
        apply_outlier_policy(ModalLog(y, rate=1000.0), "raise")


def test_a_block_copied_into_the_middle():
    x = _ar1(5000, 3, 0.9, 4)
    y = np.vstack([x[:3000], x[2000:3000], x[3000:]])
    report = assess_quality(y)
    assert report.copied_frames.tolist() == list(range(3000, 4000))
    assert report.copied_block == (3000, 4000, 2000)


def test_a_frame_resent_in_a_row_is_no_copy():
    x = _ar1(4000, 5, 0.9, 5)
    x[1001:1051] = x[1000]  # 50 re-sends: the repeated-frame rule's, not a copied block
    report = assess_quality(x)
    assert report.copied_frames.size == 0 and report.repeated_frames.size == 50


@pytest.mark.parametrize("q", [0.3, 0.01])
def test_frames_equal_by_chance_on_a_rounded_log_are_no_copy(q):
    x = np.round(_ar1(8000, 2, 0.99, 6) / q) * q
    z = x.view(np.complex128).ravel()  # each frame as one value, to count equal frames
    assert np.unique(z).size < len(z) - 1  # frames do agree by chance (numpy)
    assert assess_quality(x).copied_frames.size == 0


def test_info_names_both_and_raise_exits_2(tmp_path, capsys):
    x = _ar1(3000, 6, 0.95, 7)
    for name, y in (("swapped", _swapped(x)), ("copied", np.vstack([x, x[2000:2500]]))):
        save(ModalLog(y, rate=1000.0, wavelength=5e-7), tmp_path / f"{name}.npz")
    assert main(["info", str(tmp_path / "swapped.npz")]) == 0
    out = capsys.readouterr()
    assert "frames in swapped pairs?" in out.out + out.err
    assert main(["info", str(tmp_path / "copied.npz")]) == 0
    out = capsys.readouterr()
    assert "rows 3000..3499 repeat rows 2000..2499" in out.out + out.err
    for name in ("swapped", "copied"):
        assert main(["info", str(tmp_path / f"{name}.npz"), "--outliers", "raise"]) == 2
        err = capsys.readouterr().err
        assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
