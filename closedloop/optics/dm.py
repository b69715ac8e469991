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
actuators) would add the actuator-coupling fitting error; it is not modelled here.

The two kinds are registered here (:data:`ZERNIKE`, :data:`IDEAL`,
:class:`closedloop.kinds.MirrorKind` records): their rules against the pupil grid and the
WFSs, their memory estimate and their AOT description sit beside their shapes.
"""

from __future__ import annotations

import math
from typing import ClassVar

import numpy as np

from closedloop.config import SimulationConfig, dm_disc_diameter, wfs_meta_pupil
from closedloop.kinds import (
    MirrorCost,
    MirrorKind,
    mirror_kind,
    register_mirror_kind,
    sensor_kind,
)
from closedloop.optics import _kernels
from closedloop.optics.geometry import Geometry
from modalinfo.bases import (
    noll_residual_variance,
    noll_to_zernike,
    zernike_covariance,
    zernike_matrix,
)
from modalinfo.bases.zernike import PIXELS_PER_CYCLE, max_zernike_order
from modalinfo.bases.zernike import check_zernike_sampling as _check_sampling

__all__ = ["DeformableMirror", "ZernikeMirror", "IdealMirror", "ZERNIKE", "IDEAL",
           "check_zernike_sampling", "check_zernike_subapertures"]

#: smallest ``B`` (bytes) synthesised from a quadrant: the gain is memory traffic, and a
#: ``B`` that stays in a core's L2 cache (1 MB here) costs ~0.05 ms as a plain product
#: either way; the product also keeps the bits of runs made before the quadrant path
#: (``data/kaos_closedloop.npz``, 0.5 MB of shapes, regenerates bit for bit)
_MIRROR_MIN_BYTES = 1_000_000


#: highest Zernike radial order a Shack-Hartmann drives, as a fraction of its subapertures
#: across the disc (:func:`check_zernike_subapertures`; measured, docs/CLOSEDLOOP.md)
SUBAPERTURE_ORDER_FRACTION = 0.9


class DeformableMirror:
    """One DM on its plane (base of every kind: its disc, its surface from a command).

    A kind is a subclass that sets :attr:`kind` and gives its shapes in ``_shapes``
    (None: zonal, the identity), registered as a :class:`closedloop.kinds.MirrorKind`.

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

    #: the config's ``dms[i].kind`` this class implements (the registry key)
    kind: ClassVar[str] = ""
    #: a loop with a mirror of this kind takes its large reconstructor products in float32
    #: and its large pseudo-inverses through the Gram matrix (closedloop.optics.products);
    #: False keeps the float64 products and SVDs (and the bits) of the earlier presets
    large_products: ClassVar[bool] = False

    def __init__(self, geometry: Geometry, index: int):
        cfg = geometry.config.dms[index]
        if cfg.kind != self.kind:
            raise ValueError(f"`geometry.config.dms[{index}].kind` must be {self.kind!r} for "
                             f"{type(self).__name__}; got {cfg.kind!r} (build it through "
                             "closedloop.kinds.mirror_kind(kind).build).")
        self.index = index
        self.altitude = geometry.los(cfg.altitude)
        self.plane = geometry.dm_plane[index]
        self.diameter = geometry.dm_diameter(index)
        coords = geometry.plane_coords(self.plane)
        yy, xx = np.meshgrid(coords, coords, indexing="ij")
        rho = np.hypot(xx, yy) / (self.diameter / 2.0)
        inside = rho <= 1.0
        self.pixels = np.flatnonzero(inside).astype(np.int64)
        self.modes, self.shapes = self._shapes(cfg, rho[inside], np.arctan2(yy, xx)[inside])
        self.n_modes = int(self.pixels.size if self.shapes is None else self.shapes.shape[1])
        self._mirror = self._synthesis_tables(len(coords))
        self.labels = self._labels()

    def _shapes(self, cfg, rho: np.ndarray, theta: np.ndarray):
        """Return ``(modes, shapes)``: mode labels' indices and ``(n_disc, M)`` shapes or None.

        ``rho``, ``theta``: the disc pixels' polar coordinates (units of the disc's radius,
        rad), in the order of :attr:`pixels`.
        """
        raise NotImplementedError(f"{type(self).__name__} must implement _shapes")

    def _synthesis_tables(self, n: int):
        """Tables of :meth:`forward`'s quadrant synthesis on the ``n x n`` plane (None: ``B c``).

        A kind whose ``forward`` does not read ``shapes`` returns None (nothing to build).
        """
        if self.shapes is None or self.shapes.nbytes < _MIRROR_MIN_BYTES:
            return None
        return _mirror_tables(self.pixels, self.shapes, n)

    def sensed_by(self, operator) -> np.ndarray:
        """Return what a linear sensor on the disc measures of each mode: ``operator @ shapes``.

        ``operator``: a sparse ``(rows, n_disc)`` map from the disc's pixel values (order
        of :attr:`pixels`) to measurements; returns dense ``(rows, M)`` (the interaction
        matrices, ``closedloop.optics.wfs``). A kind whose shapes factor through a sparse
        operator (actuators) overrides it with the cheaper product.
        """
        return np.asarray(operator @ self.shapes)

    def _labels(self) -> list[str]:
        """One label per mode (``Z<j>`` for Noll modes, ``pix<k>`` for a zonal mirror's pixels)."""
        return ([f"Z{j}" for j in self.modes] if self.modes
                else [f"pix{k}" for k in range(self.n_modes)])

    def prior_variance(self) -> np.ndarray:
        """Kolmogorov variance of each mode for ``D / r0 = 1`` over the disc, ``(n_modes,)``.

        The joint MAP reconstructor's prior (:class:`closedloop.model.LoopModel`, scaled by
        the turbulence assigned to this DM). Here for Noll-indexed Zernike modes (the
        diagonal of Noll's covariance, :func:`modalinfo.bases.zernike_covariance`); a kind
        whose shapes are not Noll Zernikes overrides it.
        """
        return np.diag(zernike_covariance(self.modes))

    def residual_variance(self) -> float:
        """Kolmogorov variance of the phase beyond its modes, ``D / r0 = 1`` over the disc [rad^2].

        What a perfect fit on the mirror's modes leaves (generalised fitting; an ideal
        sensor's model error, :meth:`closedloop.optics.wfs.IdealSensor.model_error_variance`).
        Here Noll's ``Delta_J`` after Noll modes up to ``max(modes)``
        (:func:`modalinfo.bases.noll_residual_variance`), 0 for a zonal mirror; a kind
        whose shapes are not Noll Zernikes overrides it.
        """
        if self.shapes is None:
            return 0.0
        return float(noll_residual_variance(max(self.modes)))

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


