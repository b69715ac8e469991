r"""Export a simulation as an AO Telemetry (AOT) system, read back by ``aotpy`` and ``modalinfo``.

:func:`export_aot` writes one FITS
file describing the whole simulated system, built with
:func:`modalinfo.io.aot_system.build_system` and written atomically (never over an
existing file unless asked) by :func:`modalinfo.io.aot.write_system`:

* **telescope** ``"telescope"``: diameter, central obstruction, the pupil mask on the
  ``n_pixels`` grid, elevation ``90 - zenith_angle``;
* **source** ``"sun"``: a ``"natural"`` source (AOT has no extended-source type),
  ``extra = {"extended": "sun"}`` in the ``MI_GEOM`` card;
* **sensors** ``"wfs{j}"``: a Shack-Hartmann: valid subapertures, the
  ``(n_sub, n_sub)`` subaperture mask (``-1`` outside, else the index), measurements
  ``(T, 2, s_v)`` (x slopes then y slopes [rad/m] of the phase at ``r0_wavelength``:
  the result's ``(T, 2 s_v)`` rows reshaped, same bits) on the loop's timestamps;
  conjugation altitude [m above the telescope] and field of view [arcsec] in
  ``MI_GEOM`` (AOT has no field for them). An ``"ideal"`` sensor has no AOT type: it is
  written as a one-value-per-subaperture ``Pyramid`` record whose "subapertures" are
  the pixels of its DM's disc (mask on the DM's plane grid) and whose measurements are
  the field-averaged phase [rad]; ``MI_GEOM`` says ``"kind": "ideal"``; a correlating SH
  is a Shack-Hartmann record whose last entry per axis is its correlation tracker. Each
  kind writes its own record (``aot_record`` and ``aot_layout`` of its
  :class:`closedloop.kinds.SensorKind`);
* **correctors** ``"dm{i}"``: deformable mirrors, modal: each "actuator" is one mode
  (``n_valid_actuators = M``), the pupil mask is the controlled disc on the DM's plane
  grid ``(n_p, n_p)``; altitude in ``MI_GEOM``, and what an "actuator" is (the kind's
  ``aot_description``, :class:`closedloop.kinds.MirrorKind`);
* **atmosphere** ``"atmosphere"``: layer heights [m above the telescope], fractions
  ``(D/r0_l)^(5/3) / sum``, wind speeds [m/s] and directions in AOT's convention
  (:func:`aot_wind_direction`: deg, 0 = North, increasing eastward, the direction the
  wind blows *from*, with the simulator's +x taken as East and +y as North), outer
  scales [m] (``inf``: Kolmogorov) and the total r0 [m] at ``r0_wavelength`` and the
  zenith;
* **loops**, per DM ``i`` driven by sensor ``j``:

  - ``"dm{i}"``: modal coefficients = the ``dm{i}.residual`` log (the WFS-reconstructed
    modal residual, rad at ``r0_wavelength``). That is what the AOT field means for a
    closed loop (the modes seen by the sensor and corrected on the mirror), and it is
    the product ``measurements_to_modes @ measurements`` that AOT readers recompute
    when coefficients are absent. Also: the mode images ``(M, n_p, n_p)`` (unit-RMS
    Noll Zernikes Z2.. over the disc, 0 outside), ``modes_to_commands`` = identity
    (commands are modal coefficients), the commands (the ``dm{i}.commands`` log, in
    rad: ``BUNIT = 'rad'``, not AOT's metres, because the "actuators" are modes),
    ``measurements_to_modes`` (absent for an ideal sensor on a zonal DM, where it is the
    identity: a dense ``(pixels x pixels)`` image is not written), the integrator time
    filter, delay [frames] and framerate;
  - ``"dm{i}.pol"``: the pseudo-open-loop coefficients (the ``dm{i}.pol`` log, what a
    predictor forecasts). AOT has no field for them; they are a second loop record of
    the same sensor and corrector, without modes or reconstructor (their columns are
    the same Noll modes Z2..);
  - ``"dm{i}.wfs{k}"`` (global MAP reconstructor only, one per other sensor ``k``): AOT's
    ``measurements_to_modes`` maps *one* sensor to a loop's modes, but the MCAO
    reconstructor makes every DM's modes from *all* sensors. The loop ``"dm{i}"``
    holds the block of its own sensor, and each ``"dm{i}.wfs{k}"`` the block of sensor
    ``k`` (no coefficients), so that ``sum_k measurements_to_modes_ik @ s_k`` gives
    the ``dm{i}`` coefficients and the file holds the whole reconstructor.

  Each loop with coefficients carries the card ``MI_QUANT`` on its coefficient image
  (``residual`` or ``pol``: what the series is) and ``MI_WAVEL`` (the wavelength [m] of
  its phase in rad: ``r0_wavelength``, read back as the log's ``wavelength``); the
  residual of a closed loop also ``MI_TRANS``, its closure transient (the frames before
  its steady state, ``SimulationResult.transient_frames``; read back as
  ``metadata["transient_frames"]``, which ``modalinfo``'s quality pass leaves out and
  names instead of calling them glitched frames, fix54-e); the
  ``dm{i}.wfs{k}`` loops have no coefficient image, hence no card (the ``MI_CLOOP``
  card describes them). A mirror whose modes are not Noll Zernikes (a DM-space K-L
  ``DMKL1``..., a zonal mirror's ``pix0``...) also carries its mode labels there, the
  card ``MI_MODES`` (JSON list):
  AOT has no field for them and its mode images identify only Zernikes
  (``modalinfo.io.load`` reads the labels back). The time filter is
  :func:`~modalinfo.io.aot_system.integrator_filter` ``(gain, leak)``:
  ``c_k = (1 - leak) c_{k-1} + gain m_k`` (with a predictor the controller filters the
  forecast POL instead; the card ``MI_CLOOP`` names it).

* the configuration as TOML (``aotpy``: ``AOSystem.config``; JSON-quoted because FITS
  cards hold no newlines: :func:`modalinfo.io.aot_system.config_of` unquotes it), the
  mean Strehl over the field after loop closure at the science wavelength
  (``strehl_ratio``, ``strehl_wavelength``; :func:`export_aot` writes the wavelength's
  ``STREHL-L`` keyword itself, around an aotpy 3.2.1 bug that writes it over
  ``STREHL-R``), and the card ``MI_CLOOP`` (JSON: version, seed, predictor, what each
  loop holds, conventions).

Reading back, ``aotpy.AOSystem.read_from_file`` and ``modalinfo.io.load(path,
loop="dm0")`` give the result's arrays bit for bit (coefficients, timestamps,
measurements, commands: AOT images keep their float64 dtype).
"""

