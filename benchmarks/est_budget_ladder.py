"""EST MCAO budget ladder: where the on-axis "aliasing" of ``est-mcao@16`` comes from.

The error budget's fitting and aliasing terms (:mod:`closedloop.budget`) are projections
of the *open-loop* turbulence, so they need no closed loop: this script takes
``--snapshots`` instants of one atmosphere (seed ``--seed``, every ``--spacing`` s) and,
for each rung of a ladder of configurations built from ``presets.est_mcao_variant(n)``
(same telescope, layers, science field and atmosphere), computes per direction

- ``fitting``: the turbulence less the mirrors driven by the ideal sensors' joint
  projection ``c_id`` (the budget's fitting term);
- ``sh``: the same with the Shack-Hartmanns' projection ``c_sh = R s(phi)`` (the budget's
  aliasing term is ``sh - fitting``);
- the split of ``c_sh - c_id`` into ``(R G - 1) c_id`` (**reconstructor**: what the SH
  reconstructor -- its MAP prior, model error and truncation -- does to a turbulence the
  mirrors *can* represent, as the ideal sensors see it) and ``R (s(phi) - G c_id)``
  (**aliasing proper**: the slopes of the part the mirrors cannot represent, folded
  into their modes), each as the variance of the mirrors' shape alone.

Rungs: ``scao`` (ground DM, one on-axis SH), ``glao`` (ground DM, the 60" SH), ``2dm``
(0 + 9 km), ``3dm`` (0, 5, 14 km), ``5dm`` (the preset), each with the preset's mode
counts and subaperture pitch for the mirrors it keeps. Prints one JSON line per rung
(rad^2 at the science wavelength; on axis and field mean over the 7 x 7 directions).

Usage::

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=$PWD python benchmarks/est_budget_ladder.py
    ... --rungs 5dm --model-error 0.03        # the reconstructor's model error changed
    ... --rungs 5dm --reconstructor truncated # the truncated joint reconstructor
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import time

import numpy as np

from closedloop import LoopModel, presets
from closedloop.budget import _ideal_config
from closedloop.optics import _kernels
from closedloop.optics.science import ScienceCamera
from closedloop.state import LoopState

RUNGS = {"scao": (0,), "glao": (0,), "2dm": (0, 3), "3dm": (0, 2, 4), "5dm": (0, 1, 2, 3, 4)}


def rung_config(base, rung: str, wfs_field: float | None = None):
    """``base`` with only the DMs (and their WFSs) of ``rung``; ``scao``: on-axis WFS.

    ``wfs_field``: the altitude WFSs' field [arcsec] (None: the preset's 60").
    """
    keep = RUNGS[rung]
    dms = tuple(base.dms[i] for i in keep)
    wfss = []
    for new, i in enumerate(keep):
        w = dataclasses.replace(base.wfss[i], dm=new)
        if rung == "scao":
            w = dataclasses.replace(w, field_of_view=0.0, field_samples=1)
        elif wfs_field is not None and w.altitude > 0:
            w = dataclasses.replace(w, field_of_view=wfs_field)
        wfss.append(w)
    return base.replace(name=f"{base.name}:{rung}", dms=dms, wfss=tuple(wfss))


def shape_variance(model, cam, turbulence, commands) -> np.ndarray:
    """Piston-removed variance per direction of ``turbulence - DMs(commands)``."""
    views = cam.plane_views()
    for p, v in enumerate(views):
        v[:] = 0.0 if turbulence is None else turbulence[p]
    for d, dm in enumerate(model.dms):
        _kernels.subtract_scatter(views[dm.plane], dm.pixels,
                                  dm.forward(commands[model.mode_slices[d]]), 1.0)
    return cam.forward().copy()


def reconstructor_times_interaction(model) -> np.ndarray:
    """``R G`` of the loop's reconstruction (with the MAP not a projector, so not
    ``controlled_projector``; one mirror: each WFS's least squares, whose ``R G`` it is)."""
    if model.reconstructor is None:
        return model.controlled_projector
    return model.reconstructor @ model.interaction


def ladder_rung(config, seed: int, snapshots: int, spacing: float) -> dict:
    t0 = time.process_time()
    model = LoopModel(config)
    ideal = LoopModel(_ideal_config(config))
    setup = time.process_time() - t0
    state = LoopState(model, model.atmosphere(seed, snapshots * spacing + 0.01))
    cam = ScienceCamera(model.geometry, model.science.directions)
    turb = [np.zeros_like(v) for v in cam.plane_views()]
    rg = reconstructor_times_interaction(model)
    rows = {k: [] for k in ("open", "fitting", "sh", "reconstructor", "aliasing_proper")}
    for i in range(snapshots):
        state.evolve_until((i + 1) * spacing)
        state.turbulence(turb)
        c_id = ideal.sense(turb, None)
        c_sh = model.sense(turb, None)
        c_rg = rg @ c_id
        rows["open"].append(shape_variance(model, cam, turb, 0 * c_id))
        rows["fitting"].append(shape_variance(model, cam, turb, c_id))
        rows["sh"].append(shape_variance(model, cam, turb, c_sh))
        rows["reconstructor"].append(shape_variance(model, cam, None, c_rg - c_id))
        rows["aliasing_proper"].append(shape_variance(model, cam, None, c_sh - c_rg))
    scale = (config.r0_wavelength / config.wavelength) ** 2
    dirs = np.asarray(cam.directions)
    axis = int(np.argmin(np.hypot(*dirs.T)))
    out = {"rung": config.name, "dm_altitudes": [d.altitude for d in config.dms],
           "wfs_fields": [w.field_of_view for w in config.wfss],
           "modes": [d.n_modes for d in config.dms],
           "n_controlled": getattr(model, "n_controlled", None),
           "model_error": config.loop.model_error,
           "loop_reconstructor": config.loop.reconstructor, "setup_cpu_s": round(setup, 2),
           "planes": [p.n for p in model.geometry.planes]}
    mean = {k: np.mean(v, axis=0) * scale for k, v in rows.items()}
    mean["aliasing_term"] = mean["sh"] - mean["fitting"]
    for k, v in mean.items():
        out[k] = {"axis": round(float(v[axis]), 3), "field": round(float(v.mean()), 3)}
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--subapertures", type=int, default=presets.EST_REDUCED_SUBAPERTURES)
    ap.add_argument("--rungs", nargs="+", default=list(RUNGS), choices=list(RUNGS))
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--snapshots", type=int, default=8)
    ap.add_argument("--spacing", type=float, default=0.01)
    ap.add_argument("--model-error", type=float, default=None)
    ap.add_argument("--reconstructor", choices=("truncated", "map"), default=None,
                    help="loop.reconstructor (default: the preset's)")
    ap.add_argument("--wfs-field", type=float, default=None,
                    help="field [arcsec] of the altitude WFSs (default: the preset's 60)")
    args = ap.parse_args()
    base = presets.est_mcao_variant(args.subapertures)
    if args.model_error is not None:
        base = base.replace(loop=dataclasses.replace(base.loop, model_error=args.model_error))
    if args.reconstructor is not None:
        base = base.replace(loop=dataclasses.replace(base.loop,
                                                     reconstructor=args.reconstructor))
    for rung in args.rungs:
        out = ladder_rung(rung_config(base, rung, args.wfs_field), args.seed,
                          args.snapshots, args.spacing)
        out["load_average"] = round(os.getloadavg()[0], 1)
        print(json.dumps(out), flush=True)


if __name__ == "__main__":
    main()
