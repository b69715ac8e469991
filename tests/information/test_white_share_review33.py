"""``flow.white_share`` against a numpy copy of its documented rule (review33).

Mutation round 33 (docs/MUTATION.md): plants in fix50-c's white share (the floor on
rho_1..rho_3, the level line, the intercept's standard error) that the fix50-c and
round-49 files let through. Reference, from outside the code, the docstring's rule
computed with numpy only:

- rho_k from the biased sample autocovariance (Brockwell & Davis eq. 1.4.4), lags <= 200;
- None unless rho_1, rho_2 and rho_3 are all above ``4 / sqrt(n)``;
- ``log c``: the intercept at k = 0 of the least-squares line of ``log rho_k`` on k = 1, 2,
  3 where rho_3 < rho_1 (``numpy.polyfit``), else of the level line (the mean);
- its s.e.: Bartlett's variance ``(1 + 2 sum rho_j^2) / n`` of each rho_k propagated
  through the intercept's weights (the first row of ``numpy.linalg.pinv`` of the design,
  or 1/3 each for the level line) without covariances;
- the share ``1 - c``, None unless it exceeds 0.2 and ``-log c`` exceeds 3 s.e.
"""

import math

import numpy as np
import pytest

from modalinfo.information.flow import white_share


def _reference(x: np.ndarray) -> float | None:
    n = x.shape[0]
    d = x - x.mean()
    g = np.array([d[: n - k] @ d[k:] / n for k in range(min(n - 1, 200) + 1)])
    rho = g / g[0]
    r = rho[1:4]
    if not r.min() > 4.0 / math.sqrt(n):
        return None
    var = (1.0 + 2.0 * np.sum(rho[1:] ** 2)) / n
    k = np.array([1.0, 2.0, 3.0])
    if r[2] < r[0]:
        log_c = np.polyfit(k, np.log(r), 1)[1]
        w = np.linalg.pinv(np.column_stack([np.ones(3), k]))[0]
    else:
        log_c, w = np.mean(np.log(r)), np.full(3, 1.0 / 3.0)
    se = math.sqrt(var * np.sum((w / r) ** 2))
    share = 1.0 - math.exp(log_c)
    return None if share <= 0.2 or -log_c <= 3.0 * se else share


def _ar1_plus_noise(phi: float, noise_var: float, n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    e = rng.standard_normal(n + 500)
    z = np.zeros(n + 500)
    for t in range(1, z.size):
        z[t] = phi * z[t - 1] + e[t]
    return z[500:] + math.sqrt(noise_var) * rng.standard_normal(n)


CASES = [(phi, v, s) for phi in (0.3, 0.7, 0.9, 0.99) for v in (0.5, 3.0, 20.0, 200.0)
         for s in range(3)]
#: level lines (sampled rho_3 >= rho_1) whose -log c is 4.3 and 5.1 of its s.e.: past the
#: gate of 3, not past 9 (an s.e. three times too large)
CASES += [(0.99, 50.0, 0), (0.99, 50.0, 4)]


def test_the_cases_reach_every_branch():
    """The set holds Nones and shares, falling and level lines (else it tests little)."""
    got = [_reference(_ar1_plus_noise(p, v, 1500, s)) for p, v, s in CASES]
    assert sum(v is None for v in got) >= 5 and sum(v is not None for v in got) >= 5


@pytest.mark.parametrize("phi, noise_var, seed", CASES)
def test_white_share_is_the_documented_rule(phi, noise_var, seed):
    x = _ar1_plus_noise(phi, noise_var, 1500, seed)
    ref = _reference(x)
    got = white_share(x)
    if ref is None:
        assert got is None
    else:
        assert got == pytest.approx(ref, abs=1e-9)
