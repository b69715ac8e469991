"""A modal basis from mode images sampled on a grid (e.g. the ``modes`` of an AOT loop).

Files describe their modes as images ``(M, h, w)``: zero (or NaN) outside the
pupil. :func:`pupil_from_mask` turns the images' support into a :class:`Pupil`
(the circular/annular :class:`Pupil` itself when the support is exactly one, else a
:class:`MaskedPupil` holding the mask), and :func:`basis_from_images` samples the
images on it into a :class:`ModalBasis`. Geometry follows the package convention:
``x`` along columns (axis 1), ``y`` along rows (axis 0), the pupil centred on the
support's bounding box, whose larger side spans the diameter.
"""

from __future__ import annotations

import numpy as np

from modalinfo.bases.basis import ModalBasis
from modalinfo.bases.pupil import MAX_DIAMETER, Pupil, _readonly
from modalinfo.common.validation import as_bool_mask, as_float_array, check_real

__all__ = ["MaskedPupil", "pupil_from_mask", "support_of", "basis_from_images"]


class MaskedPupil(Pupil):
    """A pupil of arbitrary shape: a boolean mask on an ``N x N`` grid.

    Coordinates are those of :class:`Pupil` (pixel centres, ``x`` along columns, ``y``
    along rows, centred on the grid, ``N`` pixels across ``diameter``); ``rho`` is
    normalised to 1 at ``diameter / 2``. Use it for pupils that are not a centred
    disc or annulus (spiders, segments, vignetting).

    Parameters
    ----------
    mask : array_like of bool
        ``(N, N)`` True inside the pupil; at least one pixel.
    diameter : float
        Diameter ``D`` [m] spanned by the ``N`` pixels, ``> 0``.
    """

    __slots__ = ()

    def __init__(self, mask, diameter: float = 1.0) -> None:  # noqa: D107
        m = np.asarray(mask)
        if m.ndim != 2 or m.shape[0] != m.shape[1] or m.shape[0] < 2:
            raise ValueError(f"`mask` must be a square 2-D array (N, N), N >= 2; got {m.shape}.")
        if m.dtype != bool:
            raise TypeError(f"`mask` must be boolean; got dtype {m.dtype}.")
        if not m.any():
            raise ValueError("`mask` must hold at least one pupil pixel; got none.")
        d = check_real(diameter, "diameter", minimum=0.0, strict_min=True,
                       maximum=MAX_DIAMETER)
        n = m.shape[0]
        centres = (np.arange(n) + 0.5 - n / 2) * (d / n)
        x, y = np.meshgrid(centres, centres)
        rho = np.hypot(x, y) / (d / 2)
        theta = np.arctan2(y, x)
        mask = np.array(m, dtype=bool)
        values = {
            "n_pixels": n, "diameter": d, "obscuration": 0.0, "x": _readonly(x),
            "y": _readonly(y), "rho": _readonly(rho), "theta": _readonly(theta),
            "mask": _readonly(mask), "n_valid": int(mask.sum()),
            "rho_valid": _readonly(np.ascontiguousarray(rho[mask])),
            "theta_valid": _readonly(np.ascontiguousarray(theta[mask])),
            "pixel_area": (d / n) ** 2,
        }
        for name, value in values.items():
            object.__setattr__(self, name, value)

    def __reduce__(self):
        return (MaskedPupil, (np.array(self.mask), self.diameter))

    def __repr__(self) -> str:
        return (f"MaskedPupil(n_pixels={self.n_pixels}, diameter={self.diameter!r}, "
                f"n_valid={self.n_valid})")

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Pupil):
            return NotImplemented
        return (self.n_pixels == other.n_pixels and self.diameter == other.diameter
                and bool(np.array_equal(self.mask, other.mask)))

    def __hash__(self) -> int:
        return hash((self.n_pixels, self.diameter, self.n_valid))


