"""Mode orderings: standard, variance, PCA, MI marginal and MI greedy.

References: for jointly Gaussian samples I(X; Y) = -0.5 ln(1 - r^2) (Cover & Thomas
2006, eq. 8.56), so with a test-only Gaussian estimator the greedy MI of each step is
known in closed form from the sample correlation (numpy.corrcoef) and both MI orderings
must equal the descending-variance order for independent modes; a synthetic log where
one mode carries most of the wavefront (it must come first under the package's
histogram estimator); JSON round trips. The default bootstrap block length against
the analytic circular-block optimum of an AR(1) series (Politis & White 2004):
``(6 phi^2 / (1 - phi^2)^2)^(1/3) T^(1/3)``.
"""

import json

import numpy as np
import pytest

from modalinfo.ordering import OrderingResult, mi_along_order, order_modes, sample_contributions


def orthonormal_modes(n_pix, n_modes, seed=0):
    q, _ = np.linalg.qr(np.random.default_rng(seed).standard_normal((n_pix, n_modes)))
    return q * np.sqrt(n_pix)


class GaussianMI:
    """Test-only estimator: I = -0.5 ln(1 - r^2) from numpy.corrcoef."""

    def fit(self, x):
        self.x = np.asarray(x, float)
        return self

    def score(self, y):
        r = np.corrcoef(self.x, y)[0, 1]
        return -0.5 * np.log1p(-min(r * r, 1 - 1e-15))


@pytest.fixture(scope="module")
def independent_log():
    rng = np.random.default_rng(11)
    sig = np.array([0.3, 0.2, 3.0, 0.5, 0.1, 0.25, 0.15, 0.4])
    a = rng.standard_normal((300, sig.size)) * sig
    return a, orthonormal_modes(200, sig.size, seed=2), sig


def test_gaussian_greedy_matches_closed_form(independent_log):
    a, z, sig = independent_log
    res = order_modes(a, z, "mi_greedy", estimator=GaussianMI(), sample_budget=20_000,
                      seed=3, n_resamples=0)
    expected = np.argsort(-sig, kind="stable")
    np.testing.assert_array_equal(res.order, expected)
    contrib = sample_contributions(a, z, sample_budget=20_000, seed=3)
    ref = contrib.sum(axis=0)
    partial = np.cumsum(contrib[res.order], axis=0)
    r = np.array([np.corrcoef(ref, p)[0, 1] for p in partial[:-1]])
    np.testing.assert_allclose(res.mi[:-1], -0.5 * np.log1p(-r * r), rtol=1e-10)
    assert np.isnan(res.mi[-1]) and np.isnan(res.gain[-1])
    np.testing.assert_allclose(res.gain[1:-1], np.diff(res.mi[:-1]))
    assert res.estimator == "GaussianMI" and res.n_samples == 20_000 and res.pooled


def test_gaussian_marginal_is_variance_order(independent_log):
    a, z, sig = independent_log
    res = order_modes(a, z, "mi_marginal", estimator=GaussianMI(), sample_budget=20_000,
                      seed=3, n_resamples=0)
    np.testing.assert_array_equal(res.order, np.argsort(-sig, kind="stable"))
    np.testing.assert_array_equal(res.order, order_modes(a, z, "variance").order)
    np.testing.assert_allclose(res.mi[:-1], mi_along_order(
        a, z, res.order, estimator=GaussianMI(), sample_budget=20_000, seed=3)[:-1])


@pytest.mark.parametrize("method", ["mi_marginal", "mi_greedy"])
def test_dominant_mode_first_with_histogram(method):
    rng = np.random.default_rng(21)
    n_modes = 10
    sig = np.full(n_modes, 0.2)
    sig[6] = 2.0  # mode 7 carries ~ 92% of the wavefront variance
    a = rng.standard_normal((500, n_modes)) * sig
    z = orthonormal_modes(256, n_modes, seed=5)
    res = order_modes(a, z, method, estimator="histogram", sample_budget=20_000, seed=1,
                      n_resamples=10, block_length=5)
    assert res.order[0] == 6
    assert res.labels[0] == "mode7"
    assert res.scores[6] == np.nanmax(res.scores)
    # uncertainty is reported and the first gain is far above its noise
    assert res.gain_low is not None and res.n_resamples == 10
    assert res.gain_low[0] > 0.5 * res.gain[0] > 0
    finite = np.isfinite(res.gain)
    assert np.all(res.gain_low[finite] <= res.gain_high[finite])
    assert res.mi_low[0] <= res.mi[0] <= res.mi_high[0]
    assert res.n_informative is not None and res.n_informative >= 1


