"""A new MI method is one module: two methods defined in this file alone run everywhere.

The extension point of ``modalinfo.information.methods``: this file defines two methods
and registers them with :func:`register_method`, then runs them through
``mutual_information`` / ``MutualInformation`` / ``entropy``,
``conditional_mutual_information`` and ``transfer_entropy`` (with the bias rule's
fallback), ``order_modes`` and the command line (``modalinfo reorder --estimator NAME``,
in-process, so the registration is visible).

References (from outside the code under test):

* ``"hist8"``, a binned estimator with a fixed bin count that mimics the built-in
  histogram: its numbers equal ``method="histogram", bins=8`` bit for bit (MI, entropy,
  CMI, an ordering, the command line's saved ordering);
* ``"pearson"``, a Gaussian-correlation method written here from numpy alone: the
  closed forms of Gaussian data, ``-0.5 ln(1 - rho^2)`` (Cover & Thomas 2006, Example
  8.5.1), ``0.5 ln(2 pi e sigma^2)`` (Example 8.1.2), the CMI of a Gaussian triple from
  the determinants of its population covariance (eq. 8.56), and the transfer entropy
  of a VAR(1) from its stationary covariance (scipy's discrete Lyapunov solver). The
  tolerances are 5 standard deviations of the estimate at the sample size used; a
  10 % error of any of these quantities exceeds them;
* unknown, duplicate and malformed records are refused with errors naming the argument.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest
from scipy import linalg, signal

from modalinfo.cli import main
from modalinfo.information import (
    CMI_METHODS,
    METHODS,
    BiasRuleWarning,
    MIMethod,
    MutualInformation,
    conditional_mutual_information,
    entropy,
    mutual_information,
    mutual_information_ci,
    register_method,
    transfer_entropy,
    unregister_method,
)
from modalinfo.information.histogram import (
    HistogramEngine,
    histogram_bias_rule,
    histogram_cmi,
    histogram_entropy,
)
from modalinfo.io import load, save
from modalinfo.ordering import OrderingResult, order_modes
from modalinfo.ordering.compare import basis_for_log
from modalinfo.telemetry.synthetic import kaos_like


# ---------------------------------------------------------------- method 1: "hist8"
class Hist8Engine:
    """Histogram MI on a fixed 8 x 8 table (the built-in engine with ``bins=8``)."""

    def __init__(self, *, bias_correction: str = "miller-madow", binning: str = "quantile"):
        self._engine = HistogramEngine(bins=8, bias_correction=bias_correction, binning=binning)

    def fit(self, x):
        self._engine.fit(x)
        return self

    def score(self, y):
        return self._engine.score(y)


def hist8_entropy(x, *, bias_correction="miller-madow", binning="uniform"):
    return histogram_entropy(x, bins=8, bias_correction=bias_correction, binning=binning)


def hist8_cmi(x, y, z, *, bias_correction="miller-madow", binning="quantile"):
    return histogram_cmi(x, y, z, bins=8, bias_correction=bias_correction, binning=binning)


HIST8 = MIMethod(name="hist8", engine=Hist8Engine, entropy=hist8_entropy, cmi=hist8_cmi,
                 bias_rule=lambda n, d, options: histogram_bias_rule(n, d, {"bins": 8}),
                 summary="plug-in MI on 8 equiprobable bins per axis")


# ---------------------------------------------------------------- method 2: "pearson"
class PearsonEngine:
    """``-0.5 ln(1 - r^2)`` with r the Pearson correlation of the values (numpy only)."""

    def fit(self, x):
        self._xc = x - x.mean()
        return self

    def score(self, y):
        yc = y - y.mean()
        r = float(self._xc @ yc) / math.sqrt(float(self._xc @ self._xc) * float(yc @ yc))
        return -0.5 * math.log1p(-r * r)


def pearson_entropy(x):
    return 0.5 * math.log(2.0 * math.pi * math.e * float(np.var(x, ddof=1)))


def _logdet(c):
    return float(np.linalg.slogdet(c)[1]) if c.size else 0.0


def gaussian_cmi_of_covariance(c, dx, dy):
    """0.5 ln(det C_xz det C_yz / (det C_z det C_xyz)) of blocks (x, y, z) of ``c``."""
    d = c.shape[0]
    xz = np.r_[np.arange(dx), np.arange(dx + dy, d)]
    yz = np.arange(dx, d)
    z = np.arange(dx + dy, d)
    return 0.5 * (_logdet(c[np.ix_(xz, xz)]) + _logdet(c[np.ix_(yz, yz)])
                  - _logdet(c[np.ix_(z, z)]) - _logdet(c))


def pearson_cmi(x, y, z):
    return gaussian_cmi_of_covariance(np.cov(np.hstack([x, y, z]), rowvar=False),
                                      x.shape[1], y.shape[1])


def at_most_four_columns(n, d, options):
    return None if d <= 4 else f"pearson CMI over {d} columns: this test's rule is d <= 4"


PEARSON = MIMethod(name="pearson", engine=PearsonEngine, entropy=pearson_entropy,
                   cmi=pearson_cmi, bias_rule=at_most_four_columns,
                   summary="Gaussian MI of the Pearson correlation of the values")


@pytest.fixture(scope="module", autouse=True)
def registered():
    """Register the two methods for this module only (other test files see the built-ins)."""
    for m in (HIST8, PEARSON):
        register_method(m)
    yield
    for m in (HIST8, PEARSON):
        unregister_method(m.name)


@pytest.fixture(scope="module")
def pair():
    rng = np.random.default_rng(11)
    x = rng.standard_normal(3000)
    return x, 0.6 * x + 0.8 * rng.standard_normal(3000)


# ---------------------------------------------------------------- registry
def test_registered_names_appear_in_the_live_name_lists():
    assert METHODS[:4] == ("kde", "histogram", "ksg", "gaussian")
    assert "hist8" in METHODS and "pearson" in METHODS
    assert "hist8" in CMI_METHODS and "pearson" in CMI_METHODS


def test_mimic_gives_the_histogram_numbers_bit_for_bit(pair):
    x, y = pair
    assert mutual_information(x, y, method="hist8") == \
        mutual_information(x, y, method="histogram", bins=8)
    assert MutualInformation("hist8", units="bits").fit(x).score(y) == \
        mutual_information(x, y, method="histogram", units="bits", bins=8)
    assert mutual_information(x, y, method="hist8", binning="uniform") == \
        mutual_information(x, y, method="histogram", bins=8, binning="uniform")
    assert entropy(x, method="hist8") == entropy(x, method="histogram", bins=8)
    z = np.column_stack([y[::-1], np.cos(x)])
    with pytest.warns(BiasRuleWarning):  # 4 columns, 8 bins: n = 3000 < 8^4 cells
        mimic = conditional_mutual_information(x, y, z, method="hist8")
    with pytest.warns(BiasRuleWarning):
        builtin = conditional_mutual_information(x, y, z, method="histogram", bins=8)
    assert mimic == builtin
    assert conditional_mutual_information(x, y, z[:, 0], method="hist8") == \
        conditional_mutual_information(x, y, z[:, 0], method="histogram", bins=8)


def test_gaussian_plug_in_matches_the_closed_forms():
    rng = np.random.default_rng(5)
    n, rho, sigma = 100_000, 0.6, 2.0
    x = sigma * rng.standard_normal(n)
    y = rho * x / sigma + math.sqrt(1 - rho**2) * rng.standard_normal(n)
    # sd of the MI estimate ~ rho / sqrt(n) = 0.0019 nats; of the entropy sqrt(1/(2n)) = 0.0022
    assert mutual_information(x, y, method="pearson") == pytest.approx(
        -0.5 * math.log(1 - rho**2), abs=0.01)
    assert entropy(x, method="pearson") == pytest.approx(
        0.5 * math.log(2 * math.pi * math.e * sigma**2), abs=0.01)
    # a Gaussian triple z -> x, z -> y, x -> y: CMI from the population covariance
    A = np.array([[1.0, 0.0, 0.7], [0.9, 1.0, 0.4], [0.0, 0.0, 1.0]])  # (x, y, z) = A e
    e = rng.standard_normal((n, 3))
    xyz = e @ A.T
    exact = gaussian_cmi_of_covariance(A @ A.T, 1, 1)  # 0.5 ln 1.81 = 0.297
    assert exact == pytest.approx(0.5 * math.log(1.81), rel=1e-12)
    # sd of the estimate ~ r / sqrt(n) with r^2 = 0.81 / 1.81 the partial correlation: 0.0021
    assert conditional_mutual_information(xyz[:, 0], xyz[:, 1], xyz[:, 2],
                                          method="pearson") == pytest.approx(exact, abs=0.012)


def test_gaussian_plug_in_transfer_entropy_of_a_var1():
    # x_t = 0.6 x_{t-1} + 0.5 y_{t-1} + e_t, y_t = 0.8 y_{t-1} + f_t (unit noises)
    A = np.array([[0.6, 0.5], [0.0, 0.8]])
    S = linalg.solve_discrete_lyapunov(A, np.eye(2))  # stationary covariance
    g1 = (A @ S)[0, 0]  # Cov(x_t, x_{t-1})
    te = 0.5 * math.log(S[0, 0] - g1**2 / S[0, 0])  # Var(x_t | x_{t-1}) / Var(e) = 1
    rng = np.random.default_rng(7)
    n = 200_000
    f, e = rng.standard_normal(n), rng.standard_normal(n)
    y = signal.lfilter([1.0], [1.0, -0.8], f)
    x = signal.lfilter([1.0], [1.0, -0.6], e + 0.5 * np.r_[0.0, y[:-1]])
    x, y = x[1000:], y[1000:]  # past the start-up transient
    # te = 0.1854; sd of the estimate ~ r / sqrt(n), r^2 = 1 - exp(-2 te) = 0.31: 0.0013
    assert transfer_entropy(y, x, method="pearson") == pytest.approx(te, abs=0.008)
    assert transfer_entropy(x, y, method="pearson") == pytest.approx(0.0, abs=0.008)


def test_plug_in_bias_rule_falls_back_to_the_gaussian_copula(pair):
    x, y = pair
    z = np.column_stack([np.sin(x), y**2, np.cos(y)])  # 5 columns: this rule refuses
    with pytest.warns(BiasRuleWarning, match="this test's rule is d <= 4"):
        value = conditional_mutual_information(x, y, z, method="pearson")
    assert value == conditional_mutual_information(x, y, z, method="gaussian")
    with pytest.raises(ValueError, match="this test's rule is d <= 4"):
        conditional_mutual_information(x, y, z, method="pearson", fallback="raise")


def test_capabilities_are_read_from_the_record(pair):
    x, y = pair
    mi_only = dataclasses.replace(PEARSON, name="pearson-mi", entropy=None, cmi=None)
    no_boot = dataclasses.replace(PEARSON, name="pearson-noboot",
                                  bootstrap="this test's record says so")
    register_method(mi_only)
    register_method(no_boot)
    try:
        assert mutual_information(x, y, method="pearson-mi") == \
            mutual_information(x, y, method="pearson")
        assert "pearson-mi" in METHODS and "pearson-mi" not in CMI_METHODS
        with pytest.raises(ValueError, match=r"'pearson-mi' is registered with no `cmi`"):
            conditional_mutual_information(x, y, method="pearson-mi")
        with pytest.raises(ValueError, match=r"'pearson-mi' is registered with no `entropy`"):
            entropy(x, method="pearson-mi")
        with pytest.raises(ValueError, match="`method`='pearson-noboot' cannot be bootstrapped: "
                           "this test's record says so; use 'kde', 'histogram', "):
            mutual_information_ci(x, y, method="pearson-noboot", n_resamples=10, seed=0)
    finally:
        unregister_method("pearson-mi")
        unregister_method("pearson-noboot")
    assert "pearson-mi" not in METHODS


# ---------------------------------------------------------------- ordering and command line
@pytest.fixture(scope="module")
def log_path(tmp_path_factory):
    path = tmp_path_factory.mktemp("logs") / "kaos.npz"
    save(kaos_like(n_frames=120, seed=0), path)
    return path


def test_ordering_and_command_line_use_the_new_method(log_path, tmp_path, capsys):
    log = load(log_path)
    basis = basis_for_log("zernike", log, n_pixels=16)
    common = dict(sample_budget=3000, seed=1, n_resamples=0)
    ours = order_modes(log, basis, "mi_greedy", estimator="hist8", **common)
    builtin = order_modes(log, basis, "mi_greedy", estimator="histogram",
                          estimator_options={"bins": 8}, **common)
    np.testing.assert_array_equal(ours.order, builtin.order)
    np.testing.assert_array_equal(ours.gain, builtin.gain)
    np.testing.assert_array_equal(ours.mi, builtin.mi)
    assert ours.estimator == "hist8"

    out = tmp_path / "ord.json"
    assert main(["reorder", str(log_path), "--estimator", "hist8", "--method", "mi_greedy",
                 "--budget", "3000", "--seed", "1", "--resamples", "0",
                 "--pupil-pixels", "16", "--out", str(out), "--quiet"]) == 0
    saved = OrderingResult.from_json(out)
    np.testing.assert_array_equal(saved.order, builtin.order)
    np.testing.assert_array_equal(saved.gain, builtin.gain)
    assert saved.estimator == "hist8"
    capsys.readouterr()


def test_command_line_refuses_an_unregistered_name_in_one_line(log_path, capsys):
    with pytest.raises(SystemExit) as exc:
        main(["reorder", str(log_path), "--estimator", "hist9"])
    assert exc.value.code == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "invalid choice: 'hist9'" in err and "'hist8'" in err


# ---------------------------------------------------------------- refusals
def test_unknown_and_duplicate_names_are_refused(pair):
    x, y = pair
    with pytest.raises(ValueError, match=r"`method` must be one of 'kde', .*'hist8'.*; "
                                         r"got 'nope'"):
        mutual_information(x, y, method="nope")
    with pytest.raises(ValueError, match="`method` name 'ksg' is registered already"):
        register_method(dataclasses.replace(PEARSON, name="ksg"))
    with pytest.raises(ValueError, match="`method` name 'pearson' is registered already"):
        register_method(PEARSON)
    with pytest.raises(ValueError, match="`method` must be one of .*got 'nope'"):
        unregister_method("nope")
    with pytest.raises(TypeError, match="`method` must be an MIMethod record; got str"):
        register_method("pearson")
    with pytest.raises(TypeError, match=r"method='pearson' does not accept option\(s\) bins"):
        mutual_information(x, y, method="pearson", bins=8)


@pytest.mark.parametrize("fields,error,message", [
    ({"name": "two words"}, ValueError, "`name` must be a non-empty string without spaces"),
    ({"name": ""}, ValueError, "`name` must be a non-empty string"),
    ({"engine": 3}, TypeError, "`engine` of MI method 'bad' must be callable; got int"),
    ({"cmi": "f"}, TypeError, "`cmi` of MI method 'bad' must be callable or None; got str"),
    ({"bootstrap": True}, TypeError, "`bootstrap` of MI method 'bad' must be None or a"),
])
def test_malformed_records_are_refused(fields, error, message):
    with pytest.raises(error, match=message):
        MIMethod(**{"name": "bad", "engine": PearsonEngine, **fields})
