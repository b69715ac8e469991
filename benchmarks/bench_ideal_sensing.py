"""IdealSensing's set-up at est_mcao_variant(n): CPU time and peak traced memory.

The budget's streamed ideal sensors (``closedloop.budget.IdealSensing``) at the EST MCAO
resolution ``n`` (ground subapertures across). Builds the run's ``LoopModel`` once, then
``IdealSensing(model)`` ``--repeat`` times for the CPU time (``time.process_time``,
median) and once under ``tracemalloc`` for the peak of the Python/numpy allocations
during that set-up (the model held before is not counted). Prints one JSON line with the
Gram matrix's checksum, so that two code versions can be compared bit for bit.

    OPENBLAS_NUM_THREADS=1 python benchmarks/bench_ideal_sensing.py --n 16 --repeat 3
"""

from __future__ import annotations

import argparse
import hashlib
import json
import statistics
import time
import tracemalloc


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--n", type=int, default=16, help="ground subapertures across")
    parser.add_argument("--repeat", type=int, default=3, help="timed set-ups")
    args = parser.parse_args()

    import numpy as np

    from closedloop import LoopModel, presets
    from closedloop.budget import IdealSensing, streams_ideal

    cfg = presets.est_mcao_variant(args.n)
    t0 = time.process_time()
    model = LoopModel(cfg)
    model_cpu = time.process_time() - t0
    assert streams_ideal(model), "this config does not stream its ideal sensors"
    times = []
    for _ in range(args.repeat):
        t0 = time.process_time()
        sensing = IdealSensing(model)
        times.append(time.process_time() - t0)
    del sensing
    tracemalloc.start()
    sensing = IdealSensing(model)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    k = np.ascontiguousarray(sensing._k)
    print(json.dumps({
        "n": args.n, "n_modes": int(model.n_modes),
        "n_measurements": [int(w.n_measurements) for w in sensing.wfss],
        "model_cpu_s": round(model_cpu, 2),
        "ideal_sensing_cpu_s": [round(t, 3) for t in times],
        "ideal_sensing_cpu_median_s": round(statistics.median(times), 3),
        "ideal_sensing_peak_traced_mb": round(peak / 2**20, 1),
        "k_sha256": hashlib.sha256(k.tobytes()).hexdigest()[:16],
        "noise_variance": [float(v) for v in sensing.noise_variance],
    }))


if __name__ == "__main__":
    main()
