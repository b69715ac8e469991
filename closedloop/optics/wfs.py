"""Multiple-field-of-view layer-oriented wavefront sensors (geometric Shack-Hartmann).

WFS ``j`` is conjugated to altitude ``h_j`` and co-adds the light of its field (a disc
of diameter ``field_of_view``, sampled by a hexagonal set of directions ``theta_s``).
A point ``u`` of its conjugate plane, seen from direction ``theta_s``, carries the phase
``sum_p r_p(u + (h_p - h_j) theta_s)``, where ``r_p`` is the residual (turbulence minus
DMs) on plane ``p``: its own altitude's residual is seen sharply by every direction, the
others shifted by an amount that grows with the altitude difference, so averaging over
the field blurs them (Ragazzoni et al. 2002, A&A 396, 731). The light reaches ``u`` from
``theta_s`` only if it passed through the telescope pupil, ``|u - h_j theta_s| <= D/2``
(and outside the central obscuration): the co-addition counts only those beams.

Shack-Hartmann (``kind="shack_hartmann"``): ``n_subapertures`` across the sensed
meta-pupil (diameter ``D + 2 h_j tan(field/2)``). A subaperture's slope is the mean
phase gradient over its illuminated part (the G-tilt), averaged over the field; a
correlating SH on granulation measures the Z-tilt instead (Loefdahl 2010; see
``closedloop.optics.correlating``), equal to it for tilts and differing by coma-like
terms. Here: the mean over the subaperture's
square of the phase gradient, the phase taken linear between pixel centres along the
slope's axis and constant across each pixel, written as a weighted mean of the
pixel-pair differences ``(phi(u + dx) - phi(u)) / dx``, each weighted by the share of
its ``dx x dx`` cell that lies in the subaperture (:func:`_window_entries`; a pair
straddling an edge counts in both neighbours by its share, so the window is centred on
the subaperture; until issue 17 such pairs all went to the right-hand one, a window
offset by half a pixel, with 1.3-1.5 times the single-conjugate aliasing), over every
illuminated (pair, direction). A subaperture is used when some direction lights at
least half of the weight of a fully illuminated one (:func:`field_rule`: the whole
meta-pupil of a sensor at altitude; until issue 27 half lit on average over the field,
which dropped the meta-pupil's outer ring); a sensor conjugated off the pupil uses only
the pairs ``sqrt(2)`` pixels inside the pupil's edge (:func:`pupil_lit`), the valid set
and the shares coming from the beam's true light. Each slope gets white Gaussian noise
(``noise`` arcsec RMS, converted to a phase gradient ``2 pi alpha / lambda``, divided by
the square root of the subaperture's light share: fewer photons where fewer directions
light it or they light less of it, :func:`lit_noise_variance`). A least-squares modal
reconstructor (SVD pseudo-inverse of the interaction matrix of the WFS's own DM,
weighted by the inverse noise variances, modes with singular values
below 1e-3 of the largest dropped) gives the modal residual. Aliasing (high orders
leaking into the measured low orders) and noise propagation come out of this model;
nothing is added by hand.

Ideal (``kind="ideal"``): the field-averaged residual on the DM's disc is projected on
the DM's modes by least squares; no aliasing (up to the projection's own) and no noise.

The whole sensor is a fixed linear map from the plane maps to the slopes, built once as
scipy sparse matrices (one per plane), so a measurement is a few sparse products (a numba
kernel, :func:`closedloop.optics._kernels.csr_matvec`, with the same bits as scipy's product).

The two kinds are registered here (:data:`SHACK_HARTMANN`, :data:`IDEAL`,
:class:`closedloop.kinds.SensorKind` records): their rules against the pupil grid, their
memory estimate and their AOT records sit beside their classes.
"""

from __future__ import annotations

import functools
import math
from typing import ClassVar

import numpy as np
from scipy import sparse

from closedloop.config import (
    SimulationConfig,
    dm_disc_diameter,
    valid_subapertures,
    wfs_meta_pupil,
)
from closedloop.kinds import SensorCost, SensorKind, register_sensor_kind
from closedloop.optics import _kernels, products
from closedloop.optics.dm import DeformableMirror
from closedloop.optics.geometry import ARCSEC, Geometry, n_field_samples

__all__ = ["WavefrontSensor", "ShackHartmann", "IdealSensor", "SHACK_HARTMANN", "IDEAL",
           "bilinear_matrix", "field_rule", "lit_noise_variance", "metapupil_note", "pupil_lit",
           "has_noise", "check_subaperture_sampling", "slope_count", "slopes_aot_record",
           "slopes_aot_layout", "index_grid"]

#: pupil pixels per Shack-Hartmann subaperture (a gradient needs two)
PIXELS_PER_SUBAPERTURE = 2


def has_noise(noise_rms) -> bool:
    """Return whether a sensor's ``noise_rms`` (float or array) is > 0 anywhere.

    A float is compared directly (the hot loop's usual case: no numpy call per frame).
    """
    if isinstance(noise_rms, float):
        return noise_rms > 0.0
    return bool(np.any(np.asarray(noise_rms) > 0.0))


#: margin inside the pupil's edge, in pupil pixels, of the samples a sensor conjugated off
#: the pupil uses (:func:`pupil_lit`): a bilinear sample reaches one pixel either way
EDGE_MARGIN_PIXELS = math.sqrt(2.0)