def test_per_frame_ordering_uses_one_frame():
    rng = np.random.default_rng(8)
    a = rng.standard_normal((30, 5)) * 0.1
    a[4, 2] = 5.0  # in frame 4 mode 3 dominates; elsewhere nothing special
    z = orthonormal_modes(150, 5)
    res = order_modes(a, z, "mi_greedy", estimator=GaussianMI(), pooled=False, frame=4,
                      n_resamples=4, seed=0)
    assert res.order[0] == 2 and res.frame == 4 and not res.pooled
    assert res.n_samples == 150 and res.block_length is None
    var = order_modes(a, z, "variance", frame=-26)
    assert var.order[0] == 2 and var.frame == 4


def test_seed_reproducibility():
    rng = np.random.default_rng(9)
    a = rng.standard_normal((100, 6)) * np.linspace(1, 0.3, 6)
    z = orthonormal_modes(100, 6)
    r1 = order_modes(a, z, "mi_greedy", sample_budget=2000, seed=4, n_resamples=3)
    r2 = order_modes(a, z, "mi_greedy", sample_budget=2000, seed=4, n_resamples=3)
    np.testing.assert_array_equal(r1.order, r2.order)
    np.testing.assert_array_equal(r1.gain_low, r2.gain_low)
    assert r1.seed == 4


def test_default_block_length_follows_the_logs_correlation_time():
    # one mode AR(1) of 0.9 per frame, one white, T = 8000 frames: the block of the
    # pooled bootstrap is the Politis-White length of the most persistent mode, whose
    # optimum is (6 phi^2 / (1 - phi^2)^2)^(1/3) T^(1/3) = 103 frames (the former
    # default, T^(1/3) = 20 frames, ignored the correlation time); the lag-window
    # estimate of one series scatters by ~15 % at this T
    phi, T = 0.9, 8000
    rng = np.random.default_rng(12)
    e = rng.standard_normal((T, 2))
    a = e.copy()
    for t in range(1, T):
        a[t, 0] = phi * a[t - 1, 0] + e[t, 0]
    z = orthonormal_modes(64, 2)
    theory = (6 * phi**2 / (1 - phi**2) ** 2) ** (1 / 3) * T ** (1 / 3)
    kw = dict(estimator=GaussianMI(), sample_budget=500, seed=0, n_resamples=0)
    res = order_modes(a, z, "mi_marginal", **kw)
    assert res.block_length == pytest.approx(theory, rel=0.35)
    assert order_modes(a, z, "mi_marginal", block_length="auto", **kw
                       ).block_length == res.block_length
    assert order_modes(a, z, "mi_marginal", block_length=7, **kw).block_length == 7
    with pytest.raises(ValueError, match=r"`block_length` must be an int <= 8000; got 8001"):
        order_modes(a, z, "mi_marginal", block_length=8001, **kw)


def test_json_round_trip(tmp_path, independent_log):
    a, z, _ = independent_log
    res = order_modes(a, z, "mi_greedy", sample_budget=5000, seed=2, n_resamples=3,
                      estimator_options={"bins": 32})
    path = res.to_json(tmp_path / "ord.json")
    back = OrderingResult.from_json(path)
    for name in ("order", "mi", "gain", "mi_low", "mi_high", "gain_low", "gain_high", "scores"):
        np.testing.assert_array_equal(getattr(back, name), getattr(res, name))
    for name in ("labels", "basis_labels", "method", "estimator", "estimator_options",
                 "sample_budget", "n_samples", "seed", "pooled", "frame", "n_resamples",
                 "confidence_level", "block_length", "mi_units"):
        assert getattr(back, name) == getattr(res, name), name
    assert json.loads(path.read_text())["mi"][-1] is None  # NaN stored as null
    with pytest.raises(FileExistsError, match="pass overwrite=True"):
        res.to_json(path)
    res.to_json(path, overwrite=True)
    std = order_modes(a, z, "standard")
    assert OrderingResult.from_json(std.to_json(tmp_path / "s.json")).mi is None
    (tmp_path / "bad.json").write_text("{\"format\": \"other\"}")
    with pytest.raises(ValueError, match="not a serialised OrderingResult"):
        OrderingResult.from_json(tmp_path / "bad.json")
    (tmp_path / "broken.json").write_text("{")
    with pytest.raises(ValueError, match="is not valid JSON"):
        OrderingResult.from_json(tmp_path / "broken.json")


