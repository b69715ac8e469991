"""Cost of verifying a memory-mapped log's checksum inside ``info``'s summary pass.

Writes a ``T x M`` float64 log with modalinfo (NPZ: zip CRC-32; HDF5: SHA-256 in
the header), opens it memory-mapped and times, median of ``--repeats`` runs:

* peer: ``summarize(log)`` alone, the pass ``info`` made before (checksum skipped);
* ours: ``summarize(log, visit=check.update)`` + ``check.finish()`` (checksum
  streamed in the same pass, no second read);
* read: ``load(path)`` without mmap (reads and verifies) + ``summarize``, the
  other way to get a verified summary.

Files are written to ``--dir`` (default: a temporary directory) and deleted.
Not part of the test suite.

Usage::

    /work/venv/bin/python benchmarks/bench_integrity.py [--frames 1000000] [--modes 30]
"""

from __future__ import annotations

import argparse
import functools
import tempfile
from pathlib import Path

import numpy as np
from _common import timed

from modalinfo.io import integrity_check, load, save
from modalinfo.telemetry import ModalLog, summarize

_median_time = functools.partial(timed, warm=False)  # wall time, every call timed


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--frames", type=int, default=1_000_000)
    parser.add_argument("--modes", type=int, default=30)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--dir", type=Path, default=None)
    args = parser.parse_args()
    x = np.random.default_rng(0).standard_normal((args.frames, args.modes))
    with tempfile.TemporaryDirectory(dir=args.dir) as tmp:
        for ext in ("npz", "h5"):
            path = save(ModalLog(x, rate=1000.0), Path(tmp) / f"log.{ext}")
            size = path.stat().st_size / 1e6

            def peer(path=path):
                summarize(load(path, mmap=True))

            def ours(path=path):
                log = load(path, mmap=True)
                check = integrity_check(path, log, mmap=True)
                summarize(log, visit=check.update)
                check.finish()
                assert check.status == "verified"

            def read(path=path):
                summarize(load(path))

            peer()  # warm the page cache and numba
            t_peer = _median_time(peer, args.repeats)[0]
            t_ours = _median_time(ours, args.repeats)[0]
            t_read = _median_time(read, args.repeats)[0]
            print(f"{ext}: {args.frames} x {args.modes} float64 ({size:.0f} MB): "
                  f"ours {t_ours:.3f} s, peer (no checksum) {t_peer:.3f} s, "
                  f"ratio {t_ours / t_peer:.2f}; full read + verify {t_read:.3f} s")
            path.unlink()


if __name__ == "__main__":
    main()