def support_of(images, *, name: str = "images") -> np.ndarray:
    """Return the support of mode images: pixels finite in every image, non-zero in one.

    Parameters
    ----------
    images : array_like
        ``(M, h, w)`` or ``(h, w)`` images.
    name : str
        Argument name for error messages.

    Returns
    -------
    numpy.ndarray
        ``(h, w)`` bool.

    Raises
    ------
    ValueError
        Images not ``(M, h, w)`` or ``(h, w)``, or a pixel non-finite in some images and
        non-zero in another (a dead pixel inside the pupil, named with its mode).
    """
    arr = np.asarray(images)
    if arr.ndim == 2:
        arr = arr[None]
    if arr.ndim != 3:
        raise ValueError(f"`{name}` must be images (M, h, w); got shape {arr.shape}.")
    finite = np.isfinite(arr)
    live = np.any(finite & (arr != 0), axis=0)
    # a pixel non-finite in some modes but non-zero in another is a dead pixel inside the
    # pupil, not its outside: dropping it from every mode changed the pupil without a
    # word (round 53 PART a, O11 / O12)
    mixed = live & ~np.all(finite, axis=0)
    if mixed.any():
        r, c = (int(i) for i in np.argwhere(mixed)[0])
        bad = np.flatnonzero(~finite[:, r, c])
        raise ValueError(
            f"`{name}` mode {int(bad[0])} is not finite at pixel ({r}, {c}), where the "
            f"other {arr.shape[0] - bad.size} mode(s) are finite and not all zero: a dead "
            f"or unread pixel inside the pupil ({int(mixed.sum())} such pixel(s) in all); "
            "repair it, or give "
            "`mask` without it to leave it out of every mode.")
    return np.all(finite, axis=0) & live


def pupil_from_mask(mask, diameter: float = 1.0) -> Pupil:
    """Return the pupil of a support mask: a :class:`Pupil` if it is one exactly.

    The mask is cropped to the square around its bounding box (centred, side the
    larger extent). If that square's mask equals ``Pupil(N, diameter, obscuration)``
    for the obscuration read from the mask's central hole, that :class:`Pupil` is
    returned; otherwise a :class:`MaskedPupil`.

    Parameters
    ----------
    mask : array_like of bool
        ``(h, w)`` True inside the pupil.
    diameter : float
        Diameter [m] of the pupil (the bounding box's larger side), ``> 0``.

    Returns
    -------
    Pupil
        ``Pupil`` or ``MaskedPupil``.
    """
    square, _ = _square_crop(as_bool_mask(mask, "mask"))
    d = check_real(diameter, "diameter", minimum=0.0, strict_min=True, maximum=MAX_DIAMETER)
    n = square.shape[0]
    if n >= 8:
        disc = Pupil(n, diameter=d)
        if np.array_equal(disc.mask, square):
            return disc
        # an annulus: every pixel from the innermost one out to the rim
        inner = float(disc.rho[square].min())
        if 0.0 < inner < 1.0:
            annulus = Pupil(n, diameter=d, obscuration=inner)
            if np.array_equal(annulus.mask, square):
                return annulus
    return MaskedPupil(square, diameter=d)


def _square_crop(mask: np.ndarray) -> tuple[np.ndarray, tuple[slice, slice, int, int]]:
    """Crop ``mask`` to the square centred on its bounding box (zero-padded if needed).

    Returns the square mask and ``(rows, cols, pad_row, pad_col)``: the slices of the
    original array taken and the offsets at which they land in the square.
    """
    if mask.ndim != 2 or not mask.any():
        raise ValueError(f"`mask` must be 2-D with at least one pupil pixel; got {mask.shape}.")
    rows = np.flatnonzero(mask.any(axis=1))
    cols = np.flatnonzero(mask.any(axis=0))
    r0, r1, c0, c1 = rows[0], rows[-1] + 1, cols[0], cols[-1] + 1
    side = max(r1 - r0, c1 - c0)
    if side < 2:
        # MaskedPupil's "(N, N), N >= 2; got (1, 1)" named the crop, not the array the
        # user passed (adversarial round 19 PART a, p12)
        raise ValueError(f"`mask` must span at least 2 pixels across; its one pupil pixel "
                         f"fits in a 1 x 1 box of the {mask.shape} mask.")
    # grow the shorter side symmetrically (half-pixel asymmetry goes to the end)
    rs = r0 - (side - (r1 - r0)) // 2
    cs = c0 - (side - (c1 - c0)) // 2
    out = np.zeros((side, side), dtype=bool)
    src_r = slice(max(rs, 0), min(rs + side, mask.shape[0]))
    src_c = slice(max(cs, 0), min(cs + side, mask.shape[1]))
    pr, pc = src_r.start - rs, src_c.start - cs
    out[pr:pr + src_r.stop - src_r.start, pc:pc + src_c.stop - src_c.start] = mask[src_r, src_c]
    return out, (src_r, src_c, pr, pc)