class ZernikeMirror(DeformableMirror):
    """Modal mirror: unit-RMS Noll Zernikes Z2 .. Z(n_modes + 1) over its disc (``"zernike"``)."""

    kind: ClassVar[str] = "zernike"

    def _shapes(self, cfg, rho, theta):
        modes = list(range(2, cfg.n_modes + 2))
        return modes, np.ascontiguousarray(zernike_matrix(modes, rho, theta))


class IdealMirror(DeformableMirror):
    """Zonal mirror: one "mode" per disc pixel, any sampled shape (``"ideal"``)."""

    kind: ClassVar[str] = "ideal"

    def _shapes(self, cfg, rho, theta):
        return [], None


def _modes_to_order(n_max: int) -> int:
    """Modes Z2 .. ZJ of radial order <= ``n_max`` (Noll, piston excluded)."""
    return (n_max + 1) * (n_max + 2) // 2 - 1


def check_zernike_sampling(cfg: SimulationConfig, i: int) -> None:
    """Refuse Zernike modes finer than the pupil grid can represent on DM ``i``'s disc.

    A Zernike of radial order ``n`` has ``n`` zero crossings across its disc: with fewer
    than :data:`PIXELS_PER_CYCLE` pixels per cycle (``n > pixels across / 2``) its
    sampled shape aliases onto lower modes and the DM's modes stop being independent.
    The rule is modalinfo's (:func:`modalinfo.bases.zernike.check_zernike_sampling`, one
    copy), applied to the whole pixels across the disc (``floor(across / 2) =
    floor(floor(across) / 2)``, so the edge is the same); this wrapper only names the
    config's fields in the refusal.
    """
    dm = cfg.dms[i]
    dx = cfg.telescope.diameter / cfg.telescope.n_pixels
    across = dm_disc_diameter(cfg, i) / dx
    pixels = int(across)
    try:
        _check_sampling([dm.n_modes + 1], pixels)  # modes Z2 .. Z(n_modes + 1)
    except ValueError as err:
        n_max = max_zernike_order(pixels)
        if n_max < 1:  # only a configured diameter can be this small (the meta-pupil >= D)
            raise ValueError(
                f"`dms[{i}].diameter` must be >= {PIXELS_PER_CYCLE} pupil pixels "
                f"({PIXELS_PER_CYCLE * dx:g} m at telescope.n_pixels = "
                f"{cfg.telescope.n_pixels}: a mirror narrower holds no mode); got "
                f"{dm.diameter!r}.") from err
        order = noll_to_zernike(dm.n_modes + 1)[0]
        raise ValueError(
            f"`dms[{i}].n_modes` must be <= {_modes_to_order(n_max)} (Zernike radial order "
            f"<= pixels across the DM's disc / {PIXELS_PER_CYCLE} = {n_max} for "
            f"{across:.0f} pixels at telescope.n_pixels = {cfg.telescope.n_pixels}; "
            f"{dm.n_modes} modes reach order {order}); got {dm.n_modes!r}.") from err
    check_zernike_subapertures(cfg, i)


