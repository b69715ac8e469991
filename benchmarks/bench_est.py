"""EST MCAO runs: set-up time, CPU time per frame, peak RSS, SR map and error budget.

Builds ``presets.est_mcao_variant(n, solar=...)`` (``n`` ground subapertures across the
4.2 m pupil; 45 is the published ``est-mcao``, 16 the reduced-resolution variant of
docs/CLOSEDLOOP.md, "EST MCAO"), times its :class:`closedloop.LoopModel` (the set-up:
K-L modes, WFS operators, reconstructor) in process CPU time, runs the loop with the
error budget every ``--budget-every`` frames, then times ``--frames`` frames without
the budget (warm). Prints one JSON line: set-up CPU seconds, CPU seconds per frame,
peak RSS (``resource.getrusage``, the process's maximum), the loop status, SR peak and
field mean after closure, the corrected-FoV diameter, the SR map (field grid, rows y)
and the budget per term (field mean and on axis, rad^2 at 630 nm).

Usage::

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=$PWD python benchmarks/bench_est.py --subapertures 16
    ... --solar --duration 0.1 --high-share 2   # the profile above 5 km doubled
    ... --subapertures 45 --duration 0.05 --frames 20 --profile 25   # published size

``--profile N`` runs the set-up under cProfile on the CPU clock and prints its N
largest functions by own time, then by cumulative time, on stderr. ``--setups K`` builds
the model K times in the process (the second and later find the DM-space K-L modes in
the in-process cache) and ``--setup-only`` stops after the set-ups, printing their CPU
times, the load and the peak RSS::

    ... --subapertures 45 --setup-only --setups 2   # the published size's set-up
"""

from __future__ import annotations

import argparse
import cProfile
import dataclasses
import json
import os
import pstats
import resource
import sys
import time

import numpy as np

from closedloop import LoopModel, presets, simulate


def scaled_high_layers(config, factor: float, above: float = 5_000.0):
    """``config`` with the turbulence share of the layers at ``>= above`` m times
    ``factor``, the others scaled so that the total r0 stays (the sweep of the docs)."""
    s = np.array([lay.d_over_r0 ** (5 / 3) for lay in config.layers])
    high = np.array([lay.altitude >= above for lay in config.layers])
    f_high = s[high].sum() / s.sum() * factor
    if not 0 < f_high < 1:
        raise ValueError(f"`factor` must keep the high share in (0, 1); got {f_high:g}.")
    w = np.where(high, factor, (1 - f_high) / (1 - s[high].sum() / s.sum()))
    layers = tuple(dataclasses.replace(lay, d_over_r0=float((si * wi) ** 0.6))
                   for lay, si, wi in zip(config.layers, s, w, strict=True))
    return config.replace(layers=layers)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--subapertures", type=int, default=presets.EST_REDUCED_SUBAPERTURES)
    ap.add_argument("--solar", action="store_true")
    ap.add_argument("--duration", type=float, default=0.1)
    ap.add_argument("--budget-every", type=int, default=5,
                    help="frames between budget probes (0: no budget)")
    ap.add_argument("--frames", type=int, default=50)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--high-share", type=float, default=1.0)
    ap.add_argument("--altitude-pitch", type=float, default=presets.EST_ALTITUDE_PITCH)
    ap.add_argument("--model-error", type=float, default=None,
                    help="loop.model_error of the joint MAP reconstructor (default: the preset's)")
    ap.add_argument("--reconstructor", choices=("truncated", "map"), default=None,
                    help="loop.reconstructor, the joint reconstructor (default: the preset's)")
    ap.add_argument("--memory-limit", type=float, default=None,
                    help="simulate's memory_limit [GiB] (default: half the available memory)")
    ap.add_argument("--profile", type=int, default=0,
                    help="print the set-up's N largest functions (cProfile, CPU clock)")
    ap.add_argument("--setups", type=int, default=1,
                    help="build the model this many times (later ones: K-L cache hits)")
    ap.add_argument("--setup-only", action="store_true",
                    help="stop after the set-ups (no loop)")
    args = ap.parse_args()
    config = presets.est_mcao_variant(args.subapertures, solar=args.solar,
                                      altitude_pitch=args.altitude_pitch)
    if args.high_share != 1.0:
        config = scaled_high_layers(config, args.high_share)
    if args.model_error is not None:
        config = config.replace(loop=dataclasses.replace(config.loop,
                                                         model_error=args.model_error))
    if args.reconstructor is not None:
        config = config.replace(loop=dataclasses.replace(config.loop,
                                                         reconstructor=args.reconstructor))
    profiler = cProfile.Profile(time.process_time) if args.profile else None
    t0 = time.process_time()
    if profiler is not None:
        profiler.enable()
    model = LoopModel(config)
    if profiler is not None:
        profiler.disable()
    setup = time.process_time() - t0
    if profiler is not None:
        stats = pstats.Stats(profiler, stream=sys.stderr)
        stats.sort_stats("tottime").print_stats(args.profile)
        stats.sort_stats("cumulative").print_stats(args.profile)
    setups = [setup]
    for _ in range(args.setups - 1):
        del model
        t0 = time.process_time()
        model = LoopModel(config)
        setups.append(time.process_time() - t0)
    print(json.dumps({"setup_cpu_s": setup,
                      "rss_after_setup_gib": resource.getrusage(
                          resource.RUSAGE_SELF).ru_maxrss / 2**20}), file=sys.stderr,
          flush=True)
    if args.setup_only:
        print(json.dumps({"config": config.name, "setup_cpu_s": setups,
                          "load_average": os.getloadavg(),
                          "peak_rss_gib": resource.getrusage(
                              resource.RUSAGE_SELF).ru_maxrss / 2**20}))
        return
    t0 = time.process_time()
    limit = None if args.memory_limit is None else args.memory_limit * 2**30
    run = simulate(config, args.duration, seed=args.seed, model=model, progress=False,
                   budget_every=args.budget_every or None, memory_limit=limit)
    with_budget = time.process_time() - t0
    t0 = time.process_time()
    simulate(config, args.frames * config.loop.time_step, seed=args.seed, model=model,
             progress=False, memory_limit=limit)
    per_frame = (time.process_time() - t0) / args.frames
    s = run.summary()
    b = run.budget
    out = {
        "config": config.name, "high_share": args.high_share,
        "altitude_pitch": args.altitude_pitch, "model_error": config.loop.model_error,
        "reconstructor": config.loop.reconstructor, "seed": args.seed,
        "duration_s": args.duration, "load_average": os.getloadavg()[0],
        "setup_cpu_s": setup, "loop_with_budget_cpu_s": with_budget,
        "cpu_s_per_frame": per_frame,
        "peak_rss_gib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20,
        "modes": [d.n_modes for d in config.dms],
        "subapertures": [w.n_subapertures for w in config.wfss],
        "loop_status": s["loop_status"], "closure_time_s": s["closure_time_s"],
        "strehl_peak_mean": s["strehl_peak_mean"], "strehl_field_mean": s["strehl_field_mean"],
        "corrected_fov_diameter_arcsec": 60 * s["corrected_fov_diameter_arcmin"],
        "strehl_map": np.round(run.strehl_map(), 3).tolist(),
        "budget": None if b is None else {
            t: {"field_mean": float(np.mean(getattr(b, t))),
                "on_axis": float(np.asarray(getattr(b, t))[
                    int(np.argmin(np.hypot(*b.directions.T)))])}
            for t in ("fitting", "aliasing", "temporal", "noise", "measured")},
    }
    print(json.dumps(out))


if __name__ == "__main__":
    main()
