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
correlation -- exactly the Gaussian CMI of :func:`transfer_entropy` on the same rows,
with the partial-correlation scorer of :mod:`modalinfo.information.selection`. The
other methods of :func:`~modalinfo.information.conditional_mutual_information`
estimate each cell with the estimator (``cells x (1 + n_surrogates)`` estimates).

Family-wise control. One set of circular time shifts (at least the largest
Politis-White block length of the targets, at most n // 2) is drawn for the whole map;
under surrogate s every target is rotated by s against its lagged sources (each series
keeps its autocorrelation; the Gaussian path rotates the target's residual against the
sources' residuals, the null of zero partial correlation, as the selection does), and
the statistic is the *largest* TE over every cell of the map. A cell's p-value is
``(1 + #{null max >= TE}) / (1 + n_surrogates)``: the single-step maximum-statistic
adjustment (Westfall & Young 1993), which controls the family-wise error over all
``S (S - 1) L`` cells at ``alpha`` (so one spurious link anywhere in the map has
probability about alpha). It is conservative for cells whose own null is narrower than
the map's maximum. With 199 surrogates the smallest p-value is 0.005. Measured on
independent AR(1) series (coefficient 0.7, history 1, 49 surrogates, alpha = 0.1): a
2-series 1-lag map rejects 0.03 per cell (300 maps), but a 4-series 4-lag map (48 cells)
has a spurious link in 0.14 (n = 500, 500 maps) and 0.13 (n = 2000, 200 maps) of the maps,
about 2.5 standard errors above alpha: the time-shift null is slightly liberal for large
maps (cause not yet found; on the same 200 maps at n = 500, ``min_shift`` = 5, 21 (the
default), 60 and 124 gave 0.13, 0.145, 0.125 and 0.095; take ``alpha`` half the level
wanted for a strict bound).

Bivariate TE does not separate direct from indirect transfer (a chain j -> m -> i, or a
common driver of i and j, shows as j -> i); :func:`~modalinfo.information.select_inputs`
conditions on the inputs already chosen and is the tool for a predictor's inputs.

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

from modalinfo._validation import check_choice, check_int, check_real, check_rng, free_memory_bytes
from modalinfo.information.api import UNITS
from modalinfo.information.conditional import CMI_METHODS, _auto_block, _estimator
from modalinfo.information.selection import _gauss_gains, _series, unit_candidates

__all__ = ["TransferEntropyMap", "transfer_entropy_map"]

#: Multiply-adds per second assumed for the time estimate of a Gaussian map: the rate
#: measured on the project's shared 2-core machine at a load average of 13 (9 series,
#: 10 lags, n = 7990, 99 surrogates: 6.8e8 multiply-adds in 3.6 s); an idle core is
#: about 5 times faster, so the estimate errs on the long side.
_GAUSS_RATE = 2e8


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
        NaN on the diagonal j = i.
    pvalue : numpy.ndarray, shape (S, S, L)
        Family-wise adjusted (maximum-statistic) p-value of each cell; NaN on the
        diagonal.
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
        Smallest circular shift of the surrogates [samples].
    estimated_seconds : float
        The time estimate checked before work [s].
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
                f"(max-statistic over {self.te.shape[0] * (self.te.shape[0] - 1) * self.lags.size}"
                f" cells, {self.n_surrogates} time-shift surrogates): {len(links)} "
                f"significant links")
        rows = [head, f"{'source':<14} {'target':<14} {'lag':>4} {'TE':>9} {'p':>7}"]
        for s, t, lag, te, p in links[:max_rows]:
            rows.append(f"{s:<14} {t:<14} {lag:>4} {te:9.4f} {p:7.4f}")
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


def _check_lags(lags: Any) -> np.ndarray:
    if isinstance(lags, int | np.integer):
        top = check_int(lags, "lags", minimum=1)
        return np.arange(1, top + 1)
    arr = np.asarray(list(lags) if not isinstance(lags, np.ndarray) else lags)
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


def _residualiser(z: np.ndarray):
    """Return ``f(a)``: the columns of ``a`` centred and orthogonalised against ``z``."""
    zc = z - z.mean(axis=0)
    keep = np.sqrt(np.einsum("ij,ij->j", zc, zc)) > 0
    q = np.linalg.qr(zc[:, keep])[0] if keep.any() else np.empty((z.shape[0], 0))

    def resid(a: np.ndarray) -> np.ndarray:
        ac = a - a.mean(axis=0)
        return ac - q @ (q.T @ ac)

    return resid


def _gaussian_map(series, lags, history, t0, shifts):
    """TE (nats) of every cell and the null maximum, the partial-correlation way."""
    T, S = series.shape
    L = lags.size
    n = T - t0
    C = _lagged_block(series, lags, t0)
    _, alive_all = unit_candidates(C)
    te = np.zeros((S, S, L))
    null_max = np.zeros(shifts.size)
    rows = (np.arange(n)[None, :] - shifts[:, None]) % n
    for i in range(S):
        resid = _residualiser(_history(series[:, i], history, t0))
        r = resid(series[t0:, i : i + 1])[:, 0]
        R = resid(C)
        alive = alive_all.copy()
        alive[i::S] = False  # the target's own lags are not a transfer
        te[:, i, :] = _gauss_gains(r, R, alive).reshape(L, S).T
        cn = np.sqrt(np.einsum("ij,ij->j", R, R))
        ok = alive & (cn > 0)
        rn = math.sqrt(float(r @ r))
        if ok.any() and rn > 0 and shifts.size:
            rho = (r[rows] @ R[:, ok]) / (cn[ok][None, :] * rn)
            null_max = np.maximum(
                null_max, (-0.5 * np.log(np.maximum(1.0 - rho * rho, 1e-15))).max(axis=1))
    return te, null_max


def _estimator_map(series, lags, history, t0, shifts, est):
    """TE of every cell and the null maximum with a general CMI estimator."""
    T, S = series.shape
    te = np.zeros((S, S, lags.size))
    null_max = np.full(shifts.size, -np.inf)
    for i in range(S):
        x = series[t0:, i : i + 1]
        z = _history(series[:, i], history, t0)
        for j in range(S):
            if j == i:
                continue
            for a, lag in enumerate(lags):
                y = np.ascontiguousarray(series[t0 - lag : T - lag, j : j + 1])
                te[j, i, a] = est(x, y, z)
                for s_i, s in enumerate(shifts):
                    null_max[s_i] = max(null_max[s_i], est(x, np.roll(y, int(s), axis=0), z))
    return te, null_max


def transfer_entropy_map(
    data: Any, *, extra: Any = None, modes: Any = None, extra_modes: Any = None,
    lags: Any = 10, history: int = 1, method: str = "gaussian", units: str = "nats",
    alpha: float = 0.05, n_surrogates: int = 199, min_shift: int | None = None,
    max_seconds: float = 600.0, seed: Any = None, **options: Any,
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
    method : {"gaussian", "histogram", "kde", "ksg"}
        Estimator (module notes; "gaussian" scores a target in one matrix product).
    units : {"nats", "bits"}
        Units of the TE.
    alpha : float
        Family-wise level of :attr:`TransferEntropyMap.significant`, in (0, 1).
    n_surrogates : int
        Time-shift surrogates of the maximum-statistic null (>= 0; 0 gives p = 1).
    min_shift : int, optional
        Smallest surrogate shift [samples]; default the largest Politis-White block
        length of the targets (at most n // 2).
    max_seconds : float
        Refuse a map whose estimated time exceeds this [s].
    seed : None, int or numpy.random.Generator
        Randomness of the surrogate shifts.
    **options
        Estimator options (see :func:`~modalinfo.information.conditional_mutual_information`).

    Returns
    -------
    TransferEntropyMap
        TE and adjusted p-values per (source, target, lag), best lags, links.

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
        ex, ex_labels = _pick(ex, ex_labels, extra_modes, "extra_modes")
        series = np.ascontiguousarray(np.concatenate([series, ex], axis=1))
        labels = labels + [f"extra:{s}" for s in ex_labels]
        group += [1] * len(ex_labels)
    elif extra_modes is not None:
        raise ValueError("`extra_modes` selects columns of `extra`, which is not given.")
    if len(labels) < 2:
        raise ValueError(f"a transfer map needs at least 2 series; got {len(labels)}.")
    lags = _check_lags(lags)
    history = check_int(history, "history", minimum=0)
    check_choice(method, "method", CMI_METHODS)
    check_choice(units, "units", tuple(UNITS))
    alpha = check_real(alpha, "alpha", minimum=0.0, maximum=1.0, strict_min=True,
                       strict_max=True)
    n_surrogates = check_int(n_surrogates, "n_surrogates", minimum=0)
    max_seconds = check_real(max_seconds, "max_seconds", minimum=0.0, strict_min=True)
    rng = check_rng(seed)
    est = _estimator(method, units, options)
    T, S = series.shape
    L = lags.size
    t0 = max(int(lags.max()), history)
    n = T - t0
    if n < 20:
        raise ValueError(f"`data` needs at least {t0 + 20} frames for lags up to "
                         f"{lags.max()} and history={history}; got {T}.")

    # resources, before any work
    cells = S * (S - 1) * L
    if method == "gaussian":
        need = 8 * (3 * n * S * L + n_surrogates * (n + S * L) + 2 * S * S * L)
        seconds = S * n * S * L * (2 * (history + 1) + n_surrogates) / _GAUSS_RATE
    else:
        need = 8 * (n * (history + 3) * (1 + 2) + 2 * S * S * L)
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

    if min_shift is None:
        shift0 = min(_auto_block(series[t0:]), n // 2) if n_surrogates else 0
    else:
        shift0 = check_int(min_shift, "min_shift", minimum=1, maximum=n // 2)
    shifts = rng.integers(shift0, n - shift0 + 1, size=n_surrogates)
    factor = UNITS[units]
    if method == "gaussian":
        te, null_max = _gaussian_map(series, lags, history, t0, shifts)
        te, null_max = te * factor, null_max * factor
    else:
        te, null_max = _estimator_map(series, lags, history, t0, shifts, est)
    diag = np.eye(S, dtype=bool)
    te[diag] = np.nan
    # #{null max >= TE} from the sorted null
    above = n_surrogates - np.searchsorted(np.sort(null_max), np.nan_to_num(te), side="left")
    pvalue = (1.0 + above) / (1.0 + n_surrogates)
    pvalue[diag] = np.nan
    return TransferEntropyMap(
        labels=tuple(labels), group=np.array(group, dtype=np.int64), lags=lags, te=te,
        pvalue=pvalue, null_max=null_max, history=history, n_samples=n, method=method,
        units=units, alpha=alpha, n_surrogates=n_surrogates, min_shift=int(shift0),
        estimated_seconds=float(seconds),
    )