def pupil_lit(geometry: Geometry, x: np.ndarray, margin: float = 0.0) -> np.ndarray:
    """Return which pupil-plane points ``x`` [m] ``(..., 2)`` the beam lights, ``margin`` inside.

    Inside the telescope pupil (and outside its central obscuration) by ``margin`` [m].
    A sensor conjugated to altitude reads the ground plane between its pixels (bilinear):
    a sample within ``sqrt(2) dx`` of the pupil's edge mixes the ground DM's edge pixels
    with the zeros beyond its disc, a step the turbulence does not have, and a slope turns
    it into a spurious gradient (the upper WFS "sees" the ground DM's edge). The
    correlating SH has kept the margin since issue 20; the geometric SH at altitude since
    issue 27 (:func:`field_rule`: the meta-pupil's ring, lit by few directions, is made of
    such edges). ``margin = 0`` is the plain pupil (a pupil-conjugated sensor reads the
    ground plane at its pixels).
    """
    r = np.hypot(x[..., 0], x[..., 1])
    obscuration = geometry.config.telescope.obscuration
    if margin == 0.0:
        r = r / (geometry.diameter / 2.0)
        return (r <= 1.0) & (r >= obscuration)
    lit = r <= geometry.diameter / 2.0 - margin
    if obscuration > 0:
        lit &= r >= obscuration * geometry.diameter / 2.0 + margin
    return lit


def metapupil_note(d_wfs: float, diameter: float, altitude: float, field_of_view: float,
                   pitch: float) -> str:
    """Return the meta-pupil's part of a "no valid subaperture" refusal, or ``""``.

    Round 31: a field too wide for its sensor's altitude (600" at 20 km: a 62-m meta-pupil
    cut into 8 subapertures of 7.8 m for a 4-m pupil) was refused with the obscuration's
    reading only. ``""`` where the meta-pupil is the pupil (``d_wfs <= diameter`` [m]).
    """
    if d_wfs <= diameter:
        return ""
    return (f", over a meta-pupil of {d_wfs:.4g} m = D + 2 h tan(field / 2) (altitude = "
            f"{altitude:g} m, field_of_view = {field_of_view:g} arcsec): a pitch of "
            f"{pitch:.4g} m for a pupil of D = {diameter:g} m")


def field_rule(total: np.ndarray, best: np.ndarray, n_directions: int,
               full: float) -> tuple[np.ndarray, np.ndarray]:
    """Return the valid subapertures of a layer-oriented sensor and their light shares.

    A sensor conjugated to altitude ``h`` and co-adding a field sees a meta-pupil of
    diameter ``D + 2 h tan(field / 2)``; a subaperture of its outer ring is lit by some
    directions only. It is kept when *some* direction lights at least half of it
    (``best >= 0.5 full``), the single-conjugate half-lit rule applied direction by
    direction: the layer-oriented MCAO sensors' whole meta-pupil (Ragazzoni, Farinato &
    Marchetti 2000, Proc. SPIE 4007, 1076; MAD's layer-oriented WFS, Marchetti et al.
    2003), over which the DM's modes are defined. Averaged over the directions instead
    (the rule until issue 27), the ring was dropped and the modes extrapolated there
    (docs/CLOSEDLOOP.md, "A DM conjugated to a high layer").

    Its light share, ``total / (n_directions * full)``, is the light it collects over
    that of a subaperture every direction lights whole: the part of the field's
    directions that light it times the lit part of its area (a subaperture lit over a
    fraction ``f`` of its area collects ``f`` of the photons: Rousset 1999; Hardy 1998,
    ch. 5). 1 inside the pupil, about 1/2 on a half-lit edge subaperture of a
    ground-conjugated sensor, 1/n times its lit fraction for one lit by one direction of
    ``n``. Until left31-edge it was ``total / (n_directions * best)``, the directions'
    part only: a half-lit pupil-edge subaperture counted as a fully lit one. A slope's
    photon-noise variance grows as ``1 / share`` (read noise over the same pixels as
    ``1 / share**2``: :func:`lit_noise_variance`), and so does the variance of what it
    sees beyond the DMs' modes (the small-scale signal averaged over less area and fewer
    directions); the reconstructors weigh each measurement by its inverse variance
    (Wallner 1983; Ellerbroek 2002).

    Parameters
    ----------
    total : (n_sub,) ndarray
        Lit weight of each subaperture summed over the directions.
    best : (n_sub,) ndarray
        Its largest lit weight from one direction.
    n_directions : int
        Directions co-added.
    full : float
        Lit weight of a fully lit subaperture from one direction.

    Returns
    -------
    valid : (n_valid,) ndarray of int
        Indices of the valid subapertures.
    share : (n_valid,) ndarray
        Their light share, in ``(0, 1]``.
    """
    valid = np.flatnonzero(best >= 0.5 * full)
    share = total[valid] / (n_directions * full)
    # lit whole by every direction: exactly 1, not the rounding of a sum of n equal terms
    # over n times one of them
    share[share > 1.0 - 1e-9] = 1.0
    return valid, share


