"""Kraskov-Stoegbauer-Grassberger nearest-neighbour estimators (reference method).

KSG estimator 1 (Kraskov, Stoegbauer & Grassberger, Phys. Rev. E 69, 066138 (2004),
eq. 8):

    I(X; Y) = psi(k) + psi(n) - < psi(n_x + 1) + psi(n_y + 1) >,

where eps_i is the max-norm distance from point i to its k-th neighbour in the joint
space and n_x (n_y) counts the other points with |x_j - x_i| < eps_i (|y_j - y_i| <
eps_i). As in scikit-learn's ``mutual_info_regression``, each variable is first
divided by its standard deviation (the max-norm is not invariant under separate
rescaling of the axes). Unlike scikit-learn, no noise is added and negative estimates
are returned as they are (not clipped at 0), so the estimator stays unbiased near
independence, which matters for permutation tests. Ties (discrete data) break the
estimator: add noise first.

The joint k-th neighbour distance and the marginal counts (within
``nextafter(eps, 0)``, the same arithmetic as scikit-learn) use
``scipy.spatial.cKDTree``, O(n log n); the tree of the fixed x is cached by ``fit``.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree
from scipy.special import digamma

from modalinfo._validation import check_int

__all__ = ["KSGEngine", "ksg_entropy"]


def _strict_counts(tree: cKDTree, pts: np.ndarray, eps: np.ndarray) -> np.ndarray:
    """Count the other samples strictly within ``eps`` of each point (max-norm)."""
    radius = np.nextafter(eps, 0.0)
    return tree.query_ball_point(pts, radius, p=np.inf, return_length=True) - 1.0


class KSGEngine:
    """KSG estimator 1 with the standardised x and its KD-tree cached.

    Parameters
    ----------
    k : int
        Number of neighbours (>= 1); 3 as in scikit-learn.
    """

    def __init__(self, *, k: int = 3):
        self.k = check_int(k, "k", minimum=1)

    def fit(self, x: np.ndarray) -> KSGEngine:
        """Standardise x and build its KD-tree (x validated, 1-D, not constant)."""
        self._x = x / np.std(x)
        self._tree_x = cKDTree(self._x[:, None])
        self._n = x.shape[0]
        return self

    def score(self, y: np.ndarray) -> float:
        """KSG-1 estimate in nats (y validated, same length, not constant)."""
        k = min(self.k, self._n - 1)
        y = y / np.std(y)
        pts = np.column_stack((self._x, y))
        dist, _ = cKDTree(pts).query(pts, k=k + 1, p=np.inf)
        eps = dist[:, -1]
        nx = _strict_counts(self._tree_x, self._x[:, None], eps)
        ny = _strict_counts(cKDTree(y[:, None]), y[:, None], eps)
        n = self._n
        return float(
            digamma(n) + digamma(k) - np.mean(digamma(nx + 1.0)) - np.mean(digamma(ny + 1.0))
        )


def ksg_entropy(x: np.ndarray, *, k: int = 3) -> float:
    """Kozachenko-Leonenko entropy (nats) of a 1-D sample.

    ``H = psi(n) - psi(k) + < ln(2 rho_i) >`` with rho_i the distance to the k-th
    neighbour (Kraskov et al. 2004, eq. 20 with d = 1, where eps_i = 2 rho_i and the
    max-norm unit-diameter ball has volume 1). Preconditions: x validated, 1-D, no ties.
    """
    k = check_int(k, "k", minimum=1)
    n = x.shape[0]
    xs = np.sort(x)
    # k-th neighbour distance in 1-D: among the k left and k right candidates.
    idx = np.arange(n)
    cand = np.full((n, 2 * k), np.inf)
    for j in range(1, k + 1):
        lo = idx - j
        hi = idx + j
        ok = lo >= 0
        cand[ok, j - 1] = xs[idx[ok]] - xs[lo[ok]]
        ok = hi < n
        cand[ok, k + j - 1] = xs[hi[ok]] - xs[idx[ok]]
    rho = np.partition(cand, k - 1, axis=1)[:, k - 1]
    rho = np.maximum(rho, np.finfo(float).tiny)
    return float(digamma(n) - digamma(k) + np.mean(np.log(2.0 * rho)))
