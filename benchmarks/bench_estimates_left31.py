r"""Pre-work memory estimates against measured peaks (issue 27, left31-estimate).

``quality``: for each log shape (frames x modes; ``c`` in memory contiguous, ``m`` a
memory-mapped NPZ, ``s`` a strided view: every other column of a twice-wider array), in a
fresh process, ``tracemalloc``'s peak of the first ``assess_quality`` call (numba compiled
on a tiny log first; the MAD's simulated law is NOT cached: a command pays it) and the
growth of the maximum resident set during the call, beside ``quality_memory``.

Usage::

    PYTHONPATH=$PWD OPENBLAS_NUM_THREADS=1 \
        python benchmarks/bench_estimates_left31.py quality FOLDER T M KIND
"""

from __future__ import annotations

import resource
import sys
import tracemalloc
from pathlib import Path

import numpy as np


def make(frames: int, modes: int, wide: int = 1) -> np.ndarray:
    rng = np.random.default_rng(31)
    x = rng.standard_normal((frames, modes * wide))
    x[1:] += 0.5 * x[:-1]  # some memory, not an AR(1) exactly
    return x


def quality(folder: Path, frames: int, modes: int, kind: str) -> None:
    from modalinfo import io
    from modalinfo.telemetry import ModalLog
    from modalinfo.telemetry.quality import assess_quality, quality_memory

    assess_quality(make(64, 3))  # numba compiled (the MAD law of 64 frames: another size)
    if kind == "m":
        path = folder / f"q_{frames}x{modes}.npz"
        if not path.exists():
            io.save(ModalLog(make(frames, modes), rate=1000.0, units="rad"), path)
        log = io.load(path, mmap=True)
    elif kind == "s":
        log = make(frames, modes, 2)[:, ::2]
    else:
        log = make(frames, modes)
    rss0 = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    tracemalloc.start()
    assess_quality(log)
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - rss0
    est = quality_memory(frames, modes)
    print(f"quality {frames} {modes} {kind} peak_MiB {peak / 2**20:.1f} rss_growth_MiB "
          f"{rss / 1024:.1f} estimate_MiB {est / 2**20:.1f} ratio {est / peak:.2f}",
          flush=True)


if __name__ == "__main__":
    if sys.argv[1] == "quality":
        quality(Path(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), sys.argv[5])