def crop_images(images, mask) -> np.ndarray:
    """Crop ``(M, h, w)`` images to the square of :func:`pupil_from_mask` (zero padding)."""
    arr = np.asarray(images)
    square, (src_r, src_c, pr, pc) = _square_crop(as_bool_mask(mask, "mask"))
    side = square.shape[0]
    out = np.zeros(arr.shape[:-2] + (side, side), dtype=np.float64)
    out[..., pr:pr + src_r.stop - src_r.start, pc:pc + src_c.stop - src_c.start] = arr[
        ..., src_r, src_c
    ]
    return out


def basis_from_images(images, *, mask=None, diameter: float = 1.0, labels=None) -> ModalBasis:
    """Build a :class:`ModalBasis` from mode images on their own pupil.

    Parameters
    ----------
    images : array_like
        ``(M, h, w)`` mode images (values per unit coefficient; zero or NaN outside
        the pupil).
    mask : array_like of bool, optional
        ``(h, w)`` pupil mask; default: the images' support (``support_of``).
    diameter : float
        Pupil diameter [m] (the mask's bounding box, larger side), ``> 0``.
    labels : sequence of str, optional
        ``M`` mode names (default ``"mode1"``...).

    Returns
    -------
    ModalBasis
        Columns ``images[k][pupil.mask]`` after cropping to the pupil's square.

    Raises
    ------
    ValueError
        Images that are not ``(M, h, w)``, a mask of another shape or with no pixel,
        a non-finite value inside the mask, a zero mode or linearly dependent modes.
    """
    arr = np.asarray(images)
    if arr.ndim != 3 or min(arr.shape) < 1:
        raise ValueError(f"`images` must be mode images (M, h, w); got shape {arr.shape}.")
    if arr.dtype.kind not in "fiu":
        raise TypeError(f"`images` must be numeric; got dtype {arr.dtype}.")
    if mask is None:
        mask = support_of(arr)
    else:
        mask = np.asarray(mask)
        if mask.shape != arr.shape[1:]:
            raise ValueError(
                f"`mask` must have the images' shape {arr.shape[1:]}; got {mask.shape}."
            )
        mask = mask.astype(bool)
    if not mask.any():
        raise ValueError("`images` have no pupil: every pixel is zero or NaN in every mode.")
    pupil = pupil_from_mask(mask, diameter)
    cropped = crop_images(arr, mask)
    matrix = as_float_array(cropped[:, pupil.mask].T, "images inside the pupil", ndim=2)
    _check_independent(matrix)
    return ModalBasis(matrix, pupil, labels, _copy=False)


def _check_independent(matrix: np.ndarray) -> None:
    """Refuse a zero mode or linearly dependent modes (a mode exported twice, say).

    They made a basis of fewer modes than it claims: a fitting error of its truncations
    and MI orderings of modes that are one and the same (adversarial round 9, rows
    bz-from-images-dup, bz-from-images-zero). Dependent: the smallest eigenvalue of the
    Gram matrix of the unit-norm modes below 1e-12 of the largest (a singular-value ratio
    of 1e-6; one (M, M) product, cheaper than an SVD of the images).
    """
    norms = np.linalg.norm(matrix, axis=0)
    zero = np.flatnonzero(norms == 0)
    if zero.size:
        raise ValueError(f"`images` mode {int(zero[0])} is zero everywhere inside the pupil; "
                         "a basis needs every mode to be a nonzero phase map.")
    m = matrix.shape[1]
    unit = matrix / norms
    gram = unit.T @ unit
    eig = np.linalg.eigvalsh(gram)
    if m > matrix.shape[0] or eig[0] <= 1e-12 * eig[-1]:
        g = np.abs(gram) - np.eye(m)
        i, j = np.unravel_index(int(np.argmax(g)), g.shape)
        pair = (f" (modes {min(i, j)} and {max(i, j)} are proportional)"
                if g[i, j] > 1.0 - 1e-9 else "")
        raise ValueError(f"`images` are linearly dependent: {m} modes on "
                         f"{matrix.shape[0]} pupil pixels{pair}; a basis needs independent "
                         "modes.")