def lit_noise_variance(share: np.ndarray, read_fraction: float = 0.0) -> np.ndarray:
    """Slope-noise variance of a subaperture collecting ``share`` of a fully lit one's light.

    Relative to the fully lit subaperture's. A centroid's (or correlation shift's) noise
    variance is ``(S + R) / S**2`` up to the image's shape, with ``S`` the signal and
    ``R`` the read-noise variance of its pixels (Rousset 1999; Hardy 1998, ch. 5):
    collecting ``s S`` on the same pixels it is ``(s S + R) / (s S)**2``, so the ratio is
    ``(1 - r) / s + r / s**2`` with ``r = R / (S + R)`` the read noise's part of the fully
    lit variance: ``1 / s`` photon-noise limited, ``1 / s**2`` read-noise limited.

    Parameters
    ----------
    share : (n,) ndarray
        Light share (:func:`field_rule`), in ``(0, 1]``.
    read_fraction : float
        ``r``, in ``[0, 1]``: 0 for the geometric SH's ``noise`` (taken photon-limited).

    Returns
    -------
    (n,) ndarray
        Variance over the fully lit subaperture's (1 where ``share`` is 1).
    """
    share = np.asarray(share, dtype=float)
    return (1.0 - read_fraction) / share + read_fraction / share ** 2


def bilinear_matrix(cols: np.ndarray, rows: np.ndarray, n: int) -> sparse.csr_matrix:
    """Sparse ``(n_points, n*n)`` bilinear interpolation on an ``n x n`` grid.

    ``cols``/``rows`` are fractional pixel indices; points must lie in ``[0, n-1]``.
    """
    ic = np.floor(cols).astype(np.int64)
    ir = np.floor(rows).astype(np.int64)
    ic = np.minimum(ic, n - 2)
    ir = np.minimum(ir, n - 2)
    if ic.size and (ic.min() < 0 or ir.min() < 0):
        raise ValueError("a beam leaves its plane's grid (internal geometry error).")
    tc = cols - ic
    tr = rows - ir
    base = ir * n + ic
    data = np.concatenate([(1 - tr) * (1 - tc), (1 - tr) * tc, tr * (1 - tc), tr * tc])
    colidx = np.concatenate([base, base + 1, base + n, base + n + 1])
    rowidx = np.tile(np.arange(cols.size), 4)
    return sparse.csr_matrix((data, (rowidx, colidx)), shape=(cols.size, n * n))


def _window_entries(start: np.ndarray, axis: int, dx: float, d_wfs: float, n_sub: int):
    """Weights of the pixel-pair differences in the subapertures' mean gradients.

    The pair ``(u, u + dx e_axis)`` carries the derivative along ``axis`` of the phase
    taken linear along ``axis`` between the two pixel centres and constant across the
    pixel's width: a ``dx x dx`` cell centred on the pair's midpoint. Its weight in
    subaperture ``S`` is the area of that cell inside ``S`` over ``dx**2`` (its overlap
    along ``axis`` times its overlap across). With these weights the sum over pairs of
    ``weight * difference / dx``, over ``(pitch / dx)**2``, is exactly the mean over ``S``
    of that phase's gradient: centred on ``S`` (a pair straddling an edge counts in both
    subapertures by its share), exact for planes, and for quadratics where the edges
    sit symmetrically on the grid.

    Parameters
    ----------
    start : (n_pairs, 2) ndarray
        ``(x, y)`` of each pair's first pixel [m], relative to the sensed meta-pupil's centre.
    axis : int
        0 for x-slopes, 1 for y-slopes.
    dx : float
        Grid pitch [m].
    d_wfs : float
        Side of the square of subapertures [m].
    n_sub : int
        Subapertures across.

    Returns
    -------
    pair, sub, weight : (n_entries,) ndarrays
        Pair index, subaperture index ``row * n_sub + column``, and weight (> 0).
    """
    pitch = d_wfs / n_sub
    s = start[:, axis] + d_wfs / 2.0      # cell [s, s + dx] along the slope's axis
    y = start[:, 1 - axis] + d_wfs / 2.0  # and [y - dx/2, y + dx/2] across it
    i0 = np.floor(s / pitch).astype(np.int64)
    j0 = np.floor((y - dx / 2.0) / pitch).astype(np.int64)
    pairs, subs, weights = [], [], []
    for ka in range(int(math.ceil(dx / pitch)) + 1):
        i = i0 + ka
        along = np.clip(np.minimum(s + dx, (i + 1) * pitch) - np.maximum(s, i * pitch),
                        0.0, None) / dx
        for kc in range(int(math.ceil(dx / pitch)) + 1):
            j = j0 + kc
            across = np.clip(np.minimum(y + dx / 2.0, (j + 1) * pitch)
                             - np.maximum(y - dx / 2.0, j * pitch), 0.0, None) / dx
            w = along * across
            ok = (w > 1e-12) & (i >= 0) & (i < n_sub) & (j >= 0) & (j < n_sub)
            idx = np.flatnonzero(ok)
            col, row = (i[idx], j[idx]) if axis == 0 else (j[idx], i[idx])
            pairs.append(idx)
            subs.append(row * n_sub + col)
            weights.append(w[idx])
    return np.concatenate(pairs), np.concatenate(subs), np.concatenate(weights)