def check_zernike_subapertures(cfg: SimulationConfig, i: int) -> None:
    """Refuse Zernike modes finer than the Shack-Hartmann that drives DM ``i`` resolves.

    ``N`` subapertures across the disc sample each slope at ``N`` points: at most ``N / 2``
    cycles across it (the SH's Nyquist frequency, ``1 / (2 pitch)``). A Zernike of radial
    order ``n`` has ``n`` zero crossings, ``n / 2`` cycles, across its disc, and more near
    the rim, where its oscillations crowd; so the SH's limit is ``n <= N`` at best, and the
    orders beyond are seen only as aliases of lower ones: their slopes are nearly
    combinations of other modes' slopes, the interaction matrix gains a near null space,
    and the least-squares reconstructor amplifies what the modes leave (aliasing) along
    it. Measured on issue 29's 4-m case (43 x 43 SH on 172 pixels; docs/CLOSEDLOOP.md,
    "4-m single conjugate: dkist-scao"), aliasing at 630 nm over fitting: 0.43 at order
    34, 1.6 at 38, 5.7 at 40 (a near null space: condition number 122 against ~50), 25 at
    43; 1,000 modes (order 44) do not close. On 344 pixels (8 per subaperture) order 44
    still gives 5.2 (the pupil's sampling multiplies the effect, the SH's near null space
    makes it). The rule is ``n <= 0.9 N``
    (:data:`SUBAPERTURE_ORDER_FRACTION`: 38 for N = 43, the last order measured without
    the null space; ``kaos``'s order 6 at N = 7 passes). Only the geometric Shack-Hartmann
    (``kind="shack_hartmann"``), the sensor it was measured with, is concerned (the
    correlating SH's Z-tilts were not measured); ``N`` counts its subapertures across the DM's
    disc (``n_subapertures`` span the WFS's meta-pupil, the DM's default disc); tip and
    tilt (order 1) always pass (one subaperture measures them).

    The rule rests on the least-squares reconstructor of one WFS for its DM (one DM, or a
    zonal DM beside it): a joint MAP reconstructor (several modal DMs,
    :class:`closedloop.model.LoopModel`) weights every direction by its prior, the small
    Noll variance of the high orders, and is not covered by this measurement. More modes
    than slopes are left to the slopes rule (``closedloop.config``), which names them.
    """
    dm = cfg.dms[i]
    j = next((j for j, w in enumerate(cfg.wfss) if w.dm == i), None)
    if j is None:
        return
    if cfg.wfss[j].kind != "shack_hartmann":  # the sensor the rule was measured with
        return
    count = sensor_kind(cfg.wfss[j].kind).measurement_count
    joint = len(cfg.dms) > 1 and all(mirror_kind(d.kind).controlled_modes is not None
                                     for d in cfg.dms)
    if joint or dm.n_modes > count(cfg, j):
        return
    w = cfg.wfss[j]
    across = w.n_subapertures * dm_disc_diameter(cfg, i) / wfs_meta_pupil(cfg, j)
    # tip and tilt (order 1) at least: one subaperture measures them
    n_max = max(1, int(SUBAPERTURE_ORDER_FRACTION * across + 1e-9))
    order = noll_to_zernike(dm.n_modes + 1)[0]
    if order > n_max:
        limit = _modes_to_order(n_max)
        raise ValueError(
            f"`dms[{i}].n_modes` must be <= {limit} (Zernike radial order <= "
            f"{SUBAPERTURE_ORDER_FRACTION:g} x the subapertures across the DM's disc, "
            f"{across:.4g} for wfss[{j}].n_subapertures = {w.n_subapertures}: the "
            f"Shack-Hartmann's Nyquist limit, less the rim where a Zernike's oscillations "
            f"crowd; beyond it the interaction matrix has a near null space that amplifies "
            f"aliasing: 1,000 modes on 43 x 43 subapertures, 28 x the fitting error, did not "
            f"close; {dm.n_modes} modes reach order {order}); got {dm.n_modes!r}.")


