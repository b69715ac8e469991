"""The correlating (solar) Shack-Hartmann as a part of the loop (``kind="correlating"``).

On granulation each subaperture images an extended, low-contrast scene and the sensor
measures the shift of that image by correlation. Two modes share one geometry (the MFoV
layer-oriented footprints of :mod:`closedloop.optics.wfs`) and one set of subaperture
phases: each valid subaperture's ``F = f x f`` pupil samples (``f = p q``: ``p =
round(pitch / dx)`` times the oversampling ``q`` the image formation of
:class:`closedloop.optics.correlating.CorrelatingSubapertures` needs so that the PSF does
not alias), bilinear from every plane along each direction as the geometric SH samples
them, and lit where the beam passed through the telescope pupil at least ``sqrt(2) dx``
inside its edge (so that no sample interpolates a pixel outside the DMs' discs, whose
surfaces stop at their edge pixels: without the margin the fit below turns that step
into a spurious tilt). A subaperture is valid when the beam (the plain pupil, no
margin) of some direction lights half of its samples or more
(``closedloop.optics.wfs.field_rule``, the geometric SH's rule on the geometric SH's
light: the whole meta-pupil of a layer-oriented sensor at altitude; until issue 27 half
lit *averaged over the field's directions*, which dropped the meta-pupil's ring, then,
until left30-solar, half lit on the margined samples, which dropped ~20 of its 200 at
table1-solar's 10 km: the margin is a property of the bilinear reads, not of the optics,
and a subaperture the beam half-lights forms an image). Its **light share** per axis is
the contrast-weighted mean, over the directions it uses, of the lit part of its area
(below): 1 inside the pupil, about 1/2 on a half-lit edge subaperture (until left31-edge
it was over its best direction's light, so 1 on a ground-conjugated sensor's edge).

Linear mode (``image_formation=False``, the default; built once, measured by the same
sparse products as the geometric SH, so as fast):

- **Z-tilt.** A subaperture's slope seen from one direction is the least-squares plane
  fit of that lit phase: SDF and ADF^2 measure the Z-tilt, not the mean gradient
  (G-tilt) (Loefdahl 2010, A&A 524, A90). The image formation sees the same samples.
- **Contrast weights.** The field's directions (the WFS's ``field_samples``) are
  combined with the weight of the scene's contrast each one covers: the reference
  subaperture image ``r`` (the scene blurred by the subaperture's diffraction and the
  pixel), ``c_theta = sum (D r)^2`` over the correlation window's pixels nearest to
  ``theta`` (``D`` the central difference along the slope's axis), normalised to sum 1
  per axis. Linearising the square-difference function gives exactly these weights for
  a partition of the field (``CorrelatingSubapertures.direction_weights`` is the same
  law for its smooth patches; last session's tests check it against image formation).
  A direction whose beam lights less than half of a subaperture is left out of that
  subaperture's mean and the others' weights renormalised (the Z-tilt of a thin lit
  sliver is an extrapolation); a direction used is fitted on its margined samples (at
  least 3, a well-posed plane).
- **Noise.** White Gaussian noise per slope with ``sqrt(2)`` times the rms that
  :func:`closedloop.optics.shifts.sdf_noise_rms` predicts for the noise-free reference
  image at the photon budget (signal ``S`` e- per pixel, scaled by the scene, plus read
  noise: per-pixel variance ``r + RON^2``): the same-frame reference (below) is as noisy
  as the live image, which doubles the variance (test_correlating), and its share does
  not cancel in the slopes less their mean (it enters each subaperture's sub-pixel
  interpolation differently: measured 1.3-1.5x the single-image law, test
  test_correlating_sensor). Converted from pixels to the loop's units: a shift ``s``
  pixels is the angle ``s * pixel_scale`` and the phase gradient ``2 pi s pixel_scale /
  r0_wavelength`` [rad/m of the phase at ``r0_wavelength``]. The law is the linearised
  one: it holds while the predicted rms is below ~0.03 px; at lower signal x contrast^2
  the noisy reference's noise energy, which varies with the lag, adds more (2-10x at a
  predicted 0.07 px, 400 e- and 8 % contrast). The hand-set ``noise`` of the geometric
  SH is refused for this kind (the config says so). A subaperture lit by fewer
  directions or over less of its area collects the share ``s`` of the light and of the
  contrast information on the same pixels, so one image's shift variance is
  ``sigma_1^2 v(s)``, ``v = (1 - r) / s + r / s^2`` with ``r`` the read noise's part of
  the fully lit variance (``closedloop.optics.wfs.lit_noise_variance``; ``r`` ~ 3e-4
  on granulation at half the full well); a relative slope is the difference against the
  reference subaperture (the best lit, ``s_ref``), independent noises, so its variance
  is the sum ``sigma_1^2 (v(s) + v(s_ref))`` (``2 sigma_1^2`` where both are fully
  lit, the ``sqrt(2)`` above): ``noise_rms`` carries it, and a single DM's least squares
  weighs each slope by its inverse (Wallner 1983; Ellerbroek 2002).
- **Noise at sub-pixel shifts.** That law is the measurement's at a whole-pixel shift;
  at a sub-pixel one the 2QI vertex is more sensitive to the noise (Loefdahl 2010,
  Sect. 5: the error grows with the fractional shift). Every frame each slope's noise is
  scaled by the square root of ``CorrelatingShackHartmann.noise_factor`` at the
  fractional part of that slope's current noise-free shift [pixels] (the relative slope:
  the shift against a same-frame reference near the mean; the tracker's against its
  stored reference): the variance of SDF + 2QI over the variance at ``(0, 0)``, built
  once from the reference image displaced by the shift theorem
  (``CorrelatingSubapertures.displaced_references``) and
  :func:`closedloop.optics.shifts.sdf_noise_at_shifts` on an 8 x 8 grid of cell
  centres, interpolated bilinearly and periodically (1.0 at 1/16 px, ~1.3 at 3/16,
  ~2 at 5/16, 4-7 at 7/16 pixel for table1-solar's 0.5" pixels; the measurement within
  5 % on average, test_shift_noise_left29). Not modelled: the interpolation's bias
  (a deterministic ~0.03 px error of the fractional shift, no noise) and the lag flip
  within a few noise rms of half a pixel, where the noise picks either integer lag and
  the estimate jumps by the difference of the two sides' biases; the grid's cell
  centres stay 1/16 px away from it. The error budget's noise term scales
  ``noise_rms ** 2`` by the mean factor ``forward`` applied over the budget's frames
  (``noise_factor_sum``: 1.06-1.5 on table1-solar's closed loop, 1.9-2.3 open). The
  reconstructors, built once before the loop runs, keep ``noise_rms`` (the whole-pixel
  law): the minimum-variance static estimator's noise covariance is the expectation over
  the loop's stationary shifts (Wallner 1983; Ellerbroek 2002), unknown until the loop
  has closed, and a factor common to a sensor's slopes leaves its relative weights
  unchanged (docs/CLOSEDLOOP.md, "Correlating SH noise weights and ring subapertures").
- **Reference and tracker.** Solar WFSs correlate every subaperture against the image
  of one subaperture of the same frame (the scene evolves in seconds and moves with the
  image motion, so a stored reference goes stale; Rimmele & Marino 2011, Living Rev.
  Sol. Phys. 8, 2): slopes are relative, and the global tip-tilt is lost. To first order
  the reference's own noise and tilt are common to every subaperture and drop out of
  the slopes less their mean. The measurements are therefore: the x and y slopes less
  their mean over the valid subapertures (``2 n_valid``), then the two means as a
  correlation tracker measures them (its own image of the whole aperture over the same
  field, at the same pixel scale and signal, against a stored reference refreshed often
  enough to be noise-free, so the law's rms without the ``sqrt(2)``). The tracker of
  each WFS measures the mean of that WFS's subaperture Z-tilts (a simplification: a real
  system has one tracker on the telescope's tip-tilt mirror). The slopes' noise after
  the mean's removal is taken as independent (its correlation ``-sigma^2 / n_valid``
  is neglected), so ``noise_rms`` is ``(sigma_x,) * n + (sigma_y,) * n + (sigma_tx,
  sigma_ty)`` and the joint MAP reconstructor weights slopes and tracker by their own
  variances (and the model error: a slope's over its field share, the unmodelled signal
  averaged over fewer directions, and the tracker's the mean of the slopes' over
  ``n_valid``, the variance of a mean of ``n_valid`` independent terms:
  :meth:`CorrelatingShackHartmann.model_error_variance`).

Imaging mode (``image_formation=True``): every frame, the phases of the sub-directions
(``2 field_samples - 1`` patches across the field) over every valid subaperture are
imaged (:meth:`CorrelatingSubapertures.images`, with the pupil's vignetting as an
amplitude; photon and read noise drawn from a generator seeded by the frame's normal
draws, so a run is reproducible from its seed) and their shifts measured with SDF + 2QI
(``MAX_SHIFT`` = 3 pixels) against the image of the fully lit subaperture nearest the
centre; slopes less their mean as above, and the tracker as in the linear mode (linear,
with its noise). It checks the linear mode on fully lit subapertures (tests: equal
within the interpolation bias without noise; noise within 15 %). A vignetted
subaperture's image is formed with its lit pupil (a broader PSF, normalised to the same
flux): its shift has a larger bias and noise than the law's, which the linear mode does
not model. It costs milliseconds per subaperture image (benchmarks/RESULTS.md), so
``closedloop.resources.estimate`` refuses long runs of it.

The scene is a :func:`closedloop.optics.granulation.granulation_scene` (seed 0, so the
sensor does not change with the run's seed) at the WFS's pixel scale, with ``contrast``
(default: :func:`~closedloop.optics.granulation.granulation_contrast` at the WFS
wavelength, 500 nm); the photon budget is
:class:`closedloop.optics.photon_budget.PhotonBudget`'s defaults with the mean signal
``signal`` e- per pixel when given (capped at what the Sun supplies).
"""

