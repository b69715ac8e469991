"""A deformable mirror of actuators, controlled through its DM-space K-L modes.

The mirror the telescopes of issue 29 are built with (DKIST's 1,600-actuator DM, EST's
adaptive secondary and altitude DMs): Gaussian influence functions on a square grid
(:class:`modalinfo.bases.InfluenceFunctions`: coupling 0.35 at the neighbour as OOPAO,
valid actuators by illumination), conjugated to any altitude, where it covers its
plane's controlled disc (the meta-pupil of its WFS's field) with actuators at the
telescope's pitch.

**Commands are K-L coefficients**, as peers control such mirrors (OOPAO's
``M2C_KL``, COMPASS's ``KL2V``): ``n_modes`` DM-space K-L modes
(:func:`modalinfo.bases.dm_kl_modes`: DM's best tip and tilt first, then the von Karman
prior diagonalised in the DM metric, piston removed), unit RMS over the disc. The
strokes are ``m2c @ commands`` (dense ``(n_actuators, n_modes)``, 20 MB at 1,584 x 1,583)
and the surface is the separable banded influence operator applied to them
(:meth:`modalinfo.bases.InfluenceFunctions.surface`), never a dense
``(pixels x modes)`` product per frame: the loop's logs, prior and reconstructor stay
modal, and the command log is a :class:`modalinfo.bases.DMKLBasis`'s coefficients.

The class has the interface of :class:`closedloop.optics.dm.DeformableMirror`
(``index, kind, altitude, plane, diameter, pixels, shapes, modes, n_modes, labels,
reset(), forward(commands)``) plus what a modal prior needs (``prior_variances``) and
what a sparse interaction matrix needs (``influence``, ``m2c``).
"""

from __future__ import annotations

import functools
import math

import numpy as np

from closedloop.optics.geometry import Geometry
from modalinfo.bases import DMKLBasis, InfluenceFunctions, MaskedPupil, dm_kl_modes
from modalinfo.bases.influence import DEFAULT_COUPLING, DEFAULT_THRESHOLD, DEFAULT_TRUNCATION

__all__ = ["ActuatorDeformableMirror"]