def _disc_pixels(config: SimulationConfig, i: int, dx: float) -> float:
    """Pixels of DM ``i``'s disc, ``pi / 4 (disc / dx)**2`` (no grid built)."""
    return math.pi / 4.0 * (dm_disc_diameter(config, i) / dx) ** 2


def _zernike_cost(config: SimulationConfig, i: int, dx: float) -> MirrorCost:
    # its (n_disc, M) shapes and the quadrant tables of the same size; M products per pixel
    n_disc = _disc_pixels(config, i, dx)
    m = config.dms[i].n_modes
    return MirrorCost(n_modes=m, shape_bytes=2.0 * 8.0 * n_disc * m, ops_per_pixel=m,
                      driver=f"dms[{i}].n_modes")


def _ideal_cost(config: SimulationConfig, i: int, dx: float) -> MirrorCost:
    # no shape matrix; one "mode" per disc pixel, one copy per pixel per update
    return MirrorCost(n_modes=_disc_pixels(config, i, dx), shape_bytes=0.0, ops_per_pixel=1,
                      driver="telescope.n_pixels")


def _zernike_aot(dm: DeformableMirror) -> dict:
    return {"model": "modal: each actuator is one mode, commands are modal coefficients "
                     "[rad at r0_wavelength]",
            "modes": f"Z{dm.modes[0]}..Z{dm.modes[-1]} (Noll)"}


def _ideal_aot(dm: DeformableMirror) -> dict:
    return {"model": "zonal (ideal): each actuator is one pixel of the disc", "modes": "pixels"}


#: the modal Zernike mirror
ZERNIKE = register_mirror_kind(MirrorKind(
    name="zernike", build=ZernikeMirror, estimate=_zernike_cost, aot_description=_zernike_aot,
    check=check_zernike_sampling, controlled_modes=lambda cfg, i: cfg.dms[i].n_modes))
#: the zonal mirror (verification; no fitting error)
IDEAL = register_mirror_kind(MirrorKind(
    name="ideal", build=IdealMirror, estimate=_ideal_cost, aot_description=_ideal_aot))


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
