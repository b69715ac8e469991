"""Loop steps per second of the table1 MCAO simulation, against the same step in plain numpy.

Runs ``closedloop.simulate`` on the ``table1`` preset (64 px pupil, two planes of 102 and
202 px, 119 + 65 modes, two 16x16 Shack-Hartmanns, SR on 9x9 directions every frame)
after a JIT warm-up, and the same loop with the science step (the piston-removed
variance over the pupil of every direction, the hot spot) written in plain numpy
(4 x 4 reads by fancy indexing, one direction at a time). Prints the median of
``--repeats`` runs, the ratio, and a cProfile breakdown of where the time goes. The
machine may be shared: the load average is printed before and after (quote medians).

    python benchmarks/bench_closedloop.py --frames 300 --repeats 3
"""

from __future__ import annotations

import argparse
import cProfile
import io
import os
import pstats
import time

import numpy as np

from closedloop import LoopModel, presets, simulate
from closedloop.optics.science import ScienceCamera


def numpy_forward(self, weights=None):
    """The science step in plain numpy (same maths as the numba kernel)."""
    n = self.geometry.n_pixels
    jj, ii = np.meshgrid(np.arange(n), np.arange(n), indexing="xy")
    mask = self.geometry.pupil_mask
    cols, rows = jj[mask], ii[mask]
    views = self.plane_views()
    for d in range(len(self.directions)):
        v = np.zeros(cols.size)
        for p, view in enumerate(views):
            fc = self._shifts[d, p, 0]
            fr = self._shifts[d, p, 1]
            ic, ir = int(np.floor(fc)), int(np.floor(fr))
            r0, c0 = rows + ir, cols + ic
            if fc == ic and fr == ir:
                v += view[r0, c0]
                continue
            wx, wy = self._taps[d, p]
            for a in range(4):
                for b in range(4):
                    v += wy[a] * wx[b] * view[r0 + a - 1, c0 + b - 1]
        self.mean[d] = v.mean()
        self.variance[d] = v.var()
    return self.variance


def steps_per_second(config, model, frames, repeats):
    rates = []
    for _ in range(repeats):
        t = time.perf_counter()
        simulate(config, frames * config.loop.time_step, model=model, progress=False)
        rates.append(frames / (time.perf_counter() - t))
    return float(np.median(rates)), rates


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--frames", type=int, default=300)
    ap.add_argument("--repeats", type=int, default=3)
    args = ap.parse_args()

    load_before = os.getloadavg()
    config = presets.get("table1")
    t = time.perf_counter()
    model = LoopModel(config)
    setup = time.perf_counter() - t
    simulate(config, 0.01, model=model, progress=False)  # JIT warm-up (cached kernels)
    ours, ours_all = steps_per_second(config, model, args.frames, args.repeats)

    original = ScienceCamera.forward
    ScienceCamera.forward = numpy_forward
    try:
        plain, plain_all = steps_per_second(config, model, max(20, args.frames // 10),
                                            args.repeats)
    finally:
        ScienceCamera.forward = original

    cam = model.science
    cam._flat[:] = np.random.default_rng(0).standard_normal(cam._flat.size)
    cam.forward()
    reps = 200
    t = time.perf_counter()
    for _ in range(reps):
        cam.forward()
    kernel_ms = (time.perf_counter() - t) / reps * 1e3

    print(f"table1: {len(model.science.directions)} directions, planes "
          f"{[p.n for p in model.geometry.planes]} px, {model.n_modes} modes, "
          f"set-up {setup:.2f} s")
    print(f"loop, numba science kernel : {ours:8.1f} steps/s (runs: "
          f"{', '.join(f'{r:.1f}' for r in ours_all)})")
    print(f"loop, plain-numpy science  : {plain:8.1f} steps/s (runs: "
          f"{', '.join(f'{r:.1f}' for r in plain_all)})")
    print(f"ratio                      : {ours / plain:8.1f}x")
    print(f"science kernel alone       : {kernel_ms:8.3f} ms per step (81 directions)")
    print(f"real time (1000 steps/s)   : {ours / 1000:8.3f} of it")
    print(f"load average (1, 5, 15 min): before {', '.join(f'{x:.2f}' for x in load_before)}; "
          f"after {', '.join(f'{x:.2f}' for x in os.getloadavg())}")

    prof = cProfile.Profile()
    prof.enable()
    simulate(config, args.frames * config.loop.time_step, model=model, progress=False)
    prof.disable()
    out = io.StringIO()
    pstats.Stats(prof, stream=out).sort_stats("tottime").print_stats(10)
    print("\nwhere the time goes (cProfile, tottime):")
    lines = out.getvalue().splitlines()
    start = next(i for i, ln in enumerate(lines) if "ncalls" in ln)
    print("\n".join(lines[start:start + 12]))


if __name__ == "__main__":
    main()
