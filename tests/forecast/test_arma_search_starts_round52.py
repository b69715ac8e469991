"""The order search keeps, per candidate, the best optimum its starts reach (fix52-d, issue 27).

The conditional sum of squares (CSS) of an ARMA(p, q) is non-convex: from different
starts the damped Newton refinement stops at different local optima. The search refined
ONE start per candidate (the one of lowest CSS among its Hannan-Rissanen start and its
nested neighbours' converged fits), so which optimum a candidate reached, and with it
the AIC order, hung on the last bits of the BLAS kernels (Z16 of the shipped closed-loop
log: (5, 5) at AIC -16540.96 on SkylakeX kernels, -16560.25 on Sandybridge ones; fix52-c).

Reference (outside the search): every start of a candidate refined alone by the single
fit ``_css_refine`` (the Hannan-Rissanen regression of the same rows, and the
``(p - 1, q)`` / ``(p, q - 1)`` fits the search itself returned, padded with a zero
coefficient: the same model); the search's fit of each candidate must reach a CSS no
higher than the lowest of them (up to 1e-12 relative: the batch and the single fit are
the same steps, and the comparison must not rest on rounding luck). Data: Z16 (column
14) of ``data/kaos_closedloop.npz``, Figure 5's 7000-frame training window. Before the
fix (SkylakeX OpenBLAS kernels) 5 of its 30 candidates ended above the best optimum of
their starts: (2, 3), (5, 1), (5, 2), (5, 5) by 275, 279, 168 and 19.3 AIC units, (5, 4)
by rounding (the same optimum); over the log's 27 modes 74 of 810 candidates (every mode).
"""

from pathlib import Path

import numpy as np

import modalinfo.forecast.arma as arma
from modalinfo.forecast import ARMAPredictor
from modalinfo.io import load

DATA = Path(__file__).resolve().parents[2] / "data"


def test_each_candidate_reaches_the_best_optimum_of_its_starts(monkeypatch):
    x = np.asarray(load(DATA / "kaos_closedloop.npz").coeffs, dtype=float)[:7000, 14]
    seen = []
    search = arma._warm_search

    def recording(xc, shared, ar_fits, orders, margin, burn, n_iter):
        fits = search(xc, shared, ar_fits, orders, margin, burn, n_iter)
        seen.append((xc, shared, ar_fits, margin, burn, n_iter, fits))
        return fits

    monkeypatch.setattr(arma, "_warm_search", recording)
    ARMAPredictor(order="aic").fit(x)
    (xc, shared, ar_fits, margin, burn, n_iter, fits), = seen
    n_eff = xc.size - burn
    worse = []
    for (p, q), (_, _, sigma2) in sorted(fits.items()):
        starts = [shared.solve(p, q)]
        for pp, qq in ((p - 1, q), (p, q - 1)):
            prev = fits.get((pp, qq)) if qq > 0 else (
                (ar_fits[pp], np.zeros(0)) if pp in ar_fits else None)
            if prev is not None:
                phi, theta = np.zeros(p), np.zeros(q)
                phi[:pp], theta[:qq] = prev[0], prev[1]
                starts.append((phi, theta))
        alone = min(arma._css_refine(xc, phi, theta, margin, burn, n_iter)[2]
                    for phi, theta in starts)
        if sigma2 > alone * (1 + 1e-12):
            worse.append(((p, q), round(n_eff * np.log(sigma2 / alone), 2)))
    assert len(fits) == 30
    assert not worse, f"candidates above the best optimum of their starts (AIC excess): {worse}"
