"""Benchmark: the closedloop frozen-flow atmosphere against hcipy's infinite layers.

The table1 atmosphere (two layers, D/r0 = 26 and 2 at D = 4 m, winds 7 and 70 m/s along
x, 1 ms steps) sampled at 6.25 cm (4 m / 64 px):
  - at 64 px (the 4 m pupil) and at 160 px (the 10 m meta-pupil);
  - ours: ``closedloop.optics.atmosphere.AtmosphericLayer`` (FFT screen with subharmonics, sized
    for the run, bilinear sub-pixel shift in a numba kernel), ``evolve_until(t)`` then
    ``phase(out)`` for both layers per step;
  - hcipy 0.7: ``InfiniteAtmosphericLayer`` (row extrusion, Assemat et al. 2006) on
    ``make_pupil_grid(n, n dx)``, ``layer.evolve_until(t)`` then
    ``layer.phase_for(wavelength)`` for both layers per step. hcipy cannot build a
    Kolmogorov (L0 = inf) infinite layer (Cholesky failure), so it runs with L0 = 25 m;
    its speed does not depend on L0, nor does ours.
Steps per second are medians over repeats of a block of steps (after one warm-up block
that includes numba's JIT); construction time is the median of the repeats too.

Run: /work/venv/bin/python benchmarks/bench_atmosphere.py [--repeats 5] [--steps 160]
(6 blocks of 160 steps: a 0.96 s run, close to the 1 s table1 default)
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

from closedloop.optics.atmosphere import Atmosphere, AtmosphericLayer

D_TEL, WAVELENGTH = 4.0, 500e-9
LAYERS = [(26.0, 7.0, 0.0), (2.0, 70.0, 8000.0)]  # (D/r0, wind [m/s], altitude [m])
DT = 1e-3


def ours_build(n, dx, duration, seed=0):
    rng = np.random.default_rng(seed)
    return Atmosphere([
        AtmosphericLayer(n, dx, D_TEL / q, velocity=(v, 0.0), altitude=h, duration_hint=duration,
                         seed=rng)
        for q, v, h in LAYERS
    ])


def ours_run(atm, outs, k0, steps):
    for k in range(k0, k0 + steps):
        t = k * DT
        for layer, out in zip(atm.layers, outs, strict=True):
            layer.evolve_until(t)
            layer.phase(out)


def hcipy_build(n, dx, seed=0):
    import hcipy

    grid = hcipy.make_pupil_grid(n, n * dx)
    return [
        hcipy.InfiniteAtmosphericLayer(
            grid, hcipy.Cn_squared_from_fried_parameter(D_TEL / q, WAVELENGTH), L0=25.0,
            velocity=np.array([v, 0.0]), height=h, seed=seed + i)
        for i, (q, v, h) in enumerate(LAYERS)
    ]


def hcipy_run(layers, k0, steps):
    for k in range(k0, k0 + steps):
        t = k * DT
        for layer in layers:
            layer.evolve_until(t)
            layer.phase_for(WAVELENGTH)


def timed(func):
    t0 = time.perf_counter()
    func()
    return time.perf_counter() - t0


def bench(n, dx, args):
    """Return (ours s/step, hcipy s/step, ours build s, hcipy build s, phase() s, screens)."""
    # the run covers all timed blocks; duration_hint sizes the screens for it
    duration = args.steps * (args.repeats + 1) * DT
    builds = [timed(lambda: ours_build(n, dx, duration)) for _ in range(args.repeats)]
    atm = ours_build(n, dx, duration)
    outs = [np.empty((n, n)) for _ in atm.layers]
    ours_run(atm, outs, 0, args.steps)  # warm-up (JIT)
    ours = []
    for r in range(args.repeats):
        t0 = time.perf_counter()
        ours_run(atm, outs, (r + 1) * args.steps, args.steps)
        ours.append((time.perf_counter() - t0) / args.steps)
    layer, out = atm.layers[1], outs[1]
    per_phase = []
    for _ in range(args.repeats):
        t0 = time.perf_counter()
        for _ in range(args.steps):
            layer.phase(out)
        per_phase.append((time.perf_counter() - t0) / args.steps)
    hb = [timed(lambda: hcipy_build(n, dx)) for _ in range(max(1, args.repeats // 2))]
    layers = hcipy_build(n, dx)
    hcipy_run(layers, 0, 5)
    hc = []
    for r in range(args.repeats):
        t0 = time.perf_counter()
        hcipy_run(layers, 5 + r * args.hcipy_steps, args.hcipy_steps)
        hc.append((time.perf_counter() - t0) / args.hcipy_steps)
    return (float(np.median(ours)), float(np.median(hc)), float(np.median(builds)),
            float(np.median(hb)), float(np.median(per_phase)),
            ([lay.screen_pixels for lay in atm.layers], duration))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    parser.add_argument("--steps", type=int, default=160, help="steps per timed block (ours)")
    parser.add_argument("--hcipy-steps", type=int, default=100, help="steps per block (hcipy)")
    args = parser.parse_args()
    dx = D_TEL / 64
    warnings.simplefilter("ignore", DeprecationWarning)
    print(f"table1 atmosphere, 2 layers, dx = {dx * 100:.2f} cm, 1 ms steps; "
          f"medians of {args.repeats} repeats")
    print(f"{'n':>5} {'ours steps/s':>13} {'hcipy steps/s':>14} {'ratio':>7} "
          f"{'ours build':>11} {'hcipy build':>12} {'phase() per layer':>18}")
    for n in (64, 160):
        o, h, ob, hb, ph, (screens, duration) = bench(n, dx, args)
        print(f"{n:>5} {1 / o:>13.0f} {1 / h:>14.0f} {h / o:>6.1f}x "
              f"{ob * 1e3:>9.0f} ms {hb * 1e3:>10.0f} ms {ph * 1e6:>15.1f} us")
        print(f"      our screens: {screens} px, sized for {duration:.1f} s")


if __name__ == "__main__":
    main()