def test_table_and_rank():
    res = OrderingResult(order=np.array([2, 0, 1]), labels=("c", "a", "b"),
                         basis_labels=("a", "b", "c"), method="standard")
    np.testing.assert_array_equal(res.rank(), [1, 2, 0])
    assert res.table().splitlines()[1].split() == ["1", "c"]


def test_pca_requires_decorrelated_basis():
    rng = np.random.default_rng(10)
    a = rng.standard_normal((200, 4)) @ rng.standard_normal((4, 4))
    z = orthonormal_modes(64, 4)
    with pytest.raises(ValueError, match="`method`='pca' orders an empirical K-L basis"):
        order_modes(a, z, "pca")
    centred = a - a.mean(axis=0)
    _, _, vt = np.linalg.svd(centred, full_matrices=False)
    b = a @ vt.T  # covariance-PCA coefficients: uncorrelated after centring
    res = order_modes(b, z @ vt.T, "pca")
    np.testing.assert_array_equal(res.order, np.argsort(-b.var(axis=0)))
    with pytest.raises(ValueError, match="`frame` must be None for method='pca'"):
        order_modes(b, z @ vt.T, "pca", frame=0)


def test_bad_inputs():
    a = np.ones((20, 3))
    z = orthonormal_modes(40, 3)
    with pytest.raises(ValueError, match="`method` must be one of"):
        order_modes(a, z, "random")
    with pytest.raises(ValueError, match="`sample_budget` must be an int >= 10"):
        order_modes(a, z, "mi_greedy", sample_budget=5)
    with pytest.raises(ValueError, match="`frame` must be an int <= 19"):
        order_modes(a, z, "mi_greedy", frame=20)
    with pytest.raises(TypeError, match="`estimator` must be a method name"):
        order_modes(a, z, "mi_greedy", estimator=3)
    with pytest.raises(TypeError, match="`estimator_options` must be a dict or None"):
        order_modes(a, z, "mi_greedy", estimator_options=[1])
    with pytest.raises(ValueError, match="`estimator_options` must be empty"):
        order_modes(a, z, "mi_greedy", estimator=GaussianMI(), estimator_options={"bins": 3})
    with pytest.raises(ValueError, match="`n_resamples` must be an int >= 0"):
        order_modes(a, z, "mi_greedy", n_resamples=-1)
    with pytest.raises(ValueError, match="`confidence_level` must be < 1.0"):
        order_modes(a, z, "mi_greedy", confidence_level=1.0)
    with pytest.raises(TypeError, match="`seed` must be None, an int"):
        order_modes(a, z, "mi_greedy", seed="x")
    with pytest.raises(ValueError, match="`method` must be one of"):
        order_modes(a, z, "mi_greedy", estimator="bogus")
    with pytest.raises(ValueError, match="`pooled`=False \\(a per-frame ordering\\) needs `frame`"):
        order_modes(a, z, "mi_greedy", pooled=False)
    with pytest.raises(TypeError, match="`pooled` must be a bool"):
        order_modes(a, z, "mi_greedy", pooled="yes")


# --- adversarial round 5 (rows r10, f05): a dead mode or a constant piston ---------------


