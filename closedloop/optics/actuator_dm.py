"""The DM kind ``"actuators"``: a mirror of actuators, controlled through its DM-space K-L modes.

The mirror the telescopes of issue 29 are built with (DKIST's 1,600-actuator DM, EST's
adaptive secondary and altitude DMs): Gaussian influence functions on a square grid
(:class:`modalinfo.bases.InfluenceFunctions`: the coupling at the neighbour is OOPAO's
``mechCoupling`` default, 0.35, valid actuators by illumination, COMPASS's ``thresh``
rule with 0.05), conjugated to any altitude, covering its plane's controlled disc (the
meta-pupil of the WFS that drives it).

**Geometry.** ``n_actuators`` counts the actuators across the mirror's controlled disc
(``dms[i].diameter``, by default the meta-pupil its WFS senses; for a ground DM, the
pupil), at pitch ``disc / (n_actuators - 1)``: the outermost actuators on the rim. The
default is the driving WFS's ``n_subapertures + 1``: the WFS's subapertures tile the
same disc, so the actuators sit on the subapertures' corners (Fried geometry, at any
altitude); a finer pitch would add modes that WFS cannot see.

**Commands are K-L coefficients**, as peers control such mirrors (OOPAO's
``M2C_KL``, COMPASS's ``KL2V``): ``dms[i].n_modes`` DM-space K-L modes
(:func:`modalinfo.bases.dm_kl_modes`: the DM's best tip and tilt first, then the von
Karman prior diagonalised in the DM metric, piston removed), unit RMS over the disc,
at most ``n_valid - 1`` (the valid actuators less piston). The strokes are
``m2c @ commands`` and the surface is the separable banded influence operator applied
to them (:meth:`modalinfo.bases.InfluenceFunctions.surface`), never a dense
``(pixels x modes)`` product per frame; the dense ``shapes`` are held for the
interaction matrices and the AOT export. The logs, prior and reconstructor stay modal,
and a command log is a :class:`modalinfo.bases.DMKLBasis`'s coefficients
(:meth:`ActuatorDeformableMirror.basis`).

**Prior and model error.** The K-L variances are computed for ``r0`` = the disc's
diameter at the outer scale of the configuration's strongest layer, i.e. in units of
``(disc / r0)**(5/3)``: :class:`closedloop.model.LoopModel` scales them by the
turbulence assigned to this mirror (the joint MAP prior). What the modes leave of the
phase (:meth:`ActuatorDeformableMirror.residual_variance`, an ideal sensor's model
error) is the piston-removed variance over the disc less the controlled modes'
variances: the modes are orthonormal, so the rest is the phase outside their span.

The kind's record (:data:`ACTUATORS`) is registered here: options
(:class:`ActuatorOptions`), rules, memory and time estimate, AOT description, build.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import ClassVar

import numpy as np
from scipy import signal

from closedloop.config import SimulationConfig, dm_disc_diameter
from closedloop.kinds import MirrorCost, MirrorKind, register_mirror_kind
from closedloop.optics.dm import DeformableMirror
from closedloop.optics.geometry import Geometry
from closedloop.optics.products import FLOAT32_MIN_BYTES, DenseProduct
from modalinfo.bases import (
    DMKLBasis,
    InfluenceFunctions,
    MaskedPupil,
    dm_kl_modes,
    von_karman_structure_function,
)
from modalinfo.bases.influence import DEFAULT_COUPLING, DEFAULT_THRESHOLD, DEFAULT_TRUNCATION
from modalinfo.common.validation import check_int, check_real

__all__ = ["ActuatorDeformableMirror", "ActuatorOptions", "ACTUATORS", "actuators_across",
           "valid_actuators", "PIXELS_PER_PITCH"]

#: fewest pupil pixels per actuator pitch: a Gaussian of coupling 0.35 has sigma = 0.69
#: pitch, and 2 pixels per pitch are the Nyquist sampling of the finest mode the grid
#: of actuators holds (period 2 pitches; waffle) with a pixel to spare per half period
PIXELS_PER_PITCH = 2
#: CPU seconds of a K-L build per valid actuator squared and cubed: since the separable
#: prior projection and its symmetry orbits the build is mostly the projection (~n^2: a
#: contraction per pair of actuators plus one FFT column per orbit of rim-cut ones), and
#: the Cholesky / ``eigh`` (n^3) takes the lead only beyond ~5,000 actuators. Measured
#: (``time.process_time``, one BLAS thread, load 11-17 on 2 shared cores): 2.87 s for the
#: five mirrors of ``est_mcao_variant(32)`` (913 / 344 / 453 / 609 / 913 valid; estimate
#: 3.8 s), 1.27 s at 24 (estimate 1.24 s), 10.7 s at the published ``est-mcao`` (1,740 /
#: 609 / 801 / 1,200 / 1,665; estimate 14.2 s), 3.7 s at DKIST's 1,584 (estimate 4.4 s),
#: 27.6 s at 4,553 (estimate 45 s) (benchmarks/RESULTS.md, "The full-size
#: `est-mcao-solar`"). The former ``7e-10 n^3`` said 8.6 s for the 10.7 s at full size.
_KL_SECONDS_PER_ACTUATOR2 = 1.5e-6
_KL_SECONDS_PER_ACTUATOR3 = 1.5e-10
#: dense n_valid x n_valid float64 arrays alive at once while the K-L modes are built,
#: beyond the Gram matrix (kept: the influence functions cache it) and ``m2c``: the
#: structure operator, the prior, the Cholesky factor, the whitened prior and its
#: symmetrised copies, the eigen-solver's copy and vectors. Measured with tracemalloc at
#: 1,584 actuators, 1,500 modes: a peak of 9.8 n_valid^2 x 8 bytes, of which the Gram
#: matrix, ``m2c`` and its cached copy (``modalinfo.bases._dm_kl_cache``) are 2.9; 8
#: leaves 11 % (tests/closedloop/test_resources_4m.py)
_KL_BUILD_ARRAYS = 8


@dataclass(frozen=True)
class ActuatorOptions:
    """The ``"actuators"`` mirror's own keys (keys of its ``dms[i]`` table).

    Attributes
    ----------
    n_actuators : int or None
        Actuators across the controlled disc, ``>= 3``; None: the driving WFS's
        ``n_subapertures + 1`` (Fried geometry).
    coupling : float
        Influence at the nearest actuator, in (0.001, 1) (default 0.35: OOPAO's
        ``mechCoupling``, a continuous-facesheet piezo mirror).
    threshold : float
        Least illuminated fraction of a valid actuator's influence, in (0, 1] (default
        0.05: the rim's actuators just outside the disc are kept; ``modalinfo.bases.
        influence``, measured fitting error 1.04x hcipy's full grid).
    """

    n_actuators: int | None = None
    coupling: float = DEFAULT_COUPLING
    threshold: float = DEFAULT_THRESHOLD


def _validate(dm, p: str) -> None:
    """Check the options' own rules (types and ranges), each error naming ``p + key``."""
    opts = dm.options
    if opts.n_actuators is not None:
        object.__setattr__(opts, "n_actuators", check_int(opts.n_actuators, p + "n_actuators",
                                                          minimum=3))
    object.__setattr__(opts, "coupling", check_real(
        opts.coupling, p + "coupling", minimum=DEFAULT_TRUNCATION, maximum=1.0,
        strict_min=True, strict_max=True))
    object.__setattr__(opts, "threshold", check_real(
        opts.threshold, p + "threshold", minimum=0.0, maximum=1.0, strict_min=True))


