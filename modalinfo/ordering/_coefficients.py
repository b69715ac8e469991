"""Turn a log or a coefficient array into coefficients of a given basis (private).

Shared by the orderings, the fitting-error curves and the stability analysis, so the
three agree on what "the coefficients of the log in this basis" means:

- a :class:`~modalinfo.telemetry.ModalLog` is converted to radians of phase (Noll
  convention), its columns matched to the basis's Zernike modes by Noll index; for a
  K-L basis the Zernike coefficients are changed to K-L coefficients with the basis's
  ``coefficients_from_zernike``;
- a log with ``convention="labels"`` (non-Zernike columns such as ``"KL3"``) holds
  coefficients of the basis's own modes, matched to the basis's labels by name (before
  round 21 its columns were taken in order whatever their labels: a log labelled KL3,
  KL1, KL2 was read as KL1, KL2, KL3 and its orderings named the wrong modes); a
  label the basis lacks is refused. A bare mode matrix has no labels: columns in order;
- an array ``(T, M)`` or ``(M,)`` is taken as coefficients of the basis's own modes,
  in radians.

A basis is a :class:`~modalinfo.bases.ModalBasis` (anything with ``.matrix`` and
``.labels``) or a bare mode matrix ``(n_valid, M)`` (labels ``"mode1"``...).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from modalinfo.common.validation import as_float_array, check_square_range

__all__ = [
    "BasisView", "as_basis", "check_represented", "check_values", "coefficients_in_basis",
    "is_log",
]


@dataclass(frozen=True)
class BasisView:
    """The parts of a basis the ordering code uses.

    Attributes
    ----------
    matrix : numpy.ndarray, shape (n_valid, M)
        Mode values on the valid pupil pixels (C-contiguous float64).
    labels : tuple of str
        One label per mode.
    obj : object or None
        The basis object itself (None for a bare matrix).
    """

    matrix: np.ndarray
    labels: tuple[str, ...]
    obj: Any

    @property
    def n_modes(self) -> int:
        """Number of modes M."""
        return self.matrix.shape[1]

    def standard_order(self) -> np.ndarray:
        """Return the standard order ``(M,)``: ascending Noll index (Zernike basis), else 0..M-1.

        A Zernike basis built from a log whose columns are not in Noll order (e.g. Z6, Z2,
        Z11, ...) keeps the file's column order; the standard order is still Z2, Z3, ...
        (audit 9, centre: the "standard" order of such a log was the file's order).
        """
        modes = getattr(self.obj, "modes", None) if self.obj is not None else None
        if modes is None or len(modes) != self.n_modes:
            return np.arange(self.n_modes, dtype=np.int64)
        return np.argsort(np.asarray(modes, dtype=np.int64), kind="stable").astype(np.int64)

    def gram(self) -> np.ndarray:
        """``matrix.T @ matrix / n_valid`` (identity for a basis orthonormal on the pupil)."""
        from modalinfo.common.chunked import gram

        return gram(self.matrix) / self.matrix.shape[0]  # in chunks: Ctrl-C between them


def check_values(coeffs: np.ndarray, name: str) -> None:
    """Raise the error of a non-finite or overflowing coefficient array (deferred checks).

    Parameters
    ----------
    coeffs : numpy.ndarray, shape (T, M)
    name : str
        Argument name for the message.

    Raises
    ------
    ValueError
        Naming the argument and, for an overflow, the column and its largest magnitude.
    """
    as_float_array(coeffs, name)  # finiteness
    check_square_range(coeffs, name)


def is_log(value: Any) -> bool:
    """Tell whether `value` is a ModalLog-like object (has ``coeffs`` and ``to_units``)."""
    return hasattr(value, "coeffs") and hasattr(value, "to_units")


def as_basis(basis: Any, name: str = "basis") -> BasisView:
    """Return a :class:`BasisView` of a ModalBasis-like object or a mode matrix."""
    if isinstance(basis, BasisView):
        return basis
    if hasattr(basis, "matrix"):
        matrix = as_float_array(basis.matrix, f"{name}.matrix", ndim=2)
        labels = tuple(str(s) for s in getattr(basis, "labels", ()))
        if len(labels) != matrix.shape[1]:
            labels = tuple(f"mode{k + 1}" for k in range(matrix.shape[1]))
        obj = basis
    elif isinstance(basis, np.ndarray | list | tuple):
        matrix = as_float_array(basis, name, ndim=2)
        labels = tuple(f"mode{k + 1}" for k in range(matrix.shape[1]))
        obj = None
    else:
        raise TypeError(
            f"`{name}` must be a ModalBasis or a mode matrix of shape (n_valid, M); "
            f"got {type(basis).__name__}."
        )
    if matrix.shape[0] < 1 or matrix.shape[1] < 1:
        raise ValueError(f"`{name}` must have at least one pixel and one mode; got {matrix.shape}.")
    return BasisView(matrix=matrix, labels=labels, obj=obj)


def _column_index(log_modes: list, wanted: list, what: str) -> np.ndarray:
    pos = {m: i for i, m in enumerate(log_modes)}
    missing = [m for m in wanted if m not in pos]
    if missing:
        raise ValueError(
            f"`log_or_coeffs` lacks the {what} the basis needs: Noll modes {missing} are not "
            f"among the log's modes {log_modes}."
        )
    return np.array([pos[m] for m in wanted], dtype=np.intp)


def _label_index(log_labels: list, basis_labels: tuple, name: str) -> np.ndarray:
    """Columns of a labelled log holding the basis's modes, in the basis's order."""
    pos = {str(m): i for i, m in enumerate(log_labels)}
    missing = [m for m in basis_labels if m not in pos]
    if missing:
        shown = ", ".join(missing[:5]) + (f" (and {len(missing) - 5} more)"
                                          if len(missing) > 5 else "")
        raise ValueError(
            f"`{name}` has columns labelled {[str(m) for m in log_labels][:8]}"
            f"{'...' if len(log_labels) > 8 else ''} (convention 'labels'), matched to the "
            f"basis's modes by label, and lacks {shown}. Give the log the basis's labels "
            f"(ModalLog(..., modes=basis.labels, convention='labels')) or the basis the "
            f"log's; an array (log.coeffs) is taken column by column in the basis's order.")
    return np.array([pos[m] for m in basis_labels], dtype=np.intp)


def coefficients_in_basis(
    log_or_coeffs: Any, basis: BasisView, *, wavelength: float | None = None,
    name: str = "log_or_coeffs", defer_value_checks: bool = False,
) -> np.ndarray:
    """Coefficients ``(T, M)`` [rad] of the log (or array) in the basis's modes.

    Parameters
    ----------
    log_or_coeffs : ModalLog or array_like, shape (T, M) or (M,)
        A log (converted to radians, matched by Noll index) or basis coefficients [rad].
    basis : BasisView
        The basis.
    wavelength : float, optional
        Wavelength [m] for converting a log in nm or um to radians, when the log does
        not carry one.
    name : str
        Argument name for error messages.
    defer_value_checks : bool
        For an array input, skip the finiteness and overflow checks of its values (two
        passes over a large array); the caller then checks that the sums it forms are
        finite and, if not, calls :func:`check_values` for the message.

    Returns
    -------
    numpy.ndarray, shape (T, M)
        C-contiguous float64 coefficients in radians.
    """
    obj = basis.obj
    if is_log(log_or_coeffs):
        log = log_or_coeffs
        if getattr(log, "convention", "noll") not in ("noll", "labels"):
            log = log.to_convention("noll")  # labelled columns: taken in order
        if getattr(log, "units", "rad") != "rad":
            log = log.to_units("rad", wavelength=wavelength)
        coeffs = as_float_array(np.asarray(log.coeffs), f"{name}.coeffs", ndim=2)
        check_square_range(coeffs, name, getattr(log, "labels", None))
        log_modes = list(log.modes) if getattr(log, "modes", None) is not None else None
        if obj is not None and getattr(log, "convention", "noll") == "labels":
            # the basis's own coefficients, named: matched by label, never by position
            out = coeffs[:, _label_index(list(log.labels), basis.labels, name)]
        elif obj is not None and hasattr(obj, "zernike_modes") and hasattr(
            obj, "coefficients_from_zernike"
        ):
            zmodes = [int(m) for m in obj.zernike_modes]
            if log_modes is None:
                raise ValueError(f"`{name}` has no mode indices to match the K-L basis with.")
            cols = _column_index(log_modes, zmodes, "Zernike modes")
            out = np.asarray(obj.coefficients_from_zernike(coeffs[:, cols]), dtype=float)
        elif obj is not None and hasattr(obj, "modes") and log_modes is not None:
            bmodes = [int(m) for m in obj.modes]
            cols = _column_index(log_modes, bmodes, "Zernike modes")
            out = coeffs[:, cols]
        else:
            out = coeffs
        out = np.ascontiguousarray(out, dtype=np.float64)
    else:
        out = as_float_array(log_or_coeffs, name, ndim=(1, 2), finite=not defer_value_checks)
        if out.ndim == 1:
            out = out[None, :]
        if not defer_value_checks:
            check_square_range(out, name)
    if out.shape[0] < 1:
        raise ValueError(f"`{name}` must hold at least one frame; got shape {out.shape}.")
    if out.shape[1] != basis.n_modes:
        raise ValueError(
            f"`{name}` must have one coefficient per basis mode ({basis.n_modes}); "
            f"got {out.shape[1]}."
        )
    return out


def check_represented(log: Any, basis: BasisView, name: str = "coeffs_or_log") -> None:
    """Refuse a log whose wavefront the basis does not fully represent (fitting error).

    A fitting error dPhi(n) is the variance of the log's wavefront left after n modes; a
    log column the basis lacks (a Zernike basis without some of the log's modes), or a
    K-L basis keeping fewer modes than the Zernikes it combines, drops that variance from
    every dPhi(n), so dPhi(M) = 0 claims a perfect fit (audit 9, centre: a 3-mode basis on
    a 6-mode log gave dPhi(0) = 22.4 of a total 41.6 rad^2 and dPhi(3) = 0). Columns that
    are identically zero carry no variance and are ignored.

    Parameters
    ----------
    log : ModalLog-like
        The log (arrays are a basis's own coefficients: nothing to check).
    basis : BasisView
    name : str
        Argument name for the message.

    Raises
    ------
    ValueError
        Naming the modes left out and the remedies.
    """
    obj = basis.obj
    if not is_log(log) or obj is None:
        return
    if getattr(log, "convention", "noll") == "labels":
        kept_labels = set(basis.labels)
        coeffs = np.asarray(log.coeffs)
        extra = [i for i, m in enumerate(log.labels) if str(m) not in kept_labels
                 and np.any(coeffs[:, i] != 0)]
        _refuse_extra(log, extra, name)
        return
    if hasattr(obj, "zernike_modes") and hasattr(obj, "coefficients_from_zernike"):
        kept = {int(m) for m in obj.zernike_modes}
        if obj.n_modes < len(kept):
            raise ValueError(
                f"`basis` keeps {obj.n_modes} K-L modes of the {len(kept)} Zernike modes it "
                f"combines: the log's variance outside them would be missing from every "
                f"dPhi(n) (dPhi({obj.n_modes}) would claim a perfect fit). Build the K-L basis "
                f"with all {len(kept)} modes and read dPhi(n) for n <= {obj.n_modes}.")
    elif hasattr(obj, "modes"):
        kept = {int(m) for m in obj.modes}
    else:
        return
    if getattr(log, "convention", "noll") != "noll":
        log = log.to_convention("noll")
    coeffs = np.asarray(log.coeffs)
    extra = [i for i, m in enumerate(log.modes) if int(m) not in kept
             and np.any(coeffs[:, i] != 0)]
    _refuse_extra(log, extra, name)


def _refuse_extra(log: Any, extra: list, name: str) -> None:
    """Refuse the log columns ``extra`` (indices) that the basis does not represent."""
    if extra:
        labels = [str(log.labels[i]) for i in extra]
        shown = ", ".join(labels[:5]) + (f" (and {len(labels) - 5} more)" if len(labels) > 5
                                         else "")
        raise ValueError(
            f"`{name}` holds {len(extra)} mode(s) the basis does not represent ({shown}): "
            f"their variance would be missing from every dPhi(n), and dPhi(M) would claim a "
            f"perfect fit. Use a basis holding every mode of the log (and read dPhi(n) at "
            f"the n you want), or select the modes first (log.select(modes=...)).")