from __future__ import annotations

import json
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from closedloop.kinds import mirror_kind, sensor_kind
from modalinfo.common.files import quoted

# FITS overheads [bytes]: one copy, beside the modalinfo writer (left13-cli)
from modalinfo.io.aot import HDU_OVERHEAD as _HDU_OVERHEAD
from modalinfo.io.aot import TABLE_BYTES as _TABLE_BYTES

__all__ = ["AotSize", "aot_wind_direction", "build_aot_system", "check_export", "estimate_aot",
           "export_aot", "wind_direction_from_aot"]

#: system card describing what the closedloop export holds (JSON)
CLOSEDLOOP_KEY = "MI_CLOOP"

#: the wind-direction convention of the export, as written in the ``MI_CLOOP`` card
WIND_CONVENTION = ("AOT LAYERS_WIND_DIRECTION: deg, 0 = North, increasing eastward, the "
                   "direction the wind blows from (meteorological); the simulator's grid is "
                   "a map of the layer seen from above with +x = East, +y = North, and its "
                   "wind_direction a (deg from +x towards +y, where the screen moves to) is "
                   "written as (270 - a) mod 360; the configured values are in the config")


def aot_wind_direction(direction) -> np.ndarray:
    """Convert the simulator's wind direction to AOT's: ``(270 - a) mod 360`` [deg].

    The simulator's ``LayerConfig.wind_direction`` ``a`` is the direction the screen moves
    to, counter-clockwise from +x towards +y of its grid (velocity ``v (cos a, sin a)``,
    x along columns, y along rows). The AOT standard (``aotpy``:
    ``AtmosphericParameters.layers_wind_direction``) gives "0 deg being North, increasing
    eastward", the azimuth convention of its telescope field. The standard does not say
    "to" or "from"; the meteorological "wind direction" is where the wind comes *from*,
    and ``aotpy``'s ESO translators fill the field with ESO's ambient wind direction
    (``TEL AMBI WINDDIR``, a meteorological, from-direction azimuth) unchanged, so this
    export writes the from-direction. The grid has no sky orientation; it is taken as a
    map of the layer seen from above with +x = East and +y = North (the frame in which an
    azimuth runs from North through East). The blow-to bearing is then ``90 - a`` and
    the from-bearing ``270 - a``.

    Parameters
    ----------
    direction : float or array_like
        Simulator wind direction(s) [deg], any real value.

    Returns
    -------
    numpy.ndarray
        AOT wind direction(s) [deg] in ``[0, 360)``. Examples: wind along +x (to the
        East, a = 0) -> 270 (from the West); along +y (to the North, a = 90) -> 180.
    """
    a = np.asarray(direction, dtype=np.float64)
    if not np.all(np.isfinite(a)):
        raise ValueError(f"`direction` must be finite [deg]; got {direction!r}.")
    return _degrees(270.0 - a)


