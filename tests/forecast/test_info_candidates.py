"""The ``info`` predictor with restricted candidates (``InfoPredictor(candidates=...)``).

References, from outside the restricted code path:

- the unrestricted predictor (``candidates="all"``, the code before the rule existed)
  on the same data: wherever its inputs for a (horizon, mode) all lie in that mode's
  restricted set, the restricted predictor must choose the same inputs in the same
  order and fit the same weights (least squares on the same columns; 1e-12 relative);
  the test also checks that this premise holds for at least 60 % of the models (45
  of 60 here; at horizons 2-3 chains of couplings reach across radial orders), so
  that it is not vacuous;
- an all-True explicit mask: every model equal to the unrestricted one;
- the rule's mask built by hand from Noll (1976)'s radial orders: every chosen input of
  the restricted predictor lies inside it.

Data: a VAR(1) of 20 Zernike-labelled modes (Z2..Z21) whose couplings join modes at
most one radial order apart (as frozen flow does, Conan et al. 1995), 3 000 frames.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.forecast import InfoPredictor

#: Noll (1976): radial orders of Z2..Z21.
N_OF = np.array([1, 1, 2, 2, 2, 3, 3, 3, 3, 4, 4, 4, 4, 4, 5, 5, 5, 5, 5, 5])


@pytest.fixture(scope="module")
def var_log():
    rng = np.random.default_rng(7)
    M = N_OF.size
    A = np.diag(np.full(M, 0.7))
    for i in range(M):  # one coupling per mode, to a mode of a neighbouring radial order
        j = int(rng.choice(np.flatnonzero(np.abs(N_OF - N_OF[i]) == 1)))
        A[i, j] = 0.25
    x = np.zeros((3100, M))
    e = rng.standard_normal((3100, M))
    for t in range(1, 3100):
        x[t] = A @ x[t - 1] + e[t]
    return x[100:]


def _models(p):
    return {(h, m): list(zip(p.params_["src"][h, m][p.params_["coef"][h, m] != 0],
                             p.params_["lag"][h, m][p.params_["coef"][h, m] != 0],
                             strict=True))
            for h in range(p.params_["coef"].shape[0]) for m in range(p.n_modes_)}


def test_restricted_equals_unrestricted_where_it_holds_the_inputs(var_log):
    kw = dict(max_lag=4, max_inputs=4, horizon=3)
    full = InfoPredictor(**kw).fit(var_log)
    part = InfoPredictor(candidates="radial", radial_width=1, **kw).fit(var_log)
    allowed = np.abs(N_OF[:, None] - N_OF[None, :]) <= 1
    fm, pm = _models(full), _models(part)
    held = 0
    for (h, m), inputs in fm.items():
        assert all(allowed[j, m] for j, _ in pm[(h, m)])  # inside the rule, always
        if all(allowed[j, m] for j, _ in inputs):
            held += 1
            assert pm[(h, m)] == inputs
            k = len(inputs)
            np.testing.assert_allclose(part.params_["coef"][h, m, :k],
                                       full.params_["coef"][h, m, :k], rtol=1e-12)
    assert held >= 0.6 * len(fm)  # 45 of 60 here: horizons 2-3 reach across orders by chains


def test_all_true_mask_is_the_unrestricted_predictor(var_log):
    kw = dict(max_lag=3, max_inputs=3, horizon=2)
    full = InfoPredictor(**kw).fit(var_log)
    same = InfoPredictor(candidates=np.ones((20, 20), dtype=bool), **kw).fit(var_log)
    assert _models(same) == _models(full)
    np.testing.assert_allclose(same.params_["coef"], full.params_["coef"], rtol=1e-12)
    f1 = full.predict(var_log[-50:], horizon=2)
    f2 = same.predict(var_log[-50:], horizon=2)
    np.testing.assert_allclose(f2, f1, rtol=1e-10, atol=1e-12)


def test_refusals_name_the_argument(var_log):
    with pytest.raises(ValueError, match="`mode_labels` must name the 20"):
        InfoPredictor(candidates="radial", mode_labels=["Z2"]).fit(var_log)
    with pytest.raises(ValueError, match="needs Zernike"):
        InfoPredictor(candidates="radial",
                      mode_labels=[f"a{i}" for i in range(20)]).fit(var_log)
    with pytest.raises(ValueError, match="`candidates` must be one of"):
        InfoPredictor(candidates="near").fit(var_log)
    # audit 10, feedback: a label given twice names two columns one mode (the mask was
    # built for other columns)
    with pytest.raises(ValueError, match="name each column once; \\['Z2'\\]"):
        InfoPredictor(candidates="radial",
                      mode_labels=["Z2", "Z2"] + [f"Z{j}" for j in range(4, 22)]).fit(var_log)
