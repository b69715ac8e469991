"""The histogram tail rule's grid is ``floor(sqrt(n / 8))`` bins of equal width in normal scores.

Issue 27, review22 (docs/MUTATION.md, "Planted bugs, round 22", H2: half the bins per
axis passed tests/information/test_histogram_tails_left28.py, whose warnings fire at
either grid). References (outside the code under test): the documented grid, the
``"auto"`` floor ``k = floor(sqrt(n / 8))`` (8 samples per cell on average), built here
with ``scipy.stats.rankdata`` (average ranks), ``scipy.stats.norm.ppf(rank / (n + 1))``
and ``numpy.histogram2d`` on ``k`` equal bins between the scores' extremes, and the
Miller-Madow MI of that table written out (plug-in MI minus ``(m_xy - m_x - m_y + 1) /
2n``, ``m`` the occupied cells); the warning prints both numbers.
"""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
from scipy import stats

from modalinfo.information import mutual_information
from modalinfo.information.methods import BiasRuleWarning


def _grid_mi(x: np.ndarray, y: np.ndarray, k: int) -> float:
    n = x.size
    s = [stats.norm.ppf(stats.rankdata(a) / (n + 1)) for a in (x, y)]
    edges = [np.linspace(-np.abs(a).max(), np.abs(a).max(), k + 1) for a in s]
    c, _, _ = np.histogram2d(s[0], s[1], bins=edges)
    p = c / n
    px, py = p.sum(axis=1), p.sum(axis=0)
    nz = p > 0
    plug = float(np.sum(p[nz] * np.log(p[nz] / np.outer(px, py)[nz])))
    return plug - (nz.sum() - (px > 0).sum() - (py > 0).sum() + 1) / (2 * n)


@pytest.mark.parametrize("n", [4000, 10_000])
def test_the_tail_grid_is_the_documented_one(n):
    rng = np.random.default_rng(31)
    xy = rng.standard_normal((n, 2)) @ np.linalg.cholesky([[1.0, 0.6], [0.6, 1.0]]).T
    xy[n // 3:n // 3 + n // 20] *= 10.0  # 5 % of the frames x10 (round 28 PART a, N31)
    x, y = xy[:, 0], xy[:, 1]
    k = math.floor(math.sqrt(n / 8))
    with pytest.warns(BiasRuleWarning, match="normal scores") as rec:
        mutual_information(x, y, "histogram")
    text = next(str(w.message) for w in rec if "normal scores" in str(w.message))
    assert f"on {k} x {k} bins of equal width" in text
    tails = float(re.search(r"is below ([0-9.]+) nats", text).group(1))
    assert tails == pytest.approx(_grid_mi(x, y, k), abs=2e-3)
