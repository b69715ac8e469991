"""Benchmark: the package's cost models against the measured cost, before and after round 11.

One line per check: the model's value (before: the constants of main before audit
11-cost, written out here; after: the package's), the measured value and their ratios
(measured / model; > 1: the model is low, a run over the cap could be accepted; < 1: it
is high, a run that fits could be refused). Measured:

- ``frame``: CPU per frame of ``closedloop.simulate`` (``time.process_time`` at each
  callback, median over the last 2/3 of the frames, median of 3 runs on one model)
  against ``resources.estimate(...).seconds_per_frame``;
- ``memory``: peak RSS (``ru_maxrss`` of a child process running ``simulate``) against
  ``resources.estimate(...).peak_bytes``;
- ``mi-call``: CPU of one ``MutualInformation.score`` after ``fit`` (median of 3
  batches) against the least-time rule's ``MI_SECONDS_PER_CALL + n x rate(n)`` (a lower
  bound: ok when measured / bound is in [1, 3]);
- ``stability``: CPU of ``ordering_stability`` (histogram, mi_greedy, one-frame windows
  of the shipped closed-loop log) against ``least_ordering_seconds`` of its windows
  and seeds, as ``modalinfo reorder --stability`` counts them (a bound);
- ``ksg``: CPU of ``mutual_information(method="ksg")`` of a pair against
  ``ksg_cost`` (an estimate: ok within 2x).

Run (one BLAS and numba thread; the machine is shared: quote the load average)::

    OPENBLAS_NUM_THREADS=1 NUMBA_NUM_THREADS=1 PYTHONPATH=. python benchmarks/bench_cost_models.py
"""

from __future__ import annotations

import os
import subprocess
import sys
import time

import numpy as np

FRAME_CONFIGS = {"kaos": 60, "table1": 40, "dkist12": 40, "dkist32": 30, "est16": 16}
MEMORY_CONFIGS = ("kaos", "table1", "dkist20", "est16")


def config_of(name: str):
    """A preset, ``estN`` (``est_mcao_variant(N)``) or ``dkistN`` (dkist-scao at N subaps)."""
    import dataclasses

    from closedloop import presets

    if name.startswith("est") and name[3:].isdigit():
        return presets.est_mcao_variant(int(name[3:]))
    if name.startswith("dkist") and name[5:].isdigit():
        n = int(name[5:])
        c = presets.get("dkist-scao")
        return c.replace(
            name=name, telescope=dataclasses.replace(c.telescope, n_pixels=max(4 * n, 64)),
            dms=(dataclasses.replace(c.dms[0], n_modes=int(0.6 * np.pi / 4 * n * n),
                                     options={"n_actuators": n + 1}),),
            wfss=(dataclasses.replace(c.wfss[0], n_subapertures=n),))
    return presets.get(name)


def frame_before(config) -> float:
    """The per-frame model before round 11: one rate, 2.4e-10 s per op, + 0.35 ms."""
    from closedloop import resources as res
    from closedloop.optics.geometry import plane_layout

    layout = plane_layout(config)
    dx = config.telescope.diameter / config.telescope.n_pixels
    m = res._model(config, layout, dx)
    w = res._frame_work(config, layout, dx, m.n_meas, m.n_modes, m.kept_operators)
    ops = (w["planes"] + 2 * w["science"] + w["mirrors"] / 4 + w["sensors"] / 2
           + w["reconstructor"])
    return 3.5e-4 + 2.4e-10 * ops