@pytest.mark.parametrize("method", ["mi_greedy", "mi_marginal"])
@pytest.mark.parametrize("dead", ["zeros", "piston", "rounding"])
def test_a_constant_mode_goes_last_and_the_rest_is_ordered_as_without_it(method, dead):
    # Reference: the same call on the log without that mode (same seed): a constant
    # contribution adds nothing, so the other modes' order and MI must be that one's.
    # Before: the estimators refused "`y` is a strictly monotone function of `x`".
    from modalinfo.bases import Pupil, ZernikeBasis

    rng = np.random.default_rng(3)
    live = rng.standard_normal((300, 4)) * np.array([1.0, 0.7, 0.5, 0.3])
    if dead == "zeros":
        modes, column, at = [2, 3, 4, 5, 6], np.zeros((300, 1)), 2
    elif dead == "rounding":  # a data K-L basis's null mode of a log with a dead mode
        modes, column, at = [2, 3, 4, 5, 6], 1e-17 * rng.standard_normal((300, 1)), 4
    else:
        modes, column, at = [1, 2, 3, 4, 5], np.full((300, 1), 0.3), 0
    coeffs = np.insert(live, at, column[:, 0], axis=1)
    pupil = Pupil(16)
    full = order_modes(coeffs, ZernikeBasis(pupil, modes), method, sample_budget=3000,
                       seed=1, n_resamples=0)
    kept = [m for k, m in enumerate(modes) if k != at]
    ref = order_modes(live, ZernikeBasis(pupil, kept), method, sample_budget=3000, seed=1,
                      n_resamples=0)
    assert full.labels[:-1] == ref.labels and full.labels[-1] == f"Z{modes[at]}"
    np.testing.assert_array_equal(full.mi[:-1], ref.mi)
    assert np.isnan(full.mi[-1]) and np.isnan(full.gain[-1])


# --- adversarial round 6 (rows r07, f06): a mode too small to change Phi_ref's order ----


@pytest.mark.parametrize("method", ["mi_greedy", "mi_marginal"])
@pytest.mark.parametrize("scale", [1e-11, 1e-9])
def test_a_numerically_dead_mode_goes_last_as_a_constant_one(method, scale):
    # Reference: the same call on the log without that mode (same seed), as for a
    # constant mode: 1e-11..1e-9 of the others is above the 1e-12 constant rule, yet the
    # sum without it orders Phi_ref's 3000 samples exactly (infinite MI). Before: the
    # estimators refused "`y` is a strictly monotone function of `x`".
    from modalinfo.bases import Pupil, ZernikeBasis
    from modalinfo.ordering.orderings import _numerically_dead

    rng = np.random.default_rng(4)
    live = rng.standard_normal((300, 4)) * np.array([1.0, 0.7, 0.5, 0.3])
    coeffs = np.insert(live, 2, scale * rng.standard_normal(300), axis=1)
    modes, pupil = [2, 3, 4, 5, 6], Pupil(16)
    full = order_modes(coeffs, ZernikeBasis(pupil, modes), method, sample_budget=3000,
                       seed=1, n_resamples=0)
    ref = order_modes(live, ZernikeBasis(pupil, [2, 3, 5, 6]), method, sample_budget=3000,
                      seed=1, n_resamples=0)
    assert full.labels[:-1] == ref.labels and full.labels[-1] == "Z4"
    np.testing.assert_array_equal(full.mi[:-1], ref.mi)
    assert np.isnan(full.mi[-1]) and np.isnan(full.gain[-1])
    # the rule itself: a live mode of 0.3 is no such mode; ties (a discrete sum) flag none
    c = rng.standard_normal((3, 500)) * np.array([[1.0], [0.3], [1e-12]])
    assert _numerically_dead(c).tolist() == [False, False, True]
    assert not _numerically_dead(np.round(c, 1)).any()


@pytest.mark.parametrize("method", ["standard", "variance"])
def test_the_standard_order_is_noll_order_whatever_the_column_order(method):
    # audit 9, centre: a log stored Z6, Z2, Z11, ... got a "standard" order Z6, Z2, Z11
    # (the file's), so `fitting-error`'s zernike:standard curve depended on the column
    # order. Reference: Noll's index order Z2, Z3, ...; for "variance", equal mean squares
    # (two identical columns) keep that order
    from modalinfo.bases import Pupil, ZernikeBasis
    from modalinfo.telemetry import ModalLog

    rng = np.random.default_rng(8)
    a = rng.standard_normal((200, 5))
    a[:, 1] = a[:, 0]  # Z3 == Z2: equal mean squares
    a *= [2.0, 2.0, 1.0, 0.5, 0.25]
    perm = [3, 1, 4, 0, 2]
    modes = [2 + p for p in perm]
    log = ModalLog(a[:, perm], rate=1e3, modes=modes)
    basis = ZernikeBasis(Pupil(16), modes)
    r = order_modes(log, basis, method, n_resamples=0)
    assert list(r.labels) == ["Z2", "Z3", "Z4", "Z5", "Z6"]
