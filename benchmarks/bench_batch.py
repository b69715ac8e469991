"""Throughput of ``modalinfo batch`` on Dask (1 and 2 workers) against a plain loop.

    PYTHONPATH=. python benchmarks/bench_batch.py [--logs 40] [--repeats 3]

Writes ``--logs`` synthetic logs (``--frames`` x ``--modes``, NPZ/HDF5/FITS/CSV in
turn) and times, after one warm-up each (imports and numba caches loaded):

- the peer: a plain sequential loop calling the same task function
  (:func:`modalinfo.batch.analyses.run_log_task`) in this process;
- ``analyse_archive`` on a ``LocalCluster`` of 1 and of 2 worker processes (cluster
  start-up timed separately), into a fresh output directory each repeat (so SHA-256
  of every file, one task per log and analysis, rows, CSV and Parquet are all in);
- the scheduler's own cost per task: ``run_tasks`` of no-op tasks.

Prints medians over ``--repeats``: logs per minute and the ratio to the loop.
``--scale FRAMES MODES`` instead times the streaming analyses (summary, per-mode linear
forecast) on one memory-mapped float32 log of that size, with the peak allocation
(``tracemalloc``: mapped file pages are not allocations), the per-log cost used in
``docs/DISTRIBUTED.md``.
"""

from __future__ import annotations

import argparse
import contextlib
import os
import statistics
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from modalinfo.batch import analyse_archive
from modalinfo.batch.analyses import resolve_params, run_log_task
from modalinfo.batch.engine import RowStore, TaskSpec, open_client, run_tasks
from modalinfo.io import save
from modalinfo.telemetry.log import ModalLog

ANALYSES = ["summary", "ordering", "forecast"]
PARAMS = {"ordering": {"budget": 20000, "pupil_pixels": 32, "windows": 2, "seeds": [0, 1]},
          "forecast": {"predictors": "linear,linear-ls,arma", "horizon": 5}}


def write_logs(root: Path, n: int, frames: int, modes: int) -> list[Path]:
    exts = ("npz", "h5", "fits", "csv")
    paths = []
    for i in range(n):
        rng = np.random.default_rng(i)
        x = np.zeros((frames, modes))
        e = rng.normal(size=(frames, modes)) / np.arange(1, modes + 1)
        for t in range(1, frames):
            x[t] = 0.95 * x[t - 1] + e[t]
        log = ModalLog(x, rate=1000.0, modes=list(range(2, 2 + modes)), convention="noll",
                       units="rad", start_time=1.78e9 + 3600 * i)
        path = root / f"log{i:03d}.{exts[i % len(exts)]}"
        save(log, path)
        paths.append(path)
    return paths


def sequential(paths: list[Path]) -> float:
    start = time.perf_counter()
    for path in paths:
        for name in ANALYSES:
            run_log_task({"path": str(path.resolve()), "fmt": None, "hints": {},
                          "analysis": name, "params": resolve_params(name, PARAMS.get(name))})
    return time.perf_counter() - start