from __future__ import annotations

import hashlib
import math
from typing import ClassVar

import numpy as np
from scipy import sparse

from closedloop.config import FULL_WELL, SimulationConfig, wfs_meta_pupil
from closedloop.kinds import SensorCost, SensorKind, register_sensor_kind
from closedloop.optics.correlating import CorrelatingSubapertures
from closedloop.optics.geometry import ARCSEC
from closedloop.optics.granulation import granulation_contrast, granulation_scene
from closedloop.optics.image_sampling import (
    convolution_support,
    psf_subsampling,
    pupil_oversampling_needed,
)
from closedloop.optics.photon_budget import PhotonBudget
from closedloop.optics.shifts import measure_shifts, sdf_noise_at_shifts, sdf_noise_rms
from closedloop.optics.wfs import (
    EDGE_MARGIN_PIXELS,
    ShackHartmann,
    bilinear_matrix,
    check_subaperture_sampling,
    field_rule,
    lit_noise_variance,
    metapupil_note,
    pupil_lit,
    slope_count,
    slopes_aot_record,
)

__all__ = ["CorrelatingShackHartmann", "CORRELATING", "MAX_SHIFT", "SCENE_SEED"]

#: search range of the correlation [pixels]: +-1.5" at 0.5" pixels
MAX_SHIFT = 3
#: seed of every correlating WFS's granulation scene
SCENE_SEED = 0
#: smallest lit fraction of a subaperture for a direction's plane fit to be used (the
#: Z-tilt of a thin lit sliver extrapolates a plane from the pupil's edge, where the
#: DMs' sampled surfaces end, and is dominated by it)
_MIN_LIT = 0.5
#: seconds per (image x support^2 x PSF samples across) of a correlating WFS's image
#: formation: 28.6 ms per image at support 135, 65 PSF samples (table1-solar's 60" field),
#: measured under load (it over-predicts the 20" field's 2.6 ms by 1.6x: a guard)
_SECONDS_PER_IMAGE_OP = 2.4e-8
#: fractional shifts tabulated per axis for the linear mode's shift-dependent noise: the
#: cell centres ``(i + 1/2) / 8 - 1/2`` pixels, interpolated periodically (never at half a
#: pixel itself: module docstring; docs/CLOSEDLOOP.md, "Correlating SH noise")
NOISE_TABLE_STEPS = 8
#: Gaussian difference surfaces per tabulated shift (variance standard error 2.2 %, the
#: same draws at every shift, so the ratios to (0, 0) carry much less)
NOISE_TABLE_DRAWS = 4000
#: keys of ``WFSConfig`` only this kind uses
KEYS = ("pixel_scale", "signal", "contrast", "image_formation")


