"""Karhunen-Loeve bases: theoretical (turbulence) and empirical (data PCA).

Both are orthonormal linear combinations of Noll Zernike modes,
``KL_k = sum_i zernike_from_kl[i, k] Z_{zernike_modes[i]}``, ordered by decreasing
variance. The theoretical K-L diagonalises the Kolmogorov / von Karman Zernike
covariance (Wang & Markey 1978; Dai 1995, JOSA A 12, 2182); the empirical K-L
diagonalises the second-moment matrix of a log's own Zernike coefficients.
"""

from __future__ import annotations

import numbers

import numpy as np

from modalinfo.bases import _kernels
from modalinfo.bases.basis import ModalBasis
from modalinfo.bases.indexing import noll_to_zernike
from modalinfo.bases.pupil import Pupil
from modalinfo.bases.turbulence import (
    _angular_keys,
    _check_modes,
    _check_scales,
    _covariance_blocks,
)
from modalinfo.bases.zernike import ZernikeBasis, _parse_modes, check_zernike_sampling
from modalinfo.common.memory import free_memory_bytes
from modalinfo.common.records import float_digest
from modalinfo.common.validation import (
    as_float_array,
    check_int,
    check_square_floor,
    check_square_range,
)

__all__ = ["KLBasis", "default_zernike_modes"]


#: Largest K-L mode count: 10^6 modes need 3 x 10^6 Zernikes, whose covariance alone
#: is 72 TB of float64, far beyond any machine (a pupil of 16 pixels holds ~200 modes)
MAX_KL_MODES = 10**6