class WavefrontSensor:
    """One layer-oriented WFS and its reconstructor onto its DM's modes (base of every kind).

    A kind is a subclass that sets :attr:`kind` and builds :attr:`operators` in
    ``_build`` (and, for a noisy sensor, :attr:`noise_rms`), registered as the ``build``
    of a :class:`closedloop.kinds.SensorKind`; ``closedloop.model.LoopModel`` builds the
    kind the config names through the registry. The
    measurement path (:meth:`forward`, sparse products), the interaction matrix and the
    least-squares reconstructor are shared. It implements
    :class:`closedloop.parts.Sensor`.

    Parameters
    ----------
    geometry : Geometry
    index : int
        Which WFS of the configuration.
    dm : DeformableMirror
        The DM it drives.
    rcond : float
        Singular values below ``rcond`` times the largest are dropped from the
        reconstructor's pseudo-inverse.

    Attributes
    ----------
    operators : list of scipy.sparse.csr_matrix
        ``(n_meas, n_p**2)`` per plane: measurement = ``sum_p operators[p] @ r_p.ravel()``.
    reconstructor : (M, n_meas) ndarray
        Measurements to modal residual [rad per measurement unit].
    interaction : (n_meas, M) ndarray or scipy.sparse.csr_matrix
        Measurements of a unit command of each mode of its own DM (sparse for a zonal
        DM, see :meth:`interaction_with`), built on first use.
    noise_rms : float or (n_meas,) ndarray
        Per-measurement noise [rad / m for a SH; 0 for ideal]; an array when the
        measurements differ in noise (the correlating SH's slopes and tracker, a
        layer-oriented SH's meta-pupil ring).
    field_share : (n_meas,) ndarray or None
        Each measurement's light share (``field_rule``; a SH's only): the light its
        subaperture collects over a fully lit one's, 1 where every direction lights all
        of it.
    n_valid_subapertures : int
    """

    #: the config's ``wfss[j].kind`` this class implements (the registry key)
    kind: ClassVar[str] = ""
    #: margin inside the pupil's edge of the lit samples [m] (:func:`pupil_lit`)
    _edge_margin: float = 0.0

    def __init__(self, geometry: Geometry, index: int, dm: DeformableMirror, *,
                 rcond: float = 1e-3):
        cfg = geometry.config.wfss[index]
        if cfg.kind != self.kind:
            raise ValueError(f"`geometry.config.wfss[{index}].kind` must be {self.kind!r} for "
                             f"{type(self).__name__}; got {cfg.kind!r} (build it through "
                             "closedloop.kinds.sensor_kind(kind).build).")
        self.index = index
        self.altitude = geometry.los(cfg.altitude)
        self.samples = geometry.wfs_samples[index]
        self.dm = dm
        self._geometry = geometry
        self._centred = False
        self.noise_rms = 0.0
        self.field_share = None
        self._build(cfg)
        # the operators' CSR arrays as the matvec kernel takes them (unsigned columns)
        self._csr = [(op.indptr.astype(np.int64), op.indices.astype(np.uint32),
                      np.ascontiguousarray(op.data, dtype=np.float64))
                     for op in self.operators]
        self._rcond = rcond

    @functools.cached_property
    def interaction(self):
        """Interaction with its own DM, :meth:`interaction_with` ``(dm)``, built on first use.

        Read by the reconstructors (:attr:`reconstructor`, ``LoopModel``'s joint one); the
        budget's streamed ideal sensors never read it, so they never form this dense
        block (up to ~1 GB at 4-m size).
        """
        return self.interaction_with(self.dm)

    @functools.cached_property
    def reconstructor(self) -> np.ndarray | None:
        """Least-squares reconstructor onto its own DM's modes, built on first use.

        ``(M, n_meas)``, or None (a zonal DM's identity). A model with a joint MAP
        reconstructor (several DMs) never reads it, so its SVD is not paid there (at
        4-m size the pseudo-inverse of a 2,900 x 1,500 interaction matrix is ~5 s).
        """
        return self._least_squares(self._rcond)

    @property
    def rcond(self) -> float:
        """The reconstructor's cut: singular values below ``rcond`` times the largest drop."""
        return self._rcond

    @property
    def unseen_modes(self) -> int | None:
        """Modes of its own DM the reconstructor drops: the sensor does not see them.

        The singular values of the interaction matrix (modes to measurements, weighted
        as the reconstructor weighs it) at or below :attr:`rcond` times the largest:
        ``M - rank``, numpy's ``matrix_rank(G, tol=rcond * s_max)``. A mode finer than the
        subaperture pitch aliases onto coarser ones (round 47 PART a, Z06: 2,900 modes of
        a 61 x 61 DM on a 48 x 48 SH). Builds :attr:`reconstructor` if not yet built.
        None for a zonal DM (``shapes`` None): its "modes" are disc pixels, which no
        sensor resolves one by one; its pseudo-inverse is the minimum-norm command by
        design, and the config's modes <= slopes rule does not apply to it either.
        """
        if self.dm.shapes is None or self.reconstructor is None:
            return None
        return self._unseen

    def _build(self, cfg) -> None:
        """Set ``operators`` and ``n_measurements`` (and ``noise_rms``) for this kind."""
        raise NotImplementedError(f"{type(self).__name__} must implement _build")

    @property
    def _weighted(self) -> bool:
        """Whether the measurements differ in light share (``field_rule``): weigh them."""
        return self.field_share is not None and bool(np.min(self.field_share) < 1.0)

    def _inverse_variance_weights(self) -> np.ndarray:
        """Each measurement's inverse variance relative to a fully lit one (its light share)."""
        return 1.0 / lit_noise_variance(self.field_share)

    def _least_squares(self, rcond: float) -> np.ndarray | None:
        """Pseudo-inverse of the interaction matrix with its own DM.

        Weighted by each measurement's inverse noise variance (its light share,
        ``field_rule``) when they differ: ``(S^1/2 G)^+ S^1/2``.
        """
        inter = self.interaction
        inter = inter.toarray() if sparse.issparse(inter) else inter
        root = np.sqrt(self._inverse_variance_weights())[:, None] if self._weighted else None
        if root is not None:
            inter = root * inter
        if self.dm.large_products and 8.0 * inter.size >= products.GRAM_MIN_BYTES:
            r, kept = products.gram_pinv(inter, lambda s0: rcond * s0)
        else:
            r, kept = products.svd_pinv(inter, rcond)
        # the modes the pseudo-inverse drops: M less its kept singular values (a null
        # space too when M > n_meas); counted here, where the SVD is paid once
        self._unseen = inter.shape[1] - kept
        return r if root is None else r * root.T

    def reset(self) -> None:
        """Nothing to reset: a sensor's measurement is a fixed linear map (no state)."""

    def model_error_variance(self, r0s: list[float], model_error: float):
        """Extra noise per measurement the joint MAP reconstructor assumes (model error).

        See :class:`closedloop.model.LoopModel`. ``r0s``: each layer's Fried parameter [m]
        at the phase wavelength; ``model_error``: ``loop.model_error``. A float (the same
        for every measurement) or an ``(n_measurements,)`` array.
        """
        raise NotImplementedError(f"{type(self).__name__} must implement model_error_variance")

    # ------------------------------------------------------------------ building
    def _illuminated(self, u: np.ndarray, theta: np.ndarray,
                     margin: float | None = None) -> np.ndarray:
        """Which points ``u`` [m] are lit from ``theta`` [arcsec] (``margin``: the sensor's)."""
        return pupil_lit(self._geometry, u - self.altitude * theta * ARCSEC,
                         self._edge_margin if margin is None else margin)

    def _sample_matrix(self, p: int, points: np.ndarray, theta: np.ndarray):
        """Bilinear operator on plane ``p`` for points ``u`` (m) seen from ``theta`` (arcsec)."""
        g = self._geometry
        plane = g.planes[p]
        shift = (plane.altitude - self.altitude) * theta * ARCSEC
        pos = (points + shift) / g.dx + plane.centre
        return bilinear_matrix(pos[:, 0], pos[:, 1], plane.n)

    # ------------------------------------------------------------------ measuring
    def forward(self, plane_maps: list[np.ndarray],
                noise: np.ndarray | None = None) -> np.ndarray:
        """Measurements from the residual maps of every plane, ``(n_measurements,)``.

        ``noise``: standard normal draws ``(n_measurements,)`` scaled here by ``noise_rms``.
        """
        s = self._operate(plane_maps)
        if noise is not None and has_noise(self.noise_rms):
            s += self.noise_rms * noise
        if self._centred:
            s -= s.mean()
        return s

    def _operate(self, plane_maps: list[np.ndarray]) -> np.ndarray:
        """``sum_p operators[p] @ r_p`` by the sparse kernel (``(operators rows,)``)."""
        if len(plane_maps) != len(self._csr):
            raise ValueError(f"`plane_maps` must hold {len(self._csr)} maps; "
                             f"got {len(plane_maps)}.")
        # s = operators[0] @ r_0, then s += operators[p] @ r_p: scipy's arithmetic
        s = np.empty(self.operators[0].shape[0])
        for p, (indptr, indices, data) in enumerate(self._csr):
            x = np.ascontiguousarray(plane_maps[p], dtype=np.float64).reshape(-1)
            if x.size != self.operators[p].shape[1]:
                raise ValueError(f"`plane_maps[{p}]` must have {self.operators[p].shape[1]} "
                                 f"pixels; got {x.size}.")
            _kernels.csr_matvec(indptr, indices, data, x, s, p > 0)
        return s

    def interaction_with(self, dm: DeformableMirror):
        """Measurements of a unit command of each mode of ``dm``: ``(n_measurements, M_dm)``.

        A dense ndarray for a modal DM; a ``scipy.sparse.csr_matrix`` for a zonal
        (``"ideal"``) DM, whose "modes" are its disc's pixels: as a dense array that block
        is ``(pixels x pixels)``, 200 MB at 80 pixels across, and mostly zeros (each
        measurement reads a few pixels per field sample). ``_centred`` only applies to a
        modal DM, so the sparse block is never centred.
        """
        block = self.operators[dm.plane][:, dm.pixels]
        if dm.shapes is None:
            return sparse.csr_matrix(block)
        out = dm.sensed_by(block)
        return out - out.mean(axis=0) if self._centred else out


