"""A modal basis: a matrix of modes sampled on the pupil pixels."""

from __future__ import annotations

import copy
import numbers

import numpy as np
from scipy import linalg

from modalinfo.bases.pupil import Pupil
from modalinfo.common.validation import as_float_array

__all__ = ["ModalBasis"]

# Gram matrices better conditioned than this are solved by Cholesky; worse ones by SVD.
_COND_CHOLESKY = 1e8


class ModalBasis:
    """Modes sampled on the pixels of a pupil: ``phase = matrix @ coeffs``.

    Parameters
    ----------
    matrix : array_like
        ``(n_valid, M)`` mode values at the pupil pixels (``image[pupil.mask]`` order),
        in radians per unit coefficient.
    pupil : Pupil
        The pupil the modes are sampled on.
    labels : sequence of str, optional
        ``M`` mode names (default ``"mode1"``, ``"mode2"``...).

    Attributes
    ----------
    matrix : numpy.ndarray
        ``(n_valid, M)`` read-only mode matrix.
    pupil : Pupil
        Sampling pupil.
    labels : list of str
        Mode names.
    n_modes : int
        ``M``.

    Notes
    -----
    :meth:`project` is the least-squares fit on the pixels,
    ``argmin_a ||matrix @ a - phase||^2``; for an orthonormal basis (``gram()`` the
    identity) it equals ``matrix.T @ phase / n_valid``.
    """

    def __init__(self, matrix, pupil: Pupil, labels=None, *, _copy: bool = True) -> None:
        # _copy=False: private, for subclasses handing over a fresh array they own
        if not isinstance(pupil, Pupil):
            raise TypeError(f"`pupil` must be a modalinfo.bases.Pupil; got {type(pupil).__name__}.")
        mat = as_float_array(matrix, "matrix", ndim=2, copy=_copy)
        if mat.shape[0] != pupil.n_valid:
            raise ValueError(
                f"`matrix` must have n_valid={pupil.n_valid} rows (one per pupil pixel); "
                f"got shape {mat.shape}."
            )
        if mat.shape[1] < 1:
            raise ValueError(f"`matrix` must have at least one column; got shape {mat.shape}.")
        if labels is None:
            labels = [f"mode{k + 1}" for k in range(mat.shape[1])]
        elif isinstance(labels, str) or not all(isinstance(s, str) for s in labels):
            raise TypeError(f"`labels` must be a sequence of str; got {labels!r}.")
        labels = list(labels)
        if len(labels) != mat.shape[1]:
            raise ValueError(
                f"`labels` must have one entry per column ({mat.shape[1]}); got {len(labels)}."
            )
        mat.flags.writeable = False
        self._matrix = mat
        self._pupil = pupil
        self._labels = labels
        self._solver = None

    # ------------------------------------------------------------------ properties
    @property
    def matrix(self) -> np.ndarray:
        """Mode matrix ``(n_valid, M)`` (read-only)."""
        return self._matrix

    @property
    def pupil(self) -> Pupil:
        """The sampling pupil."""
        return self._pupil

    @property
    def labels(self) -> list[str]:
        """Mode names (a copy)."""
        return list(self._labels)

    @property
    def n_modes(self) -> int:
        """Number of modes ``M``."""
        return self._matrix.shape[1]

    def __len__(self) -> int:
        return self.n_modes

    def __repr__(self) -> str:
        return f"{type(self).__name__}(n_modes={self.n_modes}, pupil={self._pupil!r})"

    # ------------------------------------------------------------------ operations
    def gram(self) -> np.ndarray:
        """Return the Gram matrix ``matrix.T @ matrix / n_valid``, ``(M, M)``.

        The identity for a basis orthonormal in the pixel-mean inner product
        (unit-RMS modes, uncorrelated over the pupil).
        """
        return self._matrix.T @ self._matrix / self._matrix.shape[0]

    def synthesize(self, coeffs) -> np.ndarray:
        """Phase at the pupil pixels from modal coefficients.

        Parameters
        ----------
        coeffs : array_like
            ``(M,)`` or ``(T, M)`` coefficients [rad].

        Returns
        -------
        numpy.ndarray
            ``(n_valid,)`` or ``(T, n_valid)`` phase [rad].

        Raises
        ------
        ValueError
            If the last axis is not ``M`` long or a value is not finite.
        """
        a = as_float_array(coeffs, "coeffs", ndim=(1, 2))
        if a.shape[-1] != self.n_modes:
            raise ValueError(
                f"`coeffs` must have last axis of length n_modes={self.n_modes}; "
                f"got shape {a.shape}."
            )
        return a @ self._matrix.T

    def project(self, phase) -> np.ndarray:
        """Least-squares modal coefficients of a phase sampled at the pupil pixels.

        Parameters
        ----------
        phase : array_like
            ``(n_valid,)`` or ``(T, n_valid)`` phase [rad] at ``pupil.mask`` pixels.

        Returns
        -------
        numpy.ndarray
            ``(M,)`` or ``(T, M)`` coefficients minimising the pixel residual.

        Raises
        ------
        ValueError
            If the last axis is not ``n_valid`` long (another pupil) or a value is not
            finite.
        """
        ph = as_float_array(phase, "phase", ndim=(1, 2))
        if ph.shape[-1] != self._pupil.n_valid:
            raise ValueError(
                f"`phase` must have last axis of length n_valid={self._pupil.n_valid} "
                f"(pixels of this basis' pupil); got shape {ph.shape}."
            )
        rhs = ph @ self._matrix  # (..., M)
        kind, factor = self._get_solver()
        if kind == "cholesky":
            out = linalg.cho_solve(factor, rhs.T).T
        else:
            out = rhs @ factor.T
        return np.ascontiguousarray(out)

    def _get_solver(self):
        """Factor the normal equations once: Cholesky, or a pseudo-inverse if singular."""
        if self._solver is None:
            g = self._matrix.T @ self._matrix
            eig = np.linalg.eigvalsh(g)
            if eig[0] > eig[-1] / _COND_CHOLESKY:
                self._solver = ("cholesky", linalg.cho_factor(g, lower=True))
            else:
                # rank-deficient or badly conditioned: minimum-norm least squares
                self._solver = ("pinv", np.linalg.pinv(g, hermitian=True))
        return self._solver

    def reorder(self, order):
        """Return a copy of the basis with its columns taken in ``order``.

        Parameters
        ----------
        order : sequence of int
            Column indices (0-based), distinct; a permutation of ``range(M)`` or a
            subset of it (which keeps only those modes).

        Returns
        -------
        ModalBasis
            Same class, columns and labels (and any per-mode attribute) in the new order.
        """
        index = _check_order(order, self.n_modes)
        new = copy.copy(self)
        mat = np.ascontiguousarray(self._matrix[:, index])
        mat.flags.writeable = False
        new._matrix = mat
        new._labels = [self._labels[k] for k in index]
        new._solver = None
        self._permute_extra(new, index)
        return new

    def _permute_extra(self, new: ModalBasis, index: np.ndarray) -> None:
        """Permute the per-mode attributes of subclasses (hook for :meth:`reorder`)."""


def _check_order(order, n_modes: int) -> np.ndarray:
    if isinstance(order, numbers.Integral) or isinstance(order, str):
        raise TypeError(f"`order` must be a sequence of column indices; got {order!r}.")
    arr = np.asarray(order)
    if arr.ndim != 1 or arr.size == 0:
        raise ValueError(f"`order` must be a non-empty 1-D sequence; got shape {arr.shape}.")
    if not np.issubdtype(arr.dtype, np.integer):
        raise TypeError(f"`order` must hold integer column indices; got dtype {arr.dtype}.")
    if arr.min() < 0 or arr.max() >= n_modes:
        raise ValueError(
            f"`order` entries must be in [0, {n_modes - 1}]; got min {arr.min()}, max {arr.max()}."
        )
    if np.unique(arr).size != arr.size:
        raise ValueError("`order` must not repeat a column index.")
    return arr.astype(np.int64)