def _degrees(x: np.ndarray) -> np.ndarray:
    """``x mod 360`` in ``[0, 360)`` for ``x = 270 - a``, ``a`` any finite float64.

    ``np.mod`` rounds up to 360 only for ``x`` within half an ulp of 360 (2.8e-14) below
    a multiple of 360; ``270 - a`` is never there: near 270 the subtraction is exact
    (Sterbenz), so ``x`` is 0 or at least one ulp of ``a`` (5.7e-14) from it, and further
    out ``x``'s own ulp exceeds that gap (``test_aot_wind.py`` probes the floats next to
    270 + 360 k).
    """
    return np.mod(x, 360.0)


def wind_direction_from_aot(aot_direction) -> np.ndarray:
    """Convert AOT wind direction(s) to the simulator's: ``(270 - b) mod 360`` [deg].

    The inverse of :func:`aot_wind_direction` (the map ``x -> 270 - x`` is its own
    inverse modulo 360): ``b`` is the AOT azimuth the wind blows from (0 = North,
    increasing eastward), the result the simulator's direction of motion,
    counter-clockwise from +x (East) towards +y (North), in ``[0, 360)``.
    """
    b = np.asarray(aot_direction, dtype=np.float64)
    if not np.all(np.isfinite(b)):
        raise ValueError(f"`aot_direction` must be finite [deg]; got {aot_direction!r}.")
    return _degrees(270.0 - b)


@dataclass(frozen=True)
class AotSize:
    """What :func:`export_aot` writes and holds, estimated from the result before any work.

    Attributes
    ----------
    file_bytes : float
        Size of the FITS file [bytes].
    memory_bytes : float
        Peak memory of the export [bytes]: the interpreter, the ``LoopModel`` rebuilt when
        none is given (its set-up, :func:`closedloop.resources.estimate`), and every array
        of the system held at once while aotpy writes it.
    parts : dict of str to float
        File bytes per part: ``mode_images`` (``(M, n_p, n_p)`` float64 per mirror with a
        shape matrix: every pixel of its plane), ``reconstructor``
        (``measurements_to_modes`` blocks and ``modes_to_commands``), ``logs``
        (residual, POL, commands: ``(T, M)`` each), ``measurements`` (``(T, n_meas)``
        per sensor) and ``other`` (masks, tables, headers).
    """

    file_bytes: float
    memory_bytes: float
    parts: dict = field(default_factory=dict)

    @property
    def largest(self) -> str:
        """The part of the file that weighs most."""
        return max(self.parts, key=self.parts.__getitem__)


def _plane_sides(config) -> list[int]:
    """Side [pixels] of the plane of each DM of ``config`` (no grid built)."""
    from closedloop.optics.geometry import plane_layout

    layout = plane_layout(config)
    return [next(n for _, n, _, dms in layout if i in dms) for i in range(len(config.dms))]


