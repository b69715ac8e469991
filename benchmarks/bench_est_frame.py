"""Benchmark: CPU per frame of the 4-m presets, by part, before and after (issue 29 item 5).

One model of ``--preset`` (``est-mcao``, ``dkist-scao``, ...) or of
``est_mcao_variant(--subapertures)`` is built once; then, in the same process:

- **per part, A/B**: the frame of :func:`closedloop.simulate` (the same calls in the
  same order: commands put on the mirrors, atmosphere and residual maps per internal
  step, exposure sum, science directions, WFS measurement, reconstruction, controller
  with the MAP's pseudo-open-loop product) timed part by part with
  ``time.process_time``, frames alternating between the "before" controller (float64
  ``(M, M)`` products) and the "after" one (float32 from 8 MB, as ``simulate`` builds
  it for a loop of actuator mirrors), so that the machine's load drifts alike over
  both; medians over ``--frames`` frames each;
- **whole frames**: ``simulate`` of ``--frames`` frames with each configuration, CPU
  per frame (the screens drawn at the run's start included);
- **what float32 moves**: the two runs have the same seed; the largest relative change
  of the residual variance over frames and directions, and of the run-mean SR.

Parts of a code tree's own (kernels changed bit for bit: science, exposure) are compared
by running this script with ``--before-tree`` (a checkout, e.g. /work/main) in a
subprocess on the same model size: its part medians are printed beside. ``--kernels``
times those two in one process on the configuration's geometry only (no model, so the
published size costs seconds): the science moments with and without the shared row sums
(``direction_moments_grouped`` against ``direction_moments_serial``, same bits checked),
and the exposure sum of the planes as before (zero, add every step, divide) and now
(copy the first step).

Run (BLAS on one thread; the machine is shared: quote the load average)::

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=. python benchmarks/bench_est_frame.py \\
        [--preset est-mcao | --subapertures 24] [--frames 40]
"""

from __future__ import annotations

import argparse
import json
import math
import os
import subprocess
import sys
import time
from collections import deque

import numpy as np
from _common import cpu_median

PARTS = ("apply", "atmosphere", "subtract", "exposure", "science", "measure", "reconstruct",
         "control")


def build(args):
    from closedloop import presets
    from closedloop.model import LoopModel

    cfg = (presets.est_mcao_variant(args.subapertures) if args.subapertures
           else presets.get(args.preset))
    t = time.process_time()
    model = LoopModel(cfg)
    return cfg, model, time.process_time() - t


class Frame:
    """One loop as :func:`closedloop.simulate` runs it, timed part by part."""

    def __init__(self, model, float32_from: float | None, seed: int = 1,
                 frames: int = 100):
        from closedloop.simulation import _Clock, _Control, _Exposure
        from closedloop.state import LoopState

        cfg = model.config
        self.model = model
        self.clock = _Clock.of(cfg.loop, frames * cfg.loop.time_step)
        self.state = LoopState(model, model.atmosphere(seed, self.clock.run_time),
                               model.science.plane_views())
        self.state.reset()
        control = _Control(model, cfg.loop, None, None, "raise")
        if float32_from is not None:  # None: the tree's own controller, as simulate builds it
            from closedloop.control.controller import Controller

            c = control.controller
            control.controller = Controller(
                model.n_modes, gain=cfg.loop.gain, leak=cfg.loop.leak,
                delay_frames=cfg.loop.delay_frames,
                integration_frames=cfg.loop.integration_frames, sensed=c.sensed,
                float32_from=float32_from)
        self.control = control
        self.exposure = _Exposure(self.state.maps)
        self.pending = deque()
        self.rng = model.noise_rng(seed)
        self.k = 0

    def step(self) -> dict:
        from closedloop.optics import _kernels

        clock, state, model, P = self.clock, self.state, self.model, time.process_time
        acc = dict.fromkeys(PARTS, 0.0)
        k = self.k
        for i in range(clock.n_os):
            s = k * clock.n_os + i
            t0 = P()
            while self.pending and self.pending[0][0] <= s:
                state.apply(self.pending.popleft()[1])
            t1 = P()
            state.evolve_until(s * clock.dt)
            state.turbulence(state.maps)
            t2 = P()
            for p, plane in enumerate(model.geometry.planes):
                for d in plane.dms:
                    _kernels.subtract_scatter(state.maps[p], model.dms[d].pixels,
                                              state.surfaces[d], 1.0)
            t3 = P()
            if clock.in_exposure(i):
                self.exposure.add(state.maps)
            t4 = P()
            acc["apply"] += t1 - t0
            acc["atmosphere"] += t2 - t1
            acc["subtract"] += t3 - t2
            acc["exposure"] += t4 - t3
        t0 = P()
        model.science.forward()
        t1 = P()
        meas = model.measure(self.exposure.mean(clock.n_int), self.rng)
        t2 = P()
        m = model.reconstruct(meas)
        t3 = P()
        self.exposure.clear()
        t4 = P()
        command, _ = self.control.step(m, None)
        t5 = P()
        self.pending.append((clock.apply_step(k), command.copy()))
        acc["science"] += t1 - t0
        acc["measure"] += t2 - t1
        acc["reconstruct"] += t3 - t2
        acc["exposure"] += t4 - t3
        acc["control"] += t5 - t4
        self.k += 1
        return acc


