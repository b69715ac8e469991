r"""Pre-work memory estimates against measured peaks (issue 27, left31-estimate).

``quality``: for each log shape (frames x modes; ``c`` in memory contiguous, ``m`` a
memory-mapped NPZ, ``s`` a strided view: every other column of a twice-wider array), in a
fresh process, ``tracemalloc``'s peak of the first ``assess_quality`` call (numba compiled
on a tiny log first; the MAD's simulated law is NOT cached: a command pays it) and the
growth of the maximum resident set during the call, beside ``quality_memory``.

``command``: a command line on a seeded log written to FOLDER (``m``: NPZ, memory-mapped
when large; ``c``: NPY), ``tracemalloc``'s peak of the whole command (after a warm-up run
on a 200 x 6 log: imports and numba outside the count, the MAD law cleared) beside its
estimate, the largest ``need`` any ``check_memory`` of the run was given (what the
refusal compares with the memory available).

Usage::

    PYTHONPATH=$PWD OPENBLAS_NUM_THREADS=1 \
        python benchmarks/bench_estimates_left31.py quality FOLDER T M KIND
    PYTHONPATH=$PWD OPENBLAS_NUM_THREADS=1 \
        python benchmarks/bench_estimates_left31.py command FOLDER T M KIND info|reorder|...
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


ARGS = {
    "info": ["info"],
    "reorder": ["reorder", "--method", "variance", "--resamples", "0", "--pupil-pixels",
                "48", "--quiet"],
    "forecast": ["forecast", "--predictors", "linear", "--horizon", "2", "--quiet",
                 "--overwrite", "--out", "{folder}/fc"],
    "select": ["select", "--target", "Z3", "--max-lag", "2", "--surrogates", "19",
               "--no-intervals", "--method", "gaussian"],
}


def command(folder: Path, frames: int, modes: int, kind: str, name: str) -> None:
    import contextlib
    import io as _io

    from modalinfo import io
    from modalinfo.cli import cmd_forecast, cmd_reorder, cmd_select, main, shared
    from modalinfo.telemetry import ModalLog, quality

    def argv(path: Path) -> list[str]:
        rest = [a.format(folder=folder) for a in ARGS[name][1:]]
        return [ARGS[name][0], str(path), "--rate", "1000", "--in-units", "rad", *rest]

    folder.mkdir(parents=True, exist_ok=True)
    warm = folder / "warm.npy"
    np.save(warm, make(200, 6))
    sink = _io.StringIO()
    with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
        main(argv(warm))
    path = folder / f"c_{frames}x{modes}.{'npz' if kind == 'm' else 'npy'}"
    if not path.exists():
        if kind == "m":
            io.save(ModalLog(make(frames, modes), rate=1000.0, units="rad"), path)
        else:
            np.save(path, make(frames, modes))
    needs: list[float] = []
    for module in (shared, cmd_reorder, cmd_forecast, cmd_select):
        original = module.check_memory

        def record(need, what, fix, _original=original):
            needs.append(float(need))
            return _original(need, what, fix)

        module.check_memory = record
    quality._mad_law.cache_clear()
    tracemalloc.start()
    with contextlib.redirect_stdout(sink), contextlib.redirect_stderr(sink):
        code = main(argv(path))
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    est = max(needs, default=0.0)
    print(f"command {name} {frames} {modes} {kind} exit {code} peak_MiB {peak / 2**20:.1f} "
          f"estimate_MiB {est / 2**20:.1f} ratio {est / peak:.2f}", flush=True)


if __name__ == "__main__":
    if sys.argv[1] == "quality":
        quality(Path(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), sys.argv[5])
    else:
        command(Path(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4]), sys.argv[5],
                sys.argv[6])
