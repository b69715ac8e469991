"""Orderings of a modal basis: standard, variance, data-PCA and mutual information.

The MI orderings follow the paper's Section 2.1 made precise in DESIGN.md. Samples are
pupil-pixel values at (frame, pixel) pairs drawn without replacement (seeded) up to
``sample_budget``, pooled over frames or from one frame (the paper's "typical
wavefront representation"). With ``Phi_ref = sum_k a_k Z_k``:

- ``"mi_marginal"``: score of mode k = I(Phi_ref; a_k Z_k), modes sorted by score;
- ``"mi_greedy"``: from the empty set S, add the mode maximising I(Phi_ref; Phi_{S+k});
  the gain of a step is the increase in MI (forward selection with a fixed target).
  The last step adds the last mode and so reproduces Phi_ref exactly; the MI of a
  continuous variable with itself is infinite, so that step's MI and gain are NaN
  (not estimated) and the order of the last mode is forced.

Estimator: by default the histogram MI on equiprobable (quantile) bins with the bin
rule at the rank correlation (:mod:`modalinfo.information.histogram`), a function of
the ranks of Phi_ref and Phi_S only. A glitched frame (one mode at 100 sigma) is
1/T of the samples and moves each score by about that share: in 4000-frame logs (the
shipped kaos_closedloop, kaos_like seeds 0 and 1, budget 20 000) it changes none of the
first 10 ranks, where the former equal-width bins (``estimator_options={"binning":
"uniform"}``) changed 7-10 of them (tests/ordering/test_glitch_robustness.py).
Ranks whose MI differs by less than that share (``~`` ties, e.g. Z2 and Z3 of an
isotropic log) can still swap.

What the pooled MI measures: a mode's contribution ``a_k Z_k(p)`` also tells where in
the pupil the sample is, and the wavefront's variance changes across the pupil, so even
a mode of tiny variance carries MI through its spatial pattern (200 iid modes: 0.03
nats at a mean square of 1e-6, the exact mixture value, matched by the histogram and
sklearn's KSG; fix53-e). Where that pixel information exceeds twice the largest mode's
variance share's (:func:`envelope_information`; many modes of small shares, e.g. 1,000
iid modes) a pooled ordering warns ``SpatialEnvelopeWarning``: the order then follows
the patterns, not the variances.

The greedy search fits one :class:`~modalinfo.information.MutualInformation` on
Phi_ref (binning or bandwidth cached once) and keeps Phi_S on the samples; a score of
``Phi_S + a_k Z_k`` costs O(samples) (~3 ms at 2e5). Two searches, same estimator and
same rule (the best exact score among the modes scored wins; scores within their float
error of the best, ``_TIE_RTOL * max(1, |best|)`` nats, are a tie that the lower index
wins, so that no CPU's last bits decide a step: structurally equal scores, e.g. two
modes whose count tables are permutations of each other, differ only there):

- ``search="exhaustive"`` scores every remaining mode at every step: M^2 / 2 scores
  (230 modes: 50 s; 2,000 modes: ~2 h). The definition; ``"auto"`` uses it up to 64
  modes, so the paper's 27-mode orders (and the golden numbers) are these.
- ``search="screened"`` (``"auto"`` above 64 modes) scores every mode at step 1 (the
  marginal scores are part of the result), then at each step takes the remaining
  modes in descending *key* and scores them exactly until the next key, times 1.05,
  is below the key of the step's best (the last 16 steps score every remaining mode:
  near Phi_ref the histogram MI saturates and departs most from the key). The key is
  the mode's variance share in the Gaussian closed form: for jointly Gaussian,
  mutually orthogonal contributions the gain of adding k to S is
  ``g = -ln(1 - v_k / R_S) / 2`` (``v_k`` the variance of ``a_k Z_k``, ``R_S`` that of
  ``Phi_ref - Phi_S``), so ``R_S (1 - exp(-2 g)) = v_k``
  at every step; the key is the running mean of ``v_k`` on the samples and of
  ``R_S (1 - exp(-2 g))`` for every estimated gain of k (a mean, so one noisy low
  estimate cannot starve a mode). A few scores per step: 2,000 modes x 1e5 frames in
  under a minute (benchmarks/bench_greedy_scale.py). Not a lazy (CELF) search: these
  gains *grow* with S (the closed form above increases with ``R_S`` shrinking), so a
  stale gain is no upper bound; and the key is no bound of the histogram gain either.
  The order is therefore not guaranteed to be the exhaustive one: it can differ where
  candidates' MI differ by less than the estimator's noise (ties: modes of one radial
  order have equal variance in Kolmogorov turbulence, and which of them the exhaustive
  search takes first is decided by that noise) or where a mode's estimated gain departs
  from its Gaussian share by more than 5 % (a screening miss). Measured (300 modes,
  5000 frames, budget 2e5): the first such step differed in MI by 1e-4 nats, and
  the MI curve along the screened order stays within a fraction of the exhaustive
  order's 95 % bootstrap half-width (tests/ordering/test_greedy_search.py,
  benchmarks/RESULTS.md).

Uncertainty: with the order held fixed, the MI of every step and its gain are
recomputed on ``n_resamples`` bootstrap replicates: frames resampled in circular blocks
of ``block_length`` frames (pooled; keeps the time correlation of a loop) or pixels
resampled one by one (one frame; ignores the spatial correlation, so optimistic). The
percentile bounds measure sampling variability at this budget, not the estimator's
bias; a step whose lower gain bound is not above 0 adds no detectable information.
Ties: the *margin* of step s is I(Phi_ref; Phi_s) minus the MI had step s taken the
next step's mode instead; when its bootstrap interval reaches 0, ranks s and s + 1
are within noise of each other (their order is not determined at this budget).
Cost: one ``fit`` and M ``score`` calls per replicate.

Replicates: by default the fewest whose percentile bounds at the level have a replicate
beyond each, ``2 / (1 - level)`` (40 at 95 %;
:func:`~modalinfo.information.resampling.least_tail_replicates`, the rule that
``mutual_information_ci`` enforces and ``reorder`` cautions by). Fewer leave the bounds
at (nearly) the extreme replicates, whose range holds a new replicate with probability
``(R - 1) / (R + 1)`` whatever the level (order statistics; Davison & Hinkley 1997,
sec. 5.2.3); Efron & Tibshirani (1993, ch. 13 and 19) ask ~1000 for percentile intervals
that are stable to the second digit, a bootstrap 25 times the default's. The former default, 20
at 95 %, had none beyond either bound. Measured (issue 27; 200 logs of 200 iid frames,
6 Gaussian modes of known variance, the Gaussian estimator, whose gains are then
analytic: benchmarks/bench_ordering_bootstrap_coverage.py): the 95 % gain bounds missed
the true gain 0.044 below / 0.037 above with 20 replicates (coverage 0.919), 0.031 /
0.023 with 40 (0.946), 0.013 / 0.009 with 200 (0.978: at this size the percentile
bootstrap itself is conservative; too few replicates pull every bound inwards, towards
the estimate). The default costs 1.8x the former's CPU in ``order_modes`` (27 modes,
8000 frames, budget 2e5; 1.6x for the whole ``reorder`` command).

Baselines: ``"standard"`` (index order; ascending Noll index for a Zernike basis, whatever
the order of the log's columns), ``"variance"`` (descending mean-square coefficient; ties
in the standard order) and ``"pca"`` (the empirical K-L order: descending eigenvalue,
defined for a basis in which the log's coefficients are uncorrelated, i.e.
``KLBasis.from_data`` of the same log; its fitting-error curve is the floor of every
other ordering's).
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numpy as np

from modalinfo.common.quiet import caller_stacklevel, warn
from modalinfo.common.validation import check_choice, check_int, check_real, check_rng, seed_record
from modalinfo.information.api import InfiniteMIError
from modalinfo.information.discrete import PILE_BLIND_METHODS, pile_why
from modalinfo.information.methods import (
    BiasRuleWarning,
    check_deterministic,
    check_plugin_value,
    read_only,
)
from modalinfo.information.resampling import (
    block_bootstrap_indices,
    least_tail_replicates,
    percentile_bounds,
    resolve_block_length,
)
from modalinfo.ordering import _kernels as kern
from modalinfo.ordering import cost as _cost  # one estimate, looked up at call time
from modalinfo.ordering._coefficients import BasisView, as_basis, coefficients_in_basis
from modalinfo.ordering.cost import (  # the search's sizes live with the cost model
    _EXHAUSTIVE_MAX_MODES,
    _EXHAUSTIVE_TAIL,
    MAX_ORDERING_SECONDS,
)
from modalinfo.ordering.result import OrderingResult, basis_key
from modalinfo.telemetry.quality import (  # noqa: F401 - the floor's names, kept here
    CALIBRATION_LEVEL_P,
    CALIBRATION_MIN_FRAMES,
)

__all__ = ["CONFIDENCE_LEVEL", "METHODS", "MI_ONLY_ARGUMENTS", "SEARCHES",
           "SpatialEnvelopeWarning", "envelope_information", "order_modes",
           "mi_along_order", "refuse_unused_arguments", "sample_contributions"]

#: How to shorten an MI ordering, in the library's argument names (``_check_time``)
ORDERING_HOW = ("use fewer modes, a smaller `sample_budget`, fewer `n_resamples` (0: no "
                "bounds) or a faster `estimator` ('histogram', 'gaussian')")
#: Ordering methods accepted by :func:`order_modes`.
METHODS = ("standard", "variance", "pca", "mi_marginal", "mi_greedy")
#: Default level of :func:`order_modes`' bootstrap bounds; its default replicates are
#: ``least_tail_replicates(level)`` (40 at 95 %: module notes).
CONFIDENCE_LEVEL = 0.95
#: Searches of the greedy MI ordering accepted by :func:`order_modes`.
SEARCHES = ("auto", "screened", "exhaustive")
#: Relative margin on the screening key (module notes: measured misses against cost).
_SCREEN_TOLERANCE = 0.05
#: Greedy scores within ``_TIE_RTOL * max(1, |best|)`` nats of the step's best are a tie,
#: won by the lower index (module notes, ties of the greedy search). 2^-40 = 4096 eps:
#: the plug-in histogram MI sums one term per occupied cell, K of them, whose absolute
#: values add up to at most MI + 2 nats (``p log(p_i p_j / p) <= p_i p_j - p`` bounds the
#: negative ones by 1), so its rounding error is at most K eps (MI + 2) <= 3 K eps
#: max(1, MI): within the tolerance up to K = 1365 cells (the default bins' 35 x 35 at
#: n = 2e4 and r = 0.9), and typically (sqrt(K) eps (MI + 2), random signs) up to
#: K ~ 1e6. Far below the estimator's sampling noise (1e-4 nats and more, module notes)
_TIE_RTOL = 2.0**-40
_DECORRELATED_ATOL = 1e-6
#: Multiple of ``eps lambda_max`` a symmetric eigensolver leaves off the diagonal of
#: ``V^T C V`` (LAPACK's backward error, ``p(M) eps ||C||_2`` with a modest ``p``): the
#: data K-L logs of round 33 PART a (12 decades, 6 seeds) reached 1.4, so 64 leaves a
#: margin of 45; the absolute 1e-6 still rules every pair with sqrt(lambda_i lambda_j)
#: above 1.4e-8 lambda_max
_EIG_BACKWARD = 64.0


class _CheckedEstimator:
    """A user's fit/score object, given read-only data and its scores checked (round 13).

    Its score must be a real number of nats, finite or NaN (a candidate it cannot score),
    not negative beyond ``NEGATIVE_TOLERANCE``, and the same twice for the first
    candidate after each fit: a string "0.3", True, inf, -0.5 and an unseeded estimator
    ordered the modes silently (rows ord-est-str, -bool, -inf, -neg, -random).
    """

    def __init__(self, estimator: Any):
        self._est = estimator
        self._who = f"`estimator` {type(estimator).__name__}'s score()"
        self._probe = False

    def fit(self, x: np.ndarray) -> _CheckedEstimator:
        self._est.fit(read_only(x))
        self._probe = True
        return self

    def score(self, y: np.ndarray) -> float:
        value = check_plugin_value(self._est.score(read_only(y)), self._who, allow_nan=True)
        if self._probe:
            self._probe = False
            again = check_plugin_value(self._est.score(read_only(y)), self._who,
                                       allow_nan=True)
            check_deterministic(value, again, self._who)
        return value


def _make_estimator(estimator: Any, options: dict) -> tuple[Any, str]:
    """Return a fit/score MI estimator from a method name or a ready object."""
    if isinstance(estimator, str):
        from modalinfo.information import MutualInformation

        est = MutualInformation(method=estimator, units="nats", **options)
        # not judged at small n (fixes 34-a): an ordering ranks candidates, and the rule-
        # chosen bins' loss lowers a Gaussian pair's binned MI as a function of its
        # correlation that stays increasing (gaussian_grid_mi at the Hacine-Gharbi k,
        # checked at n = 20-500), so the order is kept; its resamples refit the
        # estimator, and the class road warns once per fit
        est._judge_resolution = False
        return est, estimator
    if hasattr(estimator, "fit") and hasattr(estimator, "score"):
        if options:
            raise ValueError(
                "`estimator_options` must be empty when `estimator` is an object; "
                f"got {options!r}."
            )
        return _CheckedEstimator(estimator), type(estimator).__name__
    raise TypeError(
        "`estimator` must be a method name (e.g. 'histogram', 'kde') or an object with "
        f"fit(x) and score(y); got {type(estimator).__name__}."
    )


#: Samples the pile rule reads per mode in an ordering (a share of 0.5 % is ~100 of them).
_PILE_SAMPLES = 20_000


def _nodal(view: BasisView, pixels: np.ndarray) -> np.ndarray | None:
    """(B, M) True where a continuous mode is exactly 0 at the sample's pixel, else None.

    The zeros are found on the (pixels, M) matrix and then gathered, as booleans: a
    float64 gather of ``view.matrix[pixels]`` was a second copy of the (B, M)
    contributions, outside ``ordering_memory_bytes`` (the command lines' estimate), and
    ran ``reorder`` out of memory after its check passed (round 42 PART b, S02).

    For modes that are continuous functions (a ``ZernikeBasis``, a ``KLBasis``), an
    exact 0 at a pixel centre is a point of a nodal line, a set of measure zero of the
    continuous mode, that the grid happens to sample: not an atom of its values. A K-L
    mode odd under ``x <-> y`` is exactly 0 on the diagonals since its values at mirror
    pixels are exact mirrors (golden40; 2.9 % of a 64-pixel pupil's pixels, more on a
    smaller one). A bare matrix or another basis holds its own samples: its zeros count.
    """
    from modalinfo.ordering.fitting_error import _continuous_zernikes

    if _continuous_zernikes(view.obj) is None:
        return None
    return (view.matrix == 0)[pixels]


def _pile_step(n_samples: int) -> int:
    """Stride of the ``_PILE_SAMPLES`` evenly spaced samples :func:`_warn_piles` judges."""
    return max(1, n_samples // _PILE_SAMPLES)


def _warn_piles(contrib: np.ndarray, labels: Any, estimator: str,
                nodal: np.ndarray | None = None) -> None:
    """Warn once (``BiasRuleWarning``) where the wavefront or a mode's contribution is piled.

    ``nodal`` (B, M): samples at a continuous mode's nodal pixels (:func:`_nodal`), left
    out of that mode's rule.

    The single-variable rules of :func:`~modalinfo.information.mutual_information`
    (discrete module notes, "Piles", issue 27: one value inside the range above 3 %,
    the ends above 10 %) on the wavefront and on each mode's contribution alone, on an
    evenly spaced ``_PILE_SAMPLES`` of the samples; once per call (not once per pair),
    naming the first and the number of others. Not the shared-atom rule (0.5 %): a
    frame of zeros (a loop started from rest, a dropped frame) is an atom the wavefront
    shares with every mode, whose exact MI it raises alike (``H(p) + (1 - p) I``, the
    same order) and whose estimates it lowers alike. Measured (left28-misc: 8
    independent Gaussian modes, variances 1 .. 0.21, against their wavefront; 4 seeds;
    pairs of modes ordered against the exact order): kde and gaussian invert as many
    pairs with a shared atom of 0.5-10 % as with none (n = 2000: 0-3; n = 1e4: 0-1;
    the modes' errors differ by 0.02-0.04 nats at every share, while each error grows
    to -0.3), the histogram as many up to 5 %, and 4-14 at 10 %, where the wavefront's
    own pile (above 3 %) is already named. The MI values, not the order, carry the
    atom's loss: read them with ``method='ksg'`` there.
    """
    step = _pile_step(contrib.shape[1])
    part = contrib[:, ::step]
    node = None if nodal is None else (nodal if nodal.shape[0] == part.shape[1]
                                       else nodal[::step])

    def columns():
        # one column at a time: a dict of every mode's masked row was a copy of the
        # judged contributions, all of them below 2 x _PILE_SAMPLES samples (round 42
        # PART b, S02)
        yield "the wavefront", part.sum(axis=0)
        for i, row in enumerate(part):
            if node is None:
                yield f"mode {labels[i]}", row
            elif np.count_nonzero(~node[:, i]) > 1:
                yield f"mode {labels[i]}", row[~node[:, i]]

    first, count = None, 0
    for name, column in columns():
        why = pile_why({name: column}, estimator)
        if why is not None:
            first, count = first or why, count + 1
    if first is not None:
        more = f" (and {count - 1} other variable(s))" if count > 1 else ""
        warn(f"order_modes with estimator={estimator!r}{more}: {first}.",
             BiasRuleWarning, stacklevel=caller_stacklevel())


def _draw_pairs(
    n_frames: int, n_valid: int, budget: int, rng: np.random.Generator, frame: int | None
) -> tuple[np.ndarray, np.ndarray]:
    """(frame, pixel) indices of the samples, sorted, without replacement."""
    if frame is not None:
        if n_valid <= budget:
            pixels = np.arange(n_valid, dtype=np.int64)
        else:
            pixels = np.sort(rng.choice(n_valid, size=budget, replace=False)).astype(np.int64)
        return np.full(pixels.size, frame, dtype=np.int64), pixels
    total = n_frames * n_valid
    if total <= budget:
        flat = np.arange(total, dtype=np.int64)
    else:
        flat = np.sort(rng.choice(total, size=budget, replace=False)).astype(np.int64)
    return flat // n_valid, flat % n_valid


def _contributions(a: np.ndarray, matrix: np.ndarray, frames: np.ndarray,
                   pixels: np.ndarray) -> np.ndarray:
    """Contributions (M, B) of every mode at the samples (rows contiguous)."""
    out = np.empty((a.shape[1], frames.size))
    kern.gather_contributions(a, matrix, frames, pixels, out)
    return out


def sample_contributions(
    log_or_coeffs: Any,
    basis: Any,
    *,
    sample_budget: int = 200_000,
    frame: int | None = None,
    seed: Any = None,
    wavelength: float | None = None,
) -> np.ndarray:
    """Per-mode wavefront contributions ``a_k Z_k`` at subsampled (frame, pixel) pairs.

    Parameters
    ----------
    log_or_coeffs : ModalLog or array_like, shape (T, M)
        The log, or coefficients of the basis's modes [rad].
    basis : ModalBasis or array_like, shape (n_valid, M)
        The basis.
    sample_budget : int
        Number of (frame, pixel) samples (all of them if there are fewer).
    frame : int, optional
        Sample only this frame's pixels.
    seed : None, int or numpy.random.Generator
        Seed of the subsampling.
    wavelength : float, optional
        Wavelength [m] for converting a log in nm or um that carries none.

    Returns
    -------
    numpy.ndarray, shape (M, B)
        Row k is mode k's contribution [rad]; ``Phi_ref`` is the sum of the rows.
    """
    view = as_basis(basis)
    a = coefficients_in_basis(log_or_coeffs, view, wavelength=wavelength)
    budget = check_int(sample_budget, "sample_budget", minimum=10)
    if frame is not None:
        frame = check_int(frame, "frame", minimum=-a.shape[0], maximum=a.shape[0] - 1)
        frame %= a.shape[0]
    frames, pixels = _draw_pairs(a.shape[0], view.matrix.shape[0], budget, check_rng(seed), frame)
    return _contributions(a, view.matrix, frames, pixels)


def _constant_modes(a: np.ndarray, matrix: np.ndarray) -> np.ndarray:
    """Return the modes (``(M,)`` bool) whose contribution ``a_k Z_k`` is one constant.

    Zero coefficients, or a constant coefficient on a mode flat over the pupil (piston),
    to 1e-12 of the largest coefficient (a data K-L basis of a log with a dead mode has
    a null mode whose coefficients are rounding, ~1e-17). Reductions only: no (T, M)
    temporary.
    """
    high, low = a.max(axis=0), a.min(axis=0)
    tol = 1e-12 * float(max(high.max(), -low.min(), 0.0))
    constant = high - low <= tol
    zero = np.maximum(high, -low) <= tol
    flat = np.ptp(matrix, axis=0) <= 1e-12 * float(np.abs(matrix).max())
    return zero | (constant & flat)


def _numerically_dead(contrib: np.ndarray) -> np.ndarray:
    """Return the modes (``(M,)`` bool) too small to change the order of Phi_ref's samples.

    Removing such modes (the smallest first) leaves a sum that is a strictly increasing
    function of Phi_ref on the drawn samples: its MI is infinite, and every estimator
    refuses it ("`y` is a strictly monotone function of `x`"). A mode of 1e-11 rad beside
    modes of 0.1 rad is one (above the 1e-12 rule of :func:`_constant_modes`). They are
    ordered last with NaN MI, as the constant modes. Tied samples (a discrete Phi_ref)
    flag nothing: the estimators score those themselves. At least one mode stays.
    """
    ref = contrib.sum(axis=0)
    order = np.argsort(ref, kind="stable")
    rest = ref[order]
    dead = np.zeros(contrib.shape[0], dtype=bool)
    if not np.all(np.diff(rest) > 0):
        return dead
    rms = np.sqrt(np.mean(contrib * contrib, axis=1))
    for k in np.argsort(rms, kind="stable")[:-1]:
        rest = rest - contrib[k][order]
        if not np.all(np.diff(rest) > 0):
            break
        dead[k] = True
    return dead


def _with_dead_modes(sub: OrderingResult, live: np.ndarray, dead: np.ndarray,
                     labels: tuple) -> OrderingResult:
    """``sub`` (an ordering of the ``live`` modes) with the ``dead`` ones appended.

    A constant mode adds no information: its steps' MI and gains are NaN (the sum is
    then the whole wavefront up to a constant, whose MI is infinite, as the last step's).
    """
    import dataclasses

    def pad(v: np.ndarray | None) -> np.ndarray | None:
        return None if v is None else np.concatenate([v, np.full(dead.size, np.nan)])

    order = np.concatenate([live[sub.order], dead]).astype(np.int64)
    scores = None
    if sub.scores is not None:
        scores = np.full(live.size + dead.size, np.nan)
        scores[live] = sub.scores
    return dataclasses.replace(
        sub, order=order, labels=tuple(labels[i] for i in order), basis_labels=tuple(labels),
        scores=scores, **{k: pad(getattr(sub, k)) for k in (
            "mi", "gain", "margin", "mi_low", "mi_high", "gain_low", "gain_high",
            "margin_low", "margin_high")})


def _cumulative_mi(est: Any, contrib: np.ndarray, order: np.ndarray) -> np.ndarray:
    """MI of Phi_ref (already fitted) with the partial sums along ``order``.

    The sum of all M modes is Phi_ref itself, whose MI with itself is infinite for a
    continuous variable: that last entry is NaN (not estimated).
    """
    phi = np.zeros(contrib.shape[1])
    mi = np.full(order.size, np.nan)
    full = order.size == contrib.shape[0]
    for s, k in enumerate(order):
        if full and s == order.size - 1:
            break
        phi += contrib[k]
        mi[s] = float(est.score(phi))
    return mi


def _swapped_mi(est: Any, contrib: np.ndarray, order: np.ndarray,
                known: np.ndarray | None = None) -> np.ndarray:
    """MI had step s taken the next step's mode instead: I(Phi_ref; Phi_{s-1} + a_{s+1}).

    ``mi[s] - swapped[s]`` is the margin by which step s's mode beat the next one;
    NaN for the last step (no next mode). Entries of ``known`` that are not NaN (the
    greedy search's own scores of the same sums, bit for bit) are taken as they are.
    """
    phi = np.zeros(contrib.shape[1])
    out = np.full(order.size, np.nan)
    for s in range(order.size - 1):
        if known is not None and not np.isnan(known[s]):
            out[s] = known[s]
        else:
            out[s] = float(est.score(phi + contrib[order[s + 1]]))
        phi += contrib[order[s]]
    return out


def _lowest_tied(scores: np.ndarray, best: float) -> int:
    """Lowest index whose score is within :data:`_TIE_RTOL` of the best (NaN: not scored).

    Scores that differ by no more than their float error are a tie, and the lower index
    (the standard order) wins it, so that the last bits of a CPU's arithmetic cannot
    decide a greedy step (module notes).
    """
    tied = scores >= best - _TIE_RTOL * max(1.0, abs(best))  # NaN compares False
    return int(np.flatnonzero(tied)[0])


def _greedy(est: Any, contrib: np.ndarray, progress: Any = None, search: str = "auto",
            tolerance: float = _SCREEN_TOLERANCE
            ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Forward selection maximising I(Phi_ref; Phi_{S+k}); Phi_ref already fitted.

    ``"exhaustive"`` scores every remaining mode at every step, in index order.
    ``"screened"`` scores every mode at step 1 (the marginal scores are part of the
    result); at a later step it takes the remaining modes in descending *key* and
    scores them exactly until the next key, times ``1 + tolerance``, is below the key
    of the best mode scored at this step. Either way the step's mode is the best exact
    score among those scored (scores within ``_TIE_RTOL * max(1, |best|)`` of the best:
    the lower index, :func:`_lowest_tied`). The key of mode k is its
    variance share in the Gaussian closed form: for jointly Gaussian, mutually
    orthogonal contributions the gain of adding k to S is ``g = -ln(1 - v_k / R_S) / 2``
    with ``v_k`` the variance of ``a_k Z_k`` and ``R_S`` that of ``Phi_ref - Phi_S``,
    so ``R_S (1 - exp(-2 g)) = v_k`` whatever S is. The key starts at ``v_k`` on the
    samples and becomes ``R_S (1 - exp(-2 g))`` of the estimated gain each time k is
    scored. It is not a bound of the histogram gain: module notes for where the two
    searches may differ. With ``_EXHAUSTIVE_TAIL`` or fewer modes left, every one is
    scored.

    Returns
    -------
    order, mi : numpy.ndarray, shape (M,)
        The order and I(Phi_ref; Phi_s) along it (last entry NaN).
    first : numpy.ndarray, shape (M,)
        Step-1 scores I(Phi_ref; a_k Z_k).
    swapped : numpy.ndarray, shape (M,)
        Step s's score of the mode chosen at step s + 1 when it was scored, else NaN
        (for :func:`_swapped_mi`).
    """
    n_modes, n_samples = contrib.shape
    if search == "auto":
        search = "exhaustive" if n_modes <= _EXHAUSTIVE_MAX_MODES else "screened"
    screened = search == "screened"
    key = np.empty(n_modes)
    if screened:
        kern.row_variances(contrib, key)
        seen = np.ones(n_modes)  # estimates averaged in each key (the first: v_k)
        ref = contrib.sum(axis=0)
        resid = np.empty(n_samples)
    remaining = np.ones(n_modes, dtype=bool)
    phi_s = np.zeros(n_samples)
    cand = np.empty(n_samples)
    order = np.empty(n_modes, dtype=np.int64)
    mi = np.empty(n_modes)
    first = np.empty(n_modes)
    swapped = np.full(n_modes, np.nan)
    now = np.full(n_modes, np.nan)  # scores of this step (NaN: not scored)
    before = np.full(n_modes, np.nan)  # scores of the previous step
    base = 0.0  # I(Phi_ref; Phi_S) of the current S
    for step in range(n_modes):
        left = np.flatnonzero(remaining)
        now, before = before, now
        now.fill(np.nan)
        if left.size == 1:
            # the last mode completes Phi_ref: I(Phi_ref; Phi_ref) is infinite, not estimated
            order[step] = left[0]
            mi[step] = np.nan
            if step == 0:
                first[left[0]] = np.nan
            else:
                swapped[step - 1] = before[left[0]]
            break
        best_k, best_v, best_key = -1, -np.inf, -np.inf
        screen = screened and step > 0 and left.size > _EXHAUSTIVE_TAIL
        if screen:
            np.subtract(ref, phi_s, out=resid)
            r_s = float(np.var(resid))
            left = left[np.argsort(-key[left], kind="stable")]
        for k in left:
            if screen:
                if best_k >= 0 and key[k] * (1.0 + tolerance) < best_key:
                    break  # every later key is smaller still
            np.add(phi_s, contrib[k], out=cand)
            v = float(est.score(cand))
            now[k] = v
            if step == 0:
                first[k] = v
            elif screen and v == v:  # a mode the estimator cannot score keeps its key
                seen[k] += 1
                key[k] += (r_s * -math.expm1(-2.0 * (v - base)) - key[k]) / seen[k]
            if v > best_v or (v == best_v and k < best_k):  # NaN never wins
                best_k, best_v = k, v
                best_key = key[k]
        if best_k < 0:
            raise ValueError(
                f"the MI estimator returned no finite score at greedy step {step + 1}; "
                "check `estimator_options`."
            )
        best_k = _lowest_tied(now, best_v)
        best_v = now[best_k]
        order[step] = best_k
        mi[step] = best_v
        if step > 0:
            swapped[step - 1] = before[best_k]
        base = best_v
        phi_s += contrib[best_k]
        remaining[best_k] = False
        if progress is not None:
            progress(1)
    return order, mi, first, swapped


def _bootstrap(
    est: Any,
    a: np.ndarray,
    matrix: np.ndarray,
    order: np.ndarray,
    *,
    frames: np.ndarray,
    pixels: np.ndarray,
    pooled: bool,
    n_resamples: int,
    block_length: int,
    rng: np.random.Generator,
    progress: Any = None,
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """MI along ``order`` on bootstrap replicates: (mi, gain, margin), each (R, M).

    ``margin`` is ``mi`` minus :func:`_swapped_mi` on the replicate.

    Pooled: circular block bootstrap of the frames
    (:func:`~modalinfo.information.resampling.block_bootstrap_indices`), then the same
    number of samples drawn uniformly over (resampled frame, pixel) pairs. One frame:
    the sampled pixels resampled with replacement.
    """
    n_frames, n_valid = a.shape[0], matrix.shape[0]
    n_samples = frames.size
    mi = np.empty((n_resamples, order.size))
    margin = np.empty((n_resamples, order.size))
    for r in range(n_resamples):
        if pooled:
            boot = block_bootstrap_indices(n_frames, block_length, 1, rng, circular=True)[0]
            f = boot[rng.integers(0, n_frames, size=n_samples)].astype(np.int64)
            p = rng.integers(0, n_valid, size=n_samples).astype(np.int64)
        else:
            pick = rng.integers(0, n_samples, size=n_samples)
            f, p = frames[pick], pixels[pick]
        contrib = _contributions(a, matrix, f, p)
        est.fit(contrib.sum(axis=0))
        mi[r] = _cumulative_mi(est, contrib, order)
        margin[r] = mi[r] - _swapped_mi(est, contrib, order)
        if progress is not None:
            progress(1)
    gain = np.diff(mi, axis=1, prepend=0.0)
    return mi, gain, margin


def _pca_order(a: np.ndarray, labels: tuple[str, ...] | None = None) -> np.ndarray:
    """Descending eigenvalue order for coefficients that are uncorrelated; else raise.

    A pair (i, j) counts as uncorrelated when its normalised correlation is within
    ``max(_DECORRELATED_ATOL, _EIG_BACKWARD * eps * lambda_max / sqrt(lambda_i lambda_j))``:
    the eigensolver leaves off-diagonal terms of about ``eps lambda_max`` (its backward
    error), which a pair of small modes magnifies by ``lambda_max / sqrt(lambda_i
    lambda_j)`` (round 33 PART a, R3c: a data K-L over 12 decades was refused).
    """
    second = a.T @ a / a.shape[0]
    centred = a - a.mean(axis=0)
    cov = centred.T @ centred / a.shape[0]
    names = labels if labels is not None else tuple(f"mode{k + 1}" for k in range(a.shape[1]))

    def worst(m: np.ndarray) -> tuple[float, tuple[int, int, float, float] | None]:
        """(largest |c_ij| / tolerance_ij, that pair (i, j, |c_ij|, tolerance_ij))."""
        diag = np.diag(m)
        top = max(float(diag.max()), 1e-300)
        keep = np.flatnonzero(diag > 1e-12 * top)  # skip numerically empty modes
        if keep.size < 2:
            return 0.0, None
        d = np.sqrt(diag[keep])
        c = np.abs(m[np.ix_(keep, keep)] / np.outer(d, d))
        np.fill_diagonal(c, 0.0)
        tol = np.maximum(_DECORRELATED_ATOL,
                         _EIG_BACKWARD * np.finfo(float).eps * top / np.outer(d, d))
        ratio = c / tol
        i, j = np.unravel_index(int(np.argmax(ratio)), ratio.shape)
        return float(ratio[i, j]), (int(keep[i]), int(keep[j]), float(c[i, j]),
                                    float(tol[i, j]))

    if worst(second)[0] <= 1.0:
        return np.argsort(-np.diag(second), kind="stable")
    ratio, pair = worst(cov)
    if ratio <= 1.0:
        return np.argsort(-np.diag(cov), kind="stable")
    i, j, value, tol = pair  # ratio > 1: a pair exists
    raise ValueError(
        "`method`='pca' orders an empirical K-L basis of the same log (coefficients "
        f"uncorrelated to rounding); this basis's modes {names[i]} and {names[j]} have "
        f"|correlation| {value:.3g} > the tolerance {tol:.3g} of that pair. Use "
        "KLBasis.from_data(zbasis, coeffs) as the basis, or method='variance'."
    )


def _check_estimator_options(estimator_options: Any) -> dict:
    """Return a copy of ``estimator_options`` (None: empty) after checking it is a dict."""
    if estimator_options is None:
        return {}
    if not isinstance(estimator_options, dict):
        raise TypeError(
            f"`estimator_options` must be a dict or None; got {type(estimator_options).__name__}."
        )
    return dict(estimator_options)


def _check_common(method, estimator_options, n_resamples, confidence_level, block_length):
    check_choice(method, "method", METHODS)
    options = _check_estimator_options(estimator_options)
    confidence_level = check_real(
        confidence_level, "confidence_level", minimum=0.0, maximum=1.0, strict_min=True,
        strict_max=True,
    )
    if n_resamples is None:
        # the fewest whose percentile bounds have a replicate beyond each (the rule of
        # mutual_information_ci): 40 at 95 %; the former 20 had none (issue 27)
        n_resamples = least_tail_replicates(confidence_level)
    n_resamples = check_int(n_resamples, "n_resamples", minimum=0)
    if block_length is not None and not (isinstance(block_length, str)
                                         and block_length == "auto"):
        block_length = check_int(block_length, "block_length", minimum=1)
    return options, n_resamples, confidence_level, block_length


#: :func:`order_modes` arguments that act on the MI methods only: the others estimate
#: nothing, draw no samples and have no gains to bootstrap; and ``seeds`` of
#: :func:`~modalinfo.ordering.stability.ordering_stability`, whose seed comparison
#: compares the MI's subsamples (a method without MI gives one order for every seed)
MI_ONLY_ARGUMENTS = ("estimator", "sample_budget", "seed", "seeds", "n_resamples",
                     "estimator_options", "confidence_level", "block_length")
#: Bases :func:`order_modes`' ``"pca"`` cannot order: a model basis, not the K-L of the log
#: (names of :data:`modalinfo.ordering.compare.BASES`)
_NOT_DATA_KL = ("zernike", "kl-theory")


def refuse_unused_arguments(methods: Any, given: Any, *, basis: Any = None,
                            words: dict | None = None, chosen: str | None = None,
                            noun: str = "methods") -> None:
    """Refuse arguments none of ``methods`` uses, and ``"pca"`` on a model basis, before work.

    The one guard of ``reorder``, ``fitting-error`` and ``batch`` (round 13, 17 and 36
    PART b; round 37 PART b, B04 / B05 / B08 / B12: batch had none): an argument of
    :data:`MI_ONLY_ARGUMENTS` given where no method is an MI one was used by nothing and
    the user believed it applied; ``"pca"`` on ``"zernike"`` or ``"kl-theory"`` fails
    only after the work, with a remedy in Python terms.

    Parameters
    ----------
    methods : iterable of str
        The ordering methods that will run (one for ``order_modes``, several for
        ``compare_orderings``).
    given : iterable of str
        The arguments of :data:`MI_ONLY_ARGUMENTS` the caller set (not defaulted).
    basis : str or sequence of str, optional
        The basis name of a single method, or one basis per method (the ``basis:method``
        pairs of ``compare_orderings``, round 37 PART b leftover: a list was not
        checked); each ``"pca"`` is checked against its basis.
    words : dict, optional
        Library name (``"method"``, ``"basis"``, ``"orderings"`` or one of
        :data:`MI_ONLY_ARGUMENTS`) -> the caller's word for it (``"--resamples"``,
        ``"ordering.resamples"``); default the name between backticks, which
        ``modalinfo.cli.cli_words`` also rewrites.
    chosen : str, optional
        The methods as the caller named them (``"--method variance"``); default
        ``method 'variance'``.
    noun : str
        What the methods are called in the message (``"methods"``, ``"orderings"``).

    Raises
    ------
    ValueError
        Naming the first unused argument, or the pca on a model basis, and the remedy.
    """
    def say(name: str) -> str:
        return (words or {}).get(name, f"`{name}`")

    methods = [str(m) for m in methods]
    if not any(m.startswith("mi_") for m in methods):
        unused = [name for name in MI_ONLY_ARGUMENTS if name in set(given)]
        if unused:
            what = chosen if chosen is not None else f"{say('method')} {methods[0]!r}"
            raise ValueError(f"{say(unused[0])} applies to the MI {noun} (mi_greedy, "
                             f"mi_marginal); {what} uses none: drop it")
    if basis is None or isinstance(basis, str):
        if basis in _NOT_DATA_KL and "pca" in methods:
            raise _pca_on_a_model_basis(f"{say('method')} pca with {say('basis')} {basis}",
                                        basis, f"{say('basis')} kl-data",
                                        f"{say('method')} variance")
        return
    pairs = list(zip([str(b) for b in basis], methods, strict=True))
    wrong = next((b for b, m in pairs if m == "pca" and b in _NOT_DATA_KL), None)
    if wrong is not None:
        raise _pca_on_a_model_basis(f"{say('orderings')} {wrong}:pca", wrong, "kl-data:pca",
                                    f"{wrong}:variance")


def _pca_on_a_model_basis(given: str, basis: str, data_kl: str, variance: str) -> ValueError:
    """Return the one refusal of ``"pca"`` on a model basis, single or in a list (fold 40-a)."""
    return ValueError(f"{given}: pca orders an empirical K-L basis of the same log; {basis} "
                      f"is not one: use {data_kl}, or {variance}")


def _refuse_unused(method: str, options: dict, confidence_level: float,
                   block_length: Any) -> None:
    """Refuse ``order_modes``' own MI options for a method without MI (round 36 PART a).

    One guard with :func:`refuse_unused_arguments` (M4-M6).

    ``"standard"``, ``"variance"`` and ``"pca"`` estimate nothing: options the caller
    set (non-empty ``estimator_options``, a ``confidence_level`` other than the
    default, a ``block_length``) would be ignored and the defaults recorded.
    ``compare_orderings`` passes its MI options to the MI specs only.
    """
    values = {"estimator_options": options, "confidence_level": confidence_level,
              "block_length": block_length}
    given = [name for name, set_ in (("estimator_options", bool(options)),
                                     ("confidence_level", confidence_level != CONFIDENCE_LEVEL),
                                     ("block_length", block_length is not None)) if set_]
    refuse_unused_arguments([method], given, chosen=f"order_modes' method={method!r}",
                            words={name: f"`{name}`={values[name]!r}" for name in given})


def order_modes(
    log_or_coeffs: Any,
    basis: Any,
    method: str = "standard",
    *,
    estimator: Any = "histogram",
    estimator_options: dict | None = None,
    pooled: bool = True,
    frame: int | None = None,
    sample_budget: int = 200_000,
    seed: Any = None,
    n_resamples: int | None = None,
    confidence_level: float = CONFIDENCE_LEVEL,
    block_length: int | None = None,
    wavelength: float | None = None,
    progress: Any = None,
    search: str = "auto",
    max_seconds: float | None = MAX_ORDERING_SECONDS,
    quality: Any = True,
) -> OrderingResult:
    """Order the modes of a basis for a log.

    Parameters
    ----------
    log_or_coeffs : ModalLog or array_like, shape (T, M)
        A log (converted to radians; matched to the basis by Noll index; changed to
        K-L coefficients with the basis's change-of-basis matrix for a K-L basis; a
        log with ``convention="labels"`` holds the basis's own coefficients, matched to
        the basis's labels by name, a missing label refused) or coefficients of the
        basis's own modes [rad], in the basis's column order. The pooled MI bootstrap
        (``n_resamples > 0``) resamples blocks of consecutive frames, so a log whose
        timestamps have gaps raises ``ValueError`` (use ``log.longest_segment()``).
    basis : ModalBasis or array_like, shape (n_valid, M)
        The basis (or its mode matrix on the valid pupil pixels).
    method : {"standard", "variance", "pca", "mi_marginal", "mi_greedy"}
        Ordering rule (see the module docstring).
    estimator : str or object
        MI estimator: a ``modalinfo.information`` method name ("histogram", "kde",
        "ksg", "gaussian") or an object with ``fit(x)`` and ``score(y)``.
    estimator_options : dict, optional
        Keyword options of the estimator (e.g. ``{"bins": 64}``).
    pooled : bool
        Pool the samples over every frame (default). ``False`` asks for a per-frame
        ordering and needs ``frame``; giving ``frame`` alone is enough.
    frame : int, optional
        Per-frame ordering on this frame's pixels (the paper's "typical wavefront
        representation"); None pools every frame. For ``"variance"`` the frame's
        squared coefficients are used. Not allowed with ``"pca"``.
    sample_budget : int
        Number of (frame, pixel) samples for the MI methods (all pairs if fewer).
    seed : None, int or numpy.random.Generator
        Seed of the subsampling and the bootstrap.
    n_resamples : int or None
        Bootstrap replicates for the MI, gain and margin bounds (0: none). ``None``
        (default): the fewest whose percentile bounds at ``confidence_level`` have a
        replicate beyond each, ``2 / (1 - confidence_level)`` rounded up
        (:func:`~modalinfo.information.resampling.least_tail_replicates`, the rule of
        ``mutual_information_ci``): 40 at 95 %. Fewer are accepted (a quick look), but
        their bounds are (nearly) the extreme replicates: they hold a new replicate with
        probability ``(R - 1) / (R + 1)`` at most, whatever the level (``reorder``
        cautions below the rule). Each replicate costs M estimates.
    confidence_level : float
        Level of the bounds, in (0, 1).
    block_length : int, "auto" or None
        Block length [frames] of the pooled bootstrap, in ``[1, T]``; ``None``/``"auto"``
        (default): the Politis-White length of the most persistent coefficient
        (:func:`~modalinfo.information.resampling.resolve_block_length`, the rule of
        every block bootstrap of the package). ``estimator_options``,
        ``confidence_level`` and ``block_length`` act on the MI methods only: set (a
        non-empty dict, a level other than the default, a length) with ``"standard"``,
        ``"variance"`` or ``"pca"`` they are refused (ValueError naming them).
    wavelength : float, optional
        Wavelength [m] to convert a log in nm or um that carries none.
    progress : callable, optional
        For the MI methods, called as ``progress(1)`` after each estimated greedy step
        (``M - 1``; once with ``M - 1`` for ``"mi_marginal"``) and each bootstrap
        replicate: ``M - 1 + n_resamples`` in all (e.g. ``tqdm.update``).
    search : {"auto", "screened", "exhaustive"}
        How ``"mi_greedy"`` looks for each step's mode (module notes): ``"exhaustive"``
        scores every remaining mode at every step (M^2 / 2 scores); ``"screened"``
        scores every mode at step 1, then only the modes whose Gaussian variance-share
        key is within 5 % of the best scored at that step, and all of them in the last
        16 steps (a few per step: 2,000 modes x 1e5 frames in about a minute); not
        guaranteed to give the exhaustive order where modes are tied within the
        estimator's noise (module notes). ``"auto"`` is exhaustive up to 64 modes,
        screened above. Ignored by the other methods.
    max_seconds : float or None
        Most CPU seconds an MI ordering may be estimated to take (default 3600, the
        hour ``reorder`` and ``batch`` allow); ``None``: no limit. The estimate is
        ``modalinfo.ordering.cost.least_ordering_seconds`` of the estimator,
        samples, modes and replicates (the command line's), made before any work;
        above 60 s an ``OrderingCostWarning`` (a ``UserWarning``) names it and how to
        shorten it.
    quality : bool or QualityReport
        Whether a pooled ordering of the log's values (every method but ``"standard"``,
        ``frame`` None) runs :func:`~modalinfo.telemetry.assess_quality` on the
        coefficients it ranks (in the basis, labelled as the basis) and warns
        (``CalibrationEventWarning``) naming each mode, event and frame the pass's
        stationarity rules find (a mean step or drift, a spread step, an innovations'
        scale change: ``QualityReport.mode_events``): the pooled ranking then reflects
        the event as much as the turbulence (a +3 sd reference change of Z5 over 40 %
        of a log ranks Z5 first; adversarial round 52 PART a, L04-L39). Default True;
        False: no pass; a ``QualityReport`` of those coefficients (same frames and
        labels) is used instead of a new pass. The ordering itself is unchanged.
        Logs of fewer than ``CALIBRATION_MIN_FRAMES`` (2,000) frames are not warned:
        there a closed loop's own wander reads as steps. Measured false warnings on
        stationary logs: docs/ADVERSARIAL.md, "Calibration events inside a log
        (fix53-a)".

    Returns
    -------
    OrderingResult
        With bootstrap replicates, ``margin`` and its bounds tell which adjacent
        ranks are ties (:attr:`OrderingResult.tied_with_previous`).

    Raises
    ------
    ValueError
        On an unknown method, mismatched shapes, a bad frame index, ``"pca"`` on a
        basis in which the coefficients are correlated, an MI ordering estimated
        above ``max_seconds``, or one whose float64 contributions (M x n, three copies
        with replicates: ``modalinfo.ordering.cost.ordering_memory_bytes``) exceed the
        usable memory, before any work.
    TypeError
        On arguments of the wrong type.
    """
    options, n_resamples, confidence_level, block_length = _check_common(
        method, estimator_options, n_resamples, confidence_level, block_length
    )
    check_choice(search, "search", SEARCHES)
    if max_seconds is not None:
        max_seconds = check_real(max_seconds, "max_seconds", minimum=0.0, strict_min=True)
    # the estimator and its options are checked for every method, also those that do not
    # use them ("standard", "variance", "pca"): a misspelt name is refused, not ignored
    # (adversarial round 8, rows b03, b04)
    _make_estimator(estimator, options)
    _refuse_unused(method, options, confidence_level, block_length)
    if n_resamples > 0 and frame is None and str(method).startswith("mi_") and hasattr(
        log_or_coeffs, "sampling"
    ):
        from modalinfo.telemetry.sampling import require_contiguous

        require_contiguous(log_or_coeffs, "the block bootstrap of the MI gains (n_resamples > 0)")
    view = as_basis(basis)
    a = coefficients_in_basis(log_or_coeffs, view, wavelength=wavelength)
    n_frames, n_modes = a.shape
    if not isinstance(pooled, bool | np.bool_):
        raise TypeError(f"`pooled` must be a bool; got {pooled!r}.")
    if not pooled and frame is None:
        raise ValueError("`pooled`=False (a per-frame ordering) needs `frame`; got frame=None.")
    if frame is not None:
        frame = check_int(frame, "frame", minimum=-n_frames, maximum=n_frames - 1) % n_frames
    budget = check_int(sample_budget, "sample_budget", minimum=10)
    seed_value = seed_record(seed)
    rng = check_rng(seed)
    common = dict(basis_labels=view.labels, method=method, pooled=frame is None, frame=frame,
                  basis_key=basis_key(view.obj))

    def result(order: np.ndarray, **kw: Any) -> OrderingResult:
        order = np.asarray(order, dtype=np.int64)
        return OrderingResult(order=order, labels=tuple(view.labels[i] for i in order),
                              **common, **kw)

    if method == "standard":
        return result(view.standard_order())
    if frame is None and quality is not False:
        _warn_calibration_events(a, view.labels, method, quality)
    if method in ("variance", "pca"):
        if method == "pca" and frame is not None:
            raise ValueError(
                f"`frame` must be None for method='pca' (a PCA order is a property of the "
                f"whole log); got {frame}."
            )
        rows = a if frame is None else a[frame:frame + 1]
        mean_square = np.mean(rows * rows, axis=0)
        # equal mean squares keep the standard (Noll) order, not the file's column order
        std = view.standard_order()
        order = _pca_order(a, view.labels) if method == "pca" else std[
            np.argsort(-mean_square[std], kind="stable")]
        return result(order, scores=mean_square)

    def without(gone: np.ndarray) -> OrderingResult:
        # the same ordering of the other modes, the ``gone`` ones (bool (M,)) appended last
        live = np.flatnonzero(~gone)
        sub = order_modes(
            a[:, live], BasisView(matrix=view.matrix[:, live],
                                  labels=tuple(view.labels[i] for i in live), obj=None),
        method, estimator=estimator, estimator_options=options, pooled=pooled,
        frame=frame, sample_budget=budget, seed=seed, n_resamples=n_resamples,
        confidence_level=confidence_level, block_length=block_length, progress=progress,
        search=search, max_seconds=max_seconds, quality=False)
        return dataclasses.replace(_with_dead_modes(sub, live, np.flatnonzero(gone),
                                                    view.labels), basis_key=basis_key(view.obj))

    dead = _constant_modes(a if frame is None else a[frame:frame + 1], view.matrix)
    if dead.any() and not dead.all():
        # a dead mode (all zeros) or a constant piston makes the other modes' sum an
        # exact copy of the wavefront up to a constant: infinite MI, refused by the
        # estimators in their own words (`x`, `y`); ordered without them, appended last
        return without(dead)
    n_pairs = view.matrix.shape[0] * (n_frames if frame is None else 1)
    # memory first: what cannot be held is refused without a time warning before it
    _check_contribution_memory(min(budget, n_pairs), n_modes, n_resamples)
    _check_time(estimator, min(budget, n_pairs), n_modes, n_resamples, method, search,
                max_seconds)
    est, est_name = _make_estimator(estimator, options)
    if frame is None:
        _warn_envelope(a, view.matrix, method)
    frames, pixels = _draw_pairs(n_frames, view.matrix.shape[0], budget, rng, frame)
    contrib = _contributions(a, view.matrix, frames, pixels)
    est.fit(contrib.sum(axis=0))
    if est_name in PILE_BLIND_METHODS:
        # the nodal flags of the judged samples only (round 42 PART b, S02)
        _warn_piles(contrib, view.labels, est_name,
                    _nodal(view, pixels[::_pile_step(contrib.shape[1])]))
    try:
        return _scored(est, contrib, a, view, method, frame, progress, search, block_length,
                       n_resamples, confidence_level, rng, frames, pixels, result,
                       dict(estimator=est_name, estimator_options=options,
                            sample_budget=budget, n_samples=int(frames.size),
                            seed=seed_value, n_resamples=n_resamples,
                            confidence_level=confidence_level))
    except InfiniteMIError as exc:
        # a sum the search scored orders Phi_ref's samples exactly: the modes it lacks are
        # too small to matter (1e-11 rad beside 0.1 rad, above the 1e-12 constant rule);
        # ordered last as the dead modes above (adversarial round 6, rows r07, f06). Only
        # here, so that an ordering that never scores such a sum is unchanged.
        tiny = _numerically_dead(contrib)
        if not tiny.any():
            if str(exc).startswith("order_modes:"):  # a mode's, already named
                raise
            raise _named(exc, "a partial sum of the modes' contributions (a_k Z_k)") from exc
    return without(tiny)


#: The advice ending ``order_modes``' ``CalibrationEventWarning``, in the API's words (the
#: command line says it in its own: ``modalinfo.cli.cmd_reorder``, fix53-d).
CALIBRATION_ADVICE = ("order each stretch of steady conditions on its own (log.select), or "
                      "pass quality=False where the event is known and meant.")
#: The same advice for a command's user (the warning's ``cli_text``, which every command
#: prints: ``fitting-error`` and ``batch`` said "log.select" and "quality=False", options
#: they have not; round 55 PART b, C52 / C54 / C59 / C60).
CLI_CALIBRATION_ADVICE = ("order each stretch of steady conditions on its own (a log cut at "
                          "the event; `modalinfo batch --window-frames N` analyses "
                          "consecutive windows), or read the order as the pooled log's where "
                          "the event is known and meant.")


# CALIBRATION_LEVEL_P (1e-6, fix56-a) and CALIBRATION_MIN_FRAMES (2,000) moved to
# modalinfo.telemetry.quality with the events' rule (fix54-b: Predictor.fit names
# them too); imported above under the same names.


class SpatialEnvelopeWarning(UserWarning):
    """A pooled MI ordering that ranks the modes' spatial patterns more than their variances.

    :func:`order_modes` warns it where the pixel position tells more than twice as much
    about the pooled wavefront as the largest mode's variance share does
    (:func:`envelope_information`).
    """


#: :func:`order_modes` warns where the pixel's information exceeds this many times the
#: largest share's (:func:`envelope_information`). Measured: w1k 8.6x, the 200-mode case
#: 2.3-3.7x (2000 / 200 frames); the shipped logs 0.27-1.01x (kaos_like_closed_loop on
#: Zernikes 0.072 against 0.071 nats: comparable, not swamped; docs/ADVERSARIAL.md)
_ENVELOPE_RATIO = 2.0
#: Points per unit of ln|phi| of the mixture-entropy quadrature of
#: :func:`envelope_information` (a width-0.01 step: the integrand is smooth on that scale)
_ENVELOPE_STEPS = 100


def envelope_information(a: np.ndarray, matrix: np.ndarray) -> tuple[float, float]:
    """Information of the pixel position and of the largest variance share, Gaussian [nats].

    For zero-mean, mutually uncorrelated Gaussian coefficients ``a`` (T, M) [rad] on the
    modes ``matrix`` (n_valid, M), the wavefront at a pixel p drawn uniformly (the pooled
    samples) is Gaussian of variance ``V_p = sum_k <a_k^2> Z_k(p)^2`` given p: a scale
    mixture. ``I(Phi; p) = H(mixture) - mean_p ln(2 pi e V_p) / 2`` is what any mode's
    contribution ``a_k Z_k(p)`` can tell about Phi through the pixel alone (its spatial
    envelope), whatever its variance; ``-ln(1 - s) / 2`` is the MI that the largest
    variance share ``s = <a_k^2> mean(Z_k^2) / mean(V)`` gives a jointly Gaussian pair.

    Measured (fix53-e: 200 iid modes of sd 1 .. 1e-3 permuted, 40-pixel pupil, 2000
    frames, budget 2e5): the pooled MI of a mode of mean square 1e-6 is 0.030 +- 0.002
    nats by Monte Carlo on the exact mixture densities (the histogram estimate 0.025,
    sklearn's KSG 0.013 on 2e4 samples), above the 0.017 of a mode of share 3.4 %; the
    pixel's information there is 0.068 nats, the largest share's 0.035. For the paper's
    Kolmogorov logs (27 modes, Noll variances) they are 0.065 and 0.18 nats.

    Returns
    -------
    (float, float)
        ``I(Phi; p)`` and the largest share's Gaussian MI [nats]; NaN, NaN where the
        mixture is not defined (fewer than 2 modes, a pixel of zero variance).
    """
    ms = np.mean(a * a, axis=0)
    v = (matrix * matrix) @ ms
    if a.shape[1] < 2 or not np.all(v > 0) or not np.all(np.isfinite(v)):
        return float("nan"), float("nan")
    share = float(np.max(ms * np.mean(matrix * matrix, axis=0)) / np.mean(v))
    top = -0.5 * math.log1p(-share) if share < 1 else float("inf")
    # H(mixture) on |phi| = exp(t), on a grid from far inside the narrowest component to
    # 20 sd of the widest: -2 int f ln f dphi = -2 int f(e^t) ln f(e^t) e^t dt
    lo, hi = 0.5 * math.log(v.min()) - 8.0, 0.5 * math.log(v.max()) + 3.0
    t = np.linspace(lo, hi, int((hi - lo) * _ENVELOPE_STEPS) + 1)
    f = np.empty(t.size)
    norm = 1.0 / np.sqrt(2 * np.pi * v)
    for i in range(0, t.size, 256):  # (256, n_valid) at a time
        x2 = np.exp(2 * t[i:i + 256])[:, None]
        f[i:i + 256] = np.mean(norm * np.exp(-0.5 * x2 / v), axis=1)
    g = f * np.log(f, where=f > 0, out=np.zeros_like(f)) * np.exp(t)
    h_mix = -2.0 * float(np.sum((g[1:] + g[:-1]) * np.diff(t)) / 2)
    h_cond = float(np.mean(0.5 * np.log(2 * np.pi * np.e * v)))
    return max(h_mix - h_cond, 0.0), top


def _warn_envelope(a: np.ndarray, matrix: np.ndarray, method: str) -> None:
    """Warn (:class:`SpatialEnvelopeWarning`) where the pixel swamps every variance share.

    There a mode's pooled MI is mostly what its spatial pattern tells about the pixel
    (:func:`envelope_information`): the estimates are right (not the estimator's bias),
    but the order follows the patterns, not the variances (round 53 PART b, w1k: 1,000
    iid modes, top share 1/72, every score 0.035-0.045 nats, Z989 of mean square 4e-4
    first): above ``_ENVELOPE_RATIO`` times the largest share's information. The
    shipped logs are not warned (at most 1.01 x).
    """
    pixel, top = envelope_information(a, matrix)
    if pixel > _ENVELOPE_RATIO * top:
        warn(f"order_modes ({method}, pooled): the pixel position tells {pixel:.3g} nats "
             "about the pooled wavefront (for Gaussian modes), more than "
             f"{_ENVELOPE_RATIO:g} x the {top:.3g} nats of the largest mode's variance "
             "share: each mode's MI is then mostly what its spatial pattern tells of the "
             "pixel, and the order follows the patterns, not the variances (a mode of "
             "tiny variance can rank first); use method='variance' or 'pca' for the order "
             "of the variances.",
             SpatialEnvelopeWarning, stacklevel=caller_stacklevel())


def _warn_calibration_events(a: np.ndarray, labels: tuple, method: str,
                             quality: Any) -> None:
    """Warn where the quality pass finds an event in a mode a pooled ordering ranks.

    ``a`` (T, M): the coefficients ranked [rad], ``labels`` their basis labels;
    ``quality``: True (run :func:`~modalinfo.telemetry.assess_quality` on ``a``) or a
    report of ``a``. The events are the pass's (``QualityReport.mode_events``), the one
    detector of steps and drifts (fix53-a, issue 27).
    """
    from modalinfo.telemetry.quality import (
        CalibrationEventWarning,
        QualityReport,
        calibration_event_list,
        calibration_events,
    )

    if isinstance(quality, QualityReport):
        if (quality.n_frames, quality.n_modes) != a.shape or (
                list(quality.labels) != list(labels)):
            raise ValueError(
                f"`quality` must be the QualityReport of the coefficients ordered ({a.shape[0]} "
                f"frames, modes {', '.join(labels[:3])}{', ...' if len(labels) > 3 else ''}); "
                f"got one of {quality.n_frames} frames, modes "
                f"{', '.join(quality.labels[:3])}{', ...' if quality.n_modes > 3 else ''}.")
    elif not (quality is True or quality is np.True_):
        raise TypeError(f"`quality` must be True, False or a QualityReport; got {quality!r}.")
    # the floor is checked before the pass runs (its answer would not be used)
    events = calibration_events(a, quality if isinstance(quality, QualityReport) else None)
    if not events:
        return
    modes = sorted({j for j, *_ in events})
    head = f"order_modes ({method}): the quality pass"
    body = (f" finds a calibration event in {len(modes)} of the {a.shape[1]} modes ranked "
            f"({calibration_event_list(events, labels)}): the "
            "pooled ordering is that of the pooled log, in which the event (a new reference, "
            "a gain or unit change, modes re-mapped, the loop closing) weighs as much as the "
            "turbulence; ")
    warning = CalibrationEventWarning(head + " (assess_quality)" + body + CALIBRATION_ADVICE)
    warning.cli_text = head + body + CLI_CALIBRATION_ADVICE  # type: ignore[attr-defined]
    warn(warning, stacklevel=caller_stacklevel())


def _named(exc: InfiniteMIError, what: str) -> InfiniteMIError:
    """Return the estimator's refusal of a pair in order_modes' terms (same class).

    The estimators name their arguments `x` and `y`, which a caller of order_modes never
    passed (round 27 PART a, s-order): `x` is the total wavefront Phi_ref on the
    samples, `y` a mode's contribution or a partial sum.
    """
    text = str(exc).replace("`x`", "the total wavefront (Phi_ref)").replace("`y`", what)
    return type(exc)(f"order_modes: {text}")


def _marginal_score(est: Any, contrib: np.ndarray, k: int, labels: tuple) -> float:
    """I(Phi_ref; a_k Z_k) of mode k (est fitted to Phi_ref); a refusal names the mode."""
    try:
        return float(est.score(contrib[k]))
    except InfiniteMIError as exc:
        named = _named(exc, f"the contribution of {labels[k]} (a_k Z_k)")
        raise type(named)(f"{named} To order the other modes, give a basis without "
                          f"{labels[k]}.") from exc


def _check_time(estimator: Any, n: int, n_modes: int, n_resamples: int, method: str,
                search: str, max_seconds: float | None) -> None:
    """Refuse above ``max_seconds``, or warn above a minute, the estimated CPU of the work.

    One estimate for the library and the command line
    (``modalinfo.ordering.cost.least_ordering_seconds``, leftovers 13-cost: a
    1000-mode ordering ran for minutes with no word before), one rule
    (``cost.check_ordering_seconds``, shared with ``ordering_stability``).
    """
    seconds, calls = _cost.least_ordering_seconds(estimator, n, n_modes, n_resamples, 1, method,
                                            search)
    what = (f"order_modes({method!r}, estimator={estimator!r}) of {n_modes} modes on {n} "
            f"samples per estimate with {n_resamples} bootstrap replicates (at least "
            f"{calls} MI estimates) {_cost.seconds_text(seconds)}")
    _cost.check_ordering_seconds(seconds, what, ORDERING_HOW, max_seconds, stacklevel=3)


def _check_contribution_memory(n: int, n_modes: int, n_resamples: int) -> None:
    """Refuse, before they are gathered, contributions that cannot fit in memory.

    ``cost.ordering_memory_bytes`` (the command line's estimate, one copy) against
    ``modalinfo.common.memory.usable_memory_bytes`` (leftovers 14-misc: 1000 modes x
    2e5 samples make 1.6 GB, gathered with no check in the library).
    """
    need = _cost.ordering_memory_bytes(n_modes, n, n_resamples)
    if need < 2**27:  # below 128 MiB nothing is read, as check_memory
        return
    from modalinfo.common import memory

    usable = memory.usable_memory_bytes()
    if need > usable:
        copies = "3 copies: the ordering's and two replicates'" if n_resamples > 0 else "1 copy"
        raise ValueError(
            f"an MI ordering of {n_modes} modes on {n} samples per estimate needs about "
            f"{need / 2**30:.3g} GiB for its float64 contributions ({copies}) and "
            f"{usable / 2**30:.3g} GiB is usable; use a smaller `sample_budget` or fewer "
            "modes" + (", or `n_resamples`=0" if n_resamples > 0 else "") + ".")


def _scored(est: Any, contrib: np.ndarray, a: np.ndarray, view: Any, method: str,
            frame: int | None, progress: Any, search: str, block_length: Any,
            n_resamples: int, confidence_level: float, rng: np.random.Generator,
            frames: np.ndarray, pixels: np.ndarray, result: Any, info: dict) -> OrderingResult:
    """Order by MI (:func:`order_modes`, the rest) once ``est`` is fitted to Phi_ref."""
    n_modes = contrib.shape[0]
    if method == "mi_greedy":
        order, mi, scores, known = _greedy(est, contrib, progress, search)
    else:
        scores = np.array([_marginal_score(est, contrib, k, view.labels) if n_modes > 1
                           else np.nan for k in range(n_modes)])
        order = np.argsort(-scores, kind="stable")
        mi = _cumulative_mi(est, contrib, order)
        known = None
        if progress is not None:
            progress(n_modes - 1)
    gain = np.diff(mi, prepend=0.0)
    margin = mi - _swapped_mi(est, contrib, order, known)
    bounds: dict[str, Any] = {}
    # the one block-length rule of the package (resampling.resolve_block_length:
    # Politis-White of the most persistent coefficient); the former T^(1/3) frames
    # ignored the log's correlation time (59 frames at T = 2e5, where a closed-loop
    # mode of AR(1) 0.99 needs ~1000)
    blen = resolve_block_length(block_length, a) if frame is None else 1
    if n_resamples > 0:
        boot_mi, boot_gain, boot_margin = _bootstrap(
            est, a, view.matrix, order, frames=frames, pixels=pixels, pooled=frame is None,
            n_resamples=n_resamples, block_length=blen, rng=rng, progress=progress,
        )
        for name, boot in (("mi", boot_mi), ("gain", boot_gain), ("margin", boot_margin)):
            bounds[f"{name}_low"], bounds[f"{name}_high"] = percentile_bounds(
                boot, confidence_level)
    return result(
        order, mi=mi, gain=gain, margin=margin, scores=scores, **info,
        block_length=blen if frame is None else None, **bounds,
    )


def mi_along_order(
    log_or_coeffs: Any,
    basis: Any,
    order: Any = None,
    *,
    estimator: Any = "histogram",
    estimator_options: dict | None = None,
    frame: int | None = None,
    sample_budget: int = 200_000,
    seed: Any = None,
    wavelength: float | None = None,
) -> np.ndarray:
    """I(Phi_ref; Phi_n) [nats] for n = 1..M along any ordering (e.g. to compare orders).

    Parameters
    ----------
    log_or_coeffs, basis, estimator, estimator_options, frame, sample_budget, seed, wavelength
        As in :func:`order_modes`.
    order : array_like of int, OrderingResult or None
        Permutation of the basis modes (None: the basis's column order 0..M-1, e.g.
        of a basis reordered by :meth:`OrderingResult.apply`; not re-sorted by Noll
        index: ``order_modes(..., "standard")`` gives that order). An
        :class:`OrderingResult` is matched to the basis by mode label.

    Returns
    -------
    numpy.ndarray, shape (M,)
        I(Phi_ref; Phi_n) [nats] for n = 1..M. The last entry is NaN: Phi_M is Phi_ref
        itself, whose MI with itself is infinite for a continuous variable (not
        estimated, as in :func:`order_modes`); so are the steps of constant modes.
    """
    from modalinfo.ordering.fitting_error import check_order

    options = _check_estimator_options(estimator_options)
    view = as_basis(basis)
    idx = check_order(order, view.n_modes, labels=view.labels, basis=view.obj)
    contrib = sample_contributions(log_or_coeffs, view, sample_budget=sample_budget,
                                   frame=frame, seed=seed, wavelength=wavelength)
    est, _ = _make_estimator(estimator, options)
    est.fit(contrib.sum(axis=0))
    return _cumulative_mi(est, contrib, idx)
