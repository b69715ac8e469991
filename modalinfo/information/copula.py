"""Gaussian-copula normalisation: the rank transform every default MI estimator uses.

Mutual information is unchanged by a strictly monotone map of each variable
separately (Kraskov, Stoegbauer & Grassberger, Phys. Rev. E 69, 066138, 2004, eq. 2
and sec. II), so an estimator may replace each variable by any monotone function of
it without changing its target. Replacing a sample by its normal scores

    u_i = Phi^-1(rank_i / (n + 1))

(the empirical Gaussian-copula transform; Ince et al., Hum. Brain Mapp. 38, 1541,
2017) makes every marginal a standard normal, whatever the data's units, scale or
tails: a glitch at 1e6 becomes the largest score, Phi^-1(n / (n + 1)) ~ 3.5 sigma at
n = 4000, and moves every other sample's score by at most one rank. An estimate
computed on normal scores therefore depends on the ranks only, so one corrupted
sample changes it by about its share 1/n of the sample, never by the size of the
corruption.

Ties (rounded, integer or boolean data) get the average of their ranks (scipy's
``rankdata(method="average")``), so tied values keep equal scores and the result is
a deterministic function of the data (no random tie breaking here; the KSG engine
adds its own seeded noise to tied scores, see :mod:`modalinfo.information.ksg`).
"""

from __future__ import annotations

import numpy as np
from scipy.special import ndtri
from scipy.stats import rankdata

from modalinfo.common.validation import as_float_array

__all__ = ["copula_scores", "copula_scores_ties", "check_copula"]


def copula_scores(x: np.ndarray) -> np.ndarray:
    """Return the normal scores ``Phi^-1(rank / (n + 1))`` of a 1-D sample, shape (n,).

    Parameters
    ----------
    x : numpy.ndarray, shape (n,)
        Finite samples, any units.

    Returns
    -------
    numpy.ndarray, shape (n,)
        Dimensionless scores in about [-Phi^-1(n / (n + 1)), +Phi^-1(n / (n + 1))];
        tied values share the score of their average rank.

    Raises
    ------
    TypeError, ValueError
        If ``x`` is not a finite, real, 1-D array (a 2-D array was ranked flattened
        against its row count, giving NaN scores; a list raised AttributeError).
    """
    x = as_float_array(x, "x", ndim=1)
    n = x.shape[0]
    return ndtri(rankdata(x) / (n + 1.0))


def copula_scores_ties(x: np.ndarray) -> tuple[np.ndarray, bool]:
    """Return the normal scores of :func:`copula_scores` and whether x has tied values.

    The tie test is O(n) on the ranks: without ties they are 1 .. n; tied values
    share their average rank, an integer or a half-integer, so twice the ranks are
    integers that repeat exactly when values do.
    """
    n = x.shape[0]
    ranks = rankdata(x)
    ties = bool(np.bincount((2.0 * ranks).astype(np.int64)).max() > 1)
    return ndtri(ranks / (n + 1.0)), ties


def check_copula(copula: object) -> bool:
    """Validate a ``copula`` option (a bool) and return it as a Python bool."""
    if not isinstance(copula, bool | np.bool_):
        raise TypeError(f"`copula` must be a bool; got {copula!r}.")
    return bool(copula)
