"""Zernike polynomials (Noll normalisation) and the Zernike modal basis.

Radial polynomials come from Kintner's three-term recurrence in ``n`` at fixed ``m``
(Kintner 1976, Optica Acta 23, 679; Chong et al. 2003, Pattern Recognit. 36, 731),
which has no cancellation between large alternating terms: it stays at machine
precision to ``n = 40`` and beyond, where the factorial sum loses every digit.
"""

from __future__ import annotations

import numbers
from collections.abc import Iterable

import numpy as np

from modalinfo.bases import _kernels
from modalinfo.bases.basis import ModalBasis
from modalinfo.bases.indexing import _as_index, _check_nm, noll_to_zernike
from modalinfo.bases.pupil import Pupil
from modalinfo.common.chunked import KERNEL_VALUES, blocks
from modalinfo.common.validation import as_float_array

__all__ = [
    "zernike_radial", "zernike_polynomial", "zernike_matrix", "ZernikeBasis",
    "check_zernike_sampling", "max_zernike_order", "PIXELS_PER_CYCLE",
]


#: pupil pixels per cycle of the finest Zernike a sampled grid represents (Nyquist)
PIXELS_PER_CYCLE = 2


def max_zernike_order(n_pixels: int) -> int:
    """Highest Zernike radial order a grid of ``n_pixels`` across samples without aliasing.

    A Zernike of radial order ``n`` has ``n`` zero crossings along a diameter, ``n / 2``
    cycles; Nyquist asks :data:`PIXELS_PER_CYCLE` pixels per cycle, so ``n <= n_pixels /
    2``. The one copy of the rule: :func:`check_zernike_sampling` and closedloop's modal
    mirrors (``closedloop.optics.dm.check_zernike_sampling``) both use it.

    Parameters
    ----------
    n_pixels : int
        Pupil grid size across [pixels] (whole pixels).

    Returns
    -------
    int
        The highest radial order resolved (0 below 2 pixels).
    """
    return int(n_pixels) // PIXELS_PER_CYCLE


def check_zernike_sampling(noll_modes, n_pixels: int) -> None:
    """Refuse Zernike modes a pupil grid of ``n_pixels`` across cannot sample.

    A Zernike of radial order ``n`` has ``n`` zero crossings along a diameter, so it is
    resolved, not aliased, on ``n_pixels >= 2 n`` pixels across (:func:`max_zernike_order`).
    On fewer pixels the sampled modes are no longer Zernikes:
    aliased, nearly dependent (198 modes on 52 pixels have rank 52), and every fitting
    error or ordering computed with them describes those samples, not the modes.

    Parameters
    ----------
    noll_modes : array_like of int
        Noll indices (``>= 1``).
    n_pixels : int
        Pupil grid size across [pixels].

    Raises
    ------
    ValueError
        Naming ``n_pixels``, the highest mode and its radial order.
    """
    top = int(np.max(np.asarray(noll_modes, dtype=np.int64)))
    order = int(noll_to_zernike(top)[0])
    if order > max_zernike_order(n_pixels):
        raise ValueError(
            f"`n_pixels` must be >= {PIXELS_PER_CYCLE * order} to sample Z{top} (radial "
            f"order {order} <= pixels across / {PIXELS_PER_CYCLE}); got {n_pixels}.")


def zernike_radial(n: int, m: int, rho) -> np.ndarray:
    """Zernike radial polynomial ``R_n^|m|(rho)`` (``R_n^m(1) = 1``, not normalised).

    Parameters
    ----------
    n : int
        Radial order, ``n >= 0``.
    m : int
        Azimuthal frequency (its sign is ignored), ``|m| <= n``, ``n - |m|`` even.
    rho : array_like
        Normalised radius (any shape); usually ``0 <= rho <= 1``.

    Returns
    -------
    numpy.ndarray
        ``R_n^|m|(rho)``, same shape as ``rho``.
    """
    n_arr, m_arr, scalar = _check_nm(n, m)
    if not scalar:
        raise TypeError("`n` and `m` must be ints; use zernike_matrix for many modes.")
    r = as_float_array(rho, "rho")
    out = np.empty(r.size)
    _kernels.radial(int(n_arr), abs(int(m_arr)), r.ravel(), out)
    return out.reshape(r.shape)