class ActuatorDeformableMirror:
    """One DM of actuators on its plane, commanded in DM-space K-L coefficients.

    Parameters
    ----------
    geometry : Geometry
    index : int
        Which DM of the configuration (``geometry.config.dms[index]``; its ``n_modes``
        is the number of K-L modes controlled, at most ``n_valid - 1``).
    n_actuators : int, optional
        Actuators across the telescope's pupil diameter; default the DM's WFS's
        ``n_subapertures + 1`` (Fried geometry: actuators on the subaperture corners).
    pitch : float, optional
        Actuator pitch [m] at the DM's plane; default ``D / (n_actuators - 1)``.
    coupling, truncation, threshold : float
        Influence-function options of :class:`modalinfo.bases.InfluenceFunctions`.
    outer_scale : float, optional
        ``L0`` [m] of the K-L prior; default that of the configuration's strongest layer.

    Attributes
    ----------
    plane : int
        Index of its plane in ``geometry.planes``.
    diameter : float
        Controlled disc [m].
    pixels : (n_disc,) int64
        Flat indices of the disc's pixels on the plane grid.
    influence : InfluenceFunctions
        The actuators on the disc (grid of ``n_grid`` across the disc).
    m2c : (n_valid, n_modes) float64
        Strokes [rad] of each K-L mode.
    prior_variances : (n_modes,) float64
        Von Karman variance of each mode in units of ``(diameter / r0)**(5/3) rad^2``.
    modes : list of int
        ``[]``: the modes are not Zernikes.
    n_modes : int
    labels : list of str
        ``"DMKL1"``, ...
    """

    kind = "actuators"

    def __init__(self, geometry: Geometry, index: int, *, n_actuators: int | None = None,
                 pitch: float | None = None, coupling: float = DEFAULT_COUPLING,
                 truncation: float = DEFAULT_TRUNCATION, threshold: float = DEFAULT_THRESHOLD,
                 outer_scale: float | None = None):
        cfg = geometry.config
        dm_cfg = cfg.dms[index]
        self.index = index
        self.altitude = geometry.los(dm_cfg.altitude)
        self.plane = geometry.dm_plane[index]
        self.diameter = geometry.dm_diameter(index)
        n = geometry.planes[self.plane].n
        coords = geometry.plane_coords(self.plane)
        yy, xx = np.meshgrid(coords, coords, indexing="ij")
        inside = np.hypot(xx, yy) <= self.diameter / 2.0
        self.pixels = np.flatnonzero(inside).astype(np.int64)
        if n_actuators is None:
            wfs = [w for w in cfg.wfss if w.dm == index]
            n_actuators = (wfs[0].n_subapertures if wfs else 16) + 1
        if pitch is None:
            pitch = geometry.diameter / (n_actuators - 1)
        # the grid spans the disc at the telescope's pitch (a meta-pupil needs more
        # actuators across than the pupil), centred on the axis
        n_grid = max(int(n_actuators), int(math.ceil(self.diameter / pitch - 1e-9)) + 1)
        # the influence functions live on the disc's bounding square (centred on the
        # plane's centre, so its pixel centres are the plane's): the prior's FFTs scale
        # with it, not with the plane (twice as wide at altitude in table1)
        used = np.flatnonzero(inside.any(axis=0))
        lo, hi = int(used[0]), int(used[-1]) + 1
        if lo + hi != n:  # pragma: no cover - a centred disc is symmetric
            lo, hi = 0, n
        pupil = MaskedPupil(inside[lo:hi, lo:hi], diameter=(hi - lo) * geometry.dx)
        self.influence = InfluenceFunctions(pupil, n_grid, pitch, coupling=coupling,
                                            truncation=truncation, threshold=threshold)
        if outer_scale is None:
            outer_scale = _strongest_outer_scale(geometry)
        self.outer_scale = float(outer_scale)
        n_modes = min(int(dm_cfg.n_modes), self.influence.n_valid - 1)
        # r0 = the disc's diameter: variances in units of (diameter / r0)**(5/3)
        self.m2c, self.prior_variances = dm_kl_modes(self.influence, self.diameter,
                                                     self.outer_scale, n_modes=n_modes)
        self.m2c.flags.writeable = False
        self.prior_variances.flags.writeable = False
        self.n_modes = n_modes
        self.modes: list[int] = []
        self.labels = [f"DMKL{k + 1}" for k in range(n_modes)]

    @functools.cached_property
    def shapes(self) -> np.ndarray:
        """Mode surfaces on the disc's pixels, dense ``(n_disc, n_modes)`` [rad per unit].

        Built on first access (for interaction matrices); ``forward`` never uses it.
        """
        out = np.ascontiguousarray(self.influence.matrix @ self.m2c)
        out.flags.writeable = False
        return out

    def basis(self) -> DMKLBasis:
        """Return the modes as a :class:`modalinfo.bases.DMKLBasis` on the disc (logs, MI)."""
        return DMKLBasis(self.influence, self.m2c, self.prior_variances, self.labels)

    def reset(self) -> None:
        """Nothing to reset: a mirror's surface is a function of its command (no state)."""

    def strokes(self, commands: np.ndarray) -> np.ndarray:
        """Actuator strokes [rad] ``(n_valid,)`` for K-L ``commands`` ``(n_modes,)``."""
        return self.m2c @ np.asarray(commands, dtype=np.float64)

    def forward(self, commands: np.ndarray) -> np.ndarray:
        """Mirror phase on its disc's pixels [rad], ``(n_disc,)``, for ``commands`` ``(M,)``."""
        return self.influence.surface(self.strokes(commands))


def _strongest_outer_scale(geometry: Geometry) -> float:
    """``L0`` of the layer with the largest ``(D / r0)**(5/3)`` (inf without layers)."""
    layers = geometry.config.layers
    if not layers:
        return math.inf
    k = int(np.argmax([lay.d_over_r0 for lay in layers]))
    return float(layers[k].outer_scale)
