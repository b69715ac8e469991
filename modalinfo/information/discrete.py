"""Plug-in information of discrete data: the table rule every MI estimator shares.

The MI of two discrete variables is that of their contingency table (Cover & Thomas
2006, eq. 2.28). Where both variables take so few values that their table holds at
least :data:`DISCRETE_MIN_PER_CELL` samples per cell on average (``m_x m_y <= n / 10``),
the kde, ksg and gaussian engines return the Miller-Madow corrected plug-in MI of that
table (Miller 1955) instead of their continuous estimate: tied values share one kernel
centre or neighbour distance of zero, and a normal model of a binary pair is not its
table (the Gaussian MI of a binary symmetric channel with 10 % errors is 0.51 nats,
its table's 0.368: audit 9, row t14). The histogram engine bins such data into that
table already.
"""

from __future__ import annotations

import numpy as np

from modalinfo.information import _kernels as kern

__all__ = ["DISCRETE_MIN_PER_CELL", "PILE_BLIND_METHODS", "PILE_EDGE_SHARE", "PILE_INTERIOR_SHARE",
           "PILE_MIN_COUNT", "PILE_SHARED_SHARE", "REPEAT_BLIND_METHODS", "REPEAT_SHARE",
           "discrete_cmi", "discrete_levels", "discrete_mi",
           "discrete_pair_mi", "discrete_x_levels", "mi_from_counts", "pile_of", "pile_why",
           "repeated_rows_why", "shared_pile_value", "TIED_COPULA_METHODS",
           "TIED_TABLE_BLIND_METHODS", "tied_columns_why", "tied_table_why"]


def mi_from_counts(counts: np.ndarray, bias_correction: str = "miller-madow") -> float:
    """MI in nats of a joint count table, plug-in or Miller-Madow corrected.

    Parameters
    ----------
    counts : numpy.ndarray, shape (kx, ky), int64
        Joint histogram.
    bias_correction : {"miller-madow", "none"}
        Correction applied to the plug-in value.

    Returns
    -------
    float
        Mutual information [nats].
    """
    out = np.empty(4)
    kern.plugin_mi_from_counts(np.ascontiguousarray(counts, dtype=np.int64), out)
    mi = out[0]
    if bias_correction == "miller-madow":
        n = float(counts.sum())
        mi -= (out[1] - out[2] - out[3] + 1.0) / (2.0 * n)
    return float(mi)


#: Least mean number of samples per cell of the contingency table of two discrete
#: variables for the discrete plug-in estimate of the kde, ksg and gaussian engines.
DISCRETE_MIN_PER_CELL = 10


def _groups(values: np.ndarray, tol: float) -> np.ndarray:
    """Group index of each sorted distinct value: a new group after each gap > ``tol``.

    Gaps and ``tol`` are halves (exact in binary): a full gap between values near the
    largest float overflows (``entropy`` of 1.7e308 tanh(x) warned, CI of stop 51).
    """
    out = np.zeros(values.size, dtype=np.int64)
    np.cumsum(np.diff(0.5 * values) > tol, out=out[1:])
    return out


def discrete_levels(x: np.ndarray, max_levels: int, rtol: float = 0.0
                    ) -> tuple[np.ndarray, int] | None:
    """Codes (n,) int64 of the distinct values of x and their number, if <= max_levels.

    None when x has more than ``max_levels`` distinct values (or ``max_levels`` < 2).
    Any ``max_levels + 1`` samples with that many distinct values prove it, so a
    continuous sample is rejected after sorting its first ``max_levels + 1`` values.
    ``rtol`` > 0: sorted values less than ``rtol`` times the range apart count as one
    (a level written by a float function carries rounding jitter: ``cos`` of a line at a
    quarter of the rate gave 15,295 distinct values of 20,000 for 4 levels, round 41
    PART a, V19).
    """
    if max_levels < 2:
        return None
    # half the range times rtol, for _groups' half gaps (no overflow near the largest float)
    tol = rtol * float(0.5 * np.max(x) - 0.5 * np.min(x)) if rtol > 0 else 0.0
    head = np.unique(x[: max_levels + 1])
    if (head.size if tol == 0 else int(_groups(head, tol)[-1]) + 1) > max_levels:
        return None
    values, codes = np.unique(x, return_inverse=True)
    if tol > 0:
        group = _groups(values, tol)
        codes, n_values = group[codes], int(group[-1]) + 1
    else:
        n_values = values.size
    if n_values > max_levels:
        return None
    return codes.astype(np.int64, copy=False).ravel(), int(n_values)


