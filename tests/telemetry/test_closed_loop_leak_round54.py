"""The synthetic closed loop with a leaky integrator (fix54-e, issue 27).

References: (1) the loop written here as its time-domain recursion, one frame at a time
(``m[k] = y[k] - sum_j w_j c[k-j]``, ``c[k] = (1 - leak) c[k-1] + g m[k]``, the WFS seeing
the command of ``d + 1`` frames earlier with a whole-frame exposure), against
``closed_loop_simulation``'s residual and commands to rounding; (2) the servo-lag
variance of the leaky loop on an AR(1) mode, exactly: the residual is the ARMA process
``L(B) / ((1 - phi B) (L(B) + g B**(d + 1))) e`` (``L = 1 - (1 - leak) B``), whose variance
statsmodels' ``arma_acovf`` gives; the package's ``rejection_transfer_function`` integrated
against the AR(1) spectrum must give it to 1e-6, and a simulated 40,000-frame log within
4 standard errors (the s.e. of a sample variance of a correlated series, ``sqrt(2 / N
sum_k rho_k**2)``, from the same ``arma_acovf``: a false failure below 1e-4). Before
fix54-e ``closed_loop_log`` took no ``leak`` (TypeError), and the leak-free rejection's
variance is x0.28 of the leaky loop's at leak 0.2 (the test says so).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import integrate, signal
from statsmodels.tsa.arima_process import arma_acovf

from modalinfo.servo import rejection_transfer_function
from modalinfo.telemetry import ModalLog
from modalinfo.telemetry.synthetic import closed_loop_log, closed_loop_simulation

RATE, PHI = 1000.0, 0.99


def _ar1(n: int, seed: int, modes: int = 1) -> np.ndarray:
    e = np.random.default_rng(seed).standard_normal((n, modes))
    return signal.lfilter([1.0], [1.0, -PHI], e, axis=0)


def _log(x: np.ndarray) -> ModalLog:
    return ModalLog(x, rate=RATE, modes=list(range(2, 2 + x.shape[1])))


@pytest.mark.parametrize("delay", [0, 1, 2])
@pytest.mark.parametrize("leak", [0.0, 0.1, 0.5])
def test_leaky_loop_is_its_recursion(delay, leak):
    y = _ar1(3000, 5401, modes=2)
    gain = 0.3
    res = closed_loop_simulation(_log(y), gain=gain, delay_frames=float(delay), leak=leak)
    m = np.zeros_like(y)
    c = np.zeros_like(y)
    for k in range(y.shape[0]):
        seen = c[k - delay - 1] if k - delay - 1 >= 0 else 0.0
        m[k] = y[k] - seen
        c[k] = (1.0 - leak) * (c[k - 1] if k else 0.0) + gain * m[k]
    np.testing.assert_allclose(res.residual.coeffs, m, atol=1e-9)
    np.testing.assert_allclose(res.commands.coeffs, c, atol=1e-9)
    meta = res.residual.metadata["closed_loop"]
    assert meta.get("leak", 0.0) == leak


def _exact_variance(gain: float, delay: int, leak: float) -> tuple[float, np.ndarray]:
    """Variance and autocorrelations of the residual on a unit-innovation AR(1) input."""
    den = np.zeros(delay + 2)
    den[:2] = [1.0, -(1.0 - leak)]
    den[delay + 1] += gain
    ar = np.polymul([1.0, -PHI], den)
    ma = np.array([1.0, -(1.0 - leak)])
    acov = arma_acovf(ar, ma, nobs=4000)
    return float(acov[0]), acov / acov[0]


@pytest.mark.parametrize(("delay", "leak"), [(1, 0.2), (2, 0.5), (1, 0.0)])
def test_servo_lag_variance_of_a_leaky_loop(delay, leak):
    gain = 0.3
    exact, rho = _exact_variance(gain, delay, leak)
    # the rejection integrated against the AR(1) spectrum 1 / |1 - phi e^{-iw}|^2
    def spectral(e_fn):
        def integrand(f):
            s_y = 1.0 / np.abs(1.0 - PHI * np.exp(-2j * np.pi * f / RATE)) ** 2
            return np.abs(e_fn(f)) ** 2 * s_y
        edges = np.concatenate([[0.0], np.geomspace(1e-3, RATE / 2, 400)])
        return sum(integrate.fixed_quad(integrand, a, b, n=40)[0]
                   for a, b in zip(edges[:-1], edges[1:], strict=True)) * 2 / RATE

    kw = dict(rate=RATE, gain=gain, delay_frames=float(delay))
    leaky = spectral(lambda f: rejection_transfer_function(f, leak=leak, **kw))
    assert leaky == pytest.approx(exact, rel=1e-6)
    if leak:
        free = spectral(lambda f: rejection_transfer_function(f, **kw))
        assert free < 0.8 * exact  # the pure integrator's answer is far off
    n = 40_000
    r = closed_loop_log(_log(_ar1(n + 1000, 5402 + delay)), gain=gain,
                        delay_frames=float(delay), leak=leak).coeffs[1000:, 0]
    se = exact * np.sqrt(2.0 / n * (1.0 + 2.0 * np.sum(rho[1:] ** 2)))
    assert abs(float(np.mean(r ** 2)) - exact) < 4.0 * se, (np.mean(r ** 2), exact, se)


def test_unstable_leaky_gain_refused_by_name():
    with pytest.raises(ValueError, match="leak"):
        closed_loop_log(_log(_ar1(100, 1)), gain=1.2, delay_frames=1.0, leak=0.1)
    with pytest.raises(ValueError, match="leak"):
        closed_loop_log(_log(_ar1(100, 1)), gain=0.3, delay_frames=1.0, leak=1.0)
