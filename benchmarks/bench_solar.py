"""Frames per second of ``table1-solar`` (correlating SH, linear mode) beside ``table1``.

Both loops are built once, warmed up (numba compilation) by a 0.01 s run, then timed in
alternation, ``--repeats`` times ``--frames`` frames each, in process CPU time (the
machine is shared: wall time would measure the other jobs). Prints the median frames/s
of each and their ratio. The imaging mode (``image_formation=True``) is timed per frame
of its sensors alone (forming and correlating every subaperture's image, both WFSs, one
sub-direction per subaperture: ``field_samples = 1``), which is its cost per frame on top
of the loop's.

Usage::

    PYTHONPATH=$PWD python benchmarks/bench_solar.py --frames 200 --repeats 5
"""

from __future__ import annotations

import dataclasses
import statistics
import time

import numpy as np
from _common import int_options

from closedloop import LoopModel, presets, simulate
from closedloop.state import LoopState


def loop_rates(frames: int, repeats: int) -> dict[str, list[float]]:
    """Frames per CPU second of each preset's loop, ``repeats`` alternated runs each."""
    setups = {}
    # table1-solar's 1 ms delay is a whole frame (one internal step per frame); table1's
    # 0.5 ms takes two: the third run isolates the sensor's cost at table1's delay
    half = presets.get("table1-solar")
    half = half.replace(loop=dataclasses.replace(half.loop, delay=0.5e-3))
    for name, config in (("table1", presets.get("table1")),
                         ("table1-solar", presets.get("table1-solar")),
                         ("solar, 0.5 ms", half)):
        model = LoopModel(config)
        simulate(config, 0.01, model=model, progress=False)
        setups[name] = (config, model)
    rates: dict[str, list[float]] = {name: [] for name in setups}
    for _ in range(repeats):
        for name, (config, model) in setups.items():
            t = time.process_time()
            simulate(config, frames * config.loop.time_step, model=model, progress=False)
            rates[name].append(frames / (time.process_time() - t))
    return rates


def imaging_seconds(repeats: int) -> tuple[float, list[int]]:
    """CPU seconds per frame of both WFSs' image formation + correlation (median)."""
    config = presets.get("table1-solar")
    wfss = tuple(dataclasses.replace(w, image_formation=True, field_samples=1)
                 for w in config.wfss)
    config = config.replace(wfss=wfss)
    model = LoopModel(config)
    state = LoopState(model, model.atmosphere(0, 0.01))
    state.evolve_until(0.0)
    maps = state.turbulence([np.zeros((p.n, p.n)) for p in model.geometry.planes])
    rng = np.random.default_rng(0)
    for w in model.wfss:
        w.image_slopes(maps)  # warm-up
    out = []
    for _ in range(repeats):
        t = time.process_time()
        for w in model.wfss:
            w.image_slopes(maps, rng.standard_normal(w.n_measurements))
        out.append(time.process_time() - t)
    return statistics.median(out), [w.n_valid_subapertures for w in model.wfss]


def main() -> None:
    args = int_options(__doc__, frames=200, repeats=5, imaging_repeats=3).parse_args()
    rates = loop_rates(args.frames, args.repeats)
    med = {k: statistics.median(v) for k, v in rates.items()}
    for name, v in rates.items():
        print(f"{name:14s} frames/s (CPU): median {med[name]:7.1f}  runs "
              + " ".join(f"{x:.1f}" for x in v))
    print(f"table1-solar / table1: {med['table1-solar'] / med['table1']:.2f}; "
          f"at table1's delay: {med['solar, 0.5 ms'] / med['table1']:.2f}")
    if args.imaging_repeats > 0:
        sec, n_valid = imaging_seconds(args.imaging_repeats)
        print(f"imaging mode (field_samples = 1, {sum(n_valid)} subaperture images): "
              f"{sec:.2f} s per frame of the sensors alone ({1.0 / sec:.2f} frames/s at most)")


if __name__ == "__main__":
    main()