def scale(frames: int, modes: int) -> None:
    """Per-log cost and peak allocation of the streaming analyses on one large log."""
    import tracemalloc

    with tempfile.TemporaryDirectory() as tmp:
        rng = np.random.default_rng(0)
        path = Path(tmp) / "big.npy"
        arr = np.lib.format.open_memmap(path, mode="w+", dtype=np.float32,
                                        shape=(frames, modes))
        for start in range(0, frames, 8192):
            stop = min(frames, start + 8192)
            arr[start:stop] = rng.normal(size=(stop - start, modes)).astype(np.float32)
        arr.flush()
        del arr
        size = path.stat().st_size
        print(f"one log: {frames} frames x {modes} modes float32 = {size / 1e6:.0f} MB (npy, "
              "memory-mapped)")
        linear = {"predictors": "linear", "horizon": 1}
        cases = [("summary", {}, None), ("forecast", linear, None),
                 ("forecast", linear, [0, frames // 2])]
        for name, params, window in cases:
            payload = {"path": str(path), "fmt": None, "hints": {"rate": 2000.0},
                       "analysis": name, "params": resolve_params(name, params),
                       "window": window}
            run_log_task({**payload, "path": str(path)})  # warm-up
            times, peaks = [], []
            for _ in range(3):
                tracemalloc.start()
                t = time.perf_counter()
                run_log_task(payload)
                times.append(time.perf_counter() - t)
                peaks.append(tracemalloc.get_traced_memory()[1])
                tracemalloc.stop()
            med = statistics.median(times)
            part = size if window is None else size * (window[1] - window[0]) / frames
            what = f"{name} {params}" + ("" if window is None else f" window {window}")
            print(f"{what:<62}: {med:6.2f} s  "
                  f"{part / med / 1e6:5.0f} MB/s  peak numpy/python allocation "
                  f"{max(peaks) / 1e6:.0f} MB")


def noop(payload: dict) -> dict:
    return {"i": payload["i"]}


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--logs", type=int, default=24)
    ap.add_argument("--frames", type=int, default=4000)
    ap.add_argument("--modes", type=int, default=20)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--noop-tasks", type=int, default=400)
    ap.add_argument("--scale", nargs=2, type=int, metavar=("FRAMES", "MODES"), default=None,
                    help="only time summary and forecast on one log of this size")
    args = ap.parse_args()
    if args.scale is not None:
        scale(*args.scale)
        return 0
    print(f"machine: {os.cpu_count()} CPUs, load average {os.getloadavg()[0]:.2f} at start "
          f"(shared with other users; medians of {args.repeats} interleaved repeats)")
    print(f"{args.logs} logs x {args.frames} frames x {args.modes} modes; analyses "
          f"{','.join(ANALYSES)} ({len(ANALYSES)} tasks per log)")
    n_tasks = args.logs * len(ANALYSES)
    with tempfile.TemporaryDirectory() as tmp, contextlib.ExitStack() as stack:
        root = Path(tmp) / "logs"
        root.mkdir()
        paths = write_logs(root, args.logs, args.frames, args.modes)
        sequential(paths[:4])  # warm-up: imports, numba caches
        clients, startup = {}, {}
        for workers in (1, 2):
            t0 = time.perf_counter()
            clients[workers] = stack.enter_context(open_client(
                n_workers=workers, threads_per_worker=1, dashboard_address=None))
            startup[workers] = time.perf_counter() - t0
            analyse_archive(paths[:4], ANALYSES, Path(tmp) / f"warm{workers}", params=PARAMS,
                            client=clients[workers], progress=False, plots=False)
        times: dict = {"loop": [], 1: [], 2: []}
        cpu: dict = {"loop": [], 1: [], 2: []}  # CPU seconds: less sensitive to the load
        busiest: dict = {1: [], 2: []}  # CPU seconds of the busiest worker process
        noops: dict = {1: [], 2: []}
        for r in range(args.repeats):  # interleaved: the machine's load hits all alike
            c0 = time.process_time()
            times["loop"].append(sequential(paths))
            cpu["loop"].append(time.process_time() - c0)
            for workers, client in clients.items():
                w0 = client.run(time.process_time)
                c0 = time.process_time()  # this process: client + local scheduler
                t = time.perf_counter()
                res = analyse_archive(root, ANALYSES, Path(tmp) / f"out{workers}_{r}",
                                      params=PARAMS, client=client, progress=False,
                                      plots=False)
                times[workers].append(time.perf_counter() - t)
                here = time.process_time() - c0
                w1 = client.run(time.process_time)
                spent = [w1[a] - w0[a] for a in w1 if a in w0]
                assert len(spent) == workers, "a worker restarted during the run"
                cpu[workers].append(here + sum(spent))
                busiest[workers].append(max(spent))
                assert res.n_ok == n_tasks, res.report
                store = RowStore(Path(tmp) / f"noop{workers}_{r}")
                specs = [TaskSpec(f"n{r}_{i}", {"i": i}) for i in range(args.noop_tasks)]
                rep = run_tasks(specs, noop, store, client, progress=False)
                noops[workers].append(rep.elapsed / args.noop_tasks)
            print(f"repeat {r + 1}: " + ", ".join(f"{k}: {v[-1]:.2f} s" for k, v in
                                                  times.items()), file=sys.stderr, flush=True)
    med = {k: statistics.median(v) for k, v in times.items()}
    seq = med["loop"]
    print(f"sequential loop   : {seq:7.2f} s  {60 * args.logs / seq:7.1f} logs/min  "
          f"({1000 * seq / args.logs:.0f} ms per log)")
    for workers in (1, 2):
        print(f"dask {workers} worker(s) : {med[workers]:7.2f} s  "
              f"{60 * args.logs / med[workers]:7.1f} logs/min  loop/dask {seq / med[workers]:.2f}"
              f"  (cluster start {startup[workers]:.1f} s, no-op task through the engine "
              f"{1000 * statistics.median(noops[workers]):.1f} ms)")
    over = (med[1] - seq) / n_tasks
    print(f"overhead of 1 worker vs loop: {1000 * over:.1f} ms per task, "
          f"{1000 * over * len(ANALYSES):.0f} ms per log")
    print(f"speed-up 2 workers vs 1     : {med[1] / med[2]:.2f}x")
    mcpu = {k: statistics.median(v) for k, v in cpu.items()}
    print(f"CPU seconds per log (all processes): loop {mcpu['loop'] / args.logs:.3f}, "
          f"1 worker {mcpu[1] / args.logs:.3f}, 2 workers {mcpu[2] / args.logs:.3f}; "
          f"busiest worker {statistics.median(busiest[2]) / args.logs:.3f} with 2 workers "
          f"(ideal 2-core time {statistics.median(busiest[2]):.2f} s = "
          f"{60 * args.logs / statistics.median(busiest[2]):.0f} logs/min if the client "
          "and scheduler had a core of their own)")
    print("all times [s]: " + "; ".join(f"{k}: {', '.join(f'{x:.2f}' for x in v)}"
                                        for k, v in times.items()))
    return 0


if __name__ == "__main__":
    sys.exit(main())