def estimate_aot(result, *, model=None, mode_images: bool = True) -> AotSize:
    """Estimate the file and the memory of ``export_aot(result, ...)`` from sizes alone.

    Nothing is built: the mirrors' mode counts are the result's logs' columns, the
    sensors' measurement counts their logged measurements' (else the config's
    estimate), the planes' sides :func:`closedloop.optics.geometry.plane_layout`'s.

    Parameters
    ----------
    result : SimulationResult
        The run to export.
    model : LoopModel, optional
        Given: the export does not rebuild it (its memory is not counted).
    mode_images : bool
        Count the mirrors' mode images (``export_aot(..., mode_images=False)`` leaves
        them out).

    Returns
    -------
    AotSize
    """
    from closedloop.resources import BASELINE_BYTES, estimate

    cfg = result.config
    n_frames = int(np.asarray(result.times).size)
    n_dm = len(cfg.dms)
    modes = [int(np.shape(result.logs[f"dm{i}.residual"].coeffs)[1]) for i in range(n_dm)]
    zonal = [mirror_kind(d.kind).controlled_modes is None for d in cfg.dms]
    if len(result.measurements) == len(cfg.wfss):
        n_meas = [int(np.shape(m)[1]) for m in result.measurements]
        measured = True
    else:
        from closedloop.resources import _sensor_costs

        dx = cfg.telescope.diameter / cfg.telescope.n_pixels
        from closedloop.optics.geometry import plane_layout

        costs = _sensor_costs(cfg, len(plane_layout(cfg)), dx)
        n_meas = [int(c.n_measurements) for c in costs]
        measured = False
    sides = _plane_sides(cfg)
    joint = n_dm > 1 and not any(zonal)
    own = {w.dm: j for j, w in enumerate(cfg.wfss)}
    hdus = 1 + len(cfg.wfss) * (2 if measured else 1) + n_dm * 6
    images = recon = logs = 0.0
    for i in range(n_dm):
        m, n = modes[i], sides[i]
        logs += 3 * 8.0 * n_frames * m
        if not zonal[i]:
            recon += 8.0 * m * m  # modes_to_commands (identity: commands are modes)
            if mode_images:
                images += 8.0 * m * n * n
                hdus += 1
        for k in range(len(cfg.wfss)):
            if (k == own.get(i) or joint) and not (zonal[i] and cfg.wfss[k].kind == "ideal"):
                recon += 8.0 * m * n_meas[k]
                hdus += 1
    meas = 8.0 * n_frames * sum(n_meas) if measured else 0.0
    masks = 2.0 * (cfg.telescope.n_pixels ** 2 + sum(n * n for n in sides))
    other = masks + _TABLE_BYTES + _HDU_OVERHEAD * hdus
    parts = {"mode_images": images, "reconstructor": recon, "logs": logs,
             "measurements": meas, "other": other}
    file_bytes = float(sum(parts.values()))
    # held at once: the system's arrays (the file less its headers and padding) and the
    # result's own logs and measurements, loaded before the export
    held = file_bytes - _HDU_OVERHEAD * hdus + logs / 3.0 * 4.0 + meas
    build = 0.0
    if model is None:
        est = estimate(cfg, max(n_frames, 1) * cfg.loop.time_step)
        kept = est.parts["pupil"] + est.parts["dm_shapes"] + est.parts["reconstructor"]
        build = max(est.setup_bytes - kept, 0.0)
        held += kept
    return AotSize(file_bytes=file_bytes, memory_bytes=BASELINE_BYTES + held + build,
                   parts=parts)


def _own_sensor(config, i: int) -> int:
    for j, w in enumerate(config.wfss):
        if w.dm == i:
            return j
    raise ValueError(f"DM {i} is driven by no WFS (`wfss[j].dm`); cannot export its loop.")


def _disc_mask(dm, n: int) -> np.ndarray:
    mask = np.zeros(n * n, dtype=np.int16)
    mask[dm.pixels] = 1
    return mask.reshape(n, n)


def _mode_images(dm, n: int) -> np.ndarray | None:
    if dm.shapes is None:
        return None
    img = np.zeros((dm.n_modes, n * n))
    img[:, dm.pixels] = dm.shapes.T
    return img.reshape(dm.n_modes, n, n)


def _as_dsv(wfs, arr: np.ndarray) -> np.ndarray:
    """``(rows, n_meas)`` -> ``(rows, d, s_v)``, as the sensor's kind lays it out."""
    return sensor_kind(wfs.kind).aot_layout(wfs, arr)


def _blocks(model, i: int) -> list[np.ndarray]:
    """Reconstructor of DM ``i``'s modes from each sensor's measurements: ``[(M_i, n_meas_k)]``."""
    sl = model.mode_slices[i]
    if model.reconstructor is not None:
        edges = np.concatenate([[0], np.cumsum([w.n_measurements for w in model.wfss])])
        return [model.reconstructor[sl, edges[k]:edges[k + 1]] for k in range(len(model.wfss))]
    out = []
    for w in model.wfss:
        if w.dm.index != i:
            out.append(None)
        elif w.reconstructor is None:
            # ideal sensor on a zonal DM: the identity, not written (a dense (pixels x
            # pixels) image, 200 MB at 80 px); the MI_CLOOP card says so
            out.append(None)
        else:
            out.append(w.reconstructor)
    return out