def actuators_across(config: SimulationConfig, i: int) -> int:
    """Actuators across DM ``i``'s disc: ``n_actuators``, or its WFS's ``n_subapertures + 1``."""
    n = config.dms[i].options.n_actuators
    if n is not None:
        return n
    j = next(j for j, w in enumerate(config.wfss) if w.dm == i)
    return config.wfss[j].n_subapertures + 1


def _disc_mask(disc: float, dx: float, parity: int) -> np.ndarray:
    """Return the disc's pixels on its bounding square, as on a plane grid of ``parity``.

    A plane's pixel centres are ``(k - (n - 1) / 2) dx`` with ``n`` of the pupil grid's
    parity (:class:`closedloop.optics.geometry.Geometry`); the same centres and the
    same test as :class:`closedloop.optics.dm.DeformableMirror`'s (``rho <= 1``) give the
    same pixels, in the same row-major order.
    """
    m = 2 * math.ceil(disc / (2.0 * dx)) + 2
    if m % 2 != parity:
        m += 1
    coords = (np.arange(m) - (m - 1) / 2.0) * dx
    yy, xx = np.meshgrid(coords, coords, indexing="ij")
    inside = np.hypot(xx, yy) / (disc / 2.0) <= 1.0
    used = np.flatnonzero(inside.any(axis=0))
    lo, hi = int(used[0]), int(used[-1]) + 1  # symmetric: the disc is centred
    return inside[lo:hi, lo:hi]


