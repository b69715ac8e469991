"""Deformable mirrors conjugated to an altitude, acting on their plane's meta-pupil.

A modal mirror (``kind="zernike"``) takes unit-RMS Noll Zernike shapes Z2 .. Z(M+1)
over its controlled disc (``modalinfo.bases.zernike_matrix``, evaluated at the plane's
pixel centres) and is flat outside: the shape is the matrix product ``B c``, done once
per command update (not per internal step). When the disc's pixels are symmetric about
both axes (an even plane side, the usual case) and ``B`` exceeds 1 MB, ``B c`` is
synthesised from one quadrant (:func:`closedloop.optics._kernels.mirror_synthesis`): every
Zernike is even or odd in x and in y, so a quarter of ``B`` is read, which matters
because ``B`` (3 MB for 119 modes on a 64-pixel disc) streams from memory at every
command. An ``"ideal"`` mirror is zonal: one
"mode" per pixel of its disc, so it can take any sampled shape (no fitting error); it
exists to verify the rest of the loop against Noll's and Fried's laws. It holds no shape
matrix (``shapes`` is None: the identity is implicit, its surface is its command vector),
and a sensor's interaction with it is a sparse matrix
(:meth:`closedloop.optics.wfs.WavefrontSensor.interaction_with`): dense, either would be
``(pixels x pixels)``, 200 MB at 80 pixels across.

Why modal Zernike shapes: the paper's analysis library orders Zernike and K-L modes, so
the mirrors speak the same basis and their command logs are Zernike coefficients that
``modalinfo`` reads unchanged. A zonal influence-function model (Gaussian or cubic
actuators) would add the actuator-coupling fitting error; it is not modelled.
"""

from __future__ import annotations

import numpy as np

from closedloop.optics import _kernels
from closedloop.optics.geometry import Geometry
from modalinfo.bases import zernike_matrix

__all__ = ["DeformableMirror"]

#: smallest ``B`` (bytes) synthesised from a quadrant: the gain is memory traffic, and a
#: ``B`` that stays in a core's L2 cache (1 MB here) costs ~0.05 ms as a plain product
#: either way; the product also keeps the bits of runs made before the quadrant path
#: (``data/kaos_closedloop.npz``, 0.5 MB of shapes, regenerates bit for bit)
_MIRROR_MIN_BYTES = 1_000_000


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
        self._mirror = (None if self.shapes is None or self.shapes.nbytes < _MIRROR_MIN_BYTES
                        else _mirror_tables(self.pixels, self.shapes, len(coords)))
        self.labels = ([f"Z{j}" for j in self.modes] if self.modes
                       else [f"pix{k}" for k in range(self.n_modes)])

    def reset(self) -> None:
        """Nothing to reset: a mirror's surface is a function of its command (no state)."""

    def forward(self, commands: np.ndarray) -> np.ndarray:
        """Mirror phase on its disc's pixels [rad], ``(n_disc,)``, for ``commands`` ``(M,)``."""
        if self.shapes is None:
            return np.asarray(commands, dtype=np.float64)
        if self._mirror is None:
            return self.shapes @ commands
        quad_t, starts, signs, order, positions, acc = self._mirror
        c = np.ascontiguousarray(np.asarray(commands, dtype=np.float64)[order])
        out = np.empty(self.pixels.size)
        _kernels.mirror_synthesis(quad_t, starts, signs, c, positions, acc, out)
        return out


def _mirror_tables(pixels: np.ndarray, shapes: np.ndarray, n: int):
    """Tables of :func:`closedloop.optics._kernels.mirror_synthesis` (None: use ``B c``).

    None if the disc is not mirror-symmetric or a mode has no definite parity.
    ``pixels``: flat indices on the ``n x n`` plane; the quadrant is rows and columns
    ``>= n / 2`` (an even ``n`` puts no pixel on an axis).
    """
    if n % 2:
        return None
    rows, cols = pixels // n, pixels % n
    where = -np.ones(n * n, dtype=np.int64)
    where[pixels] = np.arange(pixels.size)
    quad = np.flatnonzero((rows >= n // 2) & (cols >= n // 2))
    r, c = rows[quad], cols[quad]
    positions = np.stack([where[r * n + c], where[r * n + (n - 1 - c)],
                          where[(n - 1 - r) * n + c], where[(n - 1 - r) * n + (n - 1 - c)]])
    if positions.min() < 0 or 4 * quad.size != pixels.size:
        return None
    base = shapes[positions[0]]
    tol = 1e-9 * np.max(np.abs(base), axis=0)
    odd = np.empty((2, shapes.shape[1]), dtype=bool)
    for axis, image in enumerate((positions[1], positions[2])):
        mirrored = shapes[image]
        even_ = np.all(np.abs(mirrored - base) <= tol, axis=0)
        odd[axis] = np.all(np.abs(mirrored + base) <= tol, axis=0)
        if not np.all(even_ ^ odd[axis]):
            return None
    # class g = (odd in x) + 2 (odd in y); modes keep their order inside a class
    klass = odd[0].astype(np.int64) + 2 * odd[1].astype(np.int64)
    order = np.argsort(klass, kind="stable")
    starts = np.searchsorted(klass[order], np.arange(5)).astype(np.int64)
    # image k flips x if k & 1 and y if k & 2 (the order of ``positions``), class g is
    # odd in x if g & 1 and in y if g & 2: one sign change per flip along an odd axis
    bit = np.array([0, 1, 0, 1])
    signs = (-1.0) ** (np.outer(bit, bit) + np.outer(bit[[0, 0, 1, 1]], bit[[0, 0, 1, 1]]))
    quad_t = np.ascontiguousarray(base[:, order].T)
    return (quad_t, starts, np.ascontiguousarray(signs), order, positions,
            np.empty((4, quad.size)))
