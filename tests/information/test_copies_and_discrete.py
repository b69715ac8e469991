"""A continuous variable and its copy (refused), discrete pairs (exact MI), kde on ties.

References:
- a continuous X and a strictly monotone function of it have no joint density, so
  I(X; f(X)) is infinite (Cover & Thomas 2006, sec. 8.5 and eq. 8.71: I = h(X) +
  h(Y) - h(X, Y) with h(X, Y) = -inf on a curve); a discrete X and its copy have
  I(X; X) = H(X) (Cover & Thomas, eq. 2.42), ln 4 for four equiprobable values;
- a binary symmetric channel: X ~ Bernoulli(1/2), Y = X xor B with B ~ Bernoulli(q)
  independent, I = ln 2 - H_b(q) (Cover & Thomas, sec. 7.1.4);
- scikit-learn's ``mutual_info_score`` (the plug-in MI of the contingency table) plus
  the Miller-Madow term (K_x + K_y - K_xy - 1) / (2 n) (Miller 1955) for the exact
  arithmetic of the discrete rule;
- the Gaussian estimator's -0.5 ln(1 - r^2) is infinite at |r| = 1 (Cover & Thomas,
  Example 8.5.1), so a discrete variable and its copy with too few samples per cell for
  the table rule (normal scores affine in each other) is refused; with enough, the
  gaussian method too gives the table's MI (audit 9, t14: a normal model of a binary
  pair is not its MI); for y = x + s e, numpy's ``corrcoef`` (the law's
  I = 0.5 ln(1 + 1 / s^2) within sampling error);
- the exact MI of a rounded normal pair (cell probabilities by quadrature,
  ``benchmarks/bench_mi_accuracy.py``, checked in test_beyond_normal_tasks.py).
"""

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest
from sklearn.metrics import mutual_info_score

from modalinfo.information import METHODS, MutualInformation, mutual_information
from modalinfo.information.methods import BiasRuleWarning

BENCH = Path(__file__).resolve().parents[2] / "benchmarks" / "bench_mi_accuracy.py"


@pytest.fixture(scope="module")
def x():
    return np.random.default_rng(40).standard_normal(2000)


@pytest.mark.parametrize("method", METHODS)
@pytest.mark.parametrize("copy", ["same", "negated", "exp", "affine"])
def test_continuous_variable_and_its_monotone_copy_is_refused(x, method, copy):
    y = {"same": x, "negated": -x, "exp": np.exp(x), "affine": 3.0 * x + 1.0}[copy]
    with pytest.raises(ValueError, match="strictly monotone function of `x`.*infinite"):
        mutual_information(x, y, method=method)
    with pytest.raises(ValueError, match="strictly monotone"):
        MutualInformation(method).fit(x).score(y)


@pytest.mark.parametrize("method", ["kde", "histogram", "gaussian"])
def test_near_copies_are_estimated_not_refused(x, method):
    # the first 32 samples concordant and the rest independent: the screen passes and
    # the full check must clear it. (A copy with two samples swapped is still a function
    # of x, 4 turning points: refused since audit 9 as a deterministic pair,
    # tests/information/test_api.py (audit 9).)
    head = np.concatenate([x[:32], np.random.default_rng(41).standard_normal(x.size - 32)])
    assert mutual_information(x, head, method=method) < 0.1  # nearly independent


@pytest.mark.parametrize("method", ["kde", "histogram", "ksg", "gaussian"])
def test_discrete_variable_and_its_copy_give_its_entropy(method):
    n = 10_000
    x = np.random.default_rng(42).integers(0, 4, n).astype(float)
    got = mutual_information(x, x, method=method)
    # plug-in of the table + Miller-Madow with K_x = K_y = K_xy = 4
    assert got == pytest.approx(mutual_info_score(x, x) + 3 / (2 * n), rel=1e-9)
    assert got == pytest.approx(math.log(4.0), abs=2e-3)