def _influence(disc: float, dx: float, parity: int, n_act: int, coupling: float,
               threshold: float) -> InfluenceFunctions:
    mask = _disc_mask(disc, dx, parity)
    pupil = MaskedPupil(mask, diameter=mask.shape[0] * dx)
    return InfluenceFunctions(pupil, n_act, disc / (n_act - 1), coupling=coupling,
                              threshold=threshold)


@functools.lru_cache(maxsize=64)
def _valid_count(disc: float, dx: float, parity: int, n_act: int, coupling: float,
                 threshold: float) -> int:
    # cached: the config's rule and the estimate ask it for the same mirror
    return _influence(disc, dx, parity, n_act, coupling, threshold).n_valid


def valid_actuators(config: SimulationConfig, i: int) -> int:
    """Count DM ``i``'s valid actuators (illumination ``>= threshold``) from the config.

    The influence functions' illumination on the disc's pixels (no plane grid built; a
    few milliseconds, cached).
    """
    tel = config.telescope
    opts = config.dms[i].options
    return _valid_count(dm_disc_diameter(config, i), tel.diameter / tel.n_pixels,
                        tel.n_pixels % 2, actuators_across(config, i), opts.coupling,
                        opts.threshold)


def _check(config: SimulationConfig, i: int) -> None:
    """Check the mirror against the pupil grid and its modes (each error names its key)."""
    dm = config.dms[i]
    tel = config.telescope
    dx = tel.diameter / tel.n_pixels
    disc = dm_disc_diameter(config, i)
    n_act = actuators_across(config, i)
    key = f"dms[{i}].n_actuators"
    where = ("" if dm.options.n_actuators is not None
             else " (the default: its WFS's n_subapertures + 1)")
    limit = int(disc / (PIXELS_PER_PITCH * dx) + 1e-9) + 1
    if n_act > limit:
        raise ValueError(
            f"`{key}` must be <= {limit} (at least {PIXELS_PER_PITCH} pupil pixels per "
            f"actuator pitch across the {disc / dx:.0f}-pixel disc at telescope.n_pixels = "
            f"{tel.n_pixels}){where}; got {n_act!r}.")
    n_valid = valid_actuators(config, i)
    if n_valid < 4:  # the K-L modes need piston, tip, tilt and one more
        raise ValueError(f"`{key}` must leave at least 4 valid actuators (illumination >= "
                         f"dms[{i}].threshold = {dm.options.threshold:g}){where}; got "
                         f"{n_act!r} ({n_valid} valid).")
    if dm.n_modes > n_valid - 1:
        raise ValueError(
            f"`dms[{i}].n_modes` must be <= {n_valid - 1} (the DM-space K-L modes of "
            f"{n_valid} valid actuators of {n_act} x {n_act}, piston removed); "
            f"got {dm.n_modes!r}.")


def _cost(config: SimulationConfig, i: int, dx: float) -> MirrorCost:
    """Shapes, ``m2c``, influence and Gram matrices; the K-L transient; work per update."""
    opts = config.dms[i].options
    disc = dm_disc_diameter(config, i)
    n_act = actuators_across(config, i)
    n_valid = valid_actuators(config, i)
    m = config.dms[i].n_modes
    n_disc = math.pi / 4.0 * (disc / dx) ** 2
    pitch = disc / (n_act - 1)
    radius = pitch * math.sqrt(math.log(DEFAULT_TRUNCATION) / math.log(opts.coupling))
    band = 2.0 * radius / pitch + 1.0  # actuators a pixel's 1-D factor reaches
    nnz = n_valid * (2.0 * radius / dx + 1.0) ** 2  # sparse influence matrix (CSR, 12 B)
    # m2c, its copy in the K-L cache, and its float32 copy from 8 MB (optics.products)
    strokes = 8.0 * n_valid * m
    strokes = 2.0 * strokes + (0.5 * strokes if strokes >= FLOAT32_MIN_BYTES else 0.0)
    shape_bytes = 8.0 * n_disc * m + strokes + 12.0 * nnz + 8.0 * n_valid ** 2
    # per update: strokes m2c @ c, then the separable product (columns, then rows)
    side = disc / dx
    ops = n_valid * m + n_act * side * band + n_disc * band
    return MirrorCost(n_modes=m, shape_bytes=shape_bytes, ops_per_pixel=ops / n_disc,
                      driver=f"dms[{i}].n_actuators",
                      setup_seconds=(_KL_SECONDS_PER_ACTUATOR2 * float(n_valid) ** 2
                                     + _KL_SECONDS_PER_ACTUATOR3 * float(n_valid) ** 3),
                      build_bytes=_KL_BUILD_ARRAYS * 8.0 * n_valid ** 2)


