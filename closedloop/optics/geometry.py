"""Geometry of the layer-oriented MCAO model: planes, grids, directions and footprints.

Every altitude that holds a turbulent layer or a DM is a *plane*. Each plane carries
one square phase grid with the pupil's pitch ``dx = D / n_pixels``, centred on the
optical axis at that altitude, large enough for every beam the simulation uses (science
directions and WFS field samples): it is that altitude's meta-pupil. A pupil point
``x`` looking in direction ``theta`` crosses plane ``p`` at ``x + h_p theta``; because
all planes share the pitch, the sub-pixel part of that shift is the same for every
pupil pixel, so one set of read weights serves a whole (direction, plane) pair.

Grids have the parity of ``n_pixels``, so the ground plane (``h = 0``) is read at whole
pixels (no interpolation at all). Altitudes and r0 follow the zenith angle ``z``:
``h -> h sec z`` and ``(D/r0)**(5/3) -> (D/r0)**(5/3) sec z``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

# the disc and meta-pupil sizes are config's (its checks need them, and geometry needs config)
from closedloop.config import ARCSEC, SimulationConfig, dm_disc_diameter, wfs_meta_pupil
from closedloop.config import airmass as _airmass

__all__ = ["ARCSEC", "Geometry", "field_samples", "science_directions", "plane_layout",
           "dm_disc_diameter", "wfs_meta_pupil"]

#: spare pixels around every beam (the science path's 4-tap reads and rounding)
_MARGIN = 3


def science_directions(size: float, n_points: int) -> np.ndarray:
    """Return the square science grid: ``(n_points**2, 2)`` directions ``(x, y)`` [arcsec].

    Row-major: direction ``i * n_points + j`` has ``y = v[i]``, ``x = v[j]`` with
    ``v = linspace(-size/2, size/2, n_points)``, so ``.reshape(n, n)`` is an image with
    x along columns and y along rows.
    """
    v = np.linspace(-size / 2.0, size / 2.0, n_points) if n_points > 1 else np.zeros(1)
    yy, xx = np.meshgrid(v, v, indexing="ij")
    return np.column_stack([xx.ravel(), yy.ravel()])


def field_samples(field_of_view: float, rings: int) -> np.ndarray:
    """Directions sampling a WFS's circular field: ``(n, 2)`` [arcsec].

    A hexagonal grid of ``rings`` rings (``1 + 3 r (r - 1)`` points) scaled so that its
    outer ring touches the field's edge; the points' mean is the field's centre.
    """
    if rings == 1 or field_of_view == 0.0:
        return np.zeros((1, 2))
    pts = []
    for q in range(-(rings - 1), rings):
        for r in range(-(rings - 1), rings):
            s = -q - r
            if max(abs(q), abs(r), abs(s)) <= rings - 1:
                pts.append((q + r / 2.0, r * math.sqrt(3.0) / 2.0))
    pts = np.array(pts)
    return pts * (field_of_view / 2.0) / (rings - 1)


def n_field_samples(field_of_view: float, rings: int) -> int:
    """Return how many directions :func:`field_samples` gives: ``1 + 3 r (r - 1)``, 1 on axis."""
    return 1 if rings == 1 or field_of_view == 0.0 else 1 + 3 * rings * (rings - 1)


def plane_layout(config: SimulationConfig) -> list[tuple[float, int, tuple, tuple]]:
    """``(altitude, n, layers, dms)`` of every plane, lowest first, without any grid.

    ``n`` is the plane's side in pixels: the farthest reach of any beam at that altitude
    (science corners, WFS fields, the DM's disc) plus a margin, with the parity of
    ``n_pixels`` (see :class:`Geometry`).
    """
    tel = config.telescope
    airmass = _airmass(config)
    dx = tel.diameter / tel.n_pixels
    half = config.field.size / 2.0 if config.field.n_points > 1 else 0.0
    sci = math.hypot(half, half) * ARCSEC  # farthest science direction (a grid corner)
    layer_alts = [float(layer.altitude) * airmass for layer in config.layers]
    dm_alts = [float(dm.altitude) * airmass for dm in config.dms]
    out = []
    for h in sorted(set(layer_alts) | set(dm_alts)):
        reach = tel.diameter / 2.0 + h * sci
        for w in config.wfss:
            hj = float(w.altitude) * airmass
            rho = w.field_of_view / 2.0 * ARCSEC
            reach = max(reach, tel.diameter / 2.0 + hj * rho + abs(h - hj) * rho)
        for i, hd in enumerate(dm_alts):
            if hd == h:
                reach = max(reach, dm_disc_diameter(config, i) / 2.0)
        n = 2 * math.ceil(reach / dx) + 2 * _MARGIN
        if n % 2 != tel.n_pixels % 2:
            n += 1
        out.append((h, n, tuple(i for i, a in enumerate(layer_alts) if a == h),
                    tuple(i for i, a in enumerate(dm_alts) if a == h)))
    return out


@dataclass(frozen=True)
class Plane:
    """One altitude's phase grid.

    Attributes
    ----------
    altitude : float
        Height along the line of sight [m] (zenith-corrected).
    n : int
        Pixels per side.
    layers : tuple of int
        Indices of the turbulent layers at this altitude.
    dms : tuple of int
        Indices of the DMs conjugated here.
    """

    altitude: float
    n: int
    layers: tuple[int, ...]
    dms: tuple[int, ...]

    @property
    def centre(self) -> float:
        """Fractional pixel index of the optical axis (both axes)."""
        return (self.n - 1) / 2.0


class Geometry:
    """Planes, pupil and directions of a configuration.

    Parameters
    ----------
    config : SimulationConfig

    Attributes
    ----------
    dx : float
        Grid pitch [m].
    pupil_mask : (N, N) bool
        Telescope pupil on the ``N = n_pixels`` grid.
    pupil_xy : (n_valid, 2) float
        Pupil pixel centres ``(x, y)`` [m] relative to the axis.
    directions : (n_dir, 2) float
        Science directions [arcsec].
    wfs_samples : list of (n_s, 2) arrays
        Field samples of each WFS [arcsec].
    planes : list of Plane
    layer_plane, dm_plane : list of int
        Plane index of each layer / DM.
    airmass : float
        ``sec z``.
    """

    def __init__(self, config: SimulationConfig):
        tel = config.telescope
        self.config = config
        self.diameter = tel.diameter
        self.n_pixels = tel.n_pixels
        self.dx = tel.diameter / tel.n_pixels
        self.airmass = 1.0 / math.cos(math.radians(tel.zenith_angle))
        c = (self.n_pixels - 1) / 2.0
        idx = (np.arange(self.n_pixels) - c) * self.dx
        yy, xx = np.meshgrid(idx, idx, indexing="ij")
        r = np.hypot(xx, yy) / (tel.diameter / 2.0)
        self._r = r
        self.pupil_mask = (r <= 1.0) & (r >= tel.obscuration)
        self.pupil_xy = np.column_stack([xx[self.pupil_mask], yy[self.pupil_mask]])
        self.directions = science_directions(config.field.size, config.field.n_points)
        self.wfs_samples = [field_samples(w.field_of_view, w.field_samples)
                            for w in config.wfss]
        planes = [Plane(altitude=h, n=n, layers=layers, dms=dms)
                  for h, n, layers, dms in plane_layout(config)]
        alts = [plane.altitude for plane in planes]
        self.planes = planes
        self.layer_plane = [alts.index(self.los(lay.altitude)) for lay in config.layers]
        self.dm_plane = [alts.index(self.los(dm.altitude)) for dm in config.dms]

    def disc_and_hole(self) -> tuple[np.ndarray, np.ndarray]:
        """Return the pupil's outer disc and its central hole, ``(N, N)`` bool each.

        ``pupil_mask`` is ``disc & ~hole``; both are convex (one span of columns per row);
        the hole is empty without obscuration.
        """
        return self._r <= 1.0, self._r < self.config.telescope.obscuration

    def los(self, altitude: float) -> float:
        """Distance along the line of sight [m] of a plane at ``altitude`` (zenith-corrected)."""
        return float(altitude) * self.airmass

    def layer_r0(self, i: int) -> float:
        """Fried parameter [m] of layer ``i`` along the line of sight (at ``r0_wavelength``).

        ``D / (D/r0)`` at the zenith, times ``sec(z)**(-3/5)``.
        """
        layer = self.config.layers[i]
        return self.diameter / layer.d_over_r0 * self.airmass ** (-0.6)

    def dm_diameter(self, i: int) -> float:
        """Return the controlled disc of DM ``i`` [m] (configured, or its WFS's meta-pupil)."""
        return dm_disc_diameter(self.config, i)

    def plane_coords(self, p: int) -> np.ndarray:
        """Pixel-centre coordinates of plane ``p`` along one axis [m]."""
        plane = self.planes[p]
        return (np.arange(plane.n) - plane.centre) * self.dx

    def pupil_shifts(self, directions: np.ndarray) -> np.ndarray:
        """Where each direction's pupil lands on each plane: ``(n_dir, n_planes, 2)``.

        Fractional pixel index (column, row) on plane ``p`` of the pupil pixel ``(0, 0)``
        (top-left of the ``n_pixels`` grid) for each direction [arcsec].
        """
        directions = np.asarray(directions, dtype=np.float64).reshape(-1, 2)
        out = np.empty((directions.shape[0], len(self.planes), 2))
        c = (self.n_pixels - 1) / 2.0
        for p, plane in enumerate(self.planes):
            shift = directions * ARCSEC * plane.altitude / self.dx  # pixels
            out[:, p, :] = plane.centre - c + shift
        return out
