"""Benchmark: the actuator-DM loop at 4-m size (issue 29, item 5), before vs after.

Two configurations are built here (from the ``dkist-scao`` preset):

- ``dkist``: DKIST-like single-conjugate AO, ``dkist-scao`` with the changes
  :func:`dkist_config` lists (``../shared/reference/solar-mcao-notes.md``, "DKIST"):
  4 m, 172-pixel pupil, geometric 43 x 43 Shack-Hartmann on axis, a ground DM of
  44 x 44 actuators (1,584 valid) controlled through ``--modes`` (default 1,500)
  DM-space K-L modes, 2 ms frames, 2 ms exposure, 0.5 ms delay (4 internal steps per
  frame), gain 0.5, layers at 0 / 7.852 / 13.252 km with weights 0.942 / 0.038 / 0.02,
  10 m/s, L0 = 27 m, r0 = 7 cm at 500 nm, science at 630 nm in 3 x 3 directions over 10";
- ``est``: EST-like MCAO, **reduced** (say so): the same telescope and ground DM plus one
  DM at 10 km over the meta-pupil of a 60" field (6.91 m; 76 x 76 actuators at the same
  pitch, ~4,600 valid), each driven by a 60" layer-oriented SH (43 and 74 subapertures
  across, 3 field directions), ``--est-modes`` modes per DM, layers at 0 / 10 km. EST
  as published has 2-3 altitude DMs and 4.2 m; one altitude DM keeps the joint MAP's
  SVD and the K-L builds within this shared machine's minutes.

For each, in a subprocess per code tree (``--before`` = a checkout before this change,
default /work/main; then this checkout), in the same run:

- set-up: CPU time of ``LoopModel(config)`` and of its parts (K-L build, WFS operators
  and reconstructor; cProfile with the CPU clock), and, at the end, a second
  ``LoopModel`` of the same config in the same process (the in-process K-L cache);
- per frame: CPU time of ``simulate`` over ``--frames`` frames (the model reused, after a
  warm-up run; the screens drawn at the start are counted), and the per-part split
  (median over the frames of each part, timed on the same model and state: the
  atmosphere and residual maps per internal step, the exposure sum, the science
  directions, the WFS measurement, the reconstruction, the controller, the DM command);
- peak RSS of the subprocess (``ru_maxrss``, read before the second model is built)
  against ``closedloop.resources.estimate`` for the run;
- after only: the float32 products against float64 on the same model and seed (largest
  relative change of the residual variance, per direction, over the run).

CPU times are ``time.process_time`` with one BLAS thread (OPENBLAS_NUM_THREADS=1).

Run::

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=. python benchmarks/bench_4m_loop.py \\
        [--before /work/main] [--frames 200] [--which dkist est]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import time
from pathlib import Path

import numpy as np


def dkist_config(n_modes: int):
    """The ``dkist-scao`` preset as this benchmark runs it (``presets.get`` + ``replace``).

    From the preset: telescope, layers (weights, altitudes, 10 m/s, L0 = 27 m, r0 = 7 cm),
    loop, wavelengths, seed. Changed for the benchmark: ``n_modes`` K-L modes, the DM's
    actuator count left to its kind's default (43 + 1 = 44, the preset's), a noise-free
    SH, a 3 x 3 science grid over 10" (the preset: one direction), and the wind
    directions 0 / 45 / 90 deg (the preset's upper two layers blow 90 / 45 deg: the
    benchmark's choice, kept so that its numbers stay comparable).
    """
    import dataclasses

    from closedloop import presets
    from closedloop.config import FieldConfig

    base = presets.get("dkist-scao")
    layers = tuple(dataclasses.replace(layer, wind_direction=d)
                   for layer, d in zip(base.layers, (0.0, 45.0, 90.0), strict=True))
    return base.replace(
        name="dkist-like", layers=layers,
        dms=(dataclasses.replace(base.dms[0], n_modes=n_modes, options=None),),
        wfss=(dataclasses.replace(base.wfss[0], noise=0.0),),
        field=FieldConfig(size=10.0, n_points=3))


def est_config(n_modes: int):
    from closedloop.config import DMConfig, FieldConfig, LayerConfig, WFSConfig

    base = dkist_config(n_modes)
    total = (4.0 / 0.07) ** (5 / 3)
    layers = (LayerConfig(altitude=0.0, d_over_r0=(0.7 * total) ** 0.6, wind_speed=10.0,
                          outer_scale=27.0),
              LayerConfig(altitude=10_000.0, d_over_r0=(0.3 * total) ** 0.6, wind_speed=20.0,
                          wind_direction=90.0, outer_scale=27.0))
    return base.replace(
        name="est-like-reduced", layers=layers,
        dms=(DMConfig(altitude=0.0, n_modes=n_modes, kind="actuators"),
             DMConfig(altitude=10_000.0, n_modes=n_modes, kind="actuators")),
        wfss=(WFSConfig(altitude=0.0, field_of_view=60.0, n_subapertures=43, noise=0.0,
                        field_samples=2, dm=0),
              WFSConfig(altitude=10_000.0, field_of_view=60.0, n_subapertures=74,
                        noise=0.0, field_samples=2, dm=1)),
        field=FieldConfig(size=60.0, n_points=3))


def cpu(func):
    t = time.process_time()
    out = func()
    return out, time.process_time() - t


def part_split(model, frames: int) -> dict:
    """Median CPU time [ms] per frame of each part of the loop, on ``model``."""
    from closedloop.control.controller import Controller
    from closedloop.state import LoopState

    cfg = model.config
    n_os = cfg.loop.oversampling
    state = LoopState(model, model.atmosphere(1, frames * cfg.loop.time_step * 1.2),
                      model.science.plane_views())
    state.reset()
    ctrl = Controller(model.n_modes, gain=cfg.loop.gain, leak=0.0,
                      delay_frames=cfg.loop.delay_frames,
                      integration_frames=cfg.loop.integration_frames)
    sums = [np.zeros_like(m) for m in state.maps]
    times = {k: [] for k in ("atmosphere+maps", "exposure sum", "science", "WFS measure",
                             "reconstruct", "controller", "DM command")}
    dt = cfg.loop.time_step / n_os
    for k in range(frames):
        t_atm = t_exp = 0.0
        for i in range(n_os):
            _, t = cpu(lambda s=k * n_os + i: (state.evolve_until(s * dt), state.forward()))
            t_atm += t
            _, t = cpu(lambda: [a.__iadd__(v) for a, v in zip(sums, state.maps, strict=True)])
            t_exp += t
        times["atmosphere+maps"].append(t_atm)
        times["exposure sum"].append(t_exp)
        times["science"].append(cpu(model.science.forward)[1])
        t0 = time.process_time()
        meas = model.measure(sums, None)
        t1 = time.process_time()
        m = model.reconstruct(meas)
        t2 = time.process_time()
        command = ctrl.step(m)[0]
        t3 = time.process_time()
        state.apply(command)
        t4 = time.process_time()
        for key, a, b in (("WFS measure", t0, t1), ("reconstruct", t1, t2),
                          ("controller", t2, t3), ("DM command", t3, t4)):
            times[key].append(b - a)
        for a in sums:
            a[:] = 0.0
    return {k: 1e3 * float(np.median(v)) for k, v in times.items()}


def float64_twin(model) -> None:
    """Switch the model's large products back to float64 (in place)."""
    from closedloop.optics.products import DenseProduct

    if not hasattr(model, "_products"):
        return
    model._products = [None if p is None else DenseProduct(p.matrix.astype(np.float64),
                                                           math.inf)
                       for p in model._products]
    for dm in model.dms:
        if hasattr(dm, "_strokes"):
            dm._strokes = DenseProduct(dm.m2c, math.inf)


def peak_rss() -> float:
    """Peak resident memory of this process so far [bytes] (``ru_maxrss``)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024.0


def child(which: str, n_modes: int, frames: int, compare: bool) -> dict:
    """Measure one configuration in this process (the code tree on ``sys.path``)."""
    import closedloop
    from closedloop.model import LoopModel
    from closedloop.resources import estimate
    from closedloop.simulation import simulate

    cfg = dkist_config(n_modes) if which == "dkist" else est_config(n_modes)
    duration = frames * cfg.loop.time_step
    est = estimate(cfg, duration)
    out = {"tree": str(Path(closedloop.__file__).parents[1]),
           "estimate_peak_bytes": est.peak_bytes,
           "estimate_setup_seconds": est.setup_seconds,
           "estimate_seconds_per_frame": est.seconds_per_frame}
    import cProfile
    import pstats

    out["peak_rss_imports"] = peak_rss()

    prof = cProfile.Profile(time.process_time)
    prof.enable()
    model, out["setup_cpu"] = cpu(lambda: LoopModel(cfg))
    prof.disable()
    out["peak_rss_setup"] = peak_rss()
    stats = pstats.Stats(prof).stats
    parts = {"dm_kl_modes": 0.0, "pinv/svd": 0.0, "interaction": 0.0, "wfs _build": 0.0,
             "shapes (matrix @ m2c)": 0.0}
    for (file, _, name), (_, _, _, cum, _) in stats.items():
        if name == "dm_kl_modes":
            parts["dm_kl_modes"] += cum
        elif name in ("pinv", "svd") and "linalg" in file:
            parts["pinv/svd"] += cum if name == "pinv" else 0.0
        elif name == "interaction_with":
            parts["interaction"] += cum
        elif name == "_build" and "wfs" in file:
            parts["wfs _build"] += cum
    if not parts["pinv/svd"]:
        parts["pinv/svd"] = sum(v[3] for k, v in stats.items() if k[2] == "svd")
    out["setup_parts_profiled_s"] = parts
    out["n_modes"] = model.n_modes
    out["n_measurements"] = [w.n_measurements for w in model.wfss]
    out["n_valid_actuators"] = [d.influence.n_valid for d in model.dms]
    simulate(cfg, 5 * cfg.loop.time_step, model=model)  # warm-up (numba, caches)
    t0 = time.process_time()
    run = simulate(cfg, duration, model=model)
    out["simulate_ms_per_frame"] = 1e3 * (time.process_time() - t0) / frames
    out["peak_rss_run"] = peak_rss()
    out["parts_ms"] = part_split(model, min(frames, 100))
    out["residual_variance"] = run.residual_variance.mean(axis=0).tolist()
    if compare and hasattr(model, "_products"):
        out["single"] = [p.single for p in model._products if p is not None] + [
            d._strokes.single for d in model.dms if hasattr(d, "_strokes")]
        float64_twin(model)
        t0 = time.process_time()
        twin = simulate(cfg, duration, model=model)
        out["float64_simulate_ms_per_frame"] = 1e3 * (time.process_time() - t0) / frames
        out["float64_parts_ms"] = part_split(model, min(frames, 100))
        a, b = run.residual_variance, twin.residual_variance
        out["float32_max_rel_change_variance"] = float(np.max(np.abs(a - b) / b))
        out["float32_max_rel_change_mean_variance"] = float(
            np.max(np.abs(a.mean(axis=0) - b.mean(axis=0)) / b.mean(axis=0)))
    # the peak of one model's set-up and runs (before a second model exists)
    out["peak_rss_bytes"] = peak_rss()
    del model
    import gc

    gc.collect()
    _, out["setup_cpu_second"] = cpu(lambda: LoopModel(cfg))  # the K-L cache, if any
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--before", default="/work/main",
                        help="code tree of the 'before' column ('' to skip)")
    parser.add_argument("--frames", type=int, default=200)
    parser.add_argument("--modes", type=int, default=1500)
    parser.add_argument("--est-modes", type=int, default=500)
    parser.add_argument("--which", nargs="+", default=["dkist", "est"],
                        choices=["dkist", "est"])
    parser.add_argument("--child", nargs=3, metavar=("WHICH", "MODES", "COMPARE"),
                        help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.child:
        which, modes, compare = args.child
        print(json.dumps(child(which, int(modes), args.frames, compare == "1")))
        return
    here = str(Path(__file__).resolve().parents[1])
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    with open("/proc/loadavg") as f:
        load = f.read().split()[:3]
    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load {load}")
    for which in args.which:
        modes = args.modes if which == "dkist" else args.est_modes
        results = {}
        for label, root in (("before", args.before), ("after", here)):
            if not root:
                continue
            proc = subprocess.run(
                [sys.executable, __file__, "--frames", str(args.frames), "--child", which,
                 str(modes), "1" if label == "after" else "0"],
                env=dict(env, PYTHONPATH=root), capture_output=True, text=True, check=True,
                cwd=root)
            results[label] = json.loads(proc.stdout.strip().splitlines()[-1])
            print(f"## {which} {label}", json.dumps(results[label], indent=1), flush=True)


if __name__ == "__main__":
    main()