def _telescope_and_source(cfg, g):
    """Build the telescope record (pupil mask on the ``n_pixels`` grid) and the sun as a source."""
    from modalinfo.io.aot_system import SourceSpec, TelescopeSpec

    telescope = TelescopeSpec(
        uid="telescope", diameter=cfg.telescope.diameter,
        obscuration_diameter=(cfg.telescope.obscuration * cfg.telescope.diameter
                              if cfg.telescope.obscuration > 0 else None),
        pupil_mask=g.pupil_mask, elevation=90.0 - cfg.telescope.zenith_angle)
    sun = SourceSpec(uid="sun", kind="natural",
                     extra={"extended": "sun", "note": "AOT has no extended-source type"})
    return telescope, sun


def _other_code(result) -> str:
    """Why a result's arrays may not fit the model this code builds from its config.

    A result written by another version of the code holds what that version built: the
    same TOML gives a 10-km Shack-Hartmann 120 valid subapertures before 2e799ca8's field
    rule and 200 after, and ``export`` said only "has shape (20, 240); expected (20, 400)"
    (round 47 PART b V12, W12). Empty when the result was written by this code.
    """
    from modalinfo.common.provenance import code_record

    prov = result.provenance or {}
    written, here = prov.get("source_sha256"), code_record().get("source_sha256")
    if written is not None and written == here:
        return ""
    who = (f"another version of the code (git {prov['git']})" if prov.get("git") else
           "another version of the code (source " + written[:12] + ")" if written else
           "an older version of the code (it recorded no source in its results)")
    return (f": the result was written by {who}, which built its config differently; "
            "export it with that version, or run the config again with this one")


def _sensors(result, model, n_frames: int) -> list:
    """Build every sensor's record, with its measurements ``(T, d, s_v)`` if the result has them."""
    have_meas = len(result.measurements) == len(model.wfss)
    sensors = []
    for j, (wfs, wcfg) in enumerate(zip(model.wfss, result.config.wfss, strict=True)):
        meas = None
        if have_meas:
            meas = np.asarray(result.measurements[j])
            if meas.shape != (n_frames, wfs.n_measurements):
                raise ValueError(f"result.measurements[{j}] has shape {meas.shape}; expected "
                                 f"{(n_frames, wfs.n_measurements)}{_other_code(result)}.")
            meas = _as_dsv(wfs, meas)
        sensors.append(sensor_kind(wfs.kind).aot_record(model, j, wcfg, meas))
    return sensors


def _corrector(cfg, model, i: int):
    """Build DM ``i``'s record: one actuator per mode (or disc pixel), its disc as mask."""
    from modalinfo.io.aot_system import CorrectorSpec

    g, dm = model.geometry, model.dms[i]
    n_p = g.planes[dm.plane].n
    described = mirror_kind(dm.kind).aot_description(dm)
    return CorrectorSpec(
        uid=f"dm{i}", kind="dm", n_valid_actuators=dm.n_modes,
        altitude=cfg.dms[i].altitude, pupil_mask=_disc_mask(dm, n_p),
        extra={"model": described["model"], "modes": described["modes"],
               "disc_diameter": dm.diameter, "line_of_sight_altitude": dm.altitude,
               "plane_pixels": n_p, "pixel_scale": g.dx})