def zernike_polynomial(j: int, rho, theta) -> np.ndarray:
    """Noll Zernike polynomial ``Z_j(rho, theta)``, unit RMS over the unit disc.

    Parameters
    ----------
    j : int
        Noll index, ``j >= 1``.
    rho : array_like
        Normalised radius, the unit disc ``0 <= rho <= 1``. Beyond it the polynomial is
        evaluated as it stands (``Z_4(1.5) = sqrt(3) (2 rho^2 - 1) = 6.06``, no
        refusal): the unit-RMS normalisation holds over the disc only.
    theta : array_like
        Azimuth [rad], ``atan2(y, x)``; broadcast with ``rho``.

    Returns
    -------
    numpy.ndarray
        ``sqrt(n+1) R_n^0`` for ``m = 0``; ``sqrt(2(n+1)) R_n^|m| cos(m theta)`` for even
        ``j`` and ``... sin(|m| theta)`` for odd ``j`` (``m != 0``).
    """
    n, m = noll_to_zernike(j)
    if not isinstance(j, numbers.Integral):
        raise TypeError(f"`j` must be an int; got {j!r}.")
    r, t = as_float_array(rho, "rho"), as_float_array(theta, "theta")
    try:
        r, t = np.broadcast_arrays(r, t)
    except ValueError as exc:  # NumPy's message names its "arg 0" and "arg 1", not ours
        raise ValueError(f"`rho` and `theta` must broadcast together; got shapes {r.shape} "
                         f"and {t.shape}.") from exc
    return zernike_matrix([j], r.ravel(), t.ravel())[:, 0].reshape(r.shape)


def zernike_matrix(modes, rho, theta) -> np.ndarray:
    """Matrix of Noll Zernike polynomials at the given points.

    Parameters
    ----------
    modes : sequence of int
        Noll indices ``j >= 1``.
    rho, theta : array_like
        ``(P,)`` normalised radius and azimuth [rad].

    Returns
    -------
    numpy.ndarray
        ``(P, M)`` values, column ``k`` is ``Z_{modes[k]}``.
    """
    j, _ = _as_index(np.atleast_1d(modes), "modes", minimum=1)
    r = as_float_array(rho, "rho", ndim=1)
    t = as_float_array(theta, "theta", ndim=1)
    if t.shape != r.shape:  # either may be the one at fault: name both
        raise ValueError(f"`rho` and `theta` must have the same length (P,); got shapes "
                         f"{r.shape} and {t.shape}.")
    n, m = noll_to_zernike(j.ravel())
    out = np.empty((r.shape[0], j.size))
    n, m = np.ascontiguousarray(n), np.ascontiguousarray(m)
    # pixels in chunks: one call on 3,000 modes x 20,000 pixels ran 8 s, deaf to Ctrl-C
    for rows in blocks(r.shape[0], j.size, KERNEL_VALUES):
        _kernels.zernike_matrix(r[rows], t[rows], n, m, out[rows])
    return out


def _parse_modes(modes) -> np.ndarray:
    if isinstance(modes, bool):
        raise TypeError(f"`modes` must be an int or an iterable of Noll indices; got {modes!r}.")
    if isinstance(modes, numbers.Integral):
        if modes < 1:
            raise ValueError(f"`modes` as a count must be an int >= 1; got {modes}.")
        return np.arange(1, int(modes) + 1, dtype=np.int64)
    if not isinstance(modes, Iterable | np.ndarray):
        raise TypeError(f"`modes` must be an int or an iterable of Noll indices; got {modes!r}.")
    seq = list(modes) if not isinstance(modes, np.ndarray) else modes
    if np.size(seq) == 0:
        raise ValueError("`modes` must hold at least one Noll index; got none.")
    j, _ = _as_index(seq, "modes", minimum=1)
    if j.ndim != 1:
        raise ValueError(f"`modes` must be 1-D; got shape {j.shape}.")
    if np.unique(j).size != j.size:
        raise ValueError(f"`modes` must not repeat an index; got {j.tolist()}.")
    return j