def run_whole(cfg, model, frames: int, seed: int = 2):
    from closedloop import simulate

    t = time.process_time()
    res = simulate(cfg, frames * cfg.loop.time_step, model=model, progress=False, seed=seed,
                   memory_limit=1e12)
    return res, time.process_time() - t



def kernels(args) -> dict:
    """Science and exposure kernels, before and after, in this process (geometry only)."""
    from closedloop import presets
    from closedloop.optics import _kernels
    from closedloop.optics.geometry import Geometry
    from closedloop.optics.science import ScienceCamera
    from closedloop.simulation import _Exposure

    cfg = (presets.est_mcao_variant(args.subapertures) if args.subapertures
           else presets.get(args.preset))
    geometry = Geometry(cfg)
    cam = ScienceCamera(geometry, geometry.directions)
    rng = np.random.default_rng(1)
    cam._flat[:] = rng.standard_normal(cam._flat.size)
    base = (cam._flat, cam._offsets, cam._sizes, cam._span_lo, cam._span_hi, cam._shifts,
            cam._taps, np.ones(len(cam._sizes)), cam._common, cam._base)
    out = {"config": cfg.name, "directions": len(cam.directions),
           "planes": [int(n) for n in cam._sizes]}
    a, b = np.empty((2, len(cam.directions))), np.empty((2, len(cam.directions)))
    old = lambda: _kernels.direction_moments_serial(*base, a[0], a[1])  # noqa: E731
    res = {}
    for _rep in range(3):  # alternate, so that the load drifts alike over both
        res.setdefault("science_before_ms", []).append(1e3 * cpu_median(old, args.frames))
        if cam._groups is not None:
            new = lambda: _kernels.direction_moments_grouped(  # noqa: E731
                *base, *cam._groups, b[0], b[1])
            res.setdefault("science_after_ms", []).append(1e3 * cpu_median(new, args.frames))
    if cam._groups is not None:
        out["science_same_bits"] = bool(np.array_equal(a, b))
    maps = cam.plane_views()
    n_int = round(cfg.loop.integration_frames * cfg.loop.oversampling)
    exp = _Exposure(maps)
    sums = [np.zeros_like(v) for v in maps]

    def before():
        for s in sums:
            s[:] = 0.0
        for _ in range(n_int):
            for s, v in zip(sums, maps, strict=True):
                s += v
        for s in sums:
            s /= n_int

    def after():
        exp.clear()
        for _ in range(n_int):
            exp.add(maps)
        exp.mean(n_int)

    for _rep in range(3):
        res.setdefault("exposure_before_ms", []).append(1e3 * cpu_median(before, args.frames))
        res.setdefault("exposure_after_ms", []).append(1e3 * cpu_median(after, args.frames))
    before()
    after()
    out["exposure_same_bits"] = all(np.array_equal(s, e) for s, e in zip(sums, exp.maps,
                                                                         strict=True))
    out.update({k: float(np.median(v)) for k, v in res.items()})
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--preset", default="est-mcao")
    parser.add_argument("--subapertures", type=int, default=0,
                        help="est_mcao_variant(n) instead of --preset")
    parser.add_argument("--frames", type=int, default=40)
    parser.add_argument("--parts-only", action="store_true",
                        help="the per-part medians of this tree only (for --before-tree)")
    parser.add_argument("--kernels", action="store_true",
                        help="science and exposure kernels only, on the geometry")
    parser.add_argument("--before-tree", default="",
                        help="a checkout whose per-part medians are measured in a subprocess")
    args = parser.parse_args()
    out: dict = {"load_start": os.getloadavg()[0]}
    if args.kernels:
        out.update(kernels(args))
        out["load_end"] = os.getloadavg()[0]
        print(json.dumps(out, indent=1))
        return
    cfg, model, setup = build(args)
    out["setup_s"] = setup
    out["config"] = cfg.name
    if args.parts_only:
        frame = Frame(model, None, frames=args.frames + 5)
        frame.step()
        times = [frame.step() for _ in range(args.frames)]
        out["parts_ms"] = {k: 1e3 * float(np.median([t[k] for t in times])) for k in PARTS}
        print(json.dumps(out))
        return
    from closedloop.optics.products import FLOAT32_MIN_BYTES

    frames = {}
    times = {"before": [], "after": []}
    for name, after in (("before", False), ("after", True)):
        frames[name] = Frame(model, FLOAT32_MIN_BYTES if after else math.inf,
                             frames=args.frames + 5)
        frames[name].step()  # numba warm-up
    for _ in range(args.frames):
        for name in ("before", "after"):
            times[name].append(frames[name].step())
    for name in times:
        out[f"parts_ms_{name}"] = {k: 1e3 * float(np.median([t[k] for t in times[name]]))
                                   for k in PARTS}
        out[f"sum_ms_{name}"] = sum(out[f"parts_ms_{name}"].values())
    # whole runs, same seed: CPU per frame and what float32 moves
    from closedloop.optics.science import marechal_strehl

    runs = {}
    for name, after in (("before", False), ("after", True)):
        if not after:  # the controller of simulate takes its limit from the model
            import closedloop.simulation as sim

            saved = sim._float32_from
            sim._float32_from = lambda m: math.inf
        try:
            res, cpu = run_whole(cfg, model, args.frames)
        finally:
            if not after:
                sim._float32_from = saved
        runs[name] = res
        out[f"simulate_ms_per_frame_{name}"] = 1e3 * cpu / args.frames
    vb = runs["before"].residual_variance
    va = runs["after"].residual_variance
    out["variance_max_rel_change"] = float(np.max(np.abs(va - vb) / vb))
    close = runs["after"].closure_index or 0
    srb = marechal_strehl(vb[close:]).mean(axis=0)
    sra = marechal_strehl(va[close:]).mean(axis=0)
    out["mean_sr_max_rel_change"] = float(np.max(np.abs(sra - srb) / srb))
    out["closure_index"] = int(close)
    out["load_end"] = os.getloadavg()[0]
    if args.before_tree:
        env = dict(os.environ, PYTHONPATH=args.before_tree)
        cmd = [sys.executable, os.path.abspath(__file__), "--parts-only",
               "--frames", str(args.frames)]
        cmd += (["--subapertures", str(args.subapertures)] if args.subapertures
                else ["--preset", args.preset])
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
        out["before_tree"] = json.loads(proc.stdout.strip().splitlines()[-1])
        # and this tree the same way, right after
        env = dict(os.environ, PYTHONPATH=os.path.dirname(os.path.dirname(
            os.path.abspath(__file__))))
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
        out["this_tree"] = json.loads(proc.stdout.strip().splitlines()[-1])
    print(json.dumps(out, indent=1))


if __name__ == "__main__":
    main()
