r"""The quality pass's peak memory on logs longer than its sample (issue 27, left30-prov).

Writes two seeded AR(1) logs (rho 0.5 .. 0.95 across modes, float64, 2 kHz) as NPZ into
FOLDER unless present: ``a.npz`` 2e5 x 200 (stride 4) and ``b.npz`` 1e6 x 50 (stride 16),
then prints, for each mapped log, ``tracemalloc``'s peak of ``assess_quality`` (a second
call: numba and the MAD's simulated law cached), its ratio to ``min(T, 65536) x M x 8``
and ``quality_memory``'s estimate. The same files serve the commands' ``/usr/bin/time -v``
(benchmarks/RESULTS.md, "left30-prov").

Usage::

    PYTHONPATH=$PWD OPENBLAS_NUM_THREADS=1 \
        python benchmarks/bench_quality_memory_left30prov.py FOLDER
"""

from __future__ import annotations

import sys
import tracemalloc
from pathlib import Path

import numpy as np

from modalinfo import io
from modalinfo.telemetry import ModalLog
from modalinfo.telemetry.quality import assess_quality, quality_memory

LOGS = {"a.npz": (200_000, 200), "b.npz": (1_000_000, 50)}


def write_log(path: Path, frames: int, modes: int) -> None:
    from scipy.signal import lfilter

    rng = np.random.default_rng(7)
    phi = np.linspace(0.5, 0.95, modes)
    sd = 0.01 / np.sqrt(np.arange(2, modes + 2))
    x = np.empty((frames, modes))
    for j in range(modes):
        x[:, j] = lfilter([1.0], [1.0, -phi[j]], rng.standard_normal(frames) * sd[j])
    io.save(ModalLog(x, rate=2000.0, modes=list(range(2, modes + 2)), units="rad"), path)


def main(folder: Path) -> None:
    folder.mkdir(parents=True, exist_ok=True)
    for name, (frames, modes) in LOGS.items():
        path = folder / name
        if not path.exists():
            write_log(path, frames, modes)
        log = io.load(path, mmap=True)
        assess_quality(log)  # numba compiled, the MAD's law cached
        tracemalloc.start()
        assess_quality(log)
        peak = tracemalloc.get_traced_memory()[1]
        tracemalloc.stop()
        sampled = min(frames, 65536) * modes * 8
        print(f"{name} {frames} x {modes}: peak {peak / 2**20:.0f} MiB = "
              f"{peak / sampled:.2f} x the sampled values' bytes; estimate "
              f"{quality_memory(frames, modes) / 2**20:.0f} MiB", flush=True)


if __name__ == "__main__":
    main(Path(sys.argv[1]))
