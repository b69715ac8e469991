"""Ready-made synthetic logs: :func:`kaos_like` and its defaults."""

from __future__ import annotations

from typing import Any

import numpy as np

from modalinfo.common.validation import check_int, check_memory, check_real, check_rng, seed_record
from modalinfo.telemetry.log import ModalLog
from modalinfo.telemetry.synthetic.closed_loop import closed_loop_simulation
from modalinfo.telemetry.synthetic.spectra import (
    FFT_BYTES_PER_SAMPLE,
    _check_layers,
    _check_modes,
    _layers_metadata,
    open_loop_log,
)

__all__ = ["KAOS_LIKE_DEFAULTS", "kaos_like"]


#: Default parameters of :func:`kaos_like` (see its docstring for the rationale).
KAOS_LIKE_DEFAULTS: dict[str, Any] = {
    "modes": list(range(2, 29)),
    "rate": 2000.0,
    "diameter": 0.70,
    "wavelength": 500e-9,
    "outer_scale": 20.0,
    # r0 = 7 cm at 500 nm in total: 70 % of the turbulence in a slow ground layer, 30 %
    # in a faster one; r0_l = r0 * fraction_l**(-3/5).
    "layers": [
        {"r0": 0.07 * 0.7 ** (-0.6), "wind_speed": 5.0},
        {"r0": 0.07 * 0.3 ** (-0.6), "wind_speed": 10.0},
    ],
    "gain": 0.4664,
    "delay_frames": 1.0,
    "integration_frames": 1.0,
    "noise_rms": 0.02,
    "oversampling": 4,
    "discard_frames": 200,
}


def kaos_like(
    n_frames: int = 8000,
    closed_loop: bool = True,
    seed: int | np.random.Generator | None = 0,
    **overrides: Any,
) -> ModalLog:
    """Return a synthetic log resembling KAOS telemetry at the VTT (not real data).

    Defaults (:data:`KAOS_LIKE_DEFAULTS`): 27 modes Z2-Z28 (Noll), 2 kHz frames, a
    0.70 m aperture, r0 = 7 cm at 500 nm split 70/30 between a 5 m/s and a 10 m/s layer,
    von Karman outer scale 20 m, coefficients in rad at 500 nm; an integrator with
    gain 0.4664 (0 dB rejection bandwidth 130.0 Hz by the sampled model, see
    :func:`modalinfo.servo.closed_loop_bandwidth`), 1 frame WFS integration, 1 frame delay
    after it, WFS noise 0.02 rad RMS per mode per frame, simulated with 4 samples per frame.
    The first ``discard_frames`` frames (loop transient) are generated and dropped.

    Parameters
    ----------
    n_frames : int
        Frames in the returned log (>= 2).
    closed_loop : bool
        True: the WFS-measured closed-loop residual (with noise). False: the open-loop
        WFS measurement of the same turbulence (box-averaged over the integration time,
        without noise).
    seed : None, int or numpy.random.Generator
        One generator draws the turbulence, then the noise.
    **overrides
        Any key of :data:`KAOS_LIKE_DEFAULTS`; ``layers`` as Layer objects or dicts.

    Returns
    -------
    ModalLog
        ``(n_frames, M)`` in rad at ``wavelength`` with every generator parameter in
        ``metadata`` (JSON-serialisable).
    """
    unknown = sorted(set(overrides) - set(KAOS_LIKE_DEFAULTS))
    if unknown:
        raise TypeError(
            f"kaos_like() got unknown override(s) {unknown}; allowed: "
            f"{sorted(KAOS_LIKE_DEFAULTS)}."
        )
    n_frames = check_int(n_frames, "n_frames", minimum=2)
    if not isinstance(closed_loop, bool | np.bool_):
        raise TypeError(f"`closed_loop` must be a bool; got {closed_loop!r}.")
    p = {**KAOS_LIKE_DEFAULTS, **overrides}
    oversampling = check_int(p["oversampling"], "oversampling", minimum=1)
    discard = check_int(p["discard_frames"], "discard_frames", minimum=0)
    rate = check_real(p["rate"], "rate", minimum=0.0, strict_min=True)
    layers = _check_layers(p["layers"])
    rng = check_rng(seed)
    total = n_frames + discard
    # refused here so that the message names the caller's n_frames, not the oversampled
    # count passed to open_loop_log (adversarial round 18, q63)
    check_memory(FFT_BYTES_PER_SAMPLE * total * oversampling * len(_check_modes(p["modes"])),
                 "n_frames",
                 n_frames, "the oversampled open-loop series and their spectra")
    open_fine = open_loop_log(
        p["modes"], n_frames=total * oversampling, rate=rate * oversampling,
        diameter=p["diameter"], layers=layers, outer_scale=p["outer_scale"],
        wavelength=p["wavelength"], seed=rng,
    )
    result = closed_loop_simulation(
        open_fine, gain=p["gain"], delay_frames=p["delay_frames"],
        integration_frames=p["integration_frames"], noise_rms=p["noise_rms"],
        oversampling=oversampling, seed=rng,
    )
    chosen = result.residual if closed_loop else result.open_loop
    params = {k: v for k, v in p.items() if k != "layers"}
    params["layers"] = [layer.to_dict() for layer in layers]
    params["outer_scale"] = None if not np.isfinite(p["outer_scale"]) else float(
        p["outer_scale"])
    metadata = {
        "telescope": "VTT-like (synthetic)",
        "instrument": "KAOS-like WFS (synthetic)",
        "source": "modalinfo.telemetry.synthetic.kaos_like",
        "synthetic": True,
        "loop": "closed" if closed_loop else "open",
        "quantity": ("WFS-measured closed-loop residual (with noise)" if closed_loop
                     else "WFS-measured open-loop turbulence (box-averaged, no noise)"),
        "seed": seed_record(seed),
        "n_frames": n_frames,
        "generator": params,
        **{k: v for k, v in _layers_metadata(layers, float(p["diameter"]),
                                             float(p["wavelength"])).items() if k != "layers"},
        "bandwidth_rejection_0db_hz": result.bandwidth.rejection_0db,
        "bandwidth_closed_loop_3db_hz": result.bandwidth.closed_loop_3db,
        "wavelength_m": float(p["wavelength"]),
        "units_note": "coefficients in rad of phase at wavelength_m; Noll-normalised Zernikes",
    }
    coeffs = np.ascontiguousarray(chosen.coeffs[discard:])
    return ModalLog(coeffs, rate=rate, modes=list(chosen.modes), convention="noll",
                    units="rad", wavelength=float(p["wavelength"]), metadata=metadata)