class CorrelatingShackHartmann(ShackHartmann):
    """Correlating Shack-Hartmann on granulation (``kind="correlating"``; module docstring).

    Besides those of ``closedloop.optics.wfs.WavefrontSensor``:

    Attributes
    ----------
    n_valid_subapertures : int
    valid_subapertures : (n_valid,) ndarray of int
        Subaperture indices ``row * n_sub + column``.
    noise_rms : (2 n_valid + 2,) ndarray
        Per measurement [rad/m at ``r0_wavelength``]: x slopes, y slopes, tracker x, y.
    field_share : (2 n_valid + 2,) ndarray
        Each slope's contrast-weighted light share (module docstring), then 1, 1 for the
        tracker.
    read_fraction : float
        The read noise's part of a fully lit image's per-pixel variance (its mean over
        the reference image), for ``closedloop.optics.wfs.lit_noise_variance``.
    slope_noise_pixels, tracker_noise_pixels : (2,) ndarray
        Predicted rms shift error ``(x, y)`` of a subaperture and of the tracker [pixels].
    direction_weights : (n_samples, 2) ndarray
        Contrast weight of each field sample for the x and y slopes (columns sum to 1).
    imager : CorrelatingSubapertures
        The subapertures' image formation (reference image, photon budget).
    tracker : CorrelatingSubapertures
        The correlation tracker's image formation (whole aperture).
    reference_subaperture : int
        Index among the valid subapertures of the imaging mode's reference: the one
        nearest the axis among those lit whole from every direction, or among the
        best-lit ones where none is.
    noise_factor, tracker_noise_factor : (NOISE_TABLE_STEPS, NOISE_TABLE_STEPS, 2) ndarray
        Linear mode: the shift variance ``(x, y)`` at the fractional shift ``(fx, fy)`` =
        ``((ix, iy) + 1/2) / NOISE_TABLE_STEPS - 1/2`` pixels, row ``iy``, column ``ix``, over
        the variance at ``(0, 0)`` (:func:`closedloop.optics.shifts.sdf_noise_at_shifts`
        on the displaced reference images); ``forward`` scales each slope's noise by its
        square root at the slope's current fractional shift. None in the imaging mode.
    noise_factor_sum : (2 n_valid + 2,) ndarray
        Linear mode: the variance factor (``noise_factor`` at each measurement's shift)
        ``forward`` applied, summed over its noisy calls since the sensor was built;
        ``noise_factor_frames`` counts them. The error budget's noise term takes their
        mean over its frames (the variance the sensor had at the shifts the loop left).
    """

    kind: ClassVar[str] = "correlating"

    # ------------------------------------------------------------------ building
    def _build(self, cfg) -> None:
        g = self._geometry
        conf = g.config
        self.image_formation = bool(cfg.image_formation)
        self.pixel_scale = float(cfg.pixel_scale)
        d_wfs = g.diameter + 2.0 * self.altitude * math.tan(cfg.field_of_view / 2.0 * ARCSEC)
        n_sub = cfg.n_subapertures
        pitch = d_wfs / n_sub
        self.pitch = pitch
        p = max(2, int(round(pitch / g.dx)))
        budget = (PhotonBudget() if cfg.signal is None
                  else PhotonBudget(fill=cfg.signal / FULL_WELL))
        self.wavelength = budget.wavelength
        n_field = int(round(cfg.field_of_view / self.pixel_scale))
        contrast = (granulation_contrast(budget.wavelength) if cfg.contrast is None
                    else cfg.contrast)
        margin, support = convolution_support(n_field, self.pixel_scale, pitch,
                                              budget.wavelength, MAX_SHIFT)
        scene = granulation_scene(support, self.pixel_scale, seed=SCENE_SEED,
                                  contrast=contrast, wavelength=budget.wavelength)
        n_patches = min(2 * cfg.field_samples - 1, n_field // 4) if self.image_formation else 1
        # the pupil samples the image formation needs (p at the grid's pitch, times the
        # oversampling that keeps the PSF from aliasing); the phase is sampled there
        # directly from the planes, so that the fit and the images see the lit beam only
        q = pupil_oversampling_needed(2 * margin + 1, self.pixel_scale, pitch / p,
                                      budget.wavelength)
        self.n_pupil = p * q
        self.imager = CorrelatingSubapertures(scene, self.pixel_scale, pitch, p * q, n_field,
                                              n_patches=n_patches, budget=budget,
                                              max_shift=MAX_SHIFT, pupil_oversampling=1)
        self.tracker = CorrelatingSubapertures(scene, self.pixel_scale, g.diameter, 2, n_field,
                                               budget=budget, max_shift=MAX_SHIFT)
        ron2 = budget.read_noise ** 2
        ref = self.imager.reference
        # against a same-frame subaperture as noisy as the live one: twice the variance of
        # the law's noise-free reference (test_correlating; the reference's share does not
        # cancel in the slopes less their mean: it enters each subaperture's sub-pixel
        # interpolation differently, measured in test_correlating_sensor)
        self.slope_noise_pixels = math.sqrt(2.0) * sdf_noise_rms(
            ref, np.clip(ref, 0.0, None) + ron2, max_shift=MAX_SHIFT)
        tref = self.tracker.reference
        self.tracker_noise_pixels = sdf_noise_rms(tref, np.clip(tref, 0.0, None) + ron2,
                                                  max_shift=MAX_SHIFT)
        self.direction_weights = self._contrast_weights(ref)
        self.noise_factor = self.tracker_noise_factor = None
        if not self.image_formation:
            self.noise_factor = _noise_table(self.imager, ron2)
            self.tracker_noise_factor = _noise_table(self.tracker, ron2)
        f = self.n_pupil
        off = ((np.arange(f) + 0.5) / f - 0.5) * pitch
        yy, xx = np.meshgrid(off, off, indexing="ij")
        self._offsets = np.column_stack([xx.ravel(), yy.ravel()])        # (F, 2), rows along y
        jj, ii = np.meshgrid(np.arange(n_sub), np.arange(n_sub), indexing="xy")
        centres = np.column_stack([(jj.ravel() + 0.5) * pitch - d_wfs / 2.0,
                                   (ii.ravel() + 0.5) * pitch - d_wfs / 2.0])
        shares = self._valid_and_shares(centres[:, None, :] + self._offsets[None, :, :])
        n_valid = self.valid_subapertures.size
        if n_valid < 2:
            field = metapupil_note(d_wfs, g.diameter, self.altitude, cfg.field_of_view, pitch)
            raise ValueError(f"`wfss[{self.index}].n_subapertures` = {n_sub} leaves {n_valid} "
                             f"valid subaperture(s){field}; a correlating SH needs at least 2"
                             + ("; use more subapertures, a smaller field or a lower altitude."
                                if field else "."))
        self.n_valid_subapertures = int(n_valid)
        self._centres = centres[self.valid_subapertures]
        self._points = self._centres[:, None, :] + self._offsets[None]      # (n_valid, F, 2)
        self.operators = self._ztilt_operators()
        self.n_measurements = 2 * n_valid + 2
        self._transform = self._relative_transform(n_valid)
        # noise per measurement [rad/m at r0_wavelength]
        to_slope = 2.0 * math.pi * self.pixel_scale * ARCSEC / conf.r0_wavelength
        self.field_share = np.concatenate(shares + [np.ones(2)])
        # the read noise's part of a fully lit image's per-pixel variance (its mean over
        # the reference image): a partly lit image keeps its pixels (lit_noise_variance)
        self.read_fraction = ron2 / (float(np.clip(ref, 0.0, None).mean()) + ron2)
        self.noise_rms = np.concatenate([
            self.slope_noise_pixels[a] * to_slope
            * _relative_rms_factor(shares[a], self.read_fraction)
            for a in range(2)] + [self.tracker_noise_pixels * to_slope])
        self._to_slope = to_slope
        self.noise_factor_sum = np.zeros(self.n_measurements)
        self.noise_factor_frames = 0
        if self.image_formation:
            self._build_imaging()

    def _valid_and_shares(self, all_pts: np.ndarray) -> list[np.ndarray]:
        """Set ``valid_subapertures``; return the ``(n_valid,)`` field shares per axis.

        ``all_pts``: every subaperture's pupil samples ``(n_sub^2, F, 2)`` [m]. Valid: some
        direction's beam lights half of the samples or more (the geometric SH's field rule
        on the beam's light, the plain pupil: the margin is the bilinear reads'
        (``_lit``), not the optics', and a subaperture the beam half-lights forms an
        image; the fits use the margined samples of those directions). Shares weighted
        by the directions' contrast (the linearised SDF's information, module docstring).
        """
        light = np.array([self._lit(all_pts, th, 0.0).mean(axis=1) for th in self.samples])
        light[light < _MIN_LIT] = 0.0
        best = light.max(axis=0)
        n_dir = len(self.samples)
        shares = []
        for a in range(2):
            # n x the contrast-weighted mean light: field_rule's share total / (n best)
            # is then the contrast-weighted share (the plain one for equal weights)
            total = n_dir * (self.direction_weights[:, a] @ light)
            self.valid_subapertures, share = field_rule(total, best, n_dir, 1.0)
            shares.append(share)
        return shares

    def _lit(self, u: np.ndarray, theta: np.ndarray,
             margin: float | None = None) -> np.ndarray:
        """Return which samples ``u`` [m] are lit from ``theta`` [arcsec], ``sqrt(2) dx`` inside.

        ``margin`` [m]: instead of ``sqrt(2) dx`` (0: the beam's light, the plain pupil).

        The margin keeps every pixel a sample interpolates (bilinearly) inside the beam and
        so inside the DMs' discs, whose surfaces end at their edge pixels: without it a
        sample within a pixel of the edge mixes the mirror's surface with the zeros
        outside, and a subaperture's plane fit, which extrapolates from its lit part,
        turns that step into a spurious tilt (the upper WFS then "sees" the ground DM's
        tilt in its relative slopes).
        """
        return pupil_lit(self._geometry, u - self.altitude * theta * ARCSEC,
                         EDGE_MARGIN_PIXELS * self._geometry.dx if margin is None else margin)

    def _contrast_weights(self, ref: np.ndarray) -> np.ndarray:
        """``(n_samples, 2)`` contrast weights of the field samples (module docstring)."""
        n = ref.shape[0]
        lag = MAX_SHIFT + 1
        win = n - 2 * lag
        a = lag
        sl = slice(a, a + win)
        dx = (ref[sl, a + 1:a + win + 1] - ref[sl, a - 1:a + win - 1]) / 2.0
        dy = (ref[a + 1:a + win + 1, sl] - ref[a - 1:a + win - 1, sl]) / 2.0
        pos = (np.arange(a, a + win) - (n - 1) / 2.0) * self.pixel_scale   # [arcsec]
        yy, xx = np.meshgrid(pos, pos, indexing="ij")
        d2 = ((xx.ravel()[:, None] - self.samples[None, :, 0]) ** 2
              + (yy.ravel()[:, None] - self.samples[None, :, 1]) ** 2)
        cell = np.argmin(d2, axis=1)
        k = len(self.samples)
        c = np.column_stack([np.bincount(cell, weights=(dx ** 2).ravel(), minlength=k),
                             np.bincount(cell, weights=(dy ** 2).ravel(), minlength=k)])
        return c / c.sum(axis=0, keepdims=True)

    def _plane_fit_rows(self, lit: np.ndarray, beam: np.ndarray):
        """Z-tilt weights on the pupil samples for lit masks ``(n_valid, F)``.

        ``lit``: the margined samples the fit uses; ``beam``: the beam's light (plain
        pupil), which must cover half of the subaperture for the direction to be used.
        Returns ``(wx, wy, usable)``: ``(n_valid, F)`` weights (0 where unlit) of the x
        and y plane-fit slopes [1/m], and which subapertures have a well-posed fit.
        """
        off = self._offsets
        m = lit.astype(np.float64)
        cnt = m.sum(axis=1)
        safe = np.maximum(cnt, 1.0)
        xm = (m * off[None, :, 0]).sum(axis=1) / safe
        ym = (m * off[None, :, 1]).sum(axis=1) / safe
        xc = (off[None, :, 0] - xm[:, None]) * m
        yc = (off[None, :, 1] - ym[:, None]) * m
        sxx = (xc * xc).sum(axis=1)
        syy = (yc * yc).sum(axis=1)
        sxy = (xc * yc).sum(axis=1)
        det = sxx * syy - sxy ** 2
        usable = (cnt >= 3.0) & (beam.sum(axis=1) >= _MIN_LIT * lit.shape[1]) \
            & (det > 1e-9 * np.maximum(sxx * syy, 1e-300))
        inv = np.where(usable, 1.0 / np.where(usable, det, 1.0), 0.0)
        wx_f = (syy[:, None] * xc - sxy[:, None] * yc) * inv[:, None]
        wy_f = (sxx[:, None] * yc - sxy[:, None] * xc) * inv[:, None]
        return wx_f, wy_f, usable

    def _sample_clipped(self, p: int, points: np.ndarray, theta: np.ndarray):
        """Bilinear operator on plane ``p``, positions clipped into the grid.

        Only unlit samples can leave the grid; they carry no light (amplitude 0 in the
        image), so their clipped phase does not matter.
        """
        g = self._geometry
        plane = g.planes[p]
        shift = (plane.altitude - self.altitude) * theta * ARCSEC
        pos = np.clip((points + shift) / g.dx + plane.centre, 0.0, plane.n - 1)
        return bilinear_matrix(pos[:, 0], pos[:, 1], plane.n)

    def _ztilt_operators(self) -> list:
        """Sparse ``(2 n_valid, n_p^2)`` per plane: contrast-weighted raw Z-tilts."""
        g = self._geometry
        n_valid = self.valid_subapertures.size
        fits = []
        total = np.zeros((n_valid, 2))
        for t, theta in enumerate(self.samples):
            lit = self._lit(self._points, theta)
            wx, wy, usable = self._plane_fit_rows(lit, self._lit(self._points, theta, 0.0))
            fits.append((lit, wx, wy, usable))
            total += usable[:, None] * self.direction_weights[t][None, :]
        ops = [None] * len(g.planes)
        for t, theta in enumerate(self.samples):
            lit, wx, wy, usable = fits[t]
            lit = lit & usable[:, None]
            scale = self.direction_weights[t][None, :] / np.where(total > 0, total, 1.0)
            sub, k = np.nonzero(lit)                   # lit samples only: inside the grids
            col = np.arange(sub.size)
            data = np.concatenate([wx[sub, k] * scale[sub, 0], wy[sub, k] * scale[sub, 1]])
            w = sparse.csr_matrix((data, (np.concatenate([sub, sub + n_valid]),
                                          np.concatenate([col, col]))),
                                  shape=(2 * n_valid, sub.size))
            pts = self._points[sub, k]
            for p in range(len(g.planes)):
                term = w @ self._sample_matrix(p, pts, theta)
                ops[p] = term if ops[p] is None else ops[p] + term
        out = []
        for op in ops:
            op = sparse.csr_matrix(op)
            op.sum_duplicates()
            op.eliminate_zeros()
            out.append(op)
        return out

    @staticmethod
    def _relative_transform(n: int) -> np.ndarray:
        """``(2n + 2, 2n)``: raw Z-tilts to slopes less their mean, then the two means."""
        t = np.zeros((2 * n + 2, 2 * n))
        for a in range(2):
            blk = slice(a * n, (a + 1) * n)
            t[blk, blk] = np.eye(n) - 1.0 / n
            t[2 * n + a, blk] = 1.0 / n
        return t

    def _build_imaging(self) -> None:
        """Phase operators and pupil amplitudes of the imaging mode's sub-directions."""
        g = self._geometry
        dirs = self.imager.directions_arcsec
        n_valid = self.valid_subapertures.size
        f = self.n_pupil
        pts = self._points.reshape(-1, 2)
        self._image_ops = []
        for pl in range(len(g.planes)):
            op = sparse.vstack([self._sample_clipped(pl, pts, th) for th in dirs])
            self._image_ops.append(sparse.csr_matrix(op))
        self._amplitude = np.stack([
            self._lit(self._points, th).astype(np.float64) for th in dirs
        ]).reshape(len(dirs), n_valid, f, f)
        full = self._amplitude.min(axis=(0, 2, 3)) > 0
        dist = np.hypot(self._centres[:, 0], self._centres[:, 1])
        if not full.any():
            # no subaperture is lit whole from every direction (small or obscured pupils):
            # the best-lit ones (least light over the directions) are the candidates
            lit = self._amplitude.mean(axis=(2, 3)).min(axis=0)
            full = lit >= lit.max()
        self.reference_subaperture = int(np.argmin(np.where(full, dist, np.inf)))
        self._phase_scale = self._geometry.config.r0_wavelength / self.wavelength

    def model_error_variance(self, r0s: list[float], model_error: float) -> np.ndarray:
        """Per measurement: the SH's term over each slope's field share; the tracker's mean.

        The slopes less their mean carry a subaperture's unmodelled slope variance (as the
        geometric SH's, :meth:`ShackHartmann.model_error_variance`, over the field share:
        averaged over fewer directions; the reference's own is common to every slope and
        drops out of the slopes less their mean); the tracker measures the mean of
        ``n_valid`` Z-tilts, whose unmodelled (small-scale, nearly independent between
        subapertures) parts average down: the mean of their variances over ``n_valid``.
        Counted as a slope's, the two tracker rows weigh like one subaperture and the
        prior shrinks the global tip-tilt.
        """
        n = self.n_valid_subapertures
        d = self.pitch
        base = model_error * 16.0 * 0.449 * sum((d / r0) ** (5.0 / 3.0) for r0 in r0s) / d ** 2
        # a slope averaged over less area and fewer directions: 1 / share; the tracker's
        # mean of n independent ones: base * mean(1 / share) / n per axis
        inv = 1.0 / self.field_share[:2 * n]
        return np.concatenate([base * inv, base * np.array([inv[:n].mean(), inv[n:].mean()]) / n])

    def _inverse_variance_weights(self) -> np.ndarray:
        """Least-squares weights: each measurement's variance over a fully lit slope's.

        A relative slope's noise variance is ``sigma^2 (1 / s_i + 1 / s_ref)``
        (``_relative_rms_factor``); the tracker keeps weight 1.
        """
        n = self.n_valid_subapertures
        w = np.ones(self.n_measurements)
        for a in range(2):
            s = self.field_share[a * n:(a + 1) * n]
            w[a * n:(a + 1) * n] = 1.0 / _relative_rms_factor(s, self.read_fraction) ** 2
        return w

    # ------------------------------------------------------------------ measuring
    def relative(self, raw: np.ndarray) -> np.ndarray:
        """Measurements from raw per-subaperture slopes ``(x..., y...)`` (the transform)."""
        n = self.n_valid_subapertures
        out = np.empty(2 * n + 2)
        for a in range(2):
            v = raw[a * n:(a + 1) * n]
            mean = v.mean()
            out[a * n:(a + 1) * n] = v - mean
            out[2 * n + a] = mean
        return out

    def forward(self, plane_maps: list[np.ndarray],
                noise: np.ndarray | None = None) -> np.ndarray:
        """Measurements ``(2 n_valid + 2,)``: relative slopes, then the tracker [rad/m].

        ``noise``: standard normal draws ``(n_measurements,)``; the linear mode scales them
        by ``noise_rms``; the imaging mode draws its images' noise from a generator seeded
        by them and uses the last two for the tracker. None: noise-free.
        """
        raw = self._operate(plane_maps)
        s = self.relative(raw)
        if self.image_formation:
            n = self.n_valid_subapertures
            s[:2 * n] = self.image_slopes(plane_maps, noise)
            if noise is not None:
                s[2 * n:] += self.noise_rms[2 * n:] * noise[2 * n:]
            return s
        if noise is not None:
            # the shift noise at each slope's current sub-pixel shift (module docstring);
            # the relative slopes are the shifts against a reference near their mean
            n = self.n_valid_subapertures
            pix = s / self._to_slope
            gain = np.empty_like(s)
            gain[:2 * n] = _noise_gain(self.noise_factor, pix[:n], pix[n:2 * n]).T.ravel()
            gain[2 * n:] = _noise_gain(self.tracker_noise_factor, pix[2 * n:2 * n + 1],
                                       pix[2 * n + 1:]).ravel()
            s += self.noise_rms * gain * noise
            # what the loop's shifts made of the noise, for the error budget's noise term
            self.noise_factor_sum += gain * gain
            self.noise_factor_frames += 1
        return s

    def image_slopes(self, plane_maps: list[np.ndarray],
                     noise: np.ndarray | None = None) -> np.ndarray:
        """Slopes less their mean ``(2 n_valid,)`` [rad/m] from formed, correlated images.

        Needs ``image_formation=True``. ``noise`` (None: noise-free images) seeds the
        images' photon and read noise.
        """
        if not self.image_formation:
            raise ValueError(f"`wfss[{self.index}].image_formation` must be true to form "
                             "images; got false.")
        n = self.n_valid_subapertures
        phase = None
        for pl, op in enumerate(self._image_ops):
            x = np.ascontiguousarray(plane_maps[pl], dtype=np.float64).reshape(-1)
            phase = op @ x if phase is None else phase + op @ x
        phase = phase.reshape(self._amplitude.shape[0], n, self.n_pupil, self.n_pupil)
        phase *= self._phase_scale
        rng = None
        if noise is not None:
            words = np.frombuffer(np.ascontiguousarray(noise, dtype=np.float64).tobytes(),
                                  dtype=np.uint32)
            rng = np.random.default_rng(np.random.SeedSequence(words))
        imgs = self.imager.images(phase, rng, amplitude=self._amplitude)
        res = measure_shifts(imgs[self.reference_subaperture], imgs, method="sdf",
                             max_shift=MAX_SHIFT)
        raw = np.concatenate([res.shifts[:, 0], res.shifts[:, 1]]) * self._to_slope
        return self.relative(raw)[:2 * n]

    def interaction_with(self, dm):
        """Measurements of a unit command of each mode of ``dm`` (raw Z-tilts transformed)."""
        block = self.operators[dm.plane][:, dm.pixels]
        if dm.shapes is None:
            return sparse.csr_matrix(self._transform @ block.toarray())
        return self._transform @ dm.sensed_by(block)


def _relative_rms_factor(share: np.ndarray, read_fraction: float = 0.0) -> np.ndarray:
    """Rms of relative slopes over a fully lit one's, from their light shares ``(n,)``.

    A relative slope is the shift of subaperture ``i`` against the reference subaperture
    (the best lit, share ``s_ref = max(share)``); their noises are independent, so its
    variance is the sum ``sigma_1^2 (v(s_i) + v(s_ref))``, ``sigma_1^2`` a fully lit
    single image's and ``v`` its growth with the contrast-weighted light collected
    (``closedloop.optics.wfs.lit_noise_variance``: ``1 / s`` photon-limited, the
    linearised SDF, Michau et al. 1992; ``1 / s**2`` read-noise limited, the fraction
    ``read_fraction`` of the variance). ``slope_noise_pixels`` holds ``sqrt(2) sigma_1``
    (both images fully lit): the factor is ``sqrt((v(s_i) + v(s_ref)) / 2)``, 1 where
    every share is 1.
    """
    v = lit_noise_variance(share, read_fraction)
    return np.sqrt((v + v[np.argmax(share)]) / 2.0)


#: noise tables by (reference image, read noise): the WFSs of an MCAO share their trackers'
#: (and often their subapertures') images, and each table costs ~1 s
_NOISE_TABLES: dict = {}


def _noise_table(imager: CorrelatingSubapertures, ron2: float) -> np.ndarray:
    """Shift variance over fractional shifts / at (0, 0): ``(steps, steps, 2)`` (class doc)."""
    key = (hashlib.sha1(imager.reference.tobytes()).hexdigest(), imager.reference.shape,
           float(ron2))
    if key not in _NOISE_TABLES:
        if len(_NOISE_TABLES) >= 64:
            _NOISE_TABLES.clear()
        _NOISE_TABLES[key] = _compute_noise_table(imager, ron2)
    return _NOISE_TABLES[key].copy()


def _compute_noise_table(imager: CorrelatingSubapertures, ron2: float) -> np.ndarray:
    steps = NOISE_TABLE_STEPS
    f = (np.arange(steps) + 0.5) / steps - 0.5
    fy, fx = np.meshgrid(f, f, indexing="ij")
    shifts = np.column_stack([fx.ravel(), fy.ravel()])
    live = imager.displaced_references(np.vstack([[0.0, 0.0], shifts]))
    rms = sdf_noise_at_shifts(imager.reference, live, np.clip(live, 0.0, None) + ron2,
                              max_shift=MAX_SHIFT, draws=NOISE_TABLE_DRAWS)
    return ((rms[1:] / rms[0]) ** 2).reshape(steps, steps, 2)


def _noise_gain(table: np.ndarray, px: np.ndarray, py: np.ndarray) -> np.ndarray:
    """Return the rms factor ``(n, 2)`` at shifts ``px``, ``py`` [pixels] (periodic, bilinear)."""
    steps = table.shape[0]
    out = []
    for p in (px, py):
        u = (p - np.round(p) + 0.5) * steps - 0.5
        i0 = np.floor(u)
        out.append((i0.astype(np.int64) % steps, u - i0))
    (ix, tx), (iy, ty) = out
    jx, jy = (ix + 1) % steps, (iy + 1) % steps
    v = ((1 - ty) * (1 - tx))[:, None] * table[iy, ix] + ((1 - ty) * tx)[:, None] * table[iy, jx] \
        + (ty * (1 - tx))[:, None] * table[jy, ix] + (ty * tx)[:, None] * table[jy, jx]
    return np.sqrt(v)


# ---------------------------------------------------------------------- the kind's record
def _validate(w, p: str) -> None:
    """Refuse a hand-set noise and a subaperture image under 8 pixels (the kind's rules)."""
    if w.noise != 0.0:
        raise ValueError(f"`{p}noise` must be 0 for kind 'correlating' (its noise follows "
                         f"from its photon budget: set `signal` and `contrast`); got "
                         f"{w.noise!r}.")
    if w.field_of_view / w.pixel_scale < 8:
        raise ValueError(f"`{p}field_of_view` must be >= 8 detector pixels of pixel_scale = "
                         f"{w.pixel_scale:g}\" for kind 'correlating' (a subaperture image to "
                         f"correlate); got {w.field_of_view!r}.")


def _sampling(config: SimulationConfig, j: int, dx: float) -> tuple[int, int, int, int]:
    """Pupil samples across, convolution size, PSF samples across, patches of WFS ``j``.

    As :class:`CorrelatingShackHartmann` sets them (its default photon budget's
    wavelength, :data:`MAX_SHIFT`), without building anything.
    """
    w = config.wfss[j]
    lam = PhotonBudget().wavelength
    pitch = wfs_meta_pupil(config, j) / w.n_subapertures
    p = max(2, int(round(pitch / dx)))
    n_field = int(round(w.field_of_view / w.pixel_scale))
    margin, support = convolution_support(n_field, w.pixel_scale, pitch, lam, MAX_SHIFT)
    q = pupil_oversampling_needed(2 * margin + 1, w.pixel_scale, pitch / p, lam)
    k = psf_subsampling(w.pixel_scale, pitch, lam)
    n_patches = min(2 * w.field_samples - 1, n_field // 4) if w.image_formation else 1
    return p * q, support, (2 * margin + 1) * k, n_patches


def _cost(config: SimulationConfig, j: int, n_planes: int, dx: float) -> SensorCost:
    w = config.wfss[j]
    n_sub = math.pi / 4.0 * w.n_subapertures ** 2
    n_meas = 2.0 * n_sub + 2.0
    f, support, psf_across, n_patches = _sampling(config, j, dx)
    # built one field sample at a time: per plane, each pupil sample's 2 fit weights and 4
    # bilinear reads; the imaging mode keeps 4 reads per sample per sub-direction
    entries = n_planes * n_sub * f * f * 6
    if not w.image_formation:
        return SensorCost(n_measurements=n_meas, build_entries=entries)
    entries += n_patches ** 2 * n_planes * n_sub * f * f * 4
    n_images = math.pi / 4.0 * w.n_subapertures ** 2 * n_patches ** 2
    # the OTF's two Fourier sums dominate: support^2 x PSF samples per image
    seconds = _SECONDS_PER_IMAGE_OP * n_images * support ** 2 * psf_across
    return SensorCost(n_measurements=n_meas, build_entries=entries, frame_seconds=seconds,
                      frame_key=f"wfss[{j}].image_formation")


def _aot_record(model, j: int, wcfg, meas):
    # slopes less their mean, then the correlation tracker's global Z-tilt as one more
    # entry per axis (it has no subaperture in the mask)
    return slopes_aot_record(model, j, wcfg, meas, n_extra=1, extra=dict(
        kind="correlating", pixel_scale=wcfg.pixel_scale, image_formation=wcfg.image_formation,
        note=("correlating SH on granulation: Z-tilts less their mean; the last entry of "
              "each axis is the correlation tracker's global tilt (no subaperture in the "
              "mask)")))


def _aot_layout(wfs, arr: np.ndarray) -> np.ndarray:
    """``(x..., y..., tracker x, tracker y)`` -> ``(rows, 2, n_valid + 1)``, tracker last."""
    arr = np.ascontiguousarray(arr)
    n = wfs.n_valid_subapertures
    order = np.r_[0:n, 2 * n, n:2 * n, 2 * n + 1]
    return np.ascontiguousarray(arr[:, order]).reshape(arr.shape[0], 2, n + 1)


#: the correlating (solar) Shack-Hartmann
CORRELATING = register_sensor_kind(SensorKind(
    name="correlating", build=CorrelatingShackHartmann, estimate=_cost,
    aot_record=_aot_record, aot_layout=_aot_layout, validate=_validate,
    check=check_subaperture_sampling, measurement_count=slope_count, fields=KEYS))