def default_zernike_modes(n_modes: int) -> np.ndarray:
    """Zernike set used by :meth:`KLBasis.from_turbulence` when none is given.

    Noll ``j = 2 .. J`` where ``J`` closes the smallest complete radial order with at
    least ``3 * n_modes`` modes after piston. Complete orders keep the set rotation
    invariant (cos/sin pairs stay degenerate); three Zernikes per K-L mode converge every
    kept K-L variance to better than 5e-3 relative (1e-4 for ``n_modes >= 27``; with
    twice as many the last modes are 2-10% off), measured against 1325 Zernikes.

    Parameters
    ----------
    n_modes : int
        Number of K-L modes wanted, ``>= 1``.

    Returns
    -------
    numpy.ndarray
        Noll indices ``2..J``.
    """
    # at most MAX_KL_MODES: 2**70 spun in the loop below (2^35 steps) instead of refusing
    n_modes = check_int(n_modes, "n_modes", minimum=1, maximum=MAX_KL_MODES)
    n = 1
    while (n + 1) * (n + 2) // 2 - 1 < 3 * n_modes:
        n += 1
    return np.arange(2, (n + 1) * (n + 2) // 2 + 1, dtype=np.int64)


def _combination_matrix(pupil: Pupil, modes: np.ndarray, change: np.ndarray) -> np.ndarray:
    """Pixel matrix ``Z @ change`` without forming ``Z`` (fused numba kernel, sparse)."""
    n, m = noll_to_zernike(modes)
    nonzero = change != 0
    counts = nonzero.sum(axis=0)
    indptr = np.concatenate([[0], np.cumsum(counts)]).astype(np.int64)
    rows, cols = np.nonzero(nonzero.T)  # column-major order of the non-zeros
    indices = np.ascontiguousarray(cols, dtype=np.int64)
    weights = np.ascontiguousarray(change.T[rows, cols])
    out = np.empty((pupil.n_valid, change.shape[1]))
    # cos and sin from the pixels' x and y, exact mirrors at mirror pixels: a K-L mode's
    # values at pixels mirrored by the pupil's symmetries tie bit for bit, whatever the
    # eigenvectors' last bits (LAPACK's kernels differ across CPUs), so the ties of the
    # rank-based MI estimators are the same on every CPU (docs/TESTING.md, golden numbers)
    cos_t, sin_t = pupil.direction_cosines()
    _kernels.zernike_combination_matrix(
        pupil.rho_valid, cos_t, sin_t, np.ascontiguousarray(n), np.ascontiguousarray(m),
        indptr, indices, weights, out,
    )
    return out


def _fix_signs(vectors: np.ndarray) -> np.ndarray:
    """Make the largest-magnitude entry of every column positive (deterministic signs)."""
    idx = np.argmax(np.abs(vectors), axis=0)
    signs = np.sign(vectors[idx, np.arange(vectors.shape[1])])
    signs[signs == 0] = 1.0
    return vectors * signs


def _eig_by_symmetry(cov: np.ndarray, modes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Eigen-decompose a turbulence covariance block by block.

    Turbulence couples only Zernikes of the same |m| and angular function (cos, sin or
    m = 0), so the covariance is block diagonal after a permutation. Diagonalising each
    block keeps every K-L mode pure cos or pure sin, instead of an arbitrary rotation of
    the degenerate cos/sin pairs that a global ``eigh`` would return.
    """
    _, m = noll_to_zernike(modes)
    kind = np.where(m == 0, 0, np.where(modes % 2 == 0, 1, 2))  # 0: m=0, 1: cos, 2: sin
    keys = np.abs(m) * 3 + kind
    values = np.zeros(modes.size)
    vectors = np.zeros((modes.size, modes.size))
    col = 0
    for key in np.unique(keys):
        idx = np.flatnonzero(keys == key)
        w, v = np.linalg.eigh(cov[np.ix_(idx, idx)])
        values[col:col + idx.size] = w
        vectors[idx, col:col + idx.size] = v
        col += idx.size
    # decreasing variance; ties (cos/sin twins, equal to rounding) in the order cos, sin
    col_kind = kind[np.argmax(np.abs(vectors), axis=0)]
    order = _decreasing_order(values, col_kind)
    return values[order], vectors[:, order]


def _decreasing_order(values: np.ndarray, kinds: np.ndarray) -> np.ndarray:
    """Return the indices of ``values`` in decreasing order, ties (10 digits) by ``kinds``.

    Each value is rounded to 10 significant digits of its own magnitude (at least 1e-13
    of the largest: below, rounding noise), so that the cos / sin twins of one block,
    equal to rounding, stay a tie that ``kinds`` orders (cos first) whatever a CPU's last
    bits, while any two variances further apart keep their order. The former key,
    rounded to 1e-10 of the *largest* variance, merged K-L variances beyond ~900 modes
    (~5e-7 of 0.449) that differ by 4e-5 of their size and ordered them cos first,
    smaller first: 3 inversions at 1,000 modes, 37 at 2,000 (adversarial round 48 PART
    a, K01-K03).
    """
    mag = np.abs(values)
    top = mag.max() if values.size else 0.0
    mag = np.maximum(mag, 1e-13 * top if top > 0 else 1.0)
    quantum = 10.0 ** (np.floor(np.log10(mag)) - 9)
    rounded = np.round(values / quantum) * quantum
    return np.lexsort((kinds, -rounded))


def _eig_blocks(blocks: list[tuple[np.ndarray, np.ndarray]], modes: np.ndarray,
                n_keep: int) -> tuple[np.ndarray, np.ndarray]:
    """Return the ``n_keep`` leading K-L modes from the covariance blocks, signs fixed.

    The same eigen-decomposition, order and signs as :func:`_eig_by_symmetry` followed by
    :func:`_fix_signs` on the kept columns (bit for bit), without the dense ``(n_z, n_z)``
    covariance and eigenvector matrices: ``blocks`` are the ``(idx, block)`` pairs of
    ``turbulence._covariance_blocks`` in increasing key order, and only the kept columns
    are scattered into the ``(n_z, n_keep)`` result.

    Returns
    -------
    values : numpy.ndarray
        ``(n_keep,)`` decreasing variances.
    vectors : numpy.ndarray
        ``(n_z, n_keep)`` C-contiguous eigenvectors in the Zernike rows.
    """
    _, m = noll_to_zernike(modes)
    kind = _angular_keys(modes, m) % 3  # 0: m=0, 1: cos, 2: sin
    values, kinds, owners, columns = [], [], [], []
    solved: dict[bytes, tuple[np.ndarray, np.ndarray]] = {}
    for b, (idx, block) in enumerate(blocks):
        # the cos and sin blocks of one |m| are the same matrix over complete radial
        # orders: decompose it once (the same input gives the same eigh output)
        cache_key = block.tobytes()
        if cache_key not in solved:
            solved[cache_key] = np.linalg.eigh(block)
        w, v = solved[cache_key]
        values.append(w)
        # _fix_signs per column: the largest |entry| (first of ties) made positive; the
        # rows of a block ascend in idx, so "first" is the same as in the dense column
        signs = np.sign(v[np.argmax(np.abs(v), axis=0), np.arange(v.shape[1])])
        signs[signs == 0] = 1.0
        columns.append(v * signs)
        # every column of a block lives on the block's rows: its kind is the block's
        kinds.append(np.full(idx.size, kind[idx[0]]))
        owners.append(np.full(idx.size, b))
    values = np.concatenate(values)
    kinds = np.concatenate(kinds)
    owners = np.concatenate(owners)
    local = np.concatenate([np.arange(v.shape[1]) for v in columns])
    order = _decreasing_order(values, kinds)[:n_keep]
    out = np.zeros((modes.size, n_keep))
    kept_owner = owners[order]
    for b in np.unique(kept_owner):
        cols = np.flatnonzero(kept_owner == b)
        out[np.ix_(blocks[b][0], cols)] = columns[b][:, local[order[cols]]]
    return values[order], out


def _check_turbulence_memory(n_z: int, n_modes: int) -> None:
    """Refuse a theoretical K-L basis whose arrays would not fit in the free memory.

    Estimate [bytes]: the (n_z, n_modes) float64 eigenvectors plus the covariance
    blocks, one per azimuthal order and parity over the N ~ sqrt(2 n_z) radial orders,
    about N^3 / 6 entries in all. ``n_modes = 10**6`` (3 x 10^6 Zernikes) ran for
    minutes before this check; 6000 modes take ~4 s and 0.9 GB.
    """
    need = 8.0 * (float(n_z) * n_modes + (2.0 * n_z) ** 1.5 / 6.0)
    avail = free_memory_bytes()
    if need > avail:
        raise ValueError(
            f"`n_modes`={n_modes} K-L modes of {n_z} Zernikes need about "
            f"{need / 2**30:.3g} GiB (eigenvectors and covariance blocks) and "
            f"{avail / 2**30:.3g} GiB is free; use fewer modes or `zernike_modes`.")


def _check_kl_sampling(n_modes: int, pupil: Pupil) -> None:
    """Refuse more K-L modes than the grid resolves (the Zernike rule, mode k ~ Z(k+1)).

    K-L mode k of Kolmogorov turbulence is dominated by Zernikes of the radial order of
    Noll k + 1 (the K-L and Zernike variances agree mode for mode, Noll 1976; Wang &
    Markey 1978), so it is resolved where Z(k+1) is: ``n_pixels >= 2 n``.
    ``from_turbulence(Pupil(32), 1000)`` built 1000 "modes" on 812 pixels (audit 9).
    """
    try:
        check_zernike_sampling([n_modes + 1], pupil.n_pixels)
    except ValueError as exc:
        raise ValueError(
            f"`n_modes` = {n_modes} K-L modes need a finer pupil grid (K-L mode k is resolved "
            f"where Zernike k + 1 is): {exc}") from None


class KLBasis(ModalBasis):
    """Karhunen-Loeve modes as orthonormal combinations of Zernike modes.

    Usually built with :meth:`from_turbulence` or :meth:`from_data`.

    Parameters
    ----------
    zbasis : ZernikeBasis
        The Zernike modes the K-L modes are combinations of.
    zernike_from_kl : array_like
        ``(n_z, M)`` change of basis, column ``k`` = K-L mode ``k`` in Zernike
        coefficients; columns orthonormal.
    variances : array_like
        ``(M,)`` variance (or mean square) of each K-L coefficient.

    Attributes
    ----------
    variances : numpy.ndarray
        ``(M,)`` K-L variances, decreasing for a freshly built basis. Units:
        ``(D/r0)**(5/3) rad^2`` from :meth:`from_turbulence`, the log's units squared
        from :meth:`from_data`.
    zernike_modes : numpy.ndarray
        ``(n_z,)`` Noll indices of the underlying Zernikes.
    zernike_from_kl : numpy.ndarray
        ``(n_z, M)``; ``a_z = zernike_from_kl @ a_kl``.
    kl_from_zernike : numpy.ndarray
        ``(M, n_z)`` = ``zernike_from_kl.T``; ``a_kl = kl_from_zernike @ a_z`` (the
        orthogonal projection of Zernike coefficients onto the K-L modes).
    zernike_basis : ZernikeBasis
        The underlying Zernike basis.

    Notes
    -----
    The pixel matrix is ``zbasis.matrix @ zernike_from_kl``. :meth:`project` is the
    least-squares fit on the pixels (as for every :class:`ModalBasis`); it agrees with
    ``coefficients_from_zernike(zbasis.project(phase))`` exactly when the K-L modes span
    the Zernike set (``M = n_z``) and to the discretisation error of the Zernikes on the
    pixel grid otherwise (a few 1e-3 relative on 256 pixels: see ``ZernikeBasis.gram``).
    Use ``ZernikeBasis(..., orthonormalize=True)`` under a K-L basis to make the two
    routes agree to rounding.
    """

    def __init__(self, zbasis: ZernikeBasis, zernike_from_kl, variances) -> None:
        if not isinstance(zbasis, ZernikeBasis):
            raise TypeError(f"`zbasis` must be a ZernikeBasis; got {type(zbasis).__name__}.")
        change = as_float_array(zernike_from_kl, "zernike_from_kl", ndim=2, copy=True)
        if change.shape[0] != zbasis.n_modes:
            raise ValueError(
                f"`zernike_from_kl` must have n_z={zbasis.n_modes} rows (one per Zernike); "
                f"got shape {change.shape}."
            )
        var = as_float_array(variances, "variances", shape=(change.shape[1],), copy=True)
        gram = change.T @ change
        if not np.allclose(gram, np.eye(change.shape[1]), atol=1e-8):
            raise ValueError("`zernike_from_kl` must have orthonormal columns.")
        self._setup(zbasis.pupil, zbasis.modes, change, var, zbasis)

    def _setup(self, pupil: Pupil, modes: np.ndarray, change: np.ndarray, var: np.ndarray,
               zbasis: ZernikeBasis | None) -> None:
        """Set the state from validated parts (``zbasis`` None: built lazily on demand)."""
        density = np.count_nonzero(change) / change.size
        if zbasis is not None and (zbasis.orthonormalized or density > 0.25):
            matrix = zbasis.matrix @ change
        else:
            matrix = _combination_matrix(pupil, modes, change)
        super().__init__(matrix, pupil, [f"KL{k + 1}" for k in range(change.shape[1])],
                         _copy=False)
        change.flags.writeable = False
        var.flags.writeable = False
        self._zbasis = zbasis
        self._zmodes = modes
        self._change = change
        self._variances = var

    # ---------------------------------------------------------------- constructors
    @classmethod
    def from_turbulence(
        cls,
        pupil: Pupil,
        n_modes: int,
        outer_scale: float = np.inf,
        zernike_modes=None,
    ) -> KLBasis:
        """Theoretical K-L modes of Kolmogorov / von Karman turbulence.

        Parameters
        ----------
        pupil : Pupil
            Sampling pupil; its ``diameter`` [m] sets ``D / L0``. The covariance is the
            full-disc one, also on an annular pupil (then the modes are approximate).
        n_modes : int
            Number of K-L modes ``M`` kept, ``1 <= M <= n_z``.
        outer_scale : float
            Von Karman outer scale ``L0`` [m], at least ``pupil.diameter / 10`` (the
            rule of :func:`~modalinfo.bases.zernike_covariance`); ``inf`` for Kolmogorov.
        zernike_modes : iterable of int or int, optional
            Noll indices of the Zernikes combined (piston only with finite ``L0``); an
            int ``J`` means ``2..J`` (piston excluded, unlike ``ZernikeBasis``); default
            :func:`default_zernike_modes`: ``2..J`` with complete radial orders and at
            least ``3 M`` modes.

        Returns
        -------
        KLBasis
            ``M`` modes of decreasing variance; ``variances`` in
            ``(D/r0)**(5/3) rad^2``.
        """
        if not isinstance(pupil, Pupil):
            raise TypeError(f"`pupil` must be a modalinfo.bases.Pupil; got {type(pupil).__name__}.")
        n_modes = check_int(n_modes, "n_modes", minimum=1)
        # zernike_covariance's scale rule: L0 = 1e-300 gave a basis of zero variances
        # and a RuntimeWarning (adversarial round 25, KL1)
        outer_scale, _ = _check_scales(outer_scale, pupil.diameter)
        if zernike_modes is None:
            modes = default_zernike_modes(n_modes)
        elif isinstance(zernike_modes, numbers.Integral) and not isinstance(zernike_modes, bool):
            j_max = check_int(zernike_modes, "zernike_modes", minimum=2)
            modes = np.arange(2, j_max + 1, dtype=np.int64)
        else:
            modes = _parse_modes(zernike_modes)
        if n_modes > modes.size:
            raise ValueError(
                f"`n_modes` must be <= the number of Zernike modes ({modes.size}); got {n_modes}."
            )
        _check_turbulence_memory(modes.size, n_modes)
        _check_kl_sampling(n_modes, pupil)
        # the checks of zernike_covariance (piston refused for Kolmogorov), then only its
        # non-zero blocks: the dense (n_z, n_z) matrix is never formed
        checked = _check_modes(modes, outer_scale)
        blocks = _covariance_blocks(checked, outer_scale, pupil.diameter)
        values, vectors = _eig_blocks(blocks, modes, n_modes)
        modes = modes.copy()
        modes.flags.writeable = False
        new = cls.__new__(cls)
        # the (n_valid, n_z) Zernike matrix is not needed: built on demand only
        new._setup(pupil, modes, vectors, np.clip(values[:n_modes], 0, None), None)
        return new

    @classmethod
    def from_data(
        cls, zbasis: ZernikeBasis, coeffs, *, n_modes: int | None = None, center: bool = False
    ) -> KLBasis:
        """Empirical K-L modes (PCA) of a log of Zernike coefficients.

        Parameters
        ----------
        zbasis : ZernikeBasis
            Basis of the coefficients (column ``i`` of ``coeffs`` is ``zbasis.modes[i]``).
        coeffs : array_like
            ``(T, n_z)`` Zernike coefficients over time [rad or the log's units].
        n_modes : int, optional
            Number of K-L modes kept (default all ``n_z``); at most ``T`` (``T - 1``
            centred), the rank of the matrix decomposed.
        center : bool
            False (default): eigen-decompose the mean-square matrix ``A.T @ A / T``
            (non-centred). The fitting error of a truncated basis is a mean square over
            frames that includes any static aberration, and the non-centred PCA is its
            optimum. True: the sample covariance with the mean removed (``ddof=1``, as
            ``sklearn.decomposition.PCA``).

        Returns
        -------
        KLBasis
            Modes of decreasing mean square (or variance); ``variances`` in the units of
            ``coeffs`` squared.
        """
        if not isinstance(zbasis, ZernikeBasis):
            raise TypeError(f"`zbasis` must be a ZernikeBasis; got {type(zbasis).__name__}.")
        a = as_float_array(coeffs, "coeffs", ndim=2, min_length=2)
        if a.shape[1] != zbasis.n_modes:
            raise ValueError(
                f"`coeffs` must have n_z={zbasis.n_modes} columns (one per mode of "
                f"`zbasis`); got shape {a.shape}."
            )
        if not isinstance(center, bool | np.bool_):
            raise TypeError(f"`center` must be a bool; got {center!r}.")
        # the mean-square matrix sums T products per entry: beyond sqrt(max / 4T) it
        # overflowed (LinAlgError "Eigenvalues did not converge" at 1e160), below
        # SQUARE_FLOOR its subnormal products lost digits of the modes (2e-3 at 1e-160;
        # round 40 PART a, L08, L30)
        check_square_range(a, "coeffs", n_terms=a.shape[0])
        check_square_floor(a, "coeffs", consequence=(
            "the products behind the K-L covariance underflow float64 (the modes and "
            "variances would lose digits)"), task="building the K-L basis")
        n_keep = a.shape[1] if n_modes is None else check_int(
            n_modes, "n_modes", minimum=1, maximum=a.shape[1])
        rank = a.shape[0] - 1 if center else a.shape[0]
        if n_keep > rank:  # modes past the rank would be arbitrary null-space vectors
            raise ValueError(
                f"`coeffs` needs at least {n_keep + int(center)} frames for {n_keep} K-L "
                f"modes; got {a.shape[0]} (the {'covariance' if center else 'mean-square'} "
                f"matrix of {a.shape[0]} frames has rank <= {rank}, and the modes beyond it "
                "are arbitrary)")
        source = float_digest(a)  # before centring: the data as given
        if center:
            a = a - a.mean(axis=0)
            moment = a.T @ a / (a.shape[0] - 1)
        else:
            moment = a.T @ a / a.shape[0]
        values, vectors = np.linalg.eigh(0.5 * (moment + moment.T))
        # numerical rank (numpy.linalg.matrix_rank's tolerance): a column that is a sum of
        # others leaves null-space modes as arbitrary as those past the frame count above
        # (adversarial round 8, row d37); refused only where n_modes asks for them, the
        # default keeps every mode, the null ones with variance 0 (dead modes downstream)
        tol = max(float(values.max()), 0.0) * moment.shape[0] * np.finfo(float).eps
        numeric_rank = int(np.count_nonzero(values > tol))
        if n_modes is not None and n_keep > numeric_rank:
            raise ValueError(
                f"`n_modes` must be at most the rank of the "
                f"{'covariance' if center else 'mean-square'} matrix of `coeffs`, "
                f"{numeric_rank} (columns that are combinations of others); got {n_keep}: "
                "the modes beyond the rank are arbitrary")
        order = np.argsort(values)[::-1][:n_keep]
        vectors = _fix_signs(vectors[:, order])
        out = cls(zbasis, vectors, np.clip(values[order], 0, None))
        # what it was built from, for compare_orderings' check (round 37 PART a, S9-S10)
        out._source_digest = source
        return out

    # ---------------------------------------------------------------- attributes
    @property
    def variances(self) -> np.ndarray:
        """Variance of each K-L coefficient, ``(M,)``."""
        return self._variances

    @property
    def source_digest(self) -> str | None:
        """Digest of the coefficients a data K-L was built from (None: not from data).

        BLAKE2b of their shape and float64 values (``float_digest`` of
        ``modalinfo.common.records``), as given to :meth:`from_data`.
        """
        return getattr(self, "_source_digest", None)

    @property
    def zernike_modes(self) -> np.ndarray:
        """Noll indices of the underlying Zernikes, ``(n_z,)``."""
        return self._zmodes

    @property
    def zernike_basis(self) -> ZernikeBasis:
        """The underlying Zernike basis (built on first access for theoretical K-L)."""
        if self._zbasis is None:
            self._zbasis = ZernikeBasis(self.pupil, self._zmodes)
        return self._zbasis

    @property
    def zernike_from_kl(self) -> np.ndarray:
        """Change of basis ``(n_z, M)``: column ``k`` is K-L mode ``k`` in Zernikes."""
        return self._change

    @property
    def kl_from_zernike(self) -> np.ndarray:
        """Projection ``(M, n_z)`` of Zernike coefficients onto the K-L modes."""
        return self._change.T

    def coefficients_from_zernike(self, a_z) -> np.ndarray:
        """K-L coefficients of Zernike coefficients.

        Parameters
        ----------
        a_z : array_like
            ``(n_z,)`` or ``(T, n_z)`` Zernike coefficients.

        Returns
        -------
        numpy.ndarray
            ``(M,)`` or ``(T, M)`` K-L coefficients ``a_z @ zernike_from_kl``.
        """
        a = as_float_array(a_z, "a_z", ndim=(1, 2))
        if a.shape[-1] != self._change.shape[0]:
            raise ValueError(
                f"`a_z` must have last axis of length n_z={self._change.shape[0]}; "
                f"got shape {a.shape}."
            )
        return a @ self._change

    def zernike_from_coefficients(self, a_kl) -> np.ndarray:
        """Zernike coefficients of K-L coefficients.

        Parameters
        ----------
        a_kl : array_like
            ``(M,)`` or ``(T, M)`` K-L coefficients.

        Returns
        -------
        numpy.ndarray
            ``(n_z,)`` or ``(T, n_z)`` Zernike coefficients ``a_kl @ zernike_from_kl.T``.
        """
        a = as_float_array(a_kl, "a_kl", ndim=(1, 2))
        if a.shape[-1] != self.n_modes:
            raise ValueError(
                f"`a_kl` must have last axis of length n_modes={self.n_modes}; "
                f"got shape {a.shape}."
            )
        return a @ self._change.T

    def _permute_extra(self, new: ModalBasis, index: np.ndarray) -> None:
        change = np.ascontiguousarray(self._change[:, index])
        var = self._variances[index].copy()
        change.flags.writeable = False
        var.flags.writeable = False
        new._change = change
        new._variances = var

    def __repr__(self) -> str:
        return (
            f"KLBasis(n_modes={self.n_modes}, zernike_modes={self.zernike_modes[0]}.."
            f"{self.zernike_modes[-1]} ({self.zernike_modes.size}), pupil={self.pupil!r})"
        )