def _dm_loops(result, model, i: int, common: dict, described: dict,
              mode_images: bool = True) -> tuple:
    """DM ``i``'s loops: residual, POL and the global reconstructor's other-sensor blocks.

    ``common`` holds the fields every loop shares (timestamps, time filter, ...) but the
    sensor and corrector; ``described`` gets one line per loop for the ``MI_CLOOP`` card.
    """
    from modalinfo.io.aot_system import LoopSpec

    dm = model.dms[i]
    j = _own_sensor(result.config, i)
    blocks = _blocks(model, i)
    common = dict(sensor=f"wfs{j}", corrector=f"dm{i}", **common)
    # modes that are not Noll Zernikes: their labels (DMKL1..., pix0...) in MI_MODES,
    # since the mode images identify only Zernikes (a reader would say mode1...)
    labels = {} if dm.modes else {"MI_MODES": json.dumps(list(dm.labels), separators=(",", ":"))}
    # the wavelength of the phase (rad at r0_wavelength): AOT's "rad" does not say it, and
    # a log read back had none (audit 10, feedback, rows cl-aot-*: `convert --units nm`
    # then needed a --wavelength the user had to guess)
    labels["MI_WAVEL"] = float(result.config.r0_wavelength)
    # the residual and the POL are coefficients of the same modes: both loops carry the
    # one image (written once), so neither reads back "(assumed)" (issue 27, left12-cli)
    images = _mode_images(dm, model.geometry.planes[dm.plane].n) if mode_images else None
    main = LoopSpec(
        uid=f"dm{i}", **common, units="rad",
        modal_coefficients=np.ascontiguousarray(result.logs[f"dm{i}.residual"].coeffs),
        modes=images,
        measurements_to_modes=(None if blocks[j] is None
                               else _as_dsv(model.wfss[j], blocks[j])),
        modes_to_commands=np.eye(dm.n_modes) if dm.shapes is not None else None,
        commands=np.ascontiguousarray(result.logs[f"dm{i}.commands"].coeffs),
        command_units="rad", coefficient_metadata={"MI_QUANT": "residual", **labels,
                                                   **_transient_card(result)})
    described[f"dm{i}"] = ("modal residual reconstructed from the WFS measurements "
                           f"(log dm{i}.residual); commands = log dm{i}.commands"
                           + _transient_words(result))
    pol = LoopSpec(
        uid=f"dm{i}.pol", **common, units="rad",
        modal_coefficients=np.ascontiguousarray(result.logs[f"dm{i}.pol"].coeffs),
        modes=images, coefficient_metadata={"MI_QUANT": "pol", **labels})
    described[f"dm{i}.pol"] = f"pseudo-open-loop coefficients of dm{i} (log dm{i}.pol)"
    cross = []
    for k, block in enumerate(blocks):
        if k == j or block is None:
            continue
        cross.append(LoopSpec(
            uid=f"dm{i}.wfs{k}", **{**common, "sensor": f"wfs{k}"},
            measurements_to_modes=_as_dsv(model.wfss[k], block)))
        described[f"dm{i}.wfs{k}"] = (f"block of the global reconstructor: wfs{k} "
                                      f"measurements to dm{i} modes (no coefficients)")
    return main, pol, cross


#: card of the residual's closure transient: the frames before the loop's steady state
TRANSIENT_KEY = "MI_TRANS"


def _transient_card(result) -> dict:
    """Return the residual's ``MI_TRANS`` card: frames before the steady state, or none.

    The number is the result's ``SimulationResult.transient_frames`` (its
    ``averaging_start``: the detected closure of a closed loop, the second half's start of
    one that did not close; the servo model's few time constants for one still
    converging, fix56-c; 0, no card, in open loop), the number its run.h5 logs carry in
    ``metadata["transient_frames"]``: the quality pass of
    ``modalinfo`` leaves those frames out as a transient rather than calling the
    open-loop turbulence before the first command "glitched frames" (fix54-e; adversarial
    round 54 PART a, S30). The POL has no closure transient: it gets no card.
    """
    start = int(result.transient_frames)
    return {TRANSIENT_KEY: start} if start > 0 else {}


def _transient_words(result) -> str:
    """Return the ``MI_CLOOP`` words on the residual's ``MI_TRANS`` card ("" if none)."""
    start = int(result.transient_frames)
    if start <= 0:
        return ""
    return (f"; frames 0-{start - 1} are the loop's closure transient (card {TRANSIENT_KEY}: "
            "the frames before its steady state, SimulationResult.transient_frames)")


def _atmosphere(cfg):
    """Build the atmosphere record: heights, ``(D/r0_l)^(5/3)`` fractions, winds, total r0."""
    from modalinfo.io.aot_system import AtmosphereSpec

    strength = np.array([lay.d_over_r0 ** (5.0 / 3.0) for lay in cfg.layers])
    return AtmosphereSpec(
        uid="atmosphere", wavelength=cfg.r0_wavelength,
        r0=cfg.telescope.diameter / float(strength.sum()) ** 0.6,
        heights=np.array([lay.altitude for lay in cfg.layers]),
        weights=strength / strength.sum(),
        wind_speeds=np.array([lay.wind_speed for lay in cfg.layers]),
        wind_directions=aot_wind_direction([lay.wind_direction for lay in cfg.layers]),
        outer_scales=np.array([lay.outer_scale for lay in cfg.layers]))