class ShackHartmann(WavefrontSensor):
    """Geometric Shack-Hartmann (``kind="shack_hartmann"``, see the module docstring)."""

    kind: ClassVar[str] = "shack_hartmann"

    def _build(self, cfg) -> None:
        self.noise_rms = 2.0 * math.pi * cfg.noise * ARCSEC / self._geometry.config.r0_wavelength
        g = self._geometry
        if self.altitude != 0.0:  # reads the ground plane between its pixels (pupil_lit)
            self._edge_margin = EDGE_MARGIN_PIXELS * g.dx
        d_wfs = g.diameter + 2.0 * self.altitude * math.tan(cfg.field_of_view / 2.0 * ARCSEC)
        n_sub = cfg.n_subapertures
        pitch = d_wfs / n_sub
        self.pitch = pitch
        plane = g.planes[self.dm.plane]
        coords = g.plane_coords(self.dm.plane)
        # pixel pairs: start pixel (i, j) and its +x / +y neighbour
        jj, ii = np.meshgrid(np.arange(plane.n - 1), np.arange(plane.n - 1), indexing="xy")
        start = np.column_stack([coords[jj.ravel()], coords[ii.ravel()]])
        n_samples = len(self.samples)
        full = None
        # the (measurement, pair) weights of every (axis, direction), kept (one entry per
        # lit pair) so that the planes' operators are then assembled one plane at a time
        weighted = []
        for axis in (0, 1):
            step = np.zeros(2)
            step[axis] = g.dx
            pair, sub, weight = _window_entries(start, axis, g.dx, d_wfs, n_sub)
            if full is None:
                full = np.bincount(sub, weights=weight, minlength=n_sub * n_sub).max()
            # counts: weight of the pairs used (inside the margin); light, best: of the
            # pairs the beam lights (the plain pupil), for the valid set and the shares
            counts = np.zeros(n_sub * n_sub)
            light = np.zeros(n_sub * n_sub) if self._edge_margin else counts
            best = np.zeros(n_sub * n_sub)
            entries = []
            for theta in self.samples:
                lit = (self._illuminated(start, theta)
                       & self._illuminated(start + step, theta))[pair]
                entries.append((theta, pair[lit], sub[lit], weight[lit]))
                one = np.bincount(sub[lit], weights=weight[lit], minlength=n_sub * n_sub)
                counts += one
                if self._edge_margin:
                    lit = (self._illuminated(start, theta, 0.0)
                           & self._illuminated(start + step, theta, 0.0))[pair]
                    one = np.bincount(sub[lit], weights=weight[lit], minlength=n_sub * n_sub)
                    light += one
                np.maximum(best, one, out=best)
            if axis == 0:
                self.valid_subapertures, share = field_rule(light, best, n_samples, full)
                self.field_share = np.concatenate([share, share])
                if not self.valid_subapertures.size:  # nothing measured: no loop
                    obsc = self._geometry.config.telescope.obscuration
                    field = metapupil_note(d_wfs, g.diameter, self.altitude,
                                           cfg.field_of_view, pitch)
                    raise ValueError(
                        f"`wfss[{self.index}].n_subapertures` = {n_sub} leaves no valid "
                        f"subaperture (half lit or more) on this pupil (telescope."
                        f"obscuration = {obsc:g}{field}): the sensor would measure nothing; "
                        "use more subapertures" + (", a smaller obscuration" if obsc > 0
                                                   else "")
                        + (", a smaller field or a lower altitude" if field else ""))
                meas_index = -np.ones(n_sub * n_sub, dtype=np.int64)
                meas_index[self.valid_subapertures] = np.arange(self.valid_subapertures.size)
            n_valid = self.valid_subapertures.size
            for theta, lit_pair, lit_sub, lit_w in entries:
                keep = meas_index[lit_sub] >= 0
                lit_pair, lit_sub, lit_w = lit_pair[keep], lit_sub[keep], lit_w[keep]
                # the pairs this direction uses, once each; W: (measurement, pair) weights
                used, col = np.unique(lit_pair, return_inverse=True)
                row = meas_index[lit_sub] + axis * n_valid
                w = sparse.csr_matrix((lit_w / (counts[lit_sub] * g.dx), (row, col)),
                                      shape=(2 * n_valid, used.size))
                weighted.append((theta, start[used], step, w))
            del entries
        self.n_valid_subapertures = int(self.valid_subapertures.size)
        self.n_measurements = 2 * self.n_valid_subapertures
        if self._weighted:  # fewer photons where less of it is lit (field_rule)
            self.noise_rms = self.noise_rms * np.sqrt(lit_noise_variance(self.field_share))
        # one plane at a time: the (axis, direction) terms of a plane only are held
        # before they are summed into its CSR (all planes' terms at once were 7 GiB at
        # est-mcao's size, closedloop.resources); each plane's entries come in the same
        # (axis, direction) order as before, so the sums and their bits are unchanged
        self.operators = [self._plane_operator(p, weighted) for p in range(len(g.planes))]

    def _plane_operator(self, p: int, weighted: list) -> sparse.csr_matrix:
        """Plane ``p``'s ``(n_measurements, n_p**2)`` operator from the weighted pair terms."""
        g = self._geometry
        rows, cols, data = [], [], []
        for theta, points, step, w in weighted:
            a = self._sample_matrix(p, points + step, theta)
            b = self._sample_matrix(p, points, theta)
            term = (w @ (a - b)).tocoo()
            rows.append(term.row)
            cols.append(term.col)
            data.append(term.data)
        op = sparse.csr_matrix(
            (np.concatenate(data), (np.concatenate(rows), np.concatenate(cols))),
            shape=(self.n_measurements, g.planes[p].n ** 2))
        del rows, cols, data
        op.sum_duplicates()
        op.eliminate_zeros()
        return op

    def model_error_variance(self, r0s: list[float], model_error: float) -> float:
        """``model_error`` times the turbulent slope variance of one subaperture [(rad/m)^2].

        The Z-tilt of a disc of the subaperture's size, ``16 * 0.449 (d / r0)**(5/3) / d**2``,
        summed over the layers: a Shack-Hartmann also measures slopes beyond the DMs' modes.
        """
        d = self.pitch
        total = sum((d / r0) ** (5.0 / 3.0) for r0 in r0s)
        base = model_error * 16.0 * 0.449 * total / d ** 2
        # averaged over less area and fewer directions where less is lit: 1 / share
        return base / self.field_share if self._weighted else base