def _aot(dm: ActuatorDeformableMirror) -> dict:
    f = dm.influence
    return {"model": (f"modal: each actuator is one DM-space K-L mode of a mirror of "
                      f"{f.n_valid} valid actuators ({f.n_actuators} x {f.n_actuators}, "
                      f"pitch {f.pitch:.6g} m, Gaussian influence, coupling "
                      f"{f.coupling:g}); commands are K-L coefficients [rad at "
                      f"r0_wavelength], strokes = m2c @ commands"),
            "modes": f"{dm.labels[0]}..{dm.labels[-1]} (DM-space K-L, tip and tilt first)"}


def _strongest_outer_scale(config: SimulationConfig) -> float:
    """``L0`` of the layer with the largest ``(D / r0)**(5/3)`` (inf without layers)."""
    layers = config.layers
    if not layers:
        return math.inf
    k = int(np.argmax([lay.d_over_r0 for lay in layers]))
    return float(layers[k].outer_scale)


def _piston_removed_variance(mask: np.ndarray, dx: float, r0: float,
                             outer_scale: float) -> float:
    """Mean variance of the piston-removed phase over ``mask`` [rad^2].

    ``1/2 <D(|x - y|)>`` over pairs of pixels (``C = -1/2 P D P``, ``P`` the piston
    projector; Kolmogorov's infinite ``B(0)`` cancels): the pairs' lags are the mask's
    autocorrelation, one FFT.
    """
    m = mask.astype(np.float64)
    pairs = np.rint(signal.fftconvolve(m, m[::-1, ::-1]))  # lags -(n-1)..(n-1)
    lag = np.arange(-(mask.shape[0] - 1), mask.shape[0]) * dx
    dist = np.hypot(lag[:, None], lag[None, :])
    n = m.sum()
    return float(0.5 * np.sum(pairs * von_karman_structure_function(dist, r0, outer_scale))
                 / n ** 2)