def _notes(result, model, described: dict) -> dict:
    """Gather the ``MI_CLOOP`` card's content: provenance, what each loop holds, conventions."""
    cfg = result.config
    return {
        "written_by": "closedloop", "version": result.version, "seed": int(result.seed),
        # the result's record (commit, config hash, command; None for results saved
        # before it existed): the export dropped it (adversarial round 30 PART b, C05)
        "provenance": getattr(result, "provenance", None),
        "predictor": result.predictor, "loops": described,
        "reconstructor": ("global MAP: dm{i} modes = sum over sensors k of the blocks in "
                          "loops dm{i} (own sensor) and dm{i}.wfs{k}"
                          if model.reconstructor is not None else
                          "one per sensor: loop dm{i}.measurements_to_modes (absent: the "
                          "identity, an ideal sensor on a zonal DM)"),
        "units": "phase in rad at r0_wavelength; slopes in rad/m",
        "r0_wavelength": cfg.r0_wavelength,
        "altitudes": "m above the telescope (line of sight: times sec(zenith_angle))",
        "wind_direction": WIND_CONVENTION,
        "strehl_ratio": ("Marechal SR averaged over the field grid after loop closure "
                         "(over the second half of the run if the loop did not close)"),
        "time_filter": "integrator c_k = (1 - leak) c_{k-1} + gain m_k"
                       + ("" if result.predictor == "none" else
                          f"; the loop ran with predictor {result.predictor!r}, which "
                          "filters the forecast POL instead"),
    }


def build_aot_system(result, model=None, *, mode_images: bool = True):
    """Build the ``aotpy.AOSystem`` of a simulation (see the module docstring).

    Parameters
    ----------
    result : SimulationResult
        The run.
    model : LoopModel, optional
        The run's static parts (rebuilt from ``result.config`` if not given; it is
        deterministic).
    mode_images : bool
        Write each mirror's mode images (False: the loops carry no ``modes``; a mirror
        of Noll Zernikes then reads back with its labels assumed, the others with their
        ``MI_MODES`` labels). They are most of the file: :func:`estimate_aot`.

    Returns
    -------
    aotpy.AOSystem
    """
    from closedloop.config import config_text
    from closedloop.simulation import LoopModel
    from modalinfo.io.aot_system import build_system, import_aotpy, integrator_filter

    cfg = result.config
    if model is None:
        model = LoopModel(cfg)
    elif model.config != cfg:
        raise ValueError("`model` was built for another config than the result's.")
    times = np.asarray(result.times, dtype=np.float64)
    num, den = integrator_filter(cfg.loop.gain, cfg.loop.leak)
    telescope, sun = _telescope_and_source(cfg, model.geometry)
    sensors = _sensors(result, model, times.size)

    correctors, loops_main, loops_pol, loops_cross = [], [], [], []
    described = {}
    common = dict(timestamps=times, framerate=1.0 / cfg.loop.time_step,
                  delay=cfg.loop.delay_frames, time_filter_num=num, time_filter_den=den,
                  closed=not result.open_loop)
    for i in range(len(model.dms)):
        correctors.append(_corrector(cfg, model, i))
        main, pol, cross = _dm_loops(result, model, i, common, described, mode_images)
        loops_main.append(main)
        loops_pol.append(pol)
        loops_cross.extend(cross)

    system = build_system(
        loops_main + loops_pol + loops_cross, sensors=sensors, correctors=correctors,
        sources=[sun], telescope=telescope, atmosphere=[_atmosphere(cfg)],
        name=f"closedloop {cfg.name}", config=config_text(cfg, "toml"))
    s = result.summary()
    system.strehl_ratio = float(s["strehl_field_mean"])
    system.strehl_wavelength = float(cfg.wavelength)
    aotpy = import_aotpy()
    # whether the mode images were left out: a reader asked for the basis names the
    # option (adversarial round 54 PART b, P23: "has no mode images" without the why)
    notes = {**_notes(result, model, described), "mode_images": bool(mode_images)}
    system.metadata.append(aotpy.Metadatum(
        CLOSEDLOOP_KEY, json.dumps(notes, ensure_ascii=True, separators=(",", ":"))))
    return system


