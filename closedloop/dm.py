"""Deformable mirrors conjugated to an altitude, acting on their plane's meta-pupil.

A modal mirror (``kind="zernike"``) takes unit-RMS Noll Zernike shapes Z2 .. Z(M+1)
over its controlled disc (``modalinfo.bases.zernike_matrix``, evaluated at the plane's
pixel centres) and is flat outside: the shape is the matrix product ``B c``, done once
per command update (not per internal step). An ``"ideal"`` mirror is zonal: one
"mode" per pixel of its disc, so it can take any sampled shape (no fitting error); it
exists to verify the rest of the loop against Noll's and Fried's laws.

Why modal Zernike shapes: the paper's analysis library orders Zernike and K-L modes, so
the mirrors speak the same basis and their command logs are Zernike coefficients that
``modalinfo`` reads unchanged. A zonal influence-function model (Gaussian or cubic
actuators) would add the actuator-coupling fitting error; it is not modelled.
"""

from __future__ import annotations

import numpy as np

from closedloop.geometry import Geometry
from modalinfo.bases import zernike_matrix

__all__ = ["DeformableMirror"]


class DeformableMirror:
    """One DM on its plane.

    Parameters
    ----------
    geometry : Geometry
    index : int
        Which DM of the configuration.

    Attributes
    ----------
    plane : int
        Index of its plane in ``geometry.planes``.
    diameter : float
        Controlled disc [m].
    pixels : (n_disc,) int64
        Flat indices of the disc's pixels on the plane grid.
    shapes : (n_disc, M) float64 or None
        Mode shapes [rad per unit command] on those pixels (``None`` for an ideal DM: the
        identity).
    modes : list of int
        Noll indices of the modes (``[]`` for an ideal DM).
    n_modes : int
    """

    def __init__(self, geometry: Geometry, index: int):
        cfg = geometry.config.dms[index]
        self.index = index
        self.kind = cfg.kind
        self.altitude = geometry.los(cfg.altitude)
        self.plane = geometry.dm_plane[index]
        self.diameter = geometry.dm_diameter(index)
        coords = geometry.plane_coords(self.plane)
        yy, xx = np.meshgrid(coords, coords, indexing="ij")
        rho = np.hypot(xx, yy) / (self.diameter / 2.0)
        inside = rho <= 1.0
        self.pixels = np.flatnonzero(inside).astype(np.int64)
        if cfg.kind == "zernike":
            self.modes = list(range(2, cfg.n_modes + 2))
            self.shapes = np.ascontiguousarray(
                zernike_matrix(self.modes, rho[inside], np.arctan2(yy, xx)[inside]))
            self.n_modes = cfg.n_modes
        else:
            self.modes = []
            self.shapes = None
            self.n_modes = int(self.pixels.size)
        self.labels = ([f"Z{j}" for j in self.modes] if self.modes
                       else [f"pix{k}" for k in range(self.n_modes)])

    def surface(self, commands: np.ndarray) -> np.ndarray:
        """Mirror phase on its disc's pixels [rad], ``(n_disc,)``, for ``commands`` ``(M,)``."""
        if self.shapes is None:
            return np.asarray(commands, dtype=np.float64)
        return self.shapes @ commands
