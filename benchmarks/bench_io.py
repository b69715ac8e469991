"""Peak memory and wall time of summarising a log larger than a comfortable RAM budget.

Creates a ``T x M`` float64 ``.npy`` (default 10^7 x 30 = 2.4 GB; needs the disk
space, checked first), then runs in fresh subprocesses, each measured with
``/usr/bin/time -v`` (maximum resident set size, wall clock):

* ours: ``modalinfo info FILE --rate 1000 --quiet`` (memory-mapped, one chunked
  pass for the non-finite check and one numba pass for mean/RMS/std/lag-1 ACF,
  pages released after each chunk);
* naive: ``np.load`` + NumPy ``mean``, ``std``, RMS and lag-1 autocorrelation, the
  script a user would write.

The two give the same statistics (checked on the first modes). The file is
deleted afterwards. Not part of the test suite.

Usage::

    /work/venv/bin/python benchmarks/bench_io.py [--frames 10000000] [--modes 30] [--dir /tmp]
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

NAIVE = r"""
import sys, numpy as np
x = np.load(sys.argv[1])
m = x.mean(axis=0)
s = x.std(axis=0)
rms = np.sqrt((x ** 2).mean(axis=0))
d = x - m
lag1 = (d[:-1] * d[1:]).sum(axis=0) / (d ** 2).sum(axis=0)
print(" ".join(f"{v:.6g}" for v in lag1[:3]))
"""


def make_file(path: Path, frames: int, modes: int, seed: int = 0) -> None:
    """Write an AR(1)-like float64 log chunk by chunk (never the whole array in RAM)."""
    rng = np.random.default_rng(seed)
    out = np.lib.format.open_memmap(path, mode="w+", dtype=np.float64, shape=(frames, modes))
    phi = np.linspace(0.0, 0.95, modes)
    carry = np.zeros(modes)
    chunk = 500_000
    for i0 in range(0, frames, chunk):
        n = min(chunk, frames - i0)
        e = rng.standard_normal((n, modes))
        # cheap correlated series: first-order filter applied blockwise via scipy
        from scipy.signal import lfilter

        block = np.empty_like(e)
        for j in range(modes):
            block[:, j], _ = lfilter([1.0], [1.0, -phi[j]], e[:, j], zi=[phi[j] * carry[j]])
        carry = block[-1].copy()
        out[i0 : i0 + n] = block
    out.flush()
    del out


def measure(cmd: list[str]) -> tuple[float, float, str]:
    """Run ``cmd`` under /usr/bin/time -v; return (peak RSS MiB, wall s, stdout)."""
    t0 = time.perf_counter()
    res = subprocess.run(["/usr/bin/time", "-v", *cmd], capture_output=True, text=True)
    wall = time.perf_counter() - t0
    if res.returncode != 0:
        raise RuntimeError(f"{cmd} failed: {res.stderr[-2000:]}")
    kb = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", res.stderr).group(1))
    return kb / 1024.0, wall, res.stdout


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=10_000_000)
    parser.add_argument("--modes", type=int, default=30)
    parser.add_argument("--dir", default=None, help="directory for the temporary file")
    parser.add_argument("--repeats", type=int, default=3)
    args = parser.parse_args()

    size = args.frames * args.modes * 8
    root = Path(args.dir or tempfile.gettempdir())
    free = shutil.disk_usage(root).free
    if free < 2 * size:
        sys.exit(f"need {2 * size / 1e9:.1f} GB free in {root}, have {free / 1e9:.1f} GB")
    path = root / f"bench_io_{os.getpid()}.npy"
    py = sys.executable
    try:
        t0 = time.perf_counter()
        make_file(path, args.frames, args.modes)
        print(f"wrote {path} ({size / 1e9:.2f} GB) in {time.perf_counter() - t0:.1f} s")
        ours_cmd = [py, "-m", "modalinfo", "info", str(path), "--rate", "1000", "--quiet"]
        naive_cmd = [py, "-c", NAIVE, str(path)]
        measure(ours_cmd)  # warm-up: numba cache and page cache
        ours = [measure(ours_cmd) for _ in range(args.repeats)]
        naive = [measure(naive_cmd) for _ in range(args.repeats)]
        rss_o = float(np.median([r[0] for r in ours]))
        rss_n = float(np.median([r[0] for r in naive]))
        wall_o = float(np.median([r[1] for r in ours]))
        wall_n = float(np.median([r[1] for r in naive]))
        # the lag-1 values of the first three modes must agree
        table = [ln.split() for ln in ours[0][2].splitlines() if ln[:1] == "Z"]
        ours_lag1 = [float(row[4]) for row in table[:3]]
        naive_lag1 = [float(v) for v in naive[0][2].split()]
        agree = np.allclose(ours_lag1, naive_lag1, atol=1e-4)
        print(f"log: {args.frames} x {args.modes} float64 = {size / 2**20:.0f} MiB")
        print(f"modalinfo info (mmap, chunked): peak RSS {rss_o:8.0f} MiB, wall {wall_o:6.2f} s")
        print(f"naive np.load + numpy:          peak RSS {rss_n:8.0f} MiB, wall {wall_n:6.2f} s")
        print(
            f"ratio naive/ours: RSS {rss_n / rss_o:.1f}x, wall {wall_n / wall_o:.2f}x; "
            f"lag-1 agree: {agree} (ours {ours_lag1}, naive {naive_lag1})"
        )
    finally:
        if path.exists():
            path.unlink()


if __name__ == "__main__":
    main()
