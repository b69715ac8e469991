"""Information-flow map: transfer entropy between every pair of modes at every lag.

For series s_0 .. s_{S-1} (the modes of a log, optionally followed by the modes of a
second log on the same clock, e.g. the other WFS of an MCAO run), the map holds

    TE[j -> i, l] = I(s_i[t]; s_j[t - l] | s_i[t - 1], ..., s_i[t - k])

(:func:`~modalinfo.information.transfer_entropy`, Schreiber 2000) for every source j,
target i != j and lag l of ``lags``, all on the same rows t = t0 .. T - 1 with
``t0 = max(max(lags), history)`` so that the cells are comparable and share one null.
The diagonal (j = i) is not a transfer and is NaN.

Estimators. ``method="gaussian"`` (default) scores a whole target at once: the target
and every lagged source are residualised against the target's history (a QR basis of
the centred history), and each cell is ``-0.5 ln(1 - rho^2)`` of the two residuals'
correlation -- exactly the Gaussian CMI of :func:`transfer_entropy` on the same rows
with ``copula=False`` (the values, not the normal scores that are that function's
default: the closed form is the least-squares one), with the partial-correlation
scorer of :mod:`modalinfo.information.selection`. The
other methods of :func:`~modalinfo.information.conditional_mutual_information`
estimate each cell with the estimator (``cells x (1 + n_surrogates)`` estimates).

Family-wise control. One set of circular time shifts is used for the whole map; under
surrogate s every lagged source is rotated by s rows against its target and the
target's history, and each cell is recomputed exactly as the original (the Gaussian
path: the rotated source residualised against the target's history, the target's
residual unchanged), so every series keeps its autocorrelation and only the alignment
of source and target is broken. The shifts are multiples of a spacing b (about
``n / (n_surrogates + 1)``) with the original at 0 (``surrogate_shifts``), so the
original and the surrogates are all at least b apart: a randomisation test over the
rotations by multiples of b. The statistic of a surrogate is the *largest* TE over the
cells, and the p-values are the step-down maxT of Westfall & Young (1993, Algorithm
4.1; ``maxt_pvalues``): the strongest cell is compared with the surrogate maximum
over the whole map (the single-step test, as the greedy step of IDTxl; Lizier et al.
2011, Novelli et al. 2019), the next with the maximum over the cells not yet
rejected, and so on. Both control the family-wise error over all ``S (S - 1) L``
cells at ``alpha`` (the chance of one spurious link anywhere in the map); the
step-down rejects at least what the single step does. With N surrogates an exact
test rejects with probability ``floor(alpha (N + 1)) / (N + 1)`` and the smallest
p-value is ``1 / (N + 1)`` (0.005 with the default 199).

Why the earlier map was liberal (``benchmarks/bench_flow_fwer.py``, RESULTS.md): it
rotated the target's *residual* against the sources' residuals and drew the shifts
at random from ``[m, n - m]`` (m the Politis-White block length). (1) The rotated
residual is no longer orthogonal to the target's own past, and its null scale fell
short of the original's (``n rho^2`` per cell 1.010 against 1.024 on 3 000 maps of
independent AR(1) series; the rotated source: 1.016); a maximum over many cells sits
deep in the tail, where a small scale error is multiplied (about ``c / 2`` for a
threshold c of a chi-square tail), so the error grew with the map. (2) Random shifts
can fall close to each other but never close to the original, so the values most
correlated with the original (the near shifts) are missing from the comparison:
with the sources rotated but random shifts the 48-cell map still rejected 0.054 at
the exact level 0.040 (49 surrogates, 4 000 maps). (3) Near s = n / 2 the cells
``j -> i`` and ``i -> j`` read the same part of the cross-correlation and become
copies (excluded now). Measured now, 2 000 maps each of 2, 12, 48 and 100 cells
(n = 500, AR(1) 0.7, history 1, alpha = 0.05 and 0.1): within 1.8 binomial standard
errors of the exact level in every case (the earlier map: 1.5-3.5 above in 9 of 10);
recall of a planted network unchanged (1.000 at coupling 0.4; 0.892 against 0.900 at
0.15). The lattice costs power only when its spacing, about ``n / (n_surrogates +
1)``, falls below the span of the lags plus the series' correlation time (a surrogate
can then re-align a true link at another lag): for short series use fewer
surrogates. The cells share one null scale when the history whitens each target (the
Gaussian cell is then a partial correlation of a white residual); with a history
too short for a target, cells of slowly varying sources have a wider null and
dominate the maximum -- still valid, but less power for the other cells.

End-point matching. A rotation joins the last frame to the first; when a series'
correlation time is not small against the frames (AR(1) of 0.99 over 500 frames: ~ n /
5) that join is a jump between nearly independent levels, the rotated sources are less
persistent than the originals, and the map rejected 0.069 at 0.05 (1 000 maps of two
independent series, RESULTS.md). With surrogates the map is therefore computed on the
window of frames whose end points and end slopes match over all the series
(``resampling.matched_window``; Theiler et al. 1992, Schreiber & Schmitz 2000; at most
a fifth of the frames dropped, none where the join already looks like a typical step;
``rows`` of the result), which restores the level; with many series the match is a
compromise over all of them. Where the surrogates fit in the frames but not in
the window (a short log), every frame is kept.
Candidates at thousands of modes (``candidates=``, issue 30). The map is ``S (S - 1)
L`` cells and its null ``n_surrogates`` times that: 1,500 modes at 2 lags is 4.5e6
cells. ``candidates="radial"`` keeps, for each target, the sources within
``radial_width`` radial orders (frozen flow couples modes of similar radial order;
:mod:`modalinfo.information.candidates` gives the physics and the label rules), or an
explicit ``(S, S)`` mask (e.g. a DM's neighbours). Only the allowed cells are computed
(each with the operations of the full map, on its target's allowed columns), the
others are NaN, and the maxT p-values are those of the restricted family: the
family-wise error is controlled over the cells the map holds (measured,
``bench_flow_fwer.py --part restricted``). A link outside the rule is not tested at
all, so the rule is a prior, to be chosen before looking at the map.

Bivariate TE does not separate direct from indirect transfer (a chain j -> m -> i, or a
common driver of i and j, shows as j -> i); :func:`~modalinfo.information.select_inputs`
conditions on the inputs already chosen and is the tool for a predictor's inputs.

Nor does it separate a coupling from measurement noise on the target (Smirnov 2013, Phys.
Rev. E 87, 042917): a mode observed with white noise (a WFS mode's noise) is not predicted
from its own noisy past as its state would be, and a mode it drives carries that state, so
the map shows a link *into* the noisy mode that no coupling makes (adversarial round 49
PART a, N12 / N13: x drives y, x observed with white noise of ~1x / ~4x its variance,
4,000 frames: y -> x significant in 20 of 20 maps, its exact TE 0.047 / 0.033 nats, at
~4x above the true x -> y's 0.016; a longer history shrinks it slowly). The map warns
(``NoisyTargetWarning``, one per call) naming the targets of significant links whose
autocorrelation at lags 1-3, extrapolated to lag 0, falls short of 1 by more than
``NOISE_SHARE`` = 20 % and by 3 standard errors (:func:`white_share`; measured, 20 seeds
each: N12 20, N13 20 of 20 (14 before fix50-c dropped the fit's order condition); clean
pairs, a persistent driver, a bidirectional pair, a fractional delay: none).

Resources. Before any work :func:`transfer_entropy_map` estimates its peak memory
(checked against the memory available) and its time (checked against ``max_seconds``:
a Gaussian map from its multiply-adds at a conservative single-thread rate, another
method from the timed estimate of one cell), and refuses with a message naming the
sizes to reduce. The hot loop of the Gaussian path is a matrix product per target
(BLAS), not a numba kernel.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from modalinfo._stats import sample_autocovariance
from modalinfo.common.memory import free_memory_bytes
from modalinfo.common.quiet import warn
from modalinfo.common.records import array_fields_eq, check_record_fields
from modalinfo.common.text import pad
from modalinfo.common.validation import check_choice, check_int, check_real, check_rng, unmasked
from modalinfo.information.api import UNITS
from modalinfo.information.candidates import RADIAL_WIDTH, candidate_mask
from modalinfo.information.conditional import (
    CMI_METHODS,
    _estimator,
    count_failures,
    effective_sample_why,
    temporal_neighbour_why,
)
from modalinfo.information.histogram import histogram_cmi, histogram_conditioning_rule
from modalinfo.information.methods import BiasRuleWarning, get_method
from modalinfo.information.resampling import (
    GLITCH_POLICIES,
    OutlierWarning,
    check_resamples,
    check_surrogates_reach,
    clip_glitches,
    local_linear_split,
    matched_window_for,
    neighbour_rows,
    rank_based_options,
    surrogate_shifts,
)
from modalinfo.information.selection import (
    _check_simultaneous,
    _gauss_gains,
    _safe_scale,
    _series,
    unit_candidates,
)
from modalinfo.information.surrogates import circular_cross, rotated_rho2

__all__ = ["NoisyTargetWarning", "TransferEntropyMap", "maxt_pvalues", "surrogate_shifts",
           "transfer_entropy_map", "white_share"]

#: Family-wise adjustments of :func:`transfer_entropy_map`.
ADJUSTMENTS = ("step-down", "single-step")

#: Multiply-adds per second assumed for the time estimate of a Gaussian map. The count
#: below is of the BLAS products' multiply-adds; measured on the project's shared 2-core
#: machine at a load average of 12-13 (2026-11-28, 2,000-8,000 rows, single-threaded
#: BLAS), the maps ran at 3.2e9 (300 modes, radial, lags 1..2, 49 surrogates) to 8.7e9
#: (100 modes, all pairs, lags 1..10, 199 surrogates) multiply-adds per s of CPU. 2e9 keeps
#: the estimate on the long side by 1.6-4.4x; the former 2e8 (timed on 9 series, where
#: per-call overheads dominate) estimated 1,815 s for a 1,500-mode radial map (lags 1..2,
#: 199 surrogates, 2,000 rows) that ran in 43 s of CPU.
_GAUSS_RATE = 2e9


@array_fields_eq
@dataclass(frozen=True)
class TransferEntropyMap:
    """Result of :func:`transfer_entropy_map`.

    Attributes
    ----------
    labels : tuple of str
        Series labels, shape (S,): the log's mode labels, then ``"extra:<label>"``.
    group : numpy.ndarray of int, shape (S,)
        0 for a series of the log, 1 for one of ``extra``.
    lags : numpy.ndarray of int, shape (L,)
        Source lags [samples].
    te : numpy.ndarray, shape (S, S, L)
        ``te[j, i, a]``: TE from source j to target i at lag ``lags[a]``, in ``units``;
        NaN on the diagonal j = i and outside the ``candidates`` of the map.
    pvalue : numpy.ndarray, shape (S, S, L)
        Family-wise adjusted (maximum-statistic, ``adjust``) p-value of each cell; NaN
        on the diagonal.
    null_max : numpy.ndarray, shape (n_surrogates,)
        Largest TE of the whole map under each time-shift surrogate, in ``units``.
    history : int
        Target history k [samples].
    n_samples : int
        Rows of every estimate.
    method, units : str
        Estimator and units.
    alpha : float
        Family-wise level of :attr:`significant`.
    n_surrogates : int
        Number of surrogates.
    min_shift : int
        Spacing of the surrogates' circular shifts [samples] (0 without surrogates).
    estimated_seconds : float
        The time estimate checked before work [s].
    adjust : str
        Family-wise adjustment of :attr:`pvalue` ("step-down" or "single-step").
    rows : tuple of int
        ``(start, stop)``: the frames of ``data`` the map is computed on (the
        end-point-matched window with surrogates and ``match_ends``, else all).
    """

    labels: tuple[str, ...]
    group: np.ndarray
    lags: np.ndarray
    te: np.ndarray = field(repr=False)
    pvalue: np.ndarray = field(repr=False)
    null_max: np.ndarray = field(repr=False)
    history: int
    n_samples: int
    method: str
    units: str
    alpha: float
    n_surrogates: int
    min_shift: int
    estimated_seconds: float
    adjust: str = "step-down"
    rows: tuple[int, int] = (0, 0)

    def __post_init__(self) -> None:
        S, L = len(self.labels), len(np.atleast_1d(self.lags))
        check_record_fields(self, {"group": (S,), "te": (S, S, L), "pvalue": (S, S, L)})

    @property
    def significant(self) -> np.ndarray:
        """``(S, S, L)`` bool: cells with ``pvalue <= alpha`` (False on the diagonal)."""
        return np.nan_to_num(self.pvalue, nan=2.0) <= self.alpha

    @property
    def max_te(self) -> np.ndarray:
        """``(S, S)``: largest TE over the lags of each pair (NaN on the diagonal)."""
        out = np.full(self.te.shape[:2], np.nan)
        off = ~np.eye(self.te.shape[0], dtype=bool)
        out[off] = self.te[off].max(axis=-1)
        return out

    @property
    def best_lag(self) -> np.ndarray:
        """``(S, S)`` int: lag of the largest TE of each pair [samples]; -1 on the diagonal."""
        out = self.lags[np.argmax(np.nan_to_num(self.te, nan=-np.inf), axis=-1)]
        np.fill_diagonal(out, -1)
        return out

    def links(self) -> list[tuple[str, str, int, float, float]]:
        """Significant pairs at their best lag, strongest first.

        Returns
        -------
        list of (source, target, lag, te, pvalue)
            One row per (source, target) pair whose best-lag cell is significant.
        """
        best = np.argmax(np.nan_to_num(self.te, nan=-np.inf), axis=-1)
        rows = []
        for j, i in zip(*np.nonzero(~np.eye(len(self.labels), dtype=bool)), strict=True):
            a = best[j, i]
            if self.significant[j, i, a]:
                rows.append((self.labels[j], self.labels[i], int(self.lags[a]),
                             float(self.te[j, i, a]), float(self.pvalue[j, i, a])))
        return sorted(rows, key=lambda r: -r[3])

    def table(self, max_rows: int = 20) -> str:
        """Return a plain-text table of the strongest significant links."""
        links = self.links()
        head = (f"transfer entropy map: {len(self.labels)} series, lags "
                f"{self.lags.min()}..{self.lags.max()}, history {self.history}, n = "
                f"{self.n_samples}, method {self.method}; family-wise alpha {self.alpha} "
                f"({self.adjust} max-statistic over "
                f"{int(np.count_nonzero(~np.isnan(self.pvalue)))} cells, "
                f"{self.n_surrogates} time-shift surrogates): {len(links)} significant links")
        rows = [head, f"{'source':<14} {'target':<14} {'lag':>4} {'TE':>9} {'p':>7}"]
        for s, t, lag, te, p in links[:max_rows]:
            rows.append(f"{pad(s, 14)} {pad(t, 14)} {lag:>4} {te:9.4f} {p:7.4f}")
        return "\n".join(rows)


def _pick(series: np.ndarray, labels: list[str], modes: Any, name: str
          ) -> tuple[np.ndarray, list[str]]:
    """Columns of ``series`` chosen by ``modes`` (None: all; ints or labels)."""
    if modes is None:
        return series, labels
    if isinstance(modes, str | int) or not hasattr(modes, "__iter__"):
        raise TypeError(f"`{name}` must be a sequence of column indices or labels; "
                        f"got {modes!r}.")
    idx = []
    for m in modes:
        if isinstance(m, str):
            if m not in labels:
                raise ValueError(f"`{name}` holds {m!r}, not a label of the log "
                                 f"({', '.join(labels[:6])}...).")
            idx.append(labels.index(m))
        else:
            idx.append(check_int(m, name, minimum=0, maximum=len(labels) - 1))
    if not idx or len(set(idx)) != len(idx):
        raise ValueError(f"`{name}` must list at least one column, each once; got {modes!r}.")
    return np.ascontiguousarray(series[:, idx]), [labels[i] for i in idx]


def _check_lags(lags: Any, n_frames: int) -> np.ndarray:
    if isinstance(lags, int | np.integer):
        top = check_int(lags, "lags", minimum=1, maximum=2**62)  # int64
        # a lag of n_frames or more leaves no pair: the largest alone reaches the frame-count
        # refusal (2^70 tried to allocate the whole range 1..lags first)
        return np.arange(1, top + 1) if top < n_frames else np.array([top], dtype=np.int64)
    try:
        arr = np.asarray(list(lags) if not isinstance(lags, np.ndarray) else unmasked(
            lags, "lags"))
    except TypeError:  # a float, None: not iterable
        raise TypeError(f"`lags` must be an int >= 1 (lags 1..lags) or a non-empty "
                        f"sequence of ints >= 0; got {lags!r}.") from None
    if arr.ndim != 1 or arr.size == 0 or arr.dtype.kind not in "iu":
        raise ValueError(f"`lags` must be an int >= 1 (lags 1..lags) or a non-empty "
                         f"sequence of ints >= 0; got {lags!r}.")
    if arr.min() < 0 or len(set(arr.tolist())) != arr.size:
        raise ValueError(f"`lags` must be distinct ints >= 0; got {arr.tolist()}.")
    return np.sort(arr.astype(np.int64))


def _lagged_block(series: np.ndarray, lags: np.ndarray, t0: int) -> np.ndarray:
    """``(n, S L)``: column ``a S + j`` is ``series[t - lags[a], j]`` for t = t0 .. T-1."""
    T = series.shape[0]
    return np.ascontiguousarray(
        np.concatenate([series[t0 - lag : T - lag] for lag in lags], axis=1))


def _history(x: np.ndarray, k: int, t0: int) -> np.ndarray:
    T = x.shape[0]
    return np.column_stack([x[t0 - i : T - i] for i in range(1, k + 1)]) if k else \
        np.empty((T - t0, 0))


def _history_basis(z: np.ndarray) -> np.ndarray:
    """Orthonormal basis ``(n, k')`` of the centred, non-constant history columns."""
    zc = z - z.mean(axis=0)
    keep = np.sqrt(np.einsum("ij,ij->j", zc, zc)) > 0
    return np.linalg.qr(zc[:, keep])[0] if keep.any() else np.empty((z.shape[0], 0))


def _gaussian_map(series, lags, history, t0, shifts, labels=None):
    """TE (nats) of every cell and of every cell under every surrogate.

    Returns ``te`` (S, S, L) and ``null`` (n_surrogates, S, S, L), 0 on the diagonal.
    Under surrogate s the lagged source block is rotated by s rows, ``C_s[t] =
    C[(t - s) mod n]``, and residualised against the target's history like the
    original: the numerator ``r . P C_s = r . C_s`` (``r`` is orthogonal to the
    history) is the circular cross-correlation ``r[(t + s) mod n] . C[t]``, and
    ``|P C_s|^2 = |C|^2 - |Q^T C_s|^2`` with Q the history's orthonormal basis, one
    cross-correlation per history column. ``labels`` (S,): refuse an infinite cell
    (``selection._refuse_unit_rho``), naming it.
    """
    T, S = series.shape
    L = lags.size
    C = _lagged_block(series, lags, t0)
    _, alive_all = unit_candidates(C)
    Cc = C - C.mean(axis=0)
    c2 = np.einsum("ij,ij->j", Cc, Cc)
    te = np.zeros((S, S, L))
    null = np.zeros((shifts.size, S, S, L))
    for i in range(S):
        alive = alive_all.copy()
        alive[i::S] = False  # the target's own lags are not a transfer
        gains, cells = _target_cells(series, i, history, t0, Cc, c2, alive, shifts,
                                     _cell_names(labels, np.arange(S), lags, i))
        te[:, i, :] = gains.reshape(L, S).T
        if cells is not None:
            null[:, :, i, :] = cells.reshape(shifts.size, L, S).transpose(0, 2, 1)
    return te, null


def _cell_names(labels, src, lags, i):
    """``j -> "cell <source> -> <target> at lag <l>"`` of a lag-major block over ``src``."""
    if labels is None:
        return None
    return lambda j: (f"the source {labels[src[j % src.size]]} at lag "
                      f"{lags[j // src.size]} (cell {labels[src[j % src.size]]} -> "
                      f"{labels[i]})")


def _target_cells(series, i, history, t0, block, c2, alive, shifts, names=None):
    """Gaussian TE of target ``i`` from each column of ``block``, and under each shift.

    ``block`` (n, K) holds centred lagged sources, ``c2`` (K,) their squared norms and
    ``alive`` (K,) the columns scored. Returns the gains (K,) and the surrogates' cells
    (n_surrogates, K), 0 where not scored, or None when no column can be scored.
    """
    q = _history_basis(_history(series[:, i], history, t0))
    r = series[t0:, i] - series[t0:, i].mean()
    r = r - q @ (q.T @ r)
    R = block - q @ (q.T @ block)
    gains = _gauss_gains(r, R, alive, names)
    cn = np.sqrt(np.einsum("ij,ij->j", R, R))
    ok = alive & (cn > 0)
    rn = math.sqrt(float(r @ r))
    if not (ok.any() and rn > 0 and shifts.size):
        return gains, None
    Cok = block[:, ok]
    rho2 = rotated_rho2(circular_cross(r, Cok, shifts),
                        [circular_cross(q[:, a], Cok, shifts) for a in range(q.shape[1])],
                        c2[ok], rn * rn)
    cells = np.zeros((shifts.size, block.shape[1]))
    cells[:, ok] = -0.5 * np.log(np.maximum(1.0 - rho2, 1e-15))
    return gains, cells


def _gaussian_map_restricted(series, lags, history, t0, shifts, family, labels=None):
    """Return the TE of the cells of ``family`` (S, S, L) only, and their null.

    ``te`` (S, S, L) is NaN outside ``family``; ``null`` (n_surrogates, K) holds the K
    cells of ``family`` in its C order.

    Each target's cells are computed with the operations of :func:`_gaussian_map` on the
    columns of its allowed sources only (the same centred block ``Cc``, norms and
    history basis), so the restricted map's values are the full map's on those cells;
    the cost is the allowed cells' instead of ``S^2 L``. Targets with the same allowed
    sources (a radial order) share one contiguous copy of those columns, gathered once
    (measured at 1,500 modes: 20.1 s of CPU against 24.3 s gathering per target;
    RESULTS.md). The values are promised to 1e-12, not to the last bit (BLAS's
    matrix-vector kernel may sum a column in an order set by its place in the block);
    measured equal bit for bit with the contiguous copy (150 Zernike modes, lags 1..2).
    """
    T, S = series.shape
    L = lags.size
    C = _lagged_block(series, lags, t0)
    _, alive_all = unit_candidates(C)
    Cc = C - C.mean(axis=0)
    del C
    c2 = np.einsum("ij,ij->j", Cc, Cc)
    te = np.full((S, S, L), np.nan)
    pos = np.full((S, S, L), -1, dtype=np.int64)
    pos[family] = np.arange(int(family.sum()))
    null = np.zeros((shifts.size, int(family.sum())))
    # targets whose allowed sources are the same (one radial order under "radial") share
    # one gathered, contiguous block of those sources' lags (gathered once per group, not
    # once per target); each target scores it with the full map's operations
    use_all = family[:, :, 0] | np.eye(S, dtype=bool)
    groups: dict[bytes, list[int]] = {}
    for i in np.flatnonzero(family[:, :, 0].any(axis=0)):
        groups.setdefault(np.packbits(use_all[:, i]).tobytes(), []).append(int(i))
    for targets in groups.values():
        # the allowed sources and the targets themselves (not cells), so that an
        # all-True mask runs the very products of the full map
        src = np.flatnonzero(use_all[:, targets[0]])
        idx = (np.arange(L)[:, None] * S + src[None, :]).ravel()  # lag-major, as C
        block = np.ascontiguousarray(Cc[:, idx])
        for i in targets:
            alive = alive_all[idx]
            alive[np.tile(src == i, L)] = False
            gains, cells = _target_cells(series, i, history, t0, block, c2[idx], alive,
                                         shifts, _cell_names(labels, src, lags, i))
            te[src, i, :] = gains.reshape(L, src.size).T
            te[i, i, :] = np.nan
            if cells is not None:
                keep = np.tile(src != i, L)
                null[:, pos[src[src != i], i, :].T.ravel()] = cells[:, keep]
    return te, null


def _estimator_map(series, lags, history, t0, shifts, est, family=None, rank_based=True):
    """TE of every cell and of every cell under every surrogate (the source rotated).

    The source's residual on the target's history is rotated and its fit kept (round
    11): a source that the target drives (y -> x only, no x -> y) made the histogram map
    report x -> y in 23 % of 120 maps at alpha 0.05, the bins of the target's history
    leaving part of what the source's past shares with it; rotating the whole source
    put none of that in the null. The fit is the linear one plus a local-linear fit of its
    residual over the history's nearest neighbours
    (:func:`~modalinfo.information.resampling.local_linear_split`, fix51-a): with the
    linear fit alone a source that follows the target non-linearly in the same frame
    (``s_t = sin 6 a_t + e``) was called s -> a in 25 of 160 histogram maps at 5 %.
    """
    T, S = series.shape
    te = np.zeros((S, S, lags.size))
    null = np.zeros((shifts.size, S, S, lags.size))
    for i in range(S):
        x = series[t0:, i : i + 1]
        z = _history(series[:, i], history, t0)
        # the history's neighbours, shared by every source and lag of this target
        near = neighbour_rows(z, rank_based) if shifts.size and z.shape[1] else None
        for j in range(S):
            if j == i or (family is not None and not family[j, i, 0]):
                continue
            for a, lag in enumerate(lags):
                y = np.ascontiguousarray(series[t0 - lag : T - lag, j : j + 1])
                te[j, i, a] = est(x, y, z)
                fit, resid = local_linear_split(y, z, rank_based, near) if shifts.size \
                    else (y, y)
                for s_i, s in enumerate(shifts):
                    null[s_i, j, i, a] = est(x, fit + np.roll(resid, int(s), axis=0), z)
    return te, null


def _largest_cells(series, lags, history, t0, te):
    """Yield ``(x, y, z, te)`` of each target's largest cell (its strongest source and lag)."""
    T, S = series.shape
    for i in range(S):
        cells = np.array(te[:, i, :], dtype=float)
        cells[i, :] = np.nan  # no self-links
        if not np.isfinite(cells).any():
            continue
        j, a = np.unravel_index(int(np.nanargmax(cells)), cells.shape)
        lag = int(lags[a])
        yield (np.ascontiguousarray(series[t0:, i : i + 1]),
               np.ascontiguousarray(series[t0 - lag : T - lag, j : j + 1]),
               _history(series[:, i], history, t0), float(cells[j, a]))


def _judge_map(series, lags, history, t0, te, method, options, factor) -> None:
    """Warn once where the map's largest cells fail the rules of ``transfer_entropy``.

    The effective-sample rule of every method
    (:func:`~modalinfo.information.conditional.effective_sample_why`, fixes 40-a: the
    map was silent where ``transfer_entropy`` of the same cell warned), then, for the
    histogram, its conditioning rule (:func:`_judge_histogram_map`); for the KSG, a
    cell the effective-sample rule passes is judged by the temporal-neighbour rule, as
    ``transfer_entropy`` judges its estimate (:func:`~modalinfo.information.conditional.
    temporal_neighbour_why`, fixes 41-c: one more KSG estimate per such target). Judged
    once per target on its largest cell (``te`` in the units of ``factor``), one
    warning at most, naming each rule that failed.
    """
    cells = list(_largest_cells(series, lags, history, t0, te))
    few = [effective_sample_why(x, y, z) for x, y, z, _ in cells]
    S = series.shape[1]
    failed, first = count_failures(few)
    if get_method(method).cmi is histogram_cmi and not failed:
        _judge_histogram_map(series, lags, history, t0, te, options)
        return
    smooth, why = count_failures(temporal_neighbour_why(method, x, y, z, value / factor,
                                                        options)
                                 for (x, y, z, value), f in zip(cells, few, strict=True)
                                 if f is None)
    parts = ([f"{failed} of {S} target(s) fail the effective-sample rule on their "
              f"largest cell ({first})"] if failed else []) + (
        [f"{smooth} of {S} target(s) fail the temporal-neighbour rule on their largest "
         f"cell ({why})"] if smooth else [])
    if parts:
        warn(f"transfer_entropy_map with method={method!r}: {'; '.join(parts)}",
             BiasRuleWarning, stacklevel=3)


class NoisyTargetWarning(UserWarning):
    """Links into a map's target whose variance is part white may be reversed."""


#: White share of a target's variance (its autocorrelation at lags 1-3 extrapolated to
#: lag 0 falls short of 1 by it) above which :func:`_noisy_targets_why` names the links
#: into that target (round 49 PART a, N12 / N13).
NOISE_SHARE = 0.2

#: Standard errors by which the extrapolated lag-0 value must fall below 1.
_NOISE_Z = 3.0


def white_share(x: np.ndarray) -> float | None:
    """White share of ``x``'s variance from its autocorrelation at lags 1-3, or None.

    A persistent series observed with white noise (a WFS mode's measurement noise) has
    ``rho_k = c phi^k`` for k >= 1 with ``c = S / (S + N)`` < 1 where a clean AR(1) has
    ``c = 1``: ``log rho_k`` at k = 1, 2, 3 is fitted by a line (least squares, its slope
    held at <= 0: ``phi`` <= 1) and ``1 - c`` is its shortfall at k = 0 (the lag-0
    extrapolation by which AO estimates WFS noise from telemetry). None when the
    shortfall is not measured: rho_1 .. rho_3 not all above ``4 / sqrt(n)``, or
    ``log c`` within ``_NOISE_Z`` standard errors of 0 (Bartlett's variance of each
    rho_k, ``(1 + 2 sum rho_j^2) / n``, propagated to the intercept without
    covariances).

    rho_1 .. rho_3 need not decrease: at ~4x white noise (``c`` ~0.2, ``phi`` 0.9) they
    step down by ~0.02 against a sampling s.d. of ~0.02 at 4,000 frames, and requiring
    the order (dropped by fix50-c) missed 6 of 20 such targets (round 49 PART a, N13;
    68 of 200 series). A fit over
    more lags (1-5, of ``c phi^k`` by least squares) reads a clean mixture of a slow and
    a fast mode (a bidirectional pair's, rho 0.64 / 0.48 / 0.38 / 0.30 / 0.24) as 19 %
    white and passed its floor on 11 of 40 series; lags 1-3 read it 17-18 % (3 + 7 of 400
    series past the floor, as before fix50-c: the order condition never bound there).
    """
    n = x.shape[0]
    g = sample_autocovariance(x, min(n - 1, 200))
    if not g[0] > 0.0:
        return None
    rho = g / g[0]
    r = rho[1:4]
    if r.size < 3 or not r.min() > 4.0 / math.sqrt(n):
        return None
    var_rho = (1.0 + 2.0 * float(np.sum(rho[1:] ** 2))) / n
    if r[2] < r[0]:  # the fitted line falls: its intercept at k = 0
        log_c = (4.0 * math.log(r[0]) + math.log(r[1]) - 2.0 * math.log(r[2])) / 3.0
        weights = np.array([4.0, 1.0, -2.0]) / 3.0
    else:  # a level line (phi = 1): a rising one would extrapolate below its data
        log_c = float(np.mean(np.log(r)))
        weights = np.full(3, 1.0 / 3.0)
    se = math.sqrt(var_rho * float(np.sum((weights / r) ** 2)))
    share = 1.0 - math.exp(log_c)
    if share <= NOISE_SHARE or -log_c <= _NOISE_Z * se:
        return None
    return share


def _noisy_targets_why(series: np.ndarray, labels: list[str], pvalue: np.ndarray,
                       alpha: float) -> str | None:
    """Name the targets of significant links whose variance is part white (or None).

    A target observed with white noise (WFS noise) is not predicted from its own past as
    its clean state would be: a mode driven by it carries that state, and the map shows
    a link *into* the noisy mode that no coupling makes (Smirnov 2013, Phys. Rev. E 87,
    042917). Round 49 PART a, N12 / N13: x drives y (0.4), x observed with white noise of
    ~1x / ~4x its variance, n = 4000: every map of 20 showed y -> x; the exact Gaussian TE
    of the observed series y -> x is 0.047 / 0.033 nats (0.050 / 0.016 x -> y).
    """
    hit = np.nan_to_num(pvalue, nan=1.0) <= alpha  # (source, target, lag)
    noisy = []
    for i in np.flatnonzero(hit.any(axis=(0, 2))):
        share = white_share(series[:, i])
        if share is not None:
            noisy.append((labels[i], share, int(hit[:, i].any(axis=1).sum())))
    if not noisy:
        return None
    named = ", ".join(f"{lab} ({share:.0%} white, {k} source(s))" for lab, share, k in noisy[:5])
    more = ", ..." if len(noisy) > 5 else ""
    return (f"transfer_entropy_map: {len(noisy)} target(s) with significant links hold a "
            f"white share of their variance (autocorrelation at lags 1-3 extrapolated to lag "
            f"0 falls short of 1 by more than {NOISE_SHARE:.0%}, e.g. WFS measurement "
            f"noise): {named}{more}. Their own past does not hold their state, so a mode "
            "they drive shows a link into them that no coupling makes (Smirnov 2013); read "
            "the links into them as possibly reversed, or reduce the noise first (a longer "
            "`history` shrinks, but does not remove, such links)")


def _warn_noisy_targets(series, labels, pvalue, alpha, n_surrogates) -> None:
    """One warning per map naming :func:`_noisy_targets_why`'s targets (with surrogates)."""
    why = _noisy_targets_why(series, labels, pvalue, alpha) if n_surrogates else None
    if why is not None:
        warn(why + ".", NoisyTargetWarning, stacklevel=3)


def _judge_histogram_map(series, lags, history, t0, te, options) -> None:
    """Warn where the histogram's conditioning rule fails for a target's strongest cell.

    The rule of :func:`~modalinfo.information.transfer_entropy.transfer_entropy`
    (:func:`~modalinfo.information.histogram.histogram_conditioning_rule`: the bins of a
    persistent target's own past lose the TE), judged once per target on its largest
    cell (judging every cell and surrogate would cost a copula CMI each). Audit 11: the
    histogram map of ``y = 0.99 y[-1] + 0.5 x[-1] + e`` gave 0.038 for an exact 0.112
    nats, silently, where ``transfer_entropy`` warns.
    """
    failed, first = count_failures(histogram_conditioning_rule(x, y, z, options) for x, y, z, _
                                   in _largest_cells(series, lags, history, t0, te))
    if failed:
        warn(f"transfer_entropy_map with method='histogram': {failed} of "
             f"{series.shape[1]} "
             f"target(s) fail the conditioning rule on their largest cell ({first}); "
             "the map keeps the histogram (use method='gaussian' or 'ksg')",
             BiasRuleWarning, stacklevel=3)


#: Null values :func:`maxt_pvalues` compares with the statistics at once (a block of
#: columns: 4 MB of booleans).
_COMPARE_VALUES = 1 << 22


def maxt_pvalues(stat: np.ndarray, null: np.ndarray, step_down: bool = True) -> np.ndarray:
    """Family-wise adjusted p-values of the maximum statistic (Westfall & Young 1993).

    Parameters
    ----------
    stat : numpy.ndarray, shape (K,)
        Statistic of each hypothesis (larger is more significant).
    null : numpy.ndarray, shape (N, K)
        The statistics under each of N surrogates (the same surrogate for all K).
    step_down : bool
        True: the step-down maxT of Westfall & Young (Algorithm 4.1): the cell of
        rank k (largest first) is compared with the maximum over the cells of rank
        >= k only, and the p-values are made monotone. False: the single-step
        maximum over all K cells.

    Returns
    -------
    numpy.ndarray, shape (K,)
        ``(1 + #{surrogate max >= stat}) / (1 + N)``, adjusted.
    """
    N, K = null.shape
    if K == 0:
        return np.empty(0)
    if not step_down or N == 0:
        nmax = np.sort(null.max(axis=1)) if N else np.empty(0)
        above = N - np.searchsorted(nmax, stat, side="left")
        return (1.0 + above) / (1.0 + N)
    order = np.argsort(-stat, kind="stable")
    # successive maxima: column k holds the maximum over the cells of rank >= k; built in
    # place in one reordered copy of the null, and compared in column blocks, so the
    # peak is two nulls (not four: a map's null can be GBs); max and >= are exact, so
    # the p-values are those of the whole-array form
    succ = null[:, order[::-1]]
    np.maximum.accumulate(succ, axis=1, out=succ)
    succ = succ[:, ::-1]
    ranked = stat[order]
    above = np.empty(K, dtype=np.int64)
    step = max(1, _COMPARE_VALUES // N)
    for k0 in range(0, K, step):
        above[k0 : k0 + step] = np.count_nonzero(
            succ[:, k0 : k0 + step] >= ranked[None, k0 : k0 + step], axis=0)
    p = (1.0 + above) / (1.0 + N)
    out = np.empty(K)
    out[order] = np.maximum.accumulate(p)
    return out


def transfer_entropy_map(
    data: Any, *, extra: Any = None, modes: Any = None, extra_modes: Any = None,
    lags: Any = 10, history: int = 1, method: str = "gaussian", units: str = "nats",
    alpha: float = 0.05, n_surrogates: int = 199, min_shift: int | None = None,
    adjust: str = "step-down", max_seconds: float = 600.0, seed: Any = None,
    match_ends: bool = True, candidates: Any = "all", radial_width: int = RADIAL_WIDTH,
    outliers: str = "clip", **options: Any,
) -> TransferEntropyMap:
    """Transfer entropy between every pair of modes at every lag, with family-wise p-values.

    Parameters
    ----------
    data : ModalLog or array_like, shape (T, M)
        Telemetry in time order (a ``ModalLog``'s ``coeffs`` and ``labels``; an array's
        columns are ``m0, m1, ...``). Regular sampling assumed.
    extra : ModalLog or array_like, shape (T, M2), optional
        Second log on the same clock (the other WFS or DM of an MCAO run); its modes
        are series too, labelled ``"extra:<label>"``, so the map holds the transfer
        within each log and between the two.
    modes, extra_modes : sequence of int or str, optional
        Columns (indices or labels) of ``data`` / ``extra`` to include (default all).
    lags : int or sequence of int
        Source lags [samples]: an int L means 1..L; or distinct ints >= 0.
    history : int
        Target history k >= 0 [samples] conditioned on.
    method : {"gaussian", "histogram", "kde", "ksg"} or a registered name with a ``cmi``
        Estimator (module notes; "gaussian", or any method whose record has
        ``gaussian_closed_form``, scores a target in one matrix product).
    units : {"nats", "bits"}
        Units of the TE.
    alpha : float
        Family-wise level of :attr:`TransferEntropyMap.significant`, in (0, 1).
    n_surrogates : int
        Time-shift surrogates of the maximum-statistic null (0 gives the TE alone, p = 1;
        otherwise enough that ``1 / (n_surrogates + 1) <= alpha``); at
        most about ``n / (max lag + correlation time)`` for full power (module notes).
    min_shift : int, optional
        Spacing of the surrogates' circular shifts [samples] (they are multiples of it,
        ``surrogate_shifts``); default the largest that fits ``n_surrogates``
        shifts in the rows, about ``n / (n_surrogates + 1)``. Keep it above the span
        of the lags plus the series' correlation time (power), and
        ``n_surrogates x min_shift`` below the rows.
    adjust : {"step-down", "single-step"}
        Family-wise adjustment of the p-values: the step-down maxT of Westfall & Young
        (default; the same family-wise control, more power for the weaker links) or
        the single-step maximum over the whole map (``maxt_pvalues``).
    max_seconds : float
        Refuse a map whose estimated time exceeds this [s].
    seed : None, int or numpy.random.Generator
        Randomness of the surrogate shifts.
    match_ends : bool
        With surrogates, map the window of frames whose end points and end slopes
        match over all the series (:func:`~modalinfo.information.resampling.matched_window`,
        Theiler et al. 1992, Schreiber & Schmitz 2000; at most a fifth of the frames
        discarded, none when the join already looks like a typical step), so the
        rotations join like values (module notes). ``False``: every frame (liberal
        when a series' correlation time exceeds ~ n / 20).
    candidates : {"all", "radial"} or array_like of bool, shape (S, S)
        Which sources each target's cells hold (:mod:`modalinfo.information.candidates`):
        every source (default, unchanged), sources within ``radial_width`` radial
        orders of the target (frozen flow's couplings; Zernike or K-L labels), or an
        explicit mask ``allowed[j, i]``. Cells outside are NaN (``pvalue`` NaN), and the
        family-wise error is controlled over the cells inside (the maximum statistic
        over them). The cells inside equal the unrestricted map's.
    radial_width : int
        Largest radial-order difference of ``candidates="radial"``.
    outliers : {"clip", "warn"}
        Glitches on the least-squares path (``method="gaussian"``): where the outlier
        rule flags a series (AR(4) innovations beyond the heavy-tail threshold,
        family-wise 1e-4), ``"clip"`` (default) replaces the values the quality pass
        flags by their AR(4) predictions before the map (the shared policy,
        ``telemetry.apply_outlier_policy``; the surrogates rotate the cleaned series) and
        says so (``OutlierWarning``); ``"warn"`` scores the values as given, with the
        warning (before fix54-b: 4 glitched frames gave false cells in 10 of 10 maps).
        Logs the rule does not flag are untouched either way
        (``modalinfo.information.resampling.clip_glitches``). Other methods score
        ranks or neighbours and are not changed.
    **options
        Estimator options (see :func:`~modalinfo.information.conditional_mutual_information`).

    Returns
    -------
    TransferEntropyMap
        TE and adjusted p-values per (source, target, lag), best lags, links.

    Warns
    -----
    NoisyTargetWarning
        Where a target of significant links holds a white share of its variance (WFS
        noise): links into it may be reversed (module notes, round 49 PART a).

    Raises
    ------
    ValueError
        Invalid arguments; fewer than ``t0 + 20`` frames; or a map whose memory or
        estimated time exceeds what is available / ``max_seconds``.
    """
    series, labels = _series(data, "data")
    series, labels = _pick(series, labels, modes, "modes")
    group = [0] * len(labels)
    if extra is not None:
        ex, ex_labels = _series(extra, "extra")
        if ex.shape[0] != series.shape[0]:
            raise ValueError(f"`extra` must have {series.shape[0]} frames as `data`; got "
                             f"{ex.shape[0]}.")
        _check_simultaneous(data, extra)
        ex, ex_labels = _pick(ex, ex_labels, extra_modes, "extra_modes")
        series = np.ascontiguousarray(np.concatenate([series, ex], axis=1))
        labels = labels + [f"extra:{s}" for s in ex_labels]
        group += [1] * len(ex_labels)
    elif extra_modes is not None:
        raise ValueError("`extra_modes` selects columns of `extra`, which is not given.")
    if len(labels) < 2:
        raise ValueError(f"`data` (with `extra`) must hold at least 2 series for a transfer "
                         f"map; got {len(labels)}.")
    series = _safe_scale(series)
    lags = _check_lags(lags, series.shape[0])
    history = check_int(history, "history", minimum=0)
    check_choice(method, "method", CMI_METHODS)
    check_choice(units, "units", tuple(UNITS))
    alpha = check_real(alpha, "alpha", minimum=0.0, maximum=1.0, strict_min=True,
                       strict_max=True)
    n_surrogates = check_resamples(n_surrogates, "n_surrogates", minimum=0)
    if n_surrogates:  # 0: the TE alone, p = 1 (documented); a few cannot reach alpha
        check_surrogates_reach(n_surrogates, alpha)
    check_choice(adjust, "adjust", ADJUSTMENTS)
    max_seconds = check_real(max_seconds, "max_seconds", minimum=0.0, strict_min=True)
    if not isinstance(match_ends, (bool, np.bool_)):
        raise TypeError(f"`match_ends` must be a bool; got {type(match_ends).__name__}.")
    rng = check_rng(seed)
    closed = get_method(method).gaussian_closed_form  # partial correlations, not est()
    if closed and options.get("copula", False):
        raise ValueError(f"`copula`=True is not available with method={method!r} here: its "
                         "closed form scores the values (least-squares residuals); use "
                         "method='histogram' or 'ksg' for rank-based scores.")
    check_choice(outliers, "outliers", GLITCH_POLICIES)
    if closed:
        # least squares follow a glitch (round 53 a): cleaned before the end-matched
        # window, the lagged rows and the surrogates, so all see the same values (fix54-b)
        series, why = clip_glitches(series, labels, "transfer_entropy_map", outliers)
        if why:
            warn(why, OutlierWarning, stacklevel=2)
    est = _estimator(method, units, options)
    T, S = series.shape
    L = lags.size
    allowed = candidate_mask(labels, candidates, radial_width)
    t0 = max(int(lags.max()), history)
    n = T - t0
    if n < 20:
        raise ValueError(f"`data` needs at least {t0 + 20} frames for lags up to "
                         f"{lags.max()} and history={history}; got {T}.")
    if min_shift is not None:
        min_shift = check_int(min_shift, "min_shift", minimum=1, maximum=n // 2)
    rows = (0, T)
    if n_surrogates and match_ends:  # module notes: end-point matching
        rows = matched_window_for(n_surrogates, int(lags.max()), min_shift, series, offset=t0)
        if rows[1] - rows[0] - t0 < 20:
            rows = (0, T)
        series = np.ascontiguousarray(series[rows[0] : rows[1]])
        T = series.shape[0]
        n = T - t0

    # resources, before any work
    if allowed is None:
        cells = S * (S - 1) * L
    else:
        allowed = allowed & ~np.eye(S, dtype=bool)
        cells = int(allowed.sum()) * L
        if cells == 0:
            raise ValueError("`candidates` leaves no (source, target) pair off the diagonal.")
    if closed and allowed is not None:
        # the full lagged block, its centred copy, one target's columns and its null
        width = int(allowed.sum(axis=0).max()) * L
        # ... and the null of the cells with maxt_pvalues' reordered copy of it
        need = 8 * (3 * n * S * L + 3 * n * width + n_surrogates * (n + 2 * width)
                    + (2 * n_surrogates + 2) * cells + 2 * S * S * L)
        seconds = n * cells * (2 * (history + 1) + n_surrogates * (1 + history)) / _GAUSS_RATE
    elif closed:
        need = 8 * (3 * n * S * L + n_surrogates * (3 * n + 3 * S * L)
                    + (4 * n_surrogates + 2) * S * S * L)
        # original: residualise and score; null: one cross-correlation of the target's
        # residual and one per history column with every lagged source, per surrogate
        seconds = S * n * S * L * (2 * (history + 1) + n_surrogates * (1 + history)) \
            / _GAUSS_RATE
    else:
        need = 8 * (n * (history + 3) * (1 + 2) + (4 * n_surrogates + 2) * S * S * L)
        x, z = series[t0:, :1], _history(series[:, 0], history, t0)
        y = np.ascontiguousarray(series[t0 - lags[0] : T - lags[0], 1:2])
        est(x, y, z)  # the first call may compile the estimator's kernels: not timed
        t_start = time.perf_counter()
        for s in (1, 2, 3):  # as the surrogates: rolled copies
            est(x, np.roll(y, s, axis=0), z)
        seconds = (time.perf_counter() - t_start) / 3 * cells * (1 + n_surrogates)
    avail = free_memory_bytes()
    if need > avail:
        raise ValueError(f"the transfer map needs about {need / 2**20:.0f} MiB ({S} series x "
                         f"{L} lags x {n} rows, {n_surrogates} surrogates) and "
                         f"{avail / 2**20:.0f} MiB is available; use fewer modes, lags or "
                         f"frames.")
    if seconds > max_seconds:
        raise ValueError(f"the transfer map would take about {seconds:.0f} s ({cells} cells "
                         f"= {S} series x {S - 1} targets x {L} lags, n = {n}, "
                         f"{n_surrogates} surrogates, method {method!r}), more than "
                         f"`max_seconds`={max_seconds:g}; use fewer modes, lags or "
                         f"surrogates (or raise `max_seconds`).")

    shifts, shift0 = surrogate_shifts(n, n_surrogates, int(lags.max()), min_shift, rng)
    factor = UNITS[units]
    if allowed is not None:
        family = np.repeat(allowed[:, :, None], L, axis=2)
        if closed:
            te, null_cells = _gaussian_map_restricted(series, lags, history, t0, shifts,
                                                      family, labels)
            te, null_cells = te * factor, null_cells * factor
        else:
            te, null = _estimator_map(series, lags, history, t0, shifts, est, family,
                                       rank_based_options(options))
            null_cells = null[:, family]
            te[~family] = np.nan
        _judge_map(series, lags, history, t0, te, method, options, factor)
        pvalue = np.full(te.shape, np.nan)
        pvalue[family] = maxt_pvalues(te[family], null_cells,
                                      step_down=adjust == "step-down")
        null_max = null_cells.max(axis=1) if n_surrogates else np.empty(0)
        _warn_noisy_targets(series, labels, pvalue, alpha, n_surrogates)
        return TransferEntropyMap(
            labels=tuple(labels), group=np.array(group, dtype=np.int64), lags=lags, te=te,
            pvalue=pvalue, null_max=null_max, history=history, n_samples=n, method=method,
            units=units, alpha=alpha, n_surrogates=n_surrogates, min_shift=int(shift0),
            estimated_seconds=float(seconds), adjust=adjust, rows=(int(rows[0]), int(rows[1])),
        )
    if closed:
        te, null = _gaussian_map(series, lags, history, t0, shifts, labels)
        te, null = te * factor, null * factor
    else:
        te, null = _estimator_map(series, lags, history, t0, shifts, est,
                                  rank_based=rank_based_options(options))
    _judge_map(series, lags, history, t0, te, method, options, factor)
    diag = np.eye(S, dtype=bool)
    off = ~diag
    pvalue = np.full(te.shape, np.nan)
    null_cells = null[:, off].reshape(n_surrogates, off.sum() * L)
    pvalue[off] = maxt_pvalues(te[off].ravel(), null_cells,
                               step_down=adjust == "step-down").reshape(-1, L)
    null_max = null_cells.max(axis=1) if n_surrogates else np.empty(0)
    te[diag] = np.nan
    _warn_noisy_targets(series, labels, pvalue, alpha, n_surrogates)
    return TransferEntropyMap(
        labels=tuple(labels), group=np.array(group, dtype=np.int64), lags=lags, te=te,
        pvalue=pvalue, null_max=null_max, history=history, n_samples=n, method=method,
        units=units, alpha=alpha, n_surrogates=n_surrogates, min_shift=int(shift0),
        estimated_seconds=float(seconds), adjust=adjust, rows=(int(rows[0]), int(rows[1])),
    )
