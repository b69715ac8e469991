"""The quality pass's peak memory (tracemalloc) against its estimate, six log shapes.

Issue 27, left28-prov: ``assess_quality`` held 9-10 float64 copies of its sample at once
(1408 MiB at 10^4 x 2000); its per-mode steps now run a slice of modes at a time. The
log: a seeded AR(1) series (rho 0.9, unit innovations), float64 in memory (not counted:
allocated before tracing). Printed: the peak, its ratio to the sampled values' bytes
(``min(T, 65536) x M x 8``) and ``quality_memory``'s estimate.

Usage::

    PYTHONPATH=$PWD OPENBLAS_NUM_THREADS=1 python benchmarks/bench_quality_memory_left28prov.py
"""

from __future__ import annotations

import tracemalloc

import numpy as np

from modalinfo.telemetry import assess_quality
from modalinfo.telemetry.quality import DEFAULT_SAMPLE_FRAMES

SHAPES = [(10_000, 200), (10_000, 2000), (1000, 2000), (100_000, 200), (200_000, 100),
          (300, 50)]


def main() -> None:
    try:
        from modalinfo.telemetry.quality import quality_memory
    except ImportError:  # pragma: no cover - a checkout before the estimate existed
        quality_memory = None
    assess_quality(np.random.default_rng(0).standard_normal((500, 3)))  # numba compiled
    for frames, modes in SHAPES:
        rng = np.random.default_rng(27)
        x = rng.standard_normal((frames, modes))
        for t in range(1, frames):
            x[t] += 0.9 * x[t - 1]
        tracemalloc.start()
        assess_quality(x)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        sampled = min(frames, DEFAULT_SAMPLE_FRAMES) * modes * 8
        est = (f"; estimate {quality_memory(frames, modes) / 2**20:.0f} MiB"
               if quality_memory else "")
        print(f"{frames} x {modes}: peak {peak / 2**20:.1f} MiB = {peak / sampled:.2f} x the "
              f"sampled values' bytes{est}", flush=True)


if __name__ == "__main__":
    main()