class ActuatorDeformableMirror(DeformableMirror):
    """One DM of actuators on its plane, commanded in DM-space K-L coefficients.

    Built by the registry (``closedloop.kinds.mirror_kind("actuators").build``); see the
    module docstring.

    Parameters
    ----------
    geometry : Geometry
    index : int
        Which DM of the configuration (``geometry.config.dms[index]``, kind
        ``"actuators"``; its ``n_modes`` K-L modes are controlled).

    Attributes
    ----------
    influence : InfluenceFunctions
        The actuators on the disc's bounding square (pupil: the disc's pixels, in the
        order of :attr:`pixels`).
    m2c : (n_valid, n_modes) float64
        Strokes [rad] of each K-L mode (read-only).
    prior_variances : (n_modes,) float64
        Von Karman variance of each mode in units of ``(diameter / r0)**(5/3)`` rad^2 at
        :attr:`outer_scale` (read-only).
    outer_scale : float
        ``L0`` [m] of the prior (the strongest layer's).
    shapes : (n_disc, n_modes) float64
        Mode surfaces on the disc's pixels [rad per unit command] (interaction
        matrices, AOT; :meth:`forward` does not read them).
    modes : list of int
        ``[]``: the modes are not Noll Zernikes.
    labels : list of str
        ``"DMKL1"``, ...
    """

    kind: ClassVar[str] = "actuators"
    large_products: ClassVar[bool] = True  # 4-m sizes (closedloop.optics.products)

    def __init__(self, geometry: Geometry, index: int):
        self._geometry = geometry
        self._index = index
        super().__init__(geometry, index)

    def _shapes(self, cfg, rho, theta):
        g = self._geometry
        config = g.config
        opts = cfg.options
        disc = g.dm_diameter(self._index)
        self.influence = _influence(disc, g.dx, g.n_pixels % 2,
                                    actuators_across(config, self._index), opts.coupling,
                                    opts.threshold)
        if self.influence.pupil.n_valid != rho.size:  # pragma: no cover - same test, centres
            raise RuntimeError("the influence functions' disc differs from the mirror's")
        self.outer_scale = _strongest_outer_scale(config)
        # r0 = the disc's diameter: variances in units of (diameter / r0)**(5/3)
        self.m2c, self.prior_variances = dm_kl_modes(self.influence, disc, self.outer_scale,
                                                     n_modes=cfg.n_modes)
        self.m2c.flags.writeable = False
        self.prior_variances.flags.writeable = False
        self._strokes = DenseProduct(self.m2c)
        shapes = np.ascontiguousarray(self.influence.matrix @ self.m2c)
        shapes.flags.writeable = False
        return [], shapes

    def _synthesis_tables(self, n: int):
        return None  # forward is the separable influence product, not B c

    def sensed_by(self, operator) -> np.ndarray:
        """``operator @ shapes`` through the actuators: ``(operator @ matrix) @ m2c``.

        The sparse-sparse product reads ``w^2`` actuators per pixel (a band of ``w`` ~ 6
        across) instead of the ``M`` modes of every pixel, then one dense BLAS-3 product
        with ``m2c``: at ``est-mcao``'s 25 WFS-DM pairs (19.5 M operator entries, up to
        1,431 modes) 2.7 s of CPU against 16 s for ``operator @ shapes``, equal to 4e-15
        of the largest entry (benchmarks/RESULTS.md, "The full-size est-mcao set-up
        under 60 s").
        """
        through = (operator @ self.influence.matrix).toarray()
        return through @ self.m2c

    def _labels(self) -> list[str]:
        return [f"DMKL{k + 1}" for k in range(self.n_modes)]

    def prior_variance(self) -> np.ndarray:
        """Von Karman variance of each K-L mode for ``diameter / r0 = 1``, ``(n_modes,)``."""
        return self.prior_variances

    @functools.cached_property
    def _total_variance(self) -> float:
        return _piston_removed_variance(np.asarray(self.influence.pupil.mask),
                                        self._geometry.dx, self.diameter, self.outer_scale)

    def residual_variance(self) -> float:
        """Variance the controlled K-L modes leave, ``diameter / r0 = 1`` [rad^2].

        The piston-removed variance over the disc (at :attr:`outer_scale`) less the
        modes' prior variances (orthonormal modes: the rest is outside their span).
        """
        return max(self._total_variance - float(np.sum(self.prior_variances)), 0.0)

    def basis(self) -> DMKLBasis:
        """Return the modes as a :class:`modalinfo.bases.DMKLBasis` on the disc (logs, MI)."""
        return DMKLBasis(self.influence, self.m2c, self.prior_variances, self.labels)

    def strokes(self, commands: np.ndarray) -> np.ndarray:
        """Actuator strokes [rad] ``(n_valid,)`` for K-L ``commands`` ``(n_modes,)``."""
        return self.m2c @ np.asarray(commands, dtype=np.float64)

    def forward(self, commands: np.ndarray) -> np.ndarray:
        """Mirror phase on its disc's pixels [rad], ``(n_disc,)``, for ``commands`` ``(M,)``.

        The strokes ``m2c @ commands`` in float32 when ``m2c`` is large
        (:mod:`closedloop.optics.products`: 19 MB at 1,584 x 1,500), then the separable surface.
        """
        return self.influence.surface(self._strokes(np.asarray(commands, dtype=np.float64)))


#: the mirror of actuators (DM-space K-L commands)
ACTUATORS = register_mirror_kind(MirrorKind(
    name="actuators", build=ActuatorDeformableMirror, estimate=_cost, aot_description=_aot,
    options=ActuatorOptions, validate=_validate, check=_check,
    controlled_modes=lambda cfg, i: cfg.dms[i].n_modes))
