"""The EST budget's terms against the laws they should follow (issue 29, "the budget ladder").

References (outside the code): the square-cutoff fitting law ``0.2313 (p / r0)^(5/3)``
of a mirror of pitch ``p`` (Hudgin 1977; Rigaut et al. 1998), and the Shack-Hartmann
aliasing of Rigaut, Veran & Lai (1998, SPIE 3353): ~0.3-0.4 of the fitting for a Fried SH
whose mirror controls every mode its slopes allow, less when fewer modes are controlled.
The budget's "aliasing" (``closedloop.budget``: the SH projection less the ideal
sensors') is split as docs/CLOSEDLOOP.md ("the budget ladder") does: ``(R G - 1) c_id``
(the reconstructor on what the mirrors can represent) plus ``R (s - G c_id)`` (aliasing
proper); only the second may be compared with the law (with the MAP ``R G`` is no
projector, and ``R G`` itself is used, not ``controlled_projector``). Projections of
open-loop snapshots of ``presets.est_mcao_variant(16)``'s atmosphere, seed 0 (no loop).
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from closedloop import LoopModel, presets
from closedloop.budget import _ideal_config
from closedloop.optics import _kernels
from closedloop.optics.science import ScienceCamera
from closedloop.state import LoopState


def reconstructor_times_interaction(model):
    """``R G`` (one mirror: each WFS's least squares; with the MAP not a projector)."""
    if model.reconstructor is None:
        return model.controlled_projector
    return model.reconstructor @ model.interaction


def _shape_variance(model, cam, turbulence, commands):
    views = cam.plane_views()
    for p, v in enumerate(views):
        v[:] = 0.0 if turbulence is None else turbulence[p]
    for d, dm in enumerate(model.dms):
        _kernels.subtract_scatter(views[dm.plane], dm.pixels,
                                  dm.forward(commands[model.mode_slices[d]]), 1.0)
    return cam.forward().copy()


def _on_axis_terms(config, snapshots: int) -> dict[str, float]:
    """On-axis fitting, budget aliasing, reconstructor and aliasing-proper [rad^2 science]."""
    model = LoopModel(config)
    ideal = LoopModel(_ideal_config(config))
    state = LoopState(model, model.atmosphere(0, 0.01 * snapshots + 0.01))
    cam = ScienceCamera(model.geometry, np.zeros((1, 2)))
    turb = [np.zeros_like(v) for v in cam.plane_views()]
    rg = reconstructor_times_interaction(model)
    out = {"fitting": 0.0, "aliasing": 0.0, "reconstructor": 0.0, "proper": 0.0}
    for i in range(snapshots):
        state.evolve_until(0.01 * (i + 1))
        state.turbulence(turb)
        c_id = ideal.sense(turb, None)
        c_sh = model.sense(turb, None)
        c_rg = rg @ c_id
        fit = _shape_variance(model, cam, turb, c_id)[0]
        out["fitting"] += fit
        out["aliasing"] += _shape_variance(model, cam, turb, c_sh)[0] - fit
        out["reconstructor"] += _shape_variance(model, cam, None, c_rg - c_id)[0]
        out["proper"] += _shape_variance(model, cam, None, c_sh - c_rg)[0]
    scale = (config.r0_wavelength / config.wavelength) ** 2 / snapshots
    return {k: v * scale for k, v in out.items()}


def test_single_conjugate_est_follows_the_fitting_and_aliasing_laws():
    base = presets.est_mcao_variant(16)
    wfs = dataclasses.replace(base.wfss[0], field_of_view=0.0, field_samples=1)
    scao = base.replace(dms=base.dms[:1], wfss=(wfs,))
    terms = _on_axis_terms(scao, snapshots=3)
    r0 = presets.EST_R0 * (base.wavelength / base.r0_wavelength) ** 1.2
    law = 0.2313 * (base.telescope.diameter / 16 / r0) ** (5 / 3)
    # 181 K-L modes for 16 x 16 subapertures (201 would fill the square cutoff): a little
    # more than the law, never 25 % more (measured 1.09x)
    assert law <= terms["fitting"] <= 1.25 * law
    # one mirror: each WFS's least squares keeps every mode, nothing is truncated
    assert terms["reconstructor"] <= 1e-9 * terms["fitting"]  # R G = 1 up to rounding
    assert 0.1 * terms["fitting"] <= terms["proper"] <= 0.4 * terms["fitting"]
    assert terms["aliasing"] == pytest.approx(terms["proper"], rel=0.2)


@pytest.mark.slow
def test_est_mcao_budget_aliasing_was_the_reconstructors_truncation():
    """At 5 mirrors and table1's model_error 0.3 the budget's "aliasing" is ``(R G - 1) c_id``.

    With the truncated reconstructor (table1's): the aliasing proper stays within the
    law's ~0.3-0.4 of the fitting while the budget's term is 2x the fitting
    (docs/CLOSEDLOOP.md); a model error of 0.03 cuts the reconstructor's share. ~40 s of
    CPU (two 5-mirror set-ups).
    """
    preset = presets.est_mcao_variant(16)
    assert preset.loop.reconstructor == presets.EST_RECONSTRUCTOR == "map"
    truncated = preset.replace(loop=dataclasses.replace(preset.loop, model_error=0.03,
                                                        reconstructor="truncated"))
    table1 = truncated.replace(loop=dataclasses.replace(truncated.loop, model_error=0.3))
    terms = _on_axis_terms(table1, snapshots=2)
    assert terms["proper"] <= 0.4 * terms["fitting"]
    assert terms["aliasing"] >= 1.5 * terms["fitting"]
    assert terms["reconstructor"] >= 0.8 * terms["aliasing"]
    less = _on_axis_terms(truncated, snapshots=2)
    assert less["reconstructor"] <= 0.6 * terms["reconstructor"]
    assert less["proper"] <= 0.4 * less["fitting"]


@pytest.mark.slow
def test_est_model_error_is_the_share_of_the_slopes_the_modes_leave_unexplained():
    """``s - G c_id`` per WFS, over the all-layer subaperture tilt variance (the law the
    setting scales, ``16 * 0.449 (d/r0)^(5/3) / d^2`` summed over layers): the MAP's
    model error (a noise variance it weighs by) lies inside their range, 0.002-0.017
    measured (the truncated form's 0.03 was above them all)."""
    config = presets.est_mcao_variant(16)
    model = LoopModel(config)
    ideal = LoopModel(_ideal_config(config))
    state = LoopState(model, model.atmosphere(0, 0.05))
    turb = [np.zeros((p.n, p.n)) for p in model.geometry.planes]
    g = model.geometry
    r0s = [g.layer_r0(i) for i in range(len(config.layers))]
    full = np.block([[w.interaction_with(dm) for dm in model.dms] for w in model.wfss])
    share = np.zeros(len(model.wfss))
    for i in range(3):
        state.evolve_until(0.01 * (i + 1))
        state.turbulence(turb)
        rest = np.concatenate(model.measure(turb, None)) - full @ ideal.sense(turb, None)
        start = 0
        for j, w in enumerate(model.wfss):
            part = rest[start:start + w.n_measurements]
            start += w.n_measurements
            share[j] += np.mean(part ** 2) / w.model_error_variance(r0s, 1.0) / 3
    assert np.all(share > 0)
    assert share.min() < presets.EST_MODEL_ERROR < share.max()
    assert np.all(share < 0.03)