@pytest.mark.parametrize("copula", [True, False])
@pytest.mark.parametrize("copy", ["same", "flipped", "affine"])
def test_gaussian_refuses_a_discrete_variable_and_its_copy(copula, copy):
    # before: 15-17 nats (1 - r^2 floored), where the other methods give the entropy.
    # 60 levels in 2000 samples: 3600 cells, fewer than 10 samples each, so the table
    # rule does not apply and the normal model's infinite MI is refused
    b = np.random.default_rng(43).integers(0, 60, 2000).astype(float)
    y = {"same": b, "flipped": 1.0 - b, "affine": 3.0 * b + 2.0}[copy]
    with pytest.raises(ValueError, match=r"affine function of `x`.*\+-1 .*infinite"):
        mutual_information(b, y, method="gaussian", copula=copula)


@pytest.mark.parametrize("copula", [True, False])
@pytest.mark.parametrize("copy", ["same", "flipped", "affine"])
def test_gaussian_gives_a_binary_copy_its_entropy(copula, copy):
    # a binary copy has 2 x 2 cells of ~500 samples: the table's MI, H(b) ~ ln 2
    b = np.random.default_rng(43).integers(0, 2, 2000).astype(float)
    y = {"same": b, "flipped": 1.0 - b, "affine": 3.0 * b + 2.0}[copy]
    got = mutual_information(b, y, method="gaussian", copula=copula)
    assert got == pytest.approx(_miller_madow_table_mi(b, y), rel=1e-9)
    assert got == pytest.approx(math.log(2.0), abs=2e-3)


@pytest.mark.parametrize("method", METHODS)
def test_binary_symmetric_channel_is_its_table_for_every_method(method):
    # audit 9, t14: the gaussian method gave 0.565 (the normal model of phi = 0.8) for an
    # exact ln 2 - H(0.1) = 0.368; every method now gives the table's Miller-Madow MI
    n, q = 10_000, 0.1
    rng = np.random.default_rng(45)
    x = rng.integers(0, 2, n).astype(float)
    y = np.abs(x - (rng.random(n) < q))
    got = mutual_information(x, y, method=method)
    assert got == pytest.approx(_miller_madow_table_mi(x, y), rel=1e-9)
    exact = math.log(2.0) + q * math.log(q) + (1 - q) * math.log(1 - q)
    assert got == pytest.approx(exact, abs=0.015)  # sd ~0.004 nats at n = 1e4


@pytest.mark.parametrize("copula", [True, False])
def test_gaussian_engine_refuses_a_continuous_copy_itself(x, copula):
    # the engine alone (an ordering's estimator object may bypass the api's copy check)
    from modalinfo.information.gaussian import GaussianEngine

    with pytest.raises(ValueError, match="affine function of `x`"):
        GaussianEngine(copula=copula).fit(x).score(3.0 * x + 1.0)


def test_gaussian_near_copies_are_still_estimated(x):
    b = np.random.default_rng(43).integers(0, 60, 2000).astype(float)
    c = b.copy()
    c[[7, 8]] = c[[8, 7]] + 0.5  # two of 2000 moved: r ~ 0.9993, a finite normal MI
    r = np.corrcoef(b, c)[0, 1]
    # the values' normal model of a 60-level variable is not its law (its entropy, ~4.1
    # nats): the copula path's ties rule warns for copula=False too (fix54-c)
    with pytest.warns(BiasRuleWarning, match="copula=False"):
        got = mutual_information(b, c, method="gaussian", copula=False)
    assert got == pytest.approx(-0.5 * math.log(1.0 - r**2), rel=1e-6)
    # 1 - r^2 ~ 1e-10, below the 1e-6 where the residual check runs: still a number
    s = 1e-5
    y = x + s * np.random.default_rng(44).standard_normal(x.size)
    r = np.corrcoef(x, y)[0, 1]
    got = mutual_information(x, y, method="gaussian", copula=False)
    # numpy's sample r; at 1 - r^2 ~ 1e-10 rounding of r (~n eps) leaves ~1e-3 of 1 - r^2
    assert got == pytest.approx(-0.5 * math.log(1.0 - r * r), abs=1e-3)
    assert got == pytest.approx(0.5 * math.log(1.0 + 1.0 / s**2), abs=0.1)  # the law's


