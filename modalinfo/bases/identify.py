"""Identify mode images (a file's own basis) as Zernike polynomials of our convention.

Each mode is correlated with the Noll Zernikes ``Z_1 .. Z_J`` of the package
(``x`` along columns, ``y`` along rows, ``Z2 = 2x``, ``Z3 = 2y``, unit RMS) on the
mode's pupil; its match is the Zernike of largest ``|correlation|``, with the sign of
that correlation. A mode is a Zernike when ``|correlation| >= threshold``.

Systems differ in their axes (OOPAO and others transpose x and y; a detector may be
read flipped). So the identification is also run on the modes transformed by each of
the 8 symmetries of the square grid; :attr:`ZernikeIdentification.transform` names
the first (``"none"`` preferred) under which every mode is a Zernike with a positive
sign and the indices increase in Noll (or ANSI) order: the map from the file's axes
to ours. The per-mode table itself is always in our axes, untransformed: file mode
``k`` equals ``sign[k] * Z_{noll[k]}`` to within its correlation.

Correlation: ``<f, Z> / (|f| |Z|)`` over the pupil pixels (no mean removed; piston
``Z1`` is a candidate).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from modalinfo.bases.image_basis import crop_images, pupil_from_mask, support_of
from modalinfo.bases.indexing import noll_to_ansi, noll_to_zernike
from modalinfo.bases.zernike import zernike_matrix
from modalinfo.common.records import array_fields_eq
from modalinfo.common.validation import as_bool_mask, check_int, check_real

__all__ = ["TRANSFORMS", "ZernikeIdentification", "identify_zernike"]

#: Symmetries of the square grid tried, in order of preference: name -> image map
#: (on the last two axes, rows = y, columns = x).
TRANSFORMS = {
    "none": lambda a: a,
    "transpose": lambda a: np.swapaxes(a, -1, -2),
    "flip-x": lambda a: a[..., :, ::-1],
    "flip-y": lambda a: a[..., ::-1, :],
    "rotate-180": lambda a: a[..., ::-1, ::-1],
    "rotate+90": lambda a: np.rot90(a, 1, axes=(-2, -1)),
    "rotate-90": lambda a: np.rot90(a, -1, axes=(-2, -1)),
    "anti-transpose": lambda a: np.rot90(a, 2, axes=(-2, -1)).swapaxes(-1, -2),
}


@array_fields_eq
@dataclass(frozen=True)
class ZernikeIdentification:
    """Which Zernike (Noll, our convention) each mode image is.

    Attributes
    ----------
    noll : numpy.ndarray
        ``(M,)`` Noll index of the best-matching Zernike of each mode (our axes).
    correlation : numpy.ndarray
        ``(M,)`` signed correlation with that Zernike, in ``[-1, 1]``.
    sign : numpy.ndarray
        ``(M,)`` ``+1`` or ``-1``: the mode is ``sign * Z_noll``.
    second : numpy.ndarray
        ``(M,)`` the next best ``|correlation|`` (how clear the match is).
    is_zernike : numpy.ndarray
        ``(M,)`` bool, ``|correlation| >= threshold``.
    threshold : float
        The threshold used.
    transform : str or None
        Name in ``TRANSFORMS`` of the grid symmetry taking the file's axes to ours
        under which the modes are Zernikes with positive signs in increasing Noll (or
        ANSI) order; ``"none"`` when they already are; None when no symmetry makes
        them so.
    order : str or None
        ``"noll"`` or ``"ansi"``: the order of the indices under ``transform``.
    noll_after_transform : numpy.ndarray or None
        ``(M,)`` Noll indices under ``transform`` (equal to ``noll`` for ``"none"``).
    n_pixels : int
        Pupil pixels the correlations were computed on.
    """

    noll: np.ndarray
    correlation: np.ndarray
    sign: np.ndarray
    second: np.ndarray
    is_zernike: np.ndarray
    threshold: float
    transform: str | None
    order: str | None
    noll_after_transform: np.ndarray | None
    n_pixels: int

    @property
    def n_modes(self) -> int:
        """Number of modes ``M``."""
        return int(self.noll.size)

    @property
    def all_zernike(self) -> bool:
        """Every mode matches a distinct Zernike above the threshold."""
        return bool(self.is_zernike.all()) and np.unique(self.noll).size == self.noll.size

    @property
    def is_standard(self) -> bool:
        """The modes are distinct ``+Z_j`` in our axes, in increasing Noll order."""
        return (
            self.all_zernike
            and bool(np.all(self.sign > 0))
            and bool(np.all(np.diff(self.noll) > 0))
        )

    def summary(self) -> str:
        """One line: what the modes are and which axis change, if any, was found."""
        if not self.is_zernike.any():
            return f"no mode matches a Zernike (|correlation| < {self.threshold:g})"
        lo, hi = int(self.noll.min()), int(self.noll.max())
        if self.is_standard:
            return f"Zernike Z{lo}-Z{hi} (Noll) in our convention, no sign or axis flip"
        parts = []
        n_z = int(self.is_zernike.sum())
        if n_z < self.n_modes:
            parts.append(f"{n_z} of {self.n_modes} modes are Zernikes")
        flipped = int(np.sum(self.sign[self.is_zernike] < 0))
        if flipped:
            parts.append(f"{flipped} with opposite sign")
        if self.transform is not None and self.transform != "none":
            after = self.noll_after_transform
            parts.append(
                f"axes differ from ours: after '{self.transform}' they are "
                f"Z{int(after.min())}-Z{int(after.max())} in {self.order} order, all positive"
            )
        elif self.transform == "none" and self.order == "ansi":
            parts.append("in ANSI order")
        elif self.transform is None:
            parts.append("no grid symmetry makes them a positive increasing Zernike sequence")
        return "; ".join(parts) if parts else "Zernikes, unordered"

    def table(self) -> str:
        """Plain-text table: mode, Noll index, (n, m), correlation, next best, verdict."""
        lines = [f"{'mode':>5}  {'noll':>5}  {'(n,m)':>8}  {'corr':>8}  {'next':>6}  match"]
        n, m = noll_to_zernike(self.noll)
        for k in range(self.n_modes):
            verdict = ("-" if not self.is_zernike[k]
                       else ("+Z" if self.sign[k] > 0 else "-Z") + str(int(self.noll[k])))
            lines.append(
                f"{k + 1:>5}  {int(self.noll[k]):>5}  {f'({int(n[k])},{int(m[k])})':>8}  "
                f"{self.correlation[k]:>8.4f}  {self.second[k]:>6.3f}  {verdict}"
            )
        lines.append(self.summary())
        return "\n".join(lines)

    def take(self, columns) -> ZernikeIdentification:
        """Return the identification of some modes in a new order (a column selection).

        A log whose columns were selected or reordered (``ModalLog.select``,
        ``to_convention``) kept its file's identification in the file's column order:
        after ``convert --convention ansi`` the table said column 1 was Z2 while it held
        Z3 (adversarial round 32 PART b, b12). ``transform`` / ``order`` are kept when the
        modes in the new order are still a positive increasing sequence under
        ``transform``, else set to None.

        Parameters
        ----------
        columns : sequence of int
            Indices of the modes kept, in their new order.

        Returns
        -------
        ZernikeIdentification
        """
        cols = np.asarray(columns, dtype=np.int64).reshape(-1)
        if cols.size and (cols.min() < 0 or cols.max() >= self.n_modes):
            raise ValueError(f"`columns` must be indices in [0, {self.n_modes}); got {columns!r}.")
        after = transform = order = None
        if self.noll_after_transform is not None:
            after = self.noll_after_transform[cols]
            order = _ordered(after) if cols.size else self.order
            transform = self.transform if order is not None else None
            after = after if order is not None else None
        return ZernikeIdentification(
            noll=self.noll[cols], correlation=self.correlation[cols], sign=self.sign[cols],
            second=self.second[cols], is_zernike=self.is_zernike[cols],
            threshold=self.threshold, transform=transform, order=order,
            noll_after_transform=after, n_pixels=self.n_pixels,
        )

    @classmethod
    def from_dict(cls, data: dict) -> ZernikeIdentification:
        """Rebuild an identification from :meth:`to_dict` (e.g. a log's metadata)."""
        try:
            after = data.get("noll_after_transform")
            corr = np.asarray(data["correlation"], dtype=np.float64)
            return cls(
                noll=np.asarray(data["noll"], dtype=np.int64),
                correlation=corr,
                sign=np.where(corr < 0, -1, 1),
                second=np.asarray(data["second"], dtype=np.float64),
                is_zernike=np.asarray(data["is_zernike"], dtype=bool),
                threshold=float(data["threshold"]),
                transform=data.get("transform"),
                order=data.get("order"),
                noll_after_transform=None if after is None else np.asarray(after, dtype=np.int64),
                n_pixels=int(data["n_pixels"]),
            )
        except (KeyError, TypeError, ValueError) as exc:
            raise ValueError(f"`data` is not a ZernikeIdentification dict: {exc!r}.") from exc

    def to_dict(self) -> dict:
        """JSON-serialisable form (plain lists, floats rounded to 6 digits)."""
        return {
            "noll": [int(j) for j in self.noll],
            "correlation": [round(float(c), 6) for c in self.correlation],
            "second": [round(float(c), 6) for c in self.second],
            "is_zernike": [bool(b) for b in self.is_zernike],
            "threshold": float(self.threshold),
            "transform": self.transform,
            "order": self.order,
            "noll_after_transform": (None if self.noll_after_transform is None
                                     else [int(j) for j in self.noll_after_transform]),
            "n_pixels": int(self.n_pixels),
            "summary": self.summary(),
        }


def _candidates(n_modes: int, max_noll: int | None) -> np.ndarray:
    """Noll indices to test: whole radial orders covering at least ``2 (M + 1)`` modes."""
    if max_noll is None:
        want = max(2 * (n_modes + 1), 21)
        order = 0
        while (order + 1) * (order + 2) // 2 < want:
            order += 1
        max_noll = (order + 1) * (order + 2) // 2
    return np.arange(1, max_noll + 1, dtype=np.int64)


def _match(f: np.ndarray, z: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Best Zernike per mode: (column index, signed correlation, next best |corr|)."""
    fn = np.linalg.norm(f, axis=0)
    zn = np.linalg.norm(z, axis=0)
    with np.errstate(invalid="ignore", divide="ignore"):
        corr = (f.T @ z) / np.outer(fn, zn)
    corr = np.nan_to_num(corr, nan=0.0)
    absc = np.abs(corr)
    best = np.argmax(absc, axis=1)
    rows = np.arange(corr.shape[0])
    c = corr[rows, best]
    absc[rows, best] = -1.0
    second = absc.max(axis=1) if absc.shape[1] > 1 else np.zeros(corr.shape[0])
    return best, c, np.maximum(second, 0.0)


def _ordered(noll: np.ndarray) -> str | None:
    if np.all(np.diff(noll) > 0):
        return "noll"
    ansi = np.asarray(noll_to_ansi(noll))
    if np.all(np.diff(ansi) > 0):
        return "ansi"
    return None


def identify_zernike(
    images, *, mask=None, threshold: float = 0.95, max_noll: int | None = None
) -> ZernikeIdentification:
    """Identify mode images as Noll Zernikes of the package convention.

    Parameters
    ----------
    images : array_like
        ``(M, h, w)`` mode images, zero or NaN outside the pupil.
    mask : array_like of bool, optional
        ``(h, w)`` pupil; default the images' support.
    threshold : float
        ``|correlation|`` from which a mode counts as a Zernike, in ``(0, 1]``.
    max_noll : int, optional
        Largest Noll index tested (default: whole radial orders holding at least
        ``max(2 (M + 1), 21)`` modes).

    Returns
    -------
    ZernikeIdentification

    Raises
    ------
    ValueError
        Images not ``(M, h, w)``, no pupil pixel, or a bad ``threshold``/``max_noll``.
    """
    arr = np.asarray(images)
    if arr.ndim != 3 or min(arr.shape) < 1:
        raise ValueError(f"`images` must be mode images (M, h, w); got shape {arr.shape}.")
    threshold = check_real(threshold, "threshold", minimum=0.0, maximum=1.0, strict_min=True)
    if max_noll is not None:
        max_noll = check_int(max_noll, "max_noll", minimum=1)
    if mask is None:
        mask = support_of(arr)
    mask = as_bool_mask(mask, "mask")
    if mask.shape != arr.shape[1:]:
        raise ValueError(f"`mask` must have the images' shape {arr.shape[1:]}; got {mask.shape}.")
    if not mask.any():
        raise ValueError("`images` have no pupil: every pixel is zero or NaN in every mode.")
    pupil = pupil_from_mask(mask)
    square = crop_images(arr, mask)
    square = np.where(np.isfinite(square), square, 0.0)
    cands = _candidates(arr.shape[0], max_noll)
    z = zernike_matrix(cands, pupil.rho_valid, pupil.theta_valid)

    def match(name):
        f = np.ascontiguousarray(TRANSFORMS[name](square)[:, pupil.mask].T)
        return _match(f, z)

    best, corr, second = base = match("none")
    noll = cands[best]
    is_z = np.abs(corr) >= threshold
    transform = order = after = None
    for name, fn in TRANSFORMS.items():
        if not np.array_equal(fn(pupil.mask), pupil.mask):
            continue  # the pupil itself is not symmetric under this map
        b, c, _ = base if name == "none" else match(name)  # lazily: "none" usually wins
        j = cands[b]
        if np.all(c >= threshold) and np.unique(j).size == j.size:
            kind = _ordered(j)
            if kind is not None:
                transform, order, after = name, kind, j
                break
    return ZernikeIdentification(
        noll=noll,
        correlation=corr,
        sign=np.where(corr < 0, -1, 1),
        second=second,
        is_zernike=is_z,
        threshold=float(threshold),
        transform=transform,
        order=order,
        noll_after_transform=after,
        n_pixels=int(pupil.n_valid),
    )
