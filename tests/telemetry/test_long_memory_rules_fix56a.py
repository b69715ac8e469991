"""Long memory in the spread rule (fix56-a, issue 27): fractional noise's spread does not step.

References (outside the code under test):
- the exact autocovariance of fractional Gaussian noise (fGn),
  ``0.5 (|k + 1|^2H - 2 |k|^2H + |k - 1|^2H)`` (Mandelbrot & Van Ness 1968), and of
  ARFIMA(0, d, 0), ``Gamma(k + d) Gamma(1 - d) / (Gamma(k - d + 1) Gamma(d))``
  (Hosking 1981), with ``scipy.special.gammaln``;
- the covariance of the absolute values of a standard Gaussian pair of correlation
  ``rho``, ``(2 / pi) (sqrt(1 - rho^2) + rho arcsin(rho) - 1)`` (the bivariate normal's
  ``E|X||Y|``), its Toeplitz matrix (``scipy.linalg.toeplitz``) and the orthonormal
  DCT-II basis (``scipy.fft.dct``): the exact variances of the cosine terms of ``|x|``,
  whose ratios the fractional law at ``max(2d - 1/2, 0)`` must give (Taqqu 1975; Beran
  1994, sec. 3.3);
- fGn / ARFIMA draws by the Davies-Harte circulant embedding (numpy FFT), stationary by
  construction: any spread step named is a false alarm;
- planted spread steps of known ratio (numpy), and planted level steps of known size on
  AR(1) series (``scipy.signal.lfilter``): calibration events a pooling call must name
  (``CALIBRATION_LEVEL_P`` 1e-6 since fix56-a; 1e-8 named the +2 sd step below in 32 of 50
  logs);
- open-loop ``kaos_like`` logs, stationary by construction (no event to name).

Bounds from the binomial law at the stated rate (seeds fixed, so each test is one draw of
a fixed outcome): 300 series at p < 1 %, 7 or more has probability 0.034 at the nominal
1 % (fGn H 0.9: 1 of 500 after the fix, 15 of 500 before: docs/ADVERSARIAL.md "Long
memory, what fix54-a left (fix56-a)").
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.fft import dct
from scipy.linalg import toeplitz
from scipy.signal import lfilter
from scipy.special import gammaln

from modalinfo._stats import variance_steps
from modalinfo.telemetry import assess_quality
from modalinfo.telemetry.quality import calibration_events
from modalinfo.telemetry.synthetic import kaos_like


def _fgn_acvf(n: int, hurst: float) -> np.ndarray:
    k = np.arange(n, dtype=float)
    return 0.5 * (np.abs(k + 1) ** (2 * hurst) - 2 * k ** (2 * hurst)
                  + np.abs(k - 1) ** (2 * hurst))


def _arfima_acvf(n: int, d: float) -> np.ndarray:
    k = np.arange(n, dtype=float)
    return np.exp(gammaln(k + d) + gammaln(1 - d) - gammaln(k - d + 1) - gammaln(d))


def _draw(acvf: np.ndarray, rng: np.random.Generator, m: int) -> np.ndarray:
    lam = np.clip(np.fft.fft(np.concatenate([acvf, acvf[-2:0:-1]])).real, 0.0, None)
    z = rng.standard_normal((lam.size, m)) + 1j * rng.standard_normal((lam.size, m))
    return np.fft.fft(np.sqrt(lam / lam.size)[:, None] * z, axis=0).real[:acvf.size]


@pytest.mark.parametrize("acvf", [_fgn_acvf(1500, 0.9), _arfima_acvf(1500, 0.4)],
                         ids=["fgn_h0.9", "arfima_d0.4"])
def test_absolute_deviations_follow_the_fractional_law_exactly(acvf):
    from modalinfo._stats import MEMORY_GRID, deviation_memory, fractional_cosine_variances
    rho = np.clip(acvf / acvf[0], -1.0, 1.0)
    cov = 2.0 / np.pi * (np.sqrt(1.0 - rho * rho) + rho * np.arcsin(rho) - 1.0)
    n = cov.size
    basis = dct(np.eye(n), type=2, norm="ortho", axis=0)[1:22]  # rows j = 1 .. 21
    exact = np.einsum("ij,jk,ik->i", basis, toeplitz(cov), basis)
    d_y = float(deviation_memory(0.4))
    assert d_y == pytest.approx(0.3)
    row = int(np.argmin(np.abs(MEMORY_GRID - d_y)))
    np.testing.assert_allclose(fractional_cosine_variances()[row, 1:22], exact / exact[0],
                               rtol=0.03)
    # the covariance's decay k^(4d - 2) = k^-0.4 (against the level's k^-0.2)
    k = np.array([100.0, 1000.0])
    slope = np.diff(np.log(cov[k.astype(int)])) / np.diff(np.log(k))
    assert slope[0] == pytest.approx(4 * 0.4 - 2, abs=0.01)


def test_short_memory_keeps_the_short_memory_law():
    from modalinfo._stats import deviation_memory
    # d <= 1/4: summable covariances of |x| (rho^2 ~ k^(4d - 2), 4d - 2 <= -1)
    np.testing.assert_array_equal(deviation_memory(np.array([0.0, 0.1, 0.25, np.nan])), 0.0)
    assert float(deviation_memory(0.49)) == pytest.approx(0.48)


def test_spread_rule_holds_its_rate_on_long_memory():
    # 30 logs of 10 fGn H 0.9 series x 20,000 frames, every judged series' p (alpha
    # 10: the Bonferroni cut alpha / 10 = 1 passes them all): before, 15 of 500 fGn H
    # 0.9 and 14 of 500 ARFIMA d 0.4 series at p < 1 %
    p = []
    for s in range(30):
        x = _draw(_fgn_acvf(20_000, 0.9), np.random.default_rng(56_300 + s), 10)
        p += [v.p_value for v in variance_steps(x, alpha=10.0)[0]]
    assert len(p) >= 250  # judged
    assert sum(v < 0.01 for v in p) <= 6


@pytest.mark.parametrize("seed", range(3))
def test_a_spread_step_on_long_memory_is_still_named(seed):
    # fGn H 0.9 modes, 20,000 frames, one mode's spread x2 from frame 12,000
    x = _draw(_fgn_acvf(20_000, 0.9), np.random.default_rng(56_400 + seed), 5)
    x[12_000:, 2] *= 2.0
    steps = assess_quality(x).variance_steps
    assert [label for label, *_ in steps] == ["col2"]
    assert abs(steps[0][1] - 12_000) < 400


def test_a_two_sd_step_of_a_persistent_mode_is_a_calibration_event():
    # AR(1) 0.9, 5 modes x 5,000 frames, mode 2 +2 sd from frame 3,000, 20 seeds: the
    # level rule's p 3e-10 .. 8e-7 in 50 logs (fix56-a), so at 1e-6 ~98 % are named
    # (18 or more of 20: probability 0.99), at 1e-8 64 % (18 or more: 0.004)
    named = 0
    for s in range(20):
        rng = np.random.default_rng(56_500 + s)
        e = rng.standard_normal((7000, 5)) * np.sqrt(1.0 - 0.81)
        x = lfilter([1.0], [1.0, -0.9], e, axis=0)[2000:]
        x[3000:, 2] += 2.0 * x[:, 2].std()
        events = calibration_events(x, scale=False)
        assert all(j == 2 and w.startswith("the mean steps or drifts") and abs(f - 3000) < 100
                   for j, _, f, w in events), (s, events)  # no other mode, no other event
        named += bool(events)
    assert named >= 18


def test_stationary_open_loop_logs_name_no_calibration_event():
    # open-loop kaos_like, 27 modes x 2,000 frames: the level rule's smallest p over 200
    # such logs was 7e-5, far above the cut (fix56-a); fix53-a's cut had been set when the
    # rule (without its long-memory reading) named 17 of 50
    for s in range(12):
        log = kaos_like(n_frames=2000, closed_loop=False, seed=56_600 + s)
        assert calibration_events(np.asarray(log.coeffs, dtype=float)) == (), s