@pytest.mark.parametrize("q", [0.0, 0.1, 0.3])
def test_ksg_on_two_valued_data_recovers_the_exact_mi(q):
    # before the discrete rule: 0.703 nats for q = 0 (exact ln 2 = 0.693)
    n = 10_000
    rng = np.random.default_rng(43)
    x = rng.integers(0, 2, n).astype(float)
    y = np.abs(x - (rng.random(n) < q))
    hb = 0.0 if q == 0 else -(q * math.log(q) + (1 - q) * math.log(1 - q))
    got = mutual_information(x, y, method="ksg")
    # sd of the plug-in MI at n = 1e4 is ~0.004 nats for these channels (delta method)
    assert got == pytest.approx(math.log(2.0) - hb, abs=0.015)
    assert got == pytest.approx(mutual_info_score(x, y) + 1 / (2 * n)
                                if q == 0 else mutual_info_score(x, y) - 1 / (2 * n),
                                rel=1e-9)


def test_kde_cv_bandwidth_falls_back_to_scott_on_ties():
    # a normal pair (rho = 0.75) rounded to 0.2 sd: ~40 levels, too many cells for the
    # discrete rule; cv would collapse onto the atoms (measured 0.589), Scott does not
    spec = importlib.util.spec_from_file_location("bench_mi_accuracy", BENCH)
    bench = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(bench)
    truth = bench.rounded_normal_mi(0.75, 0.2)
    rng = np.random.default_rng(44)
    a = rng.standard_normal(10_000)
    b = 0.75 * a + math.sqrt(1 - 0.75**2) * rng.standard_normal(10_000)
    a, b = np.round(a / 0.2) * 0.2, np.round(b / 0.2) * 0.2
    got = mutual_information(a, b, method="kde")
    assert got == mutual_information(a, b, bandwidth="scott", method="kde")
    assert got == pytest.approx(truth, abs=0.02)


def test_ksg_on_a_discrete_continuous_mixture_stays_with_the_tie_noise():
    # X ~ Bernoulli(1/2), Y = 1.5 X + N(0, 1): I = h(Y) - h(Y | X), h(Y) of the two-normal
    # mixture by quadrature (scipy.integrate.quad), h(Y | X) = ln(2 pi e) / 2; the
    # discrete rule does not apply (y is continuous) and the seeded tie noise on x keeps
    # the estimate right (measured 0.215, 0.205, 0.216 for seeds 0-2 at n = 1e4)
    from scipy import integrate, stats

    def mixture(v):
        return 0.5 * stats.norm.pdf(v) + 0.5 * stats.norm.pdf(v - 1.5)

    h_y = integrate.quad(lambda v: -mixture(v) * math.log(mixture(v)), -12, 14, limit=200)[0]
    truth = h_y - 0.5 * math.log(2 * math.pi * math.e)
    rng = np.random.default_rng(0)
    x = rng.integers(0, 2, 10_000).astype(float)
    y = 1.5 * x + rng.standard_normal(10_000)
    # sd of one estimate ~0.006 nats (the three seeds above)
    assert mutual_information(x, y, method="ksg") == pytest.approx(truth, abs=0.025)


def _miller_madow_table_mi(a, b):
    """Plug-in MI of the contingency table (scikit-learn) plus the Miller-Madow term."""
    k_x, k_y = np.unique(a).size, np.unique(b).size
    k_xy = np.unique(np.column_stack([a, b]), axis=0).shape[0]
    return mutual_info_score(a, b) + (k_x + k_y - k_xy - 1) / (2 * a.size)


@pytest.mark.parametrize("method", ["kde", "ksg"])
def test_discrete_pair_rule_holds_at_ten_samples_per_cell(method):
    # the documented rule: the table's MI where m_x m_y <= n / 10, the kernel/neighbour
    # estimate beyond. n = 1000, x binary: y with 50 levels (100 cells) is a table, with
    # 51 levels (102 cells) it is not
    rng = np.random.default_rng(3)
    a = rng.integers(0, 2, 1000).astype(float)
    for levels, table in ((50, True), (51, False)):
        b = (np.arange(1000) % levels + 7 * a.astype(int)) % levels  # every level, tied to a
        got = mutual_information(a, b.astype(float), method=method)
        want = _miller_madow_table_mi(a, b)
        assert (abs(got - want) < 1e-12) == table, (levels, got, want)
