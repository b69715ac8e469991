"""Sampled circular or annular pupil."""

from __future__ import annotations

import numpy as np

from modalinfo.common.memory import free_memory_bytes
from modalinfo.common.validation import as_float_array, check_int, check_real

__all__ = ["Pupil"]

#: float64 n x n grids a pupil holds or builds at once (x, y, rho, theta, their meshgrid
#: and hypot temporaries); the bool mask is smaller
_GRIDS = 6
#: Largest pupil diameter [m]: 10^4 x the 39 m ELT, so a diameter typed in um or nm
#: is refused rather than overflowing the pixel area (1e300 gave an OverflowError)
MAX_DIAMETER = 1e6


def _readonly(arr: np.ndarray) -> np.ndarray:
    arr.flags.writeable = False
    return arr


#: Accepted pupil diameters [m]: a microscope objective's (~1e-3) to far beyond a 39 m
#: ELT; within float64 for the pixel area (d / n)^2 at any grid
_DIAMETER_RANGE = (1e-6, MAX_DIAMETER)


class Pupil:
    """A circular or annular pupil sampled on an ``N x N`` pixel grid.

    Pixel ``(i, j)`` (row ``i``, column ``j``) has its centre at
    ``x = (j + 0.5 - N/2) D/N``, ``y = (i + 0.5 - N/2) D/N``: ``x`` runs along columns
    (axis 1), ``y`` along rows (axis 0), the grid is centred and ``N`` pixels span the
    diameter. A pixel is inside the pupil when its centre has
    ``obscuration <= rho <= 1``.

    Parameters
    ----------
    n_pixels : int
        Pixels across the diameter, ``N >= 8``.
    diameter : float
        Pupil diameter ``D`` [m], ``> 0``.
    obscuration : float
        Central obscuration as a fraction of the diameter, ``0 <= obscuration < 1``.

    Attributes
    ----------
    n_pixels : int
        ``N``.
    diameter : float
        ``D`` [m].
    obscuration : float
        Central obscuration ratio.
    x, y : numpy.ndarray
        ``(N, N)`` pixel-centre coordinates [m].
    rho : numpy.ndarray
        ``(N, N)`` radius normalised to 1 at the rim (``2 r / D``).
    theta : numpy.ndarray
        ``(N, N)`` azimuth ``atan2(y, x)`` [rad].
    mask : numpy.ndarray
        ``(N, N)`` bool, True inside the pupil.
    n_valid : int
        Number of pixels inside the pupil.
    rho_valid, theta_valid : numpy.ndarray
        ``(n_valid,)`` values at the pupil pixels, row-major (``rho[mask]``).
    pixel_area : float
        Area of one pixel [m^2].
    """

    __slots__ = (
        "n_pixels", "diameter", "obscuration", "x", "y", "rho", "theta", "mask", "n_valid",
        "rho_valid", "theta_valid", "pixel_area",
    )

    def __init__(self, n_pixels: int, diameter: float = 1.0, obscuration: float = 0.0) -> None:
        n = check_int(n_pixels, "n_pixels", minimum=8)
        d = check_real(diameter, "diameter", minimum=0.0, strict_min=True)
        if not _DIAMETER_RANGE[0] <= d <= _DIAMETER_RANGE[1]:
            # diameter 1e300 raised OverflowError (34, 'Numerical result out of range')
            # from the pixel area (audit 9, centre)
            raise ValueError(
                f"`diameter` must be in metres within {_DIAMETER_RANGE[0]:g} - "
                f"{_DIAMETER_RANGE[1]:g} (a microscope's pupil to far beyond a 39 m ELT); "
                f"got {d:g}.")
        obs = check_real(obscuration, "obscuration", minimum=0.0, maximum=1.0, strict_max=True)
        need = _GRIDS * 8.0 * n * n
        if need > free_memory_bytes():  # refuse before numpy's MemoryError, naming the option
            raise ValueError(f"`n_pixels` = {n} needs about {need / 2**30:.3g} GiB for its "
                             f"{_GRIDS} float64 {n} x {n} grids and "
                             f"{free_memory_bytes() / 2**30:.3g} GiB is free; use fewer pixels.")
        centres = (np.arange(n) + 0.5 - n / 2) * (d / n)
        x, y = np.meshgrid(centres, centres)  # x varies along axis 1, y along axis 0
        rho = np.hypot(x, y) / (d / 2)
        theta = np.arctan2(y, x)
        mask = (rho <= 1.0) & (rho >= obs)
        if not mask.any():
            # Pupil(8, obscuration=0.99) had 0 valid pixels and gave (0, M) "bases"
            raise ValueError(
                f"`obscuration` {obs:g} leaves no pixel of the {n} x {n} grid in the annulus "
                f"(pixel centres at radius >= {obs:g} and <= 1 of the pupil radius); use a "
                f"smaller obscuration or more pixels.")
        object.__setattr__(self, "n_pixels", n)
        object.__setattr__(self, "diameter", d)
        object.__setattr__(self, "obscuration", obs)
        object.__setattr__(self, "x", _readonly(x))
        object.__setattr__(self, "y", _readonly(y))
        object.__setattr__(self, "rho", _readonly(rho))
        object.__setattr__(self, "theta", _readonly(theta))
        object.__setattr__(self, "mask", _readonly(mask))
        object.__setattr__(self, "n_valid", int(mask.sum()))
        object.__setattr__(self, "rho_valid", _readonly(np.ascontiguousarray(rho[mask])))
        object.__setattr__(self, "theta_valid", _readonly(np.ascontiguousarray(theta[mask])))
        object.__setattr__(self, "pixel_area", (d / n) ** 2)

    def __setattr__(self, name, value):
        raise AttributeError(f"Pupil is immutable; cannot set `{name}`.")

    def __reduce__(self):
        return (Pupil, (self.n_pixels, self.diameter, self.obscuration))

    def __repr__(self) -> str:
        return (
            f"Pupil(n_pixels={self.n_pixels}, diameter={self.diameter!r}, "
            f"obscuration={self.obscuration!r})"
        )

    def __eq__(self, other: object) -> bool:
        if not isinstance(other, Pupil):
            return NotImplemented
        return (self.n_pixels, self.diameter, self.obscuration) == (
            other.n_pixels, other.diameter, other.obscuration
        )

    def __hash__(self) -> int:
        return hash((self.n_pixels, self.diameter, self.obscuration))

    def direction_cosines(self) -> tuple[np.ndarray, np.ndarray]:
        """``(cos theta, sin theta)`` at the pupil pixels, as ``x / r`` and ``y / r``.

        Exact mirrors at mirror pixels: a pixel and its reflection in either axis or in
        the diagonal ``x = y`` have the same ``r = hypot(x, y)`` and coordinates that
        differ in sign or order only, so their cosines and sines do too, bit for bit.
        ``cos(theta_valid)`` is not: ``arctan2`` of ``(-x, y)`` is ``pi - theta``
        rounded, and on a 64-pixel pupil 36 % of the pairs mirrored in ``x`` had cosines
        that differed in the last bit. The pixel at the centre (``r = 0``, odd ``N``)
        gets ``(1, 0)``, as ``arctan2(0, 0) = 0``.

        Returns
        -------
        cos_theta, sin_theta : numpy.ndarray
            ``(n_valid,)`` each, row-major like ``rho_valid``.
        """
        x = self.x[self.mask]
        y = self.y[self.mask]
        r = np.hypot(x, y)
        centre = r == 0
        r = np.where(centre, 1.0, r)
        return (np.ascontiguousarray(np.where(centre, 1.0, x / r)),
                np.ascontiguousarray(np.where(centre, 0.0, y / r)))

    def to_image(self, values) -> np.ndarray:
        """Scatter pupil-pixel vectors back into ``N x N`` images.

        Parameters
        ----------
        values : array_like
            ``(..., n_valid)`` values at the pupil pixels (row-major order of ``mask``).

        Returns
        -------
        numpy.ndarray
            ``(..., N, N)`` float images, NaN outside the pupil.

        Raises
        ------
        ValueError
            If the last axis is not ``n_valid`` long.
        """
        arr = as_float_array(values, "values", finite=False)
        if arr.ndim == 0 or arr.shape[-1] != self.n_valid:
            raise ValueError(
                f"`values` must have last axis of length n_valid={self.n_valid}; "
                f"got shape {arr.shape}."
            )
        out = np.full(arr.shape[:-1] + (self.n_pixels, self.n_pixels), np.nan)
        out[..., self.mask] = arr
        return out