class IdealSensor(WavefrontSensor):
    """The field-averaged residual on the DM's disc (``kind="ideal"``; noise-free)."""

    kind: ClassVar[str] = "ideal"

    def _build(self, cfg) -> None:
        # an ideal sensor of a modal DM measures the phase less its mean: piston is not
        # sensed (as by a SH), and pixel-sampled Zernikes are not exactly zero-mean, so
        # a fit with piston left in would spend modes on it
        self._centred = self.dm.shapes is not None
        g = self._geometry
        coords = g.plane_coords(self.dm.plane)
        n = g.planes[self.dm.plane].n
        pix = self.dm.pixels
        points = np.column_stack([coords[pix % n], coords[pix // n]])
        # average, per disc pixel, over the field directions whose light reaches it
        # through the pupil (as the SH does); pixels no direction reaches are not measured
        lit = np.array([self._illuminated(points, theta) for theta in self.samples])
        count = lit.sum(axis=0)
        rows = np.flatnonzero(count > 0)
        if self.dm.shapes is None:
            # a zonal DM's reconstructor is the identity, one measurement per DM pixel:
            # a pixel no direction reaches (an obscured pupil's hole) is measured as 0,
            # so the mirror stays flat there (all pixels are reached without obscuration)
            rows = np.arange(count.size)
        self.measured_pixels = rows
        self.operators = []
        for p in range(len(g.planes)):
            op = None
            for s_idx, theta in enumerate(self.samples):
                keep = rows[lit[s_idx, rows]]
                m = self._sample_matrix(p, points[keep], theta)
                w = sparse.csr_matrix((1.0 / count[keep], (np.searchsorted(rows, keep),
                                                           np.arange(keep.size))),
                                      shape=(rows.size, keep.size))
                term = w @ m
                op = term if op is None else op + term
            op = sparse.csr_matrix(op)
            op.sum_duplicates()
            self.operators.append(op)
        self.n_measurements = int(rows.size)
        self.n_valid_subapertures = 0

    def _inverse_variance_weights(self) -> np.ndarray:
        """Each measurement's inverse variance relative to a fully lit one: its field share."""
        return self.field_share

    def _least_squares(self, rcond: float) -> np.ndarray | None:
        """None on a zonal DM (the identity: the measurement is the disc's phase)."""
        if self.dm.shapes is None:
            return None
        return super()._least_squares(rcond)

    def model_error_variance(self, r0s: list[float], model_error: float) -> float:
        """Return the residual after the DM's modes [rad^2], summed over the layers.

        ``dm.residual_variance() (D_dm / r0)**(5/3)`` per layer (Noll's ``Delta_J`` for a
        Zernike mirror, :meth:`closedloop.optics.dm.DeformableMirror.residual_variance`):
        generalised fitting, the phase beyond the DMs' modes; 0 on a zonal DM.
        ``model_error`` is not used (it scales the SH's term).
        """
        dm = self.dm
        if dm.shapes is None:
            return 0.0
        return dm.residual_variance() * sum((dm.diameter / r0) ** (5.0 / 3.0) for r0 in r0s)


# ---------------------------------------------------------------------- the kinds' records
def check_subaperture_sampling(cfg: SimulationConfig, j: int) -> None:
    """Refuse subapertures of WFS ``j`` narrower than :data:`PIXELS_PER_SUBAPERTURE` pixels."""
    w = cfg.wfss[j]
    dx = cfg.telescope.diameter / cfg.telescope.n_pixels
    across = wfs_meta_pupil(cfg, j) / dx
    limit = int(across // PIXELS_PER_SUBAPERTURE)
    if w.n_subapertures > limit:
        raise ValueError(
            f"`wfss[{j}].n_subapertures` must be <= {limit} (at least "
            f"{PIXELS_PER_SUBAPERTURE} pixels per subaperture across the "
            f"{across:.0f}-pixel meta-pupil at telescope.n_pixels = "
            f"{cfg.telescope.n_pixels}); got {w.n_subapertures!r}.")


def slope_count(cfg: SimulationConfig, j: int) -> int:
    """Slopes WFS ``j`` measures, ``2 n_valid``, from the config (no grid).

    ``n_valid``: :func:`closedloop.config.valid_subapertures` with the telescope's
    obscuration scaled to the meta-pupil the WFS's grid spans.
    """
    tel = cfg.telescope
    obsc = tel.obscuration * tel.diameter / wfs_meta_pupil(cfg, j)
    return 2 * valid_subapertures(cfg.wfss[j].n_subapertures, obsc)


def _shack_hartmann_cost(config: SimulationConfig, j: int, n_planes: int,
                         dx: float) -> SensorCost:
    w = config.wfss[j]
    samples = n_field_samples(w.field_of_view, w.field_samples)
    across = wfs_meta_pupil(config, j) / dx
    n_meas = 2.0 * math.pi / 4.0 * w.n_subapertures ** 2
    # two axes, 8 entries (two bilinear reads) per pixel pair; assembled one plane at a
    # time (ShackHartmann._build), so a plane's share is held at once
    entries = 2 * samples * n_planes * (math.pi / 4.0 * across ** 2) * 8
    return SensorCost(n_measurements=n_meas, build_entries=entries,
                      held_entries=entries / n_planes)


def _ideal_cost(config: SimulationConfig, j: int, n_planes: int, dx: float) -> SensorCost:
    w = config.wfss[j]
    samples = n_field_samples(w.field_of_view, w.field_samples)
    n_meas = math.pi / 4.0 * (dm_disc_diameter(config, w.dm) / dx) ** 2
    # a bilinear read (4 entries) per disc pixel per direction
    return SensorCost(n_measurements=n_meas, build_entries=samples * n_planes * n_meas * 4)


def index_grid(n: int, flat: np.ndarray) -> np.ndarray:
    """``(n, n)`` int32 grid: ``k`` at ``flat[k]``, ``-1`` elsewhere (AOT's subaperture mask)."""
    grid = -np.ones(n * n, dtype=np.int32)
    grid[flat] = np.arange(flat.size, dtype=np.int32)
    return grid.reshape(n, n)


def sensing_wavelength(model, j: int) -> float:
    """Return the AOT ``WavefrontSensor.wavelength`` of sensor ``j`` of ``model`` [m].

    A sensor that forms images (the correlating Shack-Hartmann) has its own wavelength
    (``wfs.wavelength``, its photon budget's); the geometric ones are achromatic and
    measure the phase in rad at ``r0_wavelength``, the wavelength every log and
    measurement of a result is stated at (the export's ``MI_WAVEL`` card). The AOT field
    was left empty, so a reader of the standard found no wavelength for the sensors
    (fix55-c).
    """
    own = getattr(model.wfss[j], "wavelength", None)
    return float(own if own is not None else model.config.r0_wavelength)


def _sensor_extra(wfs, wcfg) -> dict:
    return {"drives": f"dm{wcfg.dm}", "line_of_sight_altitude": wfs.altitude,
            "field_samples": int(len(wfs.samples)), "noise_arcsec": wcfg.noise}


def slopes_aot_record(model, j: int, wcfg, meas, *, extra: dict | None = None,
                      n_extra: int = 0):
    """AOT ``SensorSpec`` of a Shack-Hartmann WFS ``j`` (``"shack-hartmann"``, slopes [rad/m]).

    ``extra``: more ``MI_GEOM`` entries (a kind's own); ``n_extra``: entries per axis
    beyond the valid subapertures (the correlating SH's tracker).
    """
    from modalinfo.io.aot_system import SensorSpec

    wfs = model.wfss[j]
    info = _sensor_extra(wfs, wcfg)
    info.update(subaperture_pitch=wfs.pitch, n_subapertures=wcfg.n_subapertures,
                order="d = 0: x slopes, d = 1: y slopes; mask rows are y")
    info.update(extra or {})
    return SensorSpec(
        uid=f"wfs{j}", source="sun", kind="shack-hartmann",
        n_valid_subapertures=wfs.n_valid_subapertures + n_extra, measurements=meas,
        subaperture_mask=index_grid(wcfg.n_subapertures, wfs.valid_subapertures),
        field_of_view=wcfg.field_of_view, altitude=wcfg.altitude, units="rad/m",
        wavelength=sensing_wavelength(model, j), extra=info)


def slopes_aot_layout(wfs, arr: np.ndarray) -> np.ndarray:
    """``(rows, 2 n)`` slopes ``(x..., y...)`` -> ``(rows, 2, n)``."""
    arr = np.ascontiguousarray(arr)
    return arr.reshape(arr.shape[0], 2, wfs.n_measurements // 2)


def _sensed_pixels(wfs) -> np.ndarray:
    """Flat plane-grid indices of the pixels an ideal sensor measures, in measurement order."""
    rows = getattr(wfs, "measured_pixels", None)  # the lit part of the disc, when recorded
    pixels = wfs.dm.pixels if rows is None else wfs.dm.pixels[rows]
    if pixels.size != wfs.n_measurements:
        raise ValueError(f"ideal sensor {wfs.index}: {pixels.size} pixels for "
                         f"{wfs.n_measurements} measurements (internal geometry error).")
    return pixels


def _ideal_aot_record(model, j: int, wcfg, meas):
    """Return an ideal sensor as a one-value-per-subaperture Pyramid record (no AOT type)."""
    from modalinfo.io.aot_system import SensorSpec

    wfs = model.wfss[j]
    info = _sensor_extra(wfs, wcfg)
    info.update(kind="ideal", note=(
        "AOT has no ideal (phase) sensor type: written as a Pyramid record with one "
        "value per subaperture; its subapertures are the measured pixels of its DM's "
        "disc (mask on the DM plane grid), its measurements their field-averaged "
        "phase [rad] as the simulator's sensor gives them"))
    n_p = model.geometry.planes[wfs.dm.plane].n
    return SensorSpec(
        uid=f"wfs{j}", source="sun", kind="pyramid", dimensions=1,
        n_valid_subapertures=wfs.n_measurements, measurements=meas,
        subaperture_mask=index_grid(n_p, _sensed_pixels(wfs)),
        field_of_view=wcfg.field_of_view, altitude=wcfg.altitude, units="rad",
        wavelength=sensing_wavelength(model, j), extra=info)


def _ideal_aot_layout(wfs, arr: np.ndarray) -> np.ndarray:
    """``(rows, n)`` phase values -> ``(rows, 1, n)``."""
    arr = np.ascontiguousarray(arr)
    return arr.reshape(arr.shape[0], 1, wfs.n_measurements)


#: the geometric Shack-Hartmann
SHACK_HARTMANN = register_sensor_kind(SensorKind(
    name="shack_hartmann", build=ShackHartmann, estimate=_shack_hartmann_cost,
    aot_record=slopes_aot_record, aot_layout=slopes_aot_layout,
    check=check_subaperture_sampling, measurement_count=slope_count))
#: the ideal (phase) sensor (verification; no aliasing, no noise)
IDEAL = register_sensor_kind(SensorKind(
    name="ideal", build=IdealSensor, estimate=_ideal_cost, aot_record=_ideal_aot_record,
    aot_layout=_ideal_aot_layout))