class ZernikeBasis(ModalBasis):
    """Noll Zernike modes sampled on a pupil.

    Parameters
    ----------
    pupil : Pupil
        Sampling grid.
    modes : int or iterable of int
        Noll indices of the columns, in order (default ``2..28``: tip to the 27th mode
        after piston, the paper's 27 modes). An int ``J`` means Noll ``1..J`` (piston
        included), as in ``aotools.zernikeArray`` and ``hcipy.make_zernike_basis``.
    orthonormalize : bool
        If True, re-orthonormalise the sampled modes on the pixel grid (Gram-Schmidt in
        the given order through a Cholesky factor of the Gram matrix): column ``k`` becomes
        ``Z_k`` minus its projection on the previous columns, rescaled to unit RMS, so
        it keeps the sign and leading structure of ``Z_k`` and ``gram()`` is the identity
        to rounding. Use it for annular pupils or coarse grids. Without piston among the
        modes, the orthonormalised modes are not forced to zero mean.

    Attributes
    ----------
    modes : numpy.ndarray
        ``(M,)`` Noll indices of the columns.
    orthonormalized : bool
        Whether the columns were re-orthonormalised.
    """

    def __init__(self, pupil: Pupil, modes=range(2, 29), orthonormalize: bool = False) -> None:
        if not isinstance(pupil, Pupil):
            raise TypeError(f"`pupil` must be a modalinfo.bases.Pupil; got {type(pupil).__name__}.")
        if not isinstance(orthonormalize, bool | np.bool_):
            raise TypeError(f"`orthonormalize` must be a bool; got {orthonormalize!r}.")
        j = _parse_modes(modes)
        check_zernike_sampling(j, pupil.n_pixels)  # audit 9, centre: was only in the CLI
        matrix = zernike_matrix(j, pupil.rho_valid, pupil.theta_valid)
        if orthonormalize:
            matrix = _orthonormalize(matrix)
        super().__init__(matrix, pupil, [f"Z{k}" for k in j], _copy=False)
        j.flags.writeable = False
        self._modes = j
        self._orthonormalized = bool(orthonormalize)

    @property
    def modes(self) -> np.ndarray:
        """Noll indices of the columns, ``(M,)``."""
        return self._modes

    @property
    def orthonormalized(self) -> bool:
        """Whether the columns were re-orthonormalised on the pixel grid."""
        return self._orthonormalized

    def _permute_extra(self, new: ModalBasis, index: np.ndarray) -> None:
        modes = self._modes[index]
        modes.flags.writeable = False
        new._modes = modes

    def __repr__(self) -> str:
        return (
            f"ZernikeBasis({self.pupil!r}, modes={self._modes.tolist()}, "
            f"orthonormalize={self._orthonormalized})"
        )


def _orthonormalize(matrix: np.ndarray) -> np.ndarray:
    """Gram-Schmidt of the columns in order, unit RMS (matrix.T @ matrix / P = I)."""
    n_valid = matrix.shape[0]
    gram = matrix.T @ matrix / n_valid
    try:
        chol = np.linalg.cholesky(gram)
    except np.linalg.LinAlgError as exc:
        raise ValueError(
            "`modes` are linearly dependent on this pupil (too few pixels for that many "
            "modes); use fewer modes or more pixels."
        ) from exc
    from scipy.linalg import solve_triangular

    out = solve_triangular(chol, matrix.T, lower=True).T
    # one more pass removes the rounding left by a poorly conditioned Gram matrix
    gram2 = out.T @ out / n_valid
    chol2 = np.linalg.cholesky(gram2)
    return np.ascontiguousarray(solve_triangular(chol2, out.T, lower=True).T)
