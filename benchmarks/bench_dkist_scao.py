"""Benchmark: where the time of a ``dkist-scao`` run goes (issue 29; no optimisation here).

CPU time of this process (``time.process_time``) of

  - the set-up, ``LoopModel(config)``: the SH operators, the 44 x 44 actuator DM and its
    DM-space K-L modes, the interaction matrix and the least-squares reconstructor;
  - a run of ``--frames`` frames of 2 ms (``simulate(..., model=model)``, no budget, as
    ``python -m closedloop run --preset dkist-scao`` runs it), per frame, after a warm-up
    run of 5 frames (numba compilation excluded);
  - a cProfile of that run (timer: this process's CPU time) split per part, by the
    cumulative time of the functions that hold each part: atmosphere
    (``LoopState.turbulence`` and ``evolve_until``), DM surface (``LoopState.apply``:
    strokes ``m2c @ c`` and the separable influence product; and the subtraction of the
    surfaces from the phase, ``LoopState.forward`` less its turbulence), WFS
    (``LoopModel.measure``), reconstructor (``LoopModel.reconstruct``), science
    (``ScienceCamera.forward``), control (the integrator), and the rest.

BLAS on one thread (``OPENBLAS_NUM_THREADS=1``), as the golden runs.

Run: OPENBLAS_NUM_THREADS=1 python benchmarks/bench_dkist_scao.py [--frames 100]
     [--preset dkist-scao]
"""

from __future__ import annotations

import argparse
import cProfile
import os
import pstats
import time

#: part -> (module path suffix, function name) whose cumulative time it is
PARTS = {
    "atmosphere (per step)": [("closedloop/state.py", "turbulence"),
                              ("closedloop/state.py", "evolve_until")],
    "atmosphere (screens, once per run)": [("closedloop/optics/phase_screen.py",
                                            "fft_phase_screen")],
    "DM surface (apply)": [("closedloop/state.py", "apply")],
    "WFS (measure)": [("closedloop/model.py", "measure")],
    "reconstructor": [("closedloop/model.py", "reconstruct")],
    "science": [("closedloop/optics/science.py", "forward")],
    "control": [("closedloop/simulation.py", "step")],
}


def cumulative(stats: pstats.Stats, suffix: str, name: str) -> float:
    """Cumulative time [s] of the functions ``name`` defined in a file ending ``suffix``."""
    total = 0.0
    for (path, _line, func), row in stats.stats.items():
        if func == name and path.replace(os.sep, "/").endswith(suffix):
            total += row[3]
    return total


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=100)
    parser.add_argument("--preset", default="dkist-scao")
    args = parser.parse_args()

    from closedloop import presets, simulate
    from closedloop.model import LoopModel

    config = presets.get(args.preset)
    t0 = time.process_time()
    model = LoopModel(config)
    setup = time.process_time() - t0
    step = config.loop.time_step
    simulate(config, 5 * step, model=model, progress=False)  # warm-up (numba)
    t0 = time.process_time()
    simulate(config, args.frames * step, model=model, progress=False)
    plain = time.process_time() - t0  # the same run without the profiler

    prof = cProfile.Profile(time.process_time)  # CPU time: the machine is shared
    t0 = time.process_time()
    prof.enable()
    run = simulate(config, args.frames * step, model=model, progress=False)
    prof.disable()
    loop = time.process_time() - t0
    stats = pstats.Stats(prof)
    total = sum(row[2] for row in stats.stats.values())  # all functions' own time

    parts = {k: sum(cumulative(stats, *f) for f in v) for k, v in PARTS.items()}
    forward = cumulative(stats, "closedloop/state.py", "forward")
    turb = cumulative(stats, "closedloop/state.py", "turbulence")
    parts["DM surface (subtract from phase)"] = forward - turb
    print(f"preset {args.preset}: load average {os.getloadavg()[0]:.2f}, "
          f"{time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}")
    print(f"set-up (LoopModel) CPU {setup:.2f} s; modes {model.n_modes}; "
          f"valid actuators {model.dms[0].influence.n_valid}; slopes "
          f"{model.wfss[0].n_measurements}")
    print(f"run {args.frames} frames without the profiler: CPU {plain:.3f} s, "
          f"{1e3 * plain / args.frames:.2f} ms per frame ({args.frames / plain:.0f} frames/s)")
    print(f"run {args.frames} frames: CPU {loop:.2f} s, {1e3 * loop / args.frames:.2f} ms "
          f"per frame ({args.frames / loop:.0f} frames/s of CPU; profiled: cProfile adds "
          f"its overhead), SR {run.summary()['strehl_peak_mean']:.3f}")
    print(f"profile total {total:.2f} s")
    print("| part | CPU [s] | share | per frame [ms] |")
    print("|---|---|---|---|")
    for k, v in parts.items():
        print(f"| {k} | {v:.3f} | {100 * v / total:.1f} % | {1e3 * v / args.frames:.2f} |")
    rest = total - sum(parts.values())
    print(f"| rest (logs, exposure sum, loop overhead) | {rest:.3f} | "
          f"{100 * rest / total:.1f} % | {1e3 * rest / args.frames:.2f} |")
    stats.sort_stats("tottime").print_stats(12)


if __name__ == "__main__":
    main()