def discrete_mi(cx: np.ndarray, mx: int, cy: np.ndarray, my: int) -> float:
    """Plug-in MI (nats) of two coded discrete samples, Miller-Madow corrected."""
    counts = np.bincount(cx * my + cy, minlength=mx * my).reshape(mx, my)
    return mi_from_counts(counts, "miller-madow")


def discrete_x_levels(x: np.ndarray) -> tuple[np.ndarray, int] | None:
    """Return :func:`discrete_levels` of a fixed x that may be one side of a discrete pair.

    y needs >= 2 levels and each cell >= :data:`DISCRETE_MIN_PER_CELL` samples, so x
    has at most ``n / 20`` of them.
    """
    return discrete_levels(x, x.shape[0] // (2 * DISCRETE_MIN_PER_CELL))


def discrete_pair_mi(x_levels: tuple[np.ndarray, int] | None, y: np.ndarray) -> float | None:
    """Return the Miller-Madow plug-in MI (nats) of a discrete pair's table, else None.

    ``x_levels`` from :func:`discrete_x_levels` (None: x is not discrete). The pair is
    discrete when y too has so few values that the table holds at least
    :data:`DISCRETE_MIN_PER_CELL` samples per cell (``m_x m_y <= n / 10``): the rule of
    the kde and ksg engines (kde module notes, "Discrete data").
    """
    if x_levels is None:
        return None
    cx, mx = x_levels
    y_levels = discrete_levels(y, y.shape[0] // (DISCRETE_MIN_PER_CELL * mx))
    return None if y_levels is None else discrete_mi(cx, mx, *y_levels)


def discrete_cmi(x, y, z) -> float | None:
    """Miller-Madow plug-in CMI (nats) of all-discrete (x, y, z), else None.

    The rule of the kde and ksg MI engines (kde module notes, "Discrete data") for the joint table:
    every column takes so few values that the table of (x, y, z) holds at least
    :data:`DISCRETE_MIN_PER_CELL` samples per cell on average; the CMI is then
    ``I(x; (y, z)) - I(x; z)`` of that table. Audit 9: the kernel resolves the atoms of
    discrete data and gave 0.958 nats for the transfer entropy of a binary channel
    (exact ln 2 - H(0.1) = 0.368) and 17.6 for a binary delayed copy (exact ln 2).
    """
    n = x.shape[0]
    budget = n // DISCRETE_MIN_PER_CELL
    codes = []
    cells = 1
    for group in (x, y, z):
        code, m = np.zeros(n, dtype=np.int64), 1
        for j in range(group.shape[1]):
            lv = discrete_levels(group[:, j], budget // cells)
            if lv is None:
                return None
            code, m, cells = code * lv[1] + lv[0], m * lv[1], cells * lv[1]
        codes.append((code, m))
    (cx, mx), (cy, my), (cz, mz) = codes
    return discrete_mi(cx, mx, cy * mz + cz, my * mz) - (discrete_mi(cx, mx, cz, mz)
                                                          if mz > 1 else 0.0)


# --- Piles: one value held by a share of an otherwise continuous sample (issue 27) ---
#
# A saturated, clipped or full-well-clipped variable, or one whose dropouts are written
# as 0.0, is neither continuous nor discrete: a continuum with atoms. Its exact MI is
# that of a mixed law (the atoms as cells beside the continuous density), which the KSG
# estimator (ties broken by tiny noise) stays close to and the kde, histogram and
# gaussian estimators miss. Measured (left27-piles, issue 27; exact MI by Gauss-Legendre
# quadrature of the interior and atom terms with scipy; Gaussian pairs, seeds 1-2;
# error = estimate - exact, nats; the worst of kde / histogram / gaussian; ksg's worst
# in brackets):
#
#   dropouts written as 0.0 in both variables (an interior atom, share p):
#     p       rho 0.5 n=2000  n=1e4   rho 0.9 n=2000  n=1e4    exact (rho 0.5 / 0.9)
#     0.25 %  -0.044          -0.027  -0.073          -0.055   0.161 / 0.846
#     0.5 %   -0.044          -0.038  -0.074          -0.074   0.175 / 0.858
#     1 %     -0.055          -0.066  -0.097          -0.068   0.198 / 0.878
#     2 %     -0.096          -0.101  -0.098          -0.084   0.239 / 0.912
#     5 %     -0.184          -0.193  -0.162          -0.166   0.335 / 0.987
#     10 %    -0.303          -0.320  -0.288          -0.250   0.455 / 1.072
#     20 %    -0.455          -0.473  -0.383          -0.385   0.615 / 1.165
#     40 %    -0.641          -0.631  -0.472          -0.469   0.759 / 1.171
#     (ksg within 0.050 everywhere; gaussian is the worst from 1 %: it cannot hold the
#     atom's H(p) that the shared dropouts add.) 60 % independent dropouts and 5 % in x
#     alone at rho 0.9: gaussian -0.108 and -0.074 (exact 0.749, 0.789).
#   clipped at +-k on both variables (two atoms at the sample's ends, total share p) and
#   full-well (one atom at the maximum, share p), rho 0.9 (rho 0.5: within 0.041 up to
#   40 %); the histogram's -0.03 to -0.06 at 1-10 % is its bias without a pile at rho
#   0.9 and n = 2000; from 15 % kde is the worst (it resolves each atom as a spike):
#     p       clip n=2000  n=1e4    full-well n=2000  n=1e4    exact (clip / full-well)
#     1 %     -0.054       -0.018   -0.054            -0.018   0.828 / 0.828
#     5 %     -0.046       -0.032   -0.056            -0.032   0.816 / 0.814
#     10 %    -0.041       +0.043   -0.046            +0.052   0.798 / 0.793
#     15 %    -0.057       +0.066   +0.070            +0.080   0.778 / 0.770
#     20 %    +0.051       +0.096   -0.062            +0.111   0.756 / 0.745
#     40 %    +0.193       +0.220   +0.227            +0.239   0.660 / 0.626
#     (ksg within 0.043 on all of these.)
#
#   dropouts written as 0.0 in one variable only, or in both at independent times
#   (atoms not shared; exact (1 - p) I and (1 - p)^2 I), rho 0.9 (rho 0.5: within 0.026),
#   the worst of the three, n = 2000 / 1e4, 2 seeds:
#     p       x only            both, independent     exact (x only / both)
#     1 %     -0.078 / -0.040   -0.087 / -0.044       0.822 / 0.814
#     3 %     -0.073 / -0.045   -0.079 / -0.059       0.805 / 0.781
#     5 %     -0.078 / -0.065   -0.097 / -0.100       0.789 / 0.749
#     10 %    -0.084 / -0.096   -0.144 / -0.143       0.747 / 0.673
#     (the histogram's -0.05 to -0.08 at n = 2000 is mostly its bias without a pile at
#     rho 0.9; gaussian is the worst from 5 %; ksg within 0.037.)
#
# The error passes max(0.05 nats, 10 %) (the project's tolerance) above 0.5 % for an
# atom shared by two variables (1 %: -0.066 for 0.198), above 3 % for an atom of its
# own inside a variable's range (5 %: -0.100 for 0.749) and above 10 % for the atoms
# at a variable's ends (15 %: +0.080 for 0.770): :data:`PILE_SHARED_SHARE`,
# :data:`PILE_INTERIOR_SHARE`, :data:`PILE_EDGE_SHARE`. Rounded and integer data (many
# repeated values, no continuum beside them) are not piles: round 27 found them within
# 10 % of the exact MI for every estimator.
#
# Below n = 2000 (left28-misc; the worst of kde / histogram / gaussian, 4 seeds x 3
# methods per cell, "beyond" = outside max(0.05 nats, 10 %) of the exact MI):
#   - no pile, rho 0.9: already 1-3 of 12 beyond at n = 300 / 500 / 1000 (the
#     histogram's bias, -0.10 to -0.125); rho 0.5: 0 of 12. The lines cannot separate
#     finer than that.
#   - shared dropouts, rho 0.5 (none: 0 of 12): 0.5 % gives 4 / 7 / 2 of 12 beyond at
#     n = 300 / 500 / 1000 (-0.084 / -0.065 / -0.052), 1 % 5 / 10 / 7, 2 % 11-12 of 12.
#     :data:`PILE_MIN_COUNT` (5 samples) lifts the shared line to 5 / n there (1.7 % at
#     300, 1 % at 500, just above 0.5 % at 1000), so 2-4 shared samples at n <= 500
#     are silent while they already cost 0.06-0.10 nats (left: a lower count for a
#     shared atom would also count the coincident zeros of logs started at rest).
#   - one atom inside x (rho 0.9, none: 1-3 of 12): 1-3 %: 1-5 of 12, 5 %: 2-5, 10 %:
#     2-7 (named from 3 %); rho 0.5: at most 1 of 12. The interior line is where the
#     errors start to exceed the sampling error, as at n = 2000.
#   - clip at both ends (rho 0.9, total 5-20 %): 0-3 of 12 beyond at every share, the
#     same as without a pile (the histogram's bias); rho 0.5: 0 of 12. The ends line
#     (10 %) names piles that cost nothing beyond the sampling error at these n.
#   - conditional MI (x, y, z Gaussian, partial correlation 0.8, exact (1 - p) I or
#     H(p) + (1 - p) I): one atom in x, 1-3 %: as without a pile (1-3 of 12), 5 %: 3-6
#     of 12 (named). An atom x and y share, z not: 0.5 % 2-3 of 9 beyond, 1 % 3-4, 2 %
#     8-9 (n = 1000 / 4000), the MI's shared line. An atom all three hold at once is
#     conditioned away (z reveals it: exact (1 - p) I): 0 of 36 beyond at 1-2 %, so
#     :func:`pile_why` does not count it (``given``). The transfer entropy (a CMI of
#     lagged columns) shares a frame's atom only across a run of such frames: not
#     measured apart.

#: Largest share of the samples two variables may hold together at one value each
#: (dropouts written as 0.0 in both at once) before the kde, histogram and gaussian
#: estimates are judged meaningless (module notes, "Piles": 1 % gave -0.066 nats).
PILE_SHARED_SHARE = 0.005
#: Largest share of the samples one value strictly inside an otherwise continuous
#: variable's range may hold (5 %: -0.100 nats for 0.749).
PILE_INTERIOR_SHARE = 0.03
#: Largest share the sample's minimum and maximum values together may hold (a clip,
#: saturation or full well; 15 %: kde +0.080 for 0.770).
PILE_EDGE_SHARE = 0.10
#: Fewest samples at one value that make a pile (a continuous sample of a few hundred
#: samples may repeat a value by rounding of its source).
PILE_MIN_COUNT = 5
#: The estimators the pile rule judges (ksg breaks ties with tiny noise and stays within
#: 0.05 nats of the exact MI of every pile measured).
PILE_BLIND_METHODS = frozenset({"kde", "histogram", "gaussian"})


def _atoms(a: np.ndarray) -> tuple[float, int, float, int] | None:
    """(inner value, its count, larger end value, count at both ends) of a continuum.

    None for a sample without a continuum (fewer than half of the samples outside the
    atoms, or fewer than 5 % of all, take a value of their own: rounded or discrete
    data) or too short. Counts
    below :data:`PILE_MIN_COUNT` are 0.
    """
    a = np.asarray(a, dtype=float).ravel()
    n = a.size
    if n < 2 * PILE_MIN_COUNT:
        return None
    values, counts = np.unique(a, return_counts=True)
    if values.size < 3:
        return None
    heavy = counts >= PILE_MIN_COUNT
    ends = [i for i in (0, values.size - 1) if heavy[i]]
    edge = int(counts[ends].sum()) if ends else 0
    j = 1 + int(np.argmax(counts[1:-1]))
    top = int(counts[j]) if heavy[j] else 0
    if np.count_nonzero(counts == 1) < max(0.5 * (n - edge - top), 0.05 * n, PILE_MIN_COUNT):
        return None  # rounded or discrete: repeated values everywhere, no continuum
    end = max(ends, key=lambda e: counts[e]) if ends else 0
    return float(values[j]), top, float(values[end]), edge


def pile_of(a: np.ndarray) -> tuple[float, float, str] | None:
    """Return the pile of a continuous 1-D sample: ``(value, share, where)`` or None.

    ``where`` is ``"inside"`` (the most frequent value strictly inside the sample's range
    holds more than :data:`PILE_INTERIOR_SHARE` of the samples, e.g. dropouts written
    as 0.0) or ``"ends"`` (its minimum and maximum values hold more than
    :data:`PILE_EDGE_SHARE` together, e.g. a clip or saturation; ``value`` is the
    larger of the two atoms, ``share`` their sum). None for a sample without such a
    pile and for a discrete or rounded sample: fewer than half of the samples outside
    the atoms (or fewer than 5 % of all) take a value of their own.
    """
    return _judge(a)[1]


def _judge(a: np.ndarray) -> tuple[tuple[float, int, float, int] | None,
                                   tuple[float, float, str] | None]:
    """``(_atoms(a), pile_of(a))``: the one copy of the single-variable pile rule."""
    atoms = _atoms(a)
    if atoms is None:
        return None, None
    inner, top, end, edge = atoms
    n = np.asarray(a).size
    if top > PILE_INTERIOR_SHARE * n:
        return atoms, (inner, top / n, "inside")
    if edge > PILE_EDGE_SHARE * n:
        return atoms, (end, edge / n, "ends")
    return atoms, None


def shared_pile_value(a: np.ndarray) -> float | None:
    """Return the value a continuous sample holds often enough to share a pile, or None.

    The most frequent value strictly inside the range of a sample with a continuum
    (:func:`pile_of`'s conditions), where it holds more than :data:`PILE_SHARED_SHARE`
    of the samples: only then can :func:`pile_why`'s shared-atom rule fire on a pair
    that includes ``a`` (a caller with many pairs checks it once per variable).
    """
    atoms = _atoms(a)
    if atoms is None or not atoms[1] > PILE_SHARED_SHARE * np.asarray(a).size:
        return None
    return atoms[0]


def pile_why(columns: dict[str, np.ndarray], method: str,
             given: tuple[str, ...] = ()) -> str | None:
    """Why ``method``'s estimate on these columns is meaningless by the pile rule, or None.

    Parameters
    ----------
    columns : dict of str to ndarray, shape (n,)
        The variables by the names the caller gave them (``"x"``, ``"y"``, ``"z[:, 1]"``).
    method : str
        The estimator's name; only :data:`PILE_BLIND_METHODS` are judged.
    given : tuple of str
        The names of the conditioning columns of a conditional MI. The samples at which
        every column, these included, holds its pile (dropouts written as 0.0 in x, y
        and z at once) are not counted as a shared pile: the conditioning reveals the
        atom, whose entropy cancels from ``I(x; y | z)`` (exact ``(1 - p) I``), and the
        estimates stayed within the project's tolerance there (left28-misc: kde,
        histogram, gaussian, partial correlation 0.8, n = 1000 / 4000, 1-2 %: 0 of 36
        beyond, as without a pile; x and y alone sharing it: 24 of 36 beyond).

    Returns
    -------
    str or None
        The first piled column (or pair of columns sharing a pile), its value and
        share, and ``method='ksg'`` as the way out.
    """
    if method not in PILE_BLIND_METHODS:
        return None
    tail = (f"method={method!r} misses such a pile's information by more than "
            "max(0.05 nats, 10 %) (discrete module notes, \"Piles\"); use method='ksg'")
    inner = {}
    for name, a in columns.items():
        atoms, pile = _judge(a)
        if atoms is None:
            continue
        if pile is not None:
            value, share, where = pile
            if where == "inside":
                return (f"`{name}` holds {share:.1%} of its samples at {value:.6g}, inside "
                        "its range beside continuous values (dropouts written as a value?; "
                        f"more than {PILE_INTERIOR_SHARE:.1%}): {tail}")
            return (f"`{name}` holds {share:.1%} of its samples at its minimum or "
                    f"maximum (the larger pile at {value:.6g}) beside continuous values "
                    f"(clipped or saturated?; more than {PILE_EDGE_SHARE:.1%}): {tail}")
        value, top = atoms[0], atoms[1]
        if top > PILE_SHARED_SHARE * a.shape[0]:
            inner[name] = a == value
    names = list(inner)
    common = None  # an atom every column holds at once, conditioning columns included
    if given and len(inner) == len(columns):
        common = np.logical_and.reduce([inner[k] for k in names])
    for i, first in enumerate(names):
        for second in names[i + 1:]:
            both = inner[first] & inner[second]
            shared = np.count_nonzero(both if common is None else both & ~common)
            n = inner[first].size
            if shared > PILE_SHARED_SHARE * n:
                return (f"`{first}` and `{second}` hold {shared / n:.1%} of their samples "
                        f"together at one value each ({columns[first][inner[first]][0]:.6g}, "
                        f"{columns[second][inner[second]][0]:.6g}) beside continuous "
                        "values (dropouts written as a value in both?; more than "
                        f"{PILE_SHARED_SHARE:.1%}): {tail}")
    return None


#: The estimators that read rows repeated in every column as dependence: the nearest-
#: neighbour counts of ksg see a repeated row's twin (apart only by the ~1e-10 tie
#: noise) as its nearest neighbour in the joint space and in every margin at once.
REPEAT_BLIND_METHODS = frozenset({"ksg"})
#: Largest share of repeated rows let pass: measured bias of the KSG MI of Gaussian pairs
#: (n = 3000, 6 seeds; round 47 PART a) +0.009 / +0.016 / +0.047 nats at 1 / 2 / 5 % of
#: rows repeated (independent pair, sd 0.006-0.009), +0.018 / +0.023 / +0.048 at
#: rho = 0.8, +0.75 to +0.77 with every row doubled; at 1 % it is about one sd.
REPEAT_SHARE = 0.01


def repeated_rows_why(columns: dict[str, np.ndarray], method: str) -> str | None:
    """Why ``method``'s estimate on these columns is biased by repeated rows, or None.

    Rows repeated in every column at once, the columns tying nowhere else (each column
    has exactly as many distinct values as there are distinct rows) and fewer than
    :data:`DISCRETE_MIN_PER_CELL` rows per distinct row, each repeated row held fewer
    times than that (a row held more often is an atom, a shared pile): duplicated frames, a logger
    re-sending samples, a series resampled to a multiple of its rate. Rounded data tie
    within a column across different rows, and a discrete variable (with its copy) has
    at least that many samples per value, whose MI the estimators hold (ksg module notes,
    "Ties" and "Discrete pairs"): neither is judged. Only
    :data:`REPEAT_BLIND_METHODS` are judged, above :data:`REPEAT_SHARE` of the rows.

    Parameters
    ----------
    columns : dict of str to ndarray, shape (n,)
        The variables by the names the caller gave them.
    method : str
        The estimator's name.

    Returns
    -------
    str or None
        The count and share of repeated rows, the measured bias and the ways out.
    """
    if method not in REPEAT_BLIND_METHODS or not columns:
        return None
    cols = list(columns.values())
    n = cols[0].shape[0]
    first = np.unique(cols[0]).size
    if n - first <= REPEAT_SHARE * n:  # a cheap bound: repeated rows repeat every column
        return None
    counts = np.unique(np.column_stack(cols), axis=0, return_counts=True)[1]
    distinct = counts.size
    # a row held DISCRETE_MIN_PER_CELL times or more is an atom (dropouts written as 0.0
    # in every column: the pile rule's, within ksg's tolerance), not a duplicated frame
    repeats = int(np.sum(counts[counts < DISCRETE_MIN_PER_CELL] - 1))
    if (repeats <= REPEAT_SHARE * n or n >= DISCRETE_MIN_PER_CELL * distinct
            or first != distinct or any(np.unique(c).size != distinct for c in cols[1:])):
        return None  # few repeats, a discrete variable (and its copy), or rounding
    names = ", ".join(f"`{k}`" for k in columns)
    return (f"{repeats} of the {n} rows of {names} ({repeats / n:.1%}) repeat an earlier "
            "row in every column, the columns tying nowhere else (duplicated frames?; more "
            f"than {REPEAT_SHARE:.0%}): method={method!r} takes a repeated row's twin for its "
            "nearest neighbour in every variable, which reads as dependence (Gaussian pairs, "
            "n = 3000: about +0.01 nats per % of rows repeated, +0.77 with every row "
            "doubled); drop the repeated rows (numpy.unique(rows, axis=0)) or use "
            "method='kde', 'histogram' or 'gaussian'")


#: The estimators whose CMI resolves the atoms of all-discrete columns whose joint table
#: is too sparse for the plug-in (:func:`discrete_cmi`): the kernel of ``kde`` sits on
#: the tied normal scores (round 51 PART a, Q54).
TIED_TABLE_BLIND_METHODS = frozenset({"kde"})


def tied_table_why(columns: dict[str, np.ndarray], method: str) -> str | None:
    """Where ``method``'s CMI of all-discrete columns with a sparse table may be off, or None.

    Every column discrete (:func:`discrete_x_levels`: at most ``n / 20`` distinct values)
    but the product of their level counts above ``n / DISCRETE_MIN_PER_CELL``, so the
    table rule of :func:`discrete_cmi` does not apply and the kernel estimate is taken on
    tied normal scores: a set of atoms that the kernel resolves where they are few and
    far apart against its width, as the kde module notes say of the MI ("Discrete
    data"). Measured (round 51 PART a, 5 seeds): the transfer entropy of
    ``y_t = x_(t-1) + Poisson(1)``, x ~ Poisson(2) iid, T = 4,001 (exact H(Poisson 3) -
    H(Poisson 1) = 0.627 nats; 1,296 cells, ~3 per cell): kde 0.886 (+0.26, 41 %), ksg
    0.613, histogram 0.575; at T = 20,001 the table rule applies and every method reads
    the plug-in 0.63. With more levels the kernel smooths the atoms (Poisson(8) and
    Poisson(30) counts: kde within 0.04 of the exact TE), so the caller judges the value
    against the KSG (``conditional._tied_table_check``). Only
    :data:`TIED_TABLE_BLIND_METHODS` are judged.

    Parameters
    ----------
    columns : dict of str to ndarray, shape (n,)
        The variables (x, y and z's columns) by the names the caller gave them.
    method : str
        The estimator's name.

    Returns
    -------
    str or None
        The levels and the cells per sample.
    """
    if method not in TIED_TABLE_BLIND_METHODS or len(columns) < 2:
        return None
    n = next(iter(columns.values())).shape[0]
    levels = []
    for col in columns.values():
        found = discrete_x_levels(col)
        if found is None:
            return None
        levels.append(found[1])
    cells = float(np.prod(np.asarray(levels, dtype=float)))
    if cells * DISCRETE_MIN_PER_CELL <= n:
        return None  # the plug-in table's case (discrete_cmi)
    names = ", ".join(f"`{k}` {m}" for k, m in zip(columns, levels, strict=True))
    return (f"every column is discrete (levels: {names}) but their table has {cells:.3g} "
            f"cells for n = {n}, {n / cells:.2g} samples per cell, under the "
            f"{DISCRETE_MIN_PER_CELL} of the plug-in table, so method={method!r} smooths "
            "tied normal scores, whose atoms its kernel may resolve")


def named_columns(x: np.ndarray, y: np.ndarray, z: np.ndarray) -> dict[str, np.ndarray]:
    """Return the columns of (x, y, z) by the names a message gives them (``x``, ``z[:, 1]``)."""
    out = {}
    for name, group in (("x", x), ("y", y), ("z", z)):
        for j in range(group.shape[1]):
            out[name if group.shape[1] == 1 else f"{name}[:, {j}]"] = group[:, j]
    return out


#: The estimators whose value of a discrete column beside others is the Gaussian model of
#: its tied normal scores, not the column's law (round 51 PART a, Q28 / Q56).
TIED_COPULA_METHODS = frozenset({"gaussian"})


def tied_columns_why(columns: dict[str, np.ndarray], method: str,
                     copula: bool = True) -> str | None:
    """Where ``method``'s (Gaussian-copula) value of columns with a discrete one may be off.

    The rule of :func:`tied_table_why` for one column: a column is discrete where it
    holds at most ``n / 20`` distinct values (:func:`discrete_x_levels`); None where
    none is, or where every column is and their table takes the plug-in
    (:func:`discrete_cmi`: the engines return the table's value). A discrete column's
    normal scores are a few tied values, and the Gaussian model of them is the
    correlation of a coarsened normal, not the column's law: the gaussian MI of a
    5-level categorical x through ``x + N(0, 0.7^2)`` reads 0.541 for the exact 0.634,
    the gaussian transfer entropy of Poisson counts 0.537 for 0.627 (round 51 PART a,
    5 seeds each, s.e. 0.002); where the levels are many or the dependence weak it is
    right (a Bernoulli(0.05) flag's 0.074 for 0.081; x rounded to 0.25 sd, 0.217 for
    0.222), so the caller judges the value against the KSG
    (``ksg.gaussian_ties_why``). Only :data:`TIED_COPULA_METHODS` are judged.

    Parameters
    ----------
    columns : dict of str to ndarray, shape (n,)
        The variables (x, y and z's columns) by the names the caller gave them.
    method : str
        The estimator's name.
    copula : bool
        Whether the method models the normal scores (True) or the values (False, the
        same rule: a normal model of a few levels is not their law either; fix54-c).

    Returns
    -------
    str or None
        The discrete columns and their levels.
    """
    if method not in TIED_COPULA_METHODS or len(columns) < 2:
        return None
    n = next(iter(columns.values())).shape[0]
    levels = {name: found[1] for name, col in columns.items()
              if (found := discrete_x_levels(np.ascontiguousarray(col))) is not None}
    if not levels:
        return None
    if len(levels) == len(columns) and (
            float(np.prod(np.asarray(list(levels.values()), dtype=float)))
            * DISCRETE_MIN_PER_CELL <= n):
        return None  # the plug-in table's case (discrete_cmi, discrete_pair_mi)
    names = ", ".join(f"`{k}` {m}" for k, m in levels.items())
    return (f"discrete column(s) (levels: {names}; at most n / "
            f"{2 * DISCRETE_MIN_PER_CELL} = {n // (2 * DISCRETE_MIN_PER_CELL)} distinct "
            f"values) whose {'tied normal scores' if copula else 'values'} "
            f"method={method!r}{'' if copula else ', copula=False'} models as a "
            f"{'coarsened ' if copula else ''}normal, not as the column's law")
