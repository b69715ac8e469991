"""Tests of the candidate rule of the searches in time (``modalinfo.information.candidates``).

References, all from outside the code under test:

- the radial orders of Noll indices 1..21 written out by hand from Noll (1976), Table 1
  (n = 0; 1, 1; 2, 2, 2; 3 x 4; 4 x 5; 5 x 6), and the mask ``|n_j - n_i| <= w`` built
  from that table in the test;
- the K-L equivalent radial order: KL<k> sits on Noll k + 1 (the K-L bases start at
  tip/tilt), read off the same hand table;
- a DM geometry: the neighbour mask against distances computed pair by pair in Python;
- the unrestricted map and search themselves as the reference of the restricted ones:
  the restricted map's cells equal the full map's to 1e-12 relative (the same
  operations on a subset of the columns; BLAS's matrix-vector kernel may sum a column
  in an order that depends on its position in the block, so the last bit is not
  promised -- measured: equal bit for bit since each radial group's columns are one
  contiguous block; 7e-17 apart with history 1 before, when they were gathered per target),
  with the same p-values; an all-True explicit mask gives the same links and p-values
  as ``candidates="all"``, and the search the same inputs;
- family-wise control over the restricted family against the binomial law of an exact
  test (as ``test_flow.py``): with N = 49 surrogates an exact test rejects at 0.1 with
  probability 5/50, so over 100 maps of independent AR(1) series the number of maps
  with a significant restricted cell must lie in [3, 17] (probability 0.98 under the
  binomial);
- refusals by message.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.information import select_inputs, transfer_entropy_map
from modalinfo.information.candidates import candidate_mask, neighbour_mask, radial_orders
from modalinfo.telemetry import ModalLog

#: Noll (1976) Table 1: radial order of j = 1..21.
NOLL_N = [0, 1, 1, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 4, 5, 5, 5, 5, 5, 5]


def _ar1(rng: np.random.Generator, n: int, s: int, a: float = 0.7) -> np.ndarray:
    e = rng.standard_normal((n + 100, s))
    x = np.zeros_like(e)
    for t in range(1, n + 100):
        x[t] = a * x[t - 1] + e[t]
    return x[100:]


def _log(x: np.ndarray) -> ModalLog:
    return ModalLog(x, modes=list(range(2, 2 + x.shape[1])), rate=1000.0)


def test_radial_orders_follow_the_noll_table():
    labels = [f"Z{j}" for j in range(1, 22)]
    assert radial_orders(labels).tolist() == NOLL_N
    assert radial_orders([f"KL{k}" for k in range(1, 21)]).tolist() == NOLL_N[1:]
    assert radial_orders(["extra:Z7", "Z4"]).tolist() == [3, 2]


@pytest.mark.parametrize("width", [0, 1, 2])
def test_radial_mask_against_the_hand_table(width):
    labels = [f"Z{j}" for j in range(2, 22)]
    n = NOLL_N[1:]
    expect = np.array([[abs(n[j] - n[i]) <= width for i in range(20)] for j in range(20)])
    mask = candidate_mask(labels, "radial", width)
    assert np.array_equal(mask, expect)
    assert candidate_mask(labels, "all") is None


def test_explicit_mask_is_copied_with_its_diagonal_set():
    m = np.zeros((3, 3), dtype=bool)
    m[0, 2] = True
    out = candidate_mask(["a", "b", "c"], m)
    assert out.diagonal().all() and out[0, 2] and out.sum() == 4
    assert not m.diagonal().any()  # the caller's array is untouched


def test_neighbour_mask_against_pairwise_distances():
    rng = np.random.default_rng(0)
    p = rng.uniform(0, 5, (30, 2))
    mask = neighbour_mask(p, 1.5)
    for j in range(30):
        for i in range(30):
            d = ((p[j, 0] - p[i, 0]) ** 2 + (p[j, 1] - p[i, 1]) ** 2) ** 0.5
            assert mask[j, i] == (d <= 1.5)


def test_refusals_name_the_argument():
    with pytest.raises(ValueError, match="candidates='radial' needs Zernike"):
        candidate_mask(["m0", "m1"], "radial")
    with pytest.raises(ValueError, match="`candidates` must be one of"):
        candidate_mask(["Z2"], "nearest")
    with pytest.raises(ValueError, match=r"shape \(2, 2\)"):
        candidate_mask(["Z2", "Z3"], np.ones((3, 3), dtype=bool))
    with pytest.raises(TypeError, match="boolean array"):
        candidate_mask(["Z2", "Z3"], np.ones((2, 2)))
    with pytest.raises(ValueError, match="radial_width"):
        candidate_mask(["Z2", "Z3"], "radial", -1)
    with pytest.raises(ValueError, match="no .source, target. pair"):
        transfer_entropy_map(_log(_ar1(np.random.default_rng(0), 200, 3)),
                             candidates=np.eye(3, dtype=bool), n_surrogates=19)


@pytest.fixture(scope="module")
def coupled_log():
    """20 Zernike-labelled AR(1) modes; Z5 <- Z3 (lag 1, radial orders 2 <- 1)."""
    x = _ar1(np.random.default_rng(1), 600, 20, 0.6)
    x[1:, 3] += 0.5 * x[:-1, 1]
    return _log(x)


def test_restricted_map_equals_the_full_maps_cells(coupled_log):
    kw = dict(lags=3, history=2, n_surrogates=49, seed=3)
    full = transfer_entropy_map(coupled_log, **kw)
    part = transfer_entropy_map(coupled_log, candidates="radial", radial_width=1, **kw)
    n = np.array(NOLL_N)[1:]
    fam = (np.abs(n[:, None] - n[None, :]) <= 1) & ~np.eye(20, dtype=bool)
    fam = np.repeat(fam[:, :, None], 3, axis=2)
    np.testing.assert_allclose(part.te[fam], full.te[fam], rtol=1e-12, atol=0)
    assert np.isnan(part.te[~fam]).all() and np.isnan(part.pvalue[~fam]).all()
    assert np.isfinite(part.pvalue[fam]).all()
    # the planted link is inside the rule and stays significant
    assert ("Z3", "Z5", 1) in [row[:3] for row in part.links()]
    assert f"over {int(fam.sum())} cells" in part.table()


def test_all_true_mask_is_the_unrestricted_map(coupled_log):
    kw = dict(lags=2, history=1, n_surrogates=19, seed=5)
    full = transfer_entropy_map(coupled_log, **kw)
    same = transfer_entropy_map(coupled_log, candidates=np.ones((20, 20), dtype=bool), **kw)
    off = ~np.eye(20, dtype=bool)
    np.testing.assert_allclose(same.te[off], full.te[off], rtol=1e-12, atol=0)
    np.testing.assert_allclose(same.null_max, full.null_max, rtol=1e-12, atol=0)
    assert np.array_equal(same.pvalue[off], full.pvalue[off])
    assert [a[:3] for a in same.links()] == [a[:3] for a in full.links()]


def test_irregular_mask_cells_equal_the_full_maps(coupled_log):
    # a random mask: most targets have their own set of sources (groups of one); the
    # first three share one (the same column, each other included: one gathered block)
    rng = np.random.default_rng(9)
    mask = rng.random((20, 20)) < 0.3
    mask[:, 1:3] = mask[:, :1]
    mask[:3, :3] = True
    kw = dict(lags=2, history=1, n_surrogates=19, seed=4)
    full = transfer_entropy_map(coupled_log, **kw)
    part = transfer_entropy_map(coupled_log, candidates=mask, **kw)
    fam = np.repeat((mask & ~np.eye(20, dtype=bool))[:, :, None], 2, axis=2)
    np.testing.assert_allclose(part.te[fam], full.te[fam], rtol=1e-12, atol=0)
    assert np.isnan(part.te[~fam]).all() and np.isfinite(part.pvalue[fam]).all()


def test_family_wise_error_over_the_restricted_family():
    rng = np.random.default_rng(100)
    hits = 0
    for m in range(100):
        res = transfer_entropy_map(_log(_ar1(rng, 500, 6)), lags=2, n_surrogates=49, seed=m,
                                   candidates="radial", radial_width=1)
        hits += bool(np.nanmin(res.pvalue) <= 0.1 + 1e-12)
    assert 3 <= hits <= 17


def test_restricted_search_keeps_its_inputs_inside_the_rule(coupled_log):
    kw = dict(horizon=1, max_lag=3, n_surrogates=49, intervals=False, seed=2)
    part = select_inputs(coupled_log, "Z5", candidates="radial", radial_width=1, **kw)
    n = np.array(NOLL_N)[1:]
    inside = np.flatnonzero(np.abs(n - 2) <= 1)
    assert part.n_candidates == inside.size * 3
    assert set(part.sources.tolist()) <= set(inside.tolist())
    assert ("Z3", 0) in [(s.mode, s.lag) for s in part.inputs]  # the planted input
    full = select_inputs(coupled_log, "Z5", **kw)
    same = select_inputs(coupled_log, "Z5", candidates=np.ones((20, 20), dtype=bool), **kw)
    assert [(s.source, s.lag, s.pvalue) for s in same.inputs] == \
        [(s.source, s.lag, s.pvalue) for s in full.inputs]
    np.testing.assert_allclose([s.gain for s in same.inputs], [s.gain for s in full.inputs],
                               rtol=1e-12)