def export_aot(result, path, *, overwrite: bool = False, model=None,
               mode_images: bool = True) -> Path:
    """Write a simulation as a complete AOT system (FITS), atomically.

    Parameters
    ----------
    result : SimulationResult
        The run.
    path : str or os.PathLike
        Target file (``.fits``).
    overwrite : bool
        Replace an existing file; otherwise ``FileExistsError`` (checked before any work).
    model : LoopModel, optional
        The run's static parts (rebuilt from the config when not given).
    mode_images : bool
        Write the mirrors' mode images ``(M, n_p, n_p)`` float64, every pixel of each
        mirror's plane: most of the file (8.9 of 9.1 GB for ``est-mcao-solar``).
        False leaves them out (see :func:`build_aot_system`).

    Returns
    -------
    pathlib.Path
        The written path.

    Raises
    ------
    closedloop.resources.ResourceError
        The export would hold more than the memory available (:func:`estimate_aot`,
        checked before any work), naming the size and ``mode_images=False``.
    modalinfo.common.folders.OutputError
        The target's folder has less free space than the file needs.
    """
    from modalinfo.common.files import as_path
    from modalinfo.io.aot import write_system

    path = as_path(path)
    if path.exists() and not overwrite and not path.is_dir():
        raise FileExistsError(f"{quoted(path)} exists; pass overwrite=True to replace it")
    check_export(result, path, model=model, mode_images=mode_images)
    system = build_aot_system(result, model, mode_images=mode_images)
    _strehl_wavelength_as_card(system)
    return write_system(system, path, overwrite=overwrite)


def check_export(result, path, *, model=None, mode_images: bool = True,
                 memory: float | None = None) -> AotSize:
    """Refuse an export that cannot fit in memory or on disk, before any work.

    Parameters
    ----------
    result, model, mode_images
        As in :func:`export_aot`.
    path : str or os.PathLike
        The target file (its folder's free space is checked).
    memory : float, optional
        Memory the export may use [bytes]; default the machine's available memory
        (:func:`modalinfo.common.memory.available_memory_bytes`), capped by the address
        space an ``ulimit -v`` leaves.

    Returns
    -------
    AotSize
        The estimate.

    Raises
    ------
    closedloop.resources.ResourceError
        One line: the memory needed, the limit, the file's size and the mode images'
        share, and ``mode_images=False`` when they are written.
    modalinfo.common.folders.OutputError
        The folder lacks the file's size.
    """
    from closedloop.resources import ResourceError
    from modalinfo.common.sizes import format_size
    from modalinfo.io.aot import check_aot_size

    size = estimate_aot(result, model=model, mode_images=mode_images)
    images = size.parts["mode_images"]
    fix = (f"; the mirrors' mode images are {format_size(images)} of it: pass "
           "mode_images=False to leave them out" if images > 0 else "")
    # an address-space cap (ulimit -v) counts too: the file is then mapped whole to
    # describe its loops, and every array allocated counts against it
    check_aot_size(path, size.file_bytes, size.memory_bytes,
                   what="exporting this result as AOT", fix=fix, memory=memory,
                   error=ResourceError)
    return size


def _strehl_wavelength_as_card(system) -> None:
    """Move ``system.strehl_wavelength`` into its own ``STREHL-L`` card before writing.

    aotpy's bug (3.2.1, ``aotpy/io/fits/_file.py``, ``PrimaryHeader.to_hdu``): it
    writes ``strehl_wavelength`` under the key ``STREHL-R``, over the Strehl ratio,
    and no ``STREHL-L``: a file read back gives the wavelength as the Strehl ratio and
    no wavelength. With ``strehl_wavelength`` None, aotpy writes only ``STREHL-R`` (the
    ratio); the system card ``STREHL-L`` written here is the AOT keyword its reader
    takes as ``strehl_wavelength`` (and leaves out of ``metadata``). Correct with a
    fixed aotpy too, which then also sees no wavelength to write itself.
    """
    from modalinfo.io.aot_system import import_aotpy

    wavelength = system.strehl_wavelength
    if wavelength is None:
        return
    system.strehl_wavelength = None
    system.metadata.append(import_aotpy().Metadatum(
        "STREHL-L", float(wavelength), "Strehl ratio wavelength [m]"))