def measure_frame(name: str, frames: int) -> float:
    from closedloop.model import LoopModel
    from closedloop.simulation import simulate

    cfg = config_of(name)
    model = LoopModel(cfg)
    meds = []
    for seed in range(3):
        stamps: list[float] = []
        simulate(cfg, frames * cfg.loop.time_step, model=model, seed=seed, progress=False,
                 callback=lambda k, s=stamps: s.append(time.process_time()))
        meds.append(float(np.median(np.diff(stamps)[len(stamps) // 3:])))
    return float(np.median(meds))


def measure_memory(name: str) -> float:
    code = ("import resource, sys; sys.path.insert(0, 'benchmarks');"
            "from bench_cost_models import config_of; from closedloop.simulation import "
            f"simulate; c = config_of({name!r}); simulate(c, 20 * c.loop.time_step, "
            "progress=False); print(resource.getrusage(resource.RUSAGE_SELF).ru_maxrss)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env=os.environ)
    return float(out.stdout.split()[-1]) * 1024.0


def measure_call(method: str, n: int) -> float:
    from modalinfo.information import MutualInformation

    rng = np.random.default_rng(1)
    ref = rng.standard_normal(n)
    cand = 0.6 * ref + 0.8 * rng.standard_normal(n)
    est = MutualInformation(method=method, units="nats").fit(ref)
    est.score(cand)
    reps = max(3, int(min(200, 2e5 / n)))
    meds = []
    for _ in range(3):
        t = time.process_time()
        for _ in range(reps):
            est.score(cand)
        meds.append((time.process_time() - t) / reps)
    return float(np.median(meds))


def line(kind, name, before, after, measured, unit, scale=1.0):
    print(f"{kind:<10}{name:<22}{before * scale:>12.4g}{after * scale:>12.4g}"
          f"{measured * scale:>12.4g} {unit:<4}{measured / before:>9.2f}"
          f"{measured / after:>9.2f}", flush=True)


def main() -> None:
    from closedloop import resources as res

    print(f"# {time.strftime('%Y-%m-%d %H:%M UTC', time.gmtime())}, load "
          f"{os.getloadavg()[0]:.1f}")
    print(f"{'check':<10}{'case':<22}{'before':>12}{'after':>12}{'measured':>12} unit"
          f"{'m/before':>9}{'m/after':>9}")
    for name, frames in FRAME_CONFIGS.items():
        cfg = config_of(name)
        after = res.estimate(cfg, 0.1).seconds_per_frame
        line("frame", name, frame_before(cfg), after, measure_frame(name, frames), "ms",
             1e3)
    for name in MEMORY_CONFIGS:
        cfg = config_of(name)
        est = res.estimate(cfg, 20 * cfg.loop.time_step).peak_bytes
        line("memory", name, est, est, measure_memory(name), "MB", 1e-6)
    from modalinfo.ordering import cost

    before_rate = {"ksg": cost.MI_SECONDS_PER_SAMPLE["ksg"], "kde": lambda n: 1.5e-7,
                   "gaussian": lambda n: 1e-7, "histogram": lambda n: 2e-8}
    for method in ("histogram", "kde", "gaussian", "ksg"):
        for n in (30, 3228, 100_000):
            before = n * before_rate[method](n)
            after = cost.MI_SECONDS_PER_CALL[method] + n * cost.MI_SECONDS_PER_SAMPLE[method](n)
            line("mi-call", f"{method} n={n}", before, after, measure_call(method, n), "ms",
                 1e3)
    stability()
    from modalinfo.information import mutual_information
    from modalinfo.information.ksg import ksg_cost

    rng = np.random.default_rng(2)
    for n in (1000, 10_000, 100_000):
        x = rng.standard_normal(n)
        y = x + rng.standard_normal(n)
        mutual_information(x[:100], y[:100], method="ksg")
        t = time.process_time()
        mutual_information(x, y, method="ksg")
        spent = time.process_time() - t
        line("ksg", f"pair n={n}", ksg_cost(n, 2)[0], ksg_cost(n, 2)[0], spent, "s")
    print(f"# load {os.getloadavg()[0]:.1f}")


def stability(frames: int = 100) -> None:
    """``reorder --stability 1`` on the shipped log's first ``frames`` frames, in process."""
    from modalinfo.bases import Pupil, ZernikeBasis
    from modalinfo.ordering import ordering_stability
    from modalinfo.ordering.cost import least_ordering_seconds

    path = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data",
                        "kaos_like_closed_loop.npz")
    coeffs = np.load(path)["coefficients"][:frames]  # (T, 27): Noll Z2..Z28 [rad]
    log = coeffs
    basis = ZernikeBasis(Pupil(64), modes=range(2, 2 + coeffs.shape[1]))
    n_w = Pupil(64).n_valid
    n = min(200_000, frames * n_w)
    m = coeffs.shape[1]
    before = (frames * (2 * m - 2) * n_w * 2e-8) + 3 * (2 * m - 2) * n * 2e-8
    after = (least_ordering_seconds("histogram", n_w, m, 0, frames, "mi_greedy")[0]
             + least_ordering_seconds("histogram", n, m, 0, 3, "mi_greedy")[0])
    t = time.process_time()
    ordering_stability(log, basis, "mi_greedy", window=1, seeds=(0, 1, 2),
                       estimator="histogram", sample_budget=200_000)
    line("stability", f"window 1 x {frames}", before, after, time.process_time() - t, "s")


if __name__ == "__main__":
    main()
