"""The ``info`` predictor and the transfer-entropy map at thousands of modes (issue 30, item 3).

Run: nice /work/main/.venv/bin/python benchmarks/bench_info_scale.py
     [--modes 1500] [--frames 5000] [--width 2] [--cache DIR] [--baseline-root DIR]
     [--profile] [--skip-small] [--skip-large] [--skip-infomeasure] [--skip-map]
     [--small-sizes 27,184] [--map-sizes 300,600,1500] [--map-surrogates 49]

Data: :func:`modalinfo.telemetry.synthetic.kaos_like` (Z2 onwards, seed 0: von Karman
turbulence through the KAOS-like integrator loop); a size M takes its first M modes.
CPU time (``time.process_time``), single-threaded BLAS (set before numpy is imported).

1. Large: ``InfoPredictor(candidates="radial", radial_width=--width)`` (lags 0..9,
   8 inputs, horizons 1..10, extended-BIC stop: the preset's settings) fitted on
   ``--modes`` x ``--frames``; the number of candidate groups and mean candidates per
   target; ``--profile`` prints the top of a cProfile of that fit.
2. Small (27 modes, the paper's size, and 184): the default ``InfoPredictor()`` fit
   (``candidates="all"``) of this tree against the same fit with the package found
   under ``--baseline-root`` (e.g. /work/main, the code before the rule), each in a
   fresh subprocess, median of 3; parameters compared bit for bit.
3. infomeasure per mode: the greedy search of one mode and horizon evaluates
   ``m (k + 1)`` candidate gains (m candidates, k inputs chosen); infomeasure 0.6.3
   has no Gaussian closed form, so its cheapest conditional MI, ``cmi(approach=
   "miller_madow")`` on bin codes with a one-column condition, is timed at the same
   n (median of 7) and multiplied by the evaluations our fit did per mode -- a lower
   bound of what the same search would cost with it.
4. The map and the search at that size (``--skip-map`` to skip): the Gaussian
   ``transfer_entropy_map(candidates="radial")`` of the first M modes for each M of
   ``--map-sizes`` (default ``--modes``) on the first 2 000 frames (lags 1..2, history
   1, ``--map-surrogates`` surrogates, step-down maxT over the restricted family),
   and ``select_inputs(candidates="radial")`` of Z500 (horizon 2, lags 0..9, 199
   surrogates, no intervals) on all frames and ``--modes``; the unrestricted map's own
   resource estimate is printed beside (its time estimate, and its null of N x S^2 x L
   values).
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import cProfile  # noqa: E402
import io  # noqa: E402
import pstats  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402

from modalinfo.forecast import InfoPredictor  # noqa: E402
from modalinfo.information.candidates import candidate_mask  # noqa: E402
from modalinfo.telemetry.synthetic import kaos_like  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]


def _log(n_modes: int, n_frames: int, cache: Path | None) -> np.ndarray:
    path = None if cache is None else cache / f"kaos_like_{n_modes}x{n_frames}.npy"
    if path is not None and path.exists():
        return np.load(path)
    x = np.asarray(kaos_like(n_frames=n_frames, modes=list(range(2, 2 + n_modes)),
                             seed=0).coeffs, dtype=float)
    if path is not None:
        cache.mkdir(parents=True, exist_ok=True)
        np.save(path, x)
    return x


_SMALL = """
import os, sys, time, pickle
os.environ['OPENBLAS_NUM_THREADS'] = '1'
import numpy as np
from modalinfo.forecast import InfoPredictor
x = np.load(sys.argv[1])
InfoPredictor().fit(x[:600])  # compile / warm up
times = []
for _ in range(3):
    t0 = time.process_time()
    p = InfoPredictor().fit(x)
    times.append(time.process_time() - t0)
pickle.dump((float(np.median(times)), p.params_), sys.stdout.buffer)
"""


def _small(x: np.ndarray, sizes, baseline_root: Path, cache: Path) -> None:
    import pickle
    for m in sizes:
        path = cache / f"small_{m}.npy"
        np.save(path, np.ascontiguousarray(x[:, :m]))
        res = {}
        for name, root in (("this tree", ROOT), ("baseline", baseline_root)):
            env = dict(os.environ, PYTHONPATH=str(root))
            out = subprocess.run([sys.executable, "-c", _SMALL, str(path)], env=env,
                                 capture_output=True, check=True, cwd=str(root)).stdout
            res[name] = pickle.loads(out)
        same = all(np.array_equal(res["this tree"][1][k], res["baseline"][1][k])
                   for k in res["baseline"][1])
        t_new, t_old = res["this tree"][0], res["baseline"][0]
        print(f"small {m:4d} modes: this tree {t_new:7.2f} s, baseline {t_old:7.2f} s, "
              f"ratio baseline/this {t_old / t_new:5.2f}, "
              f"{'parameters bit-identical' if same else 'PARAMETERS DIFFER'}", flush=True)


def _infomeasure_per_eval(n: int) -> float:
    import infomeasure as im
    rng = np.random.default_rng(0)
    codes = rng.integers(0, 10, size=(n, 3))
    x, y, z = codes[:, 0], codes[:, 1], codes[:, 2]
    im.cmi(x, y, cond=z, approach="miller_madow")
    times = []
    for _ in range(7):
        t0 = time.process_time()
        im.cmi(x, y, cond=z, approach="miller_madow")
        times.append(time.process_time() - t0)
    return float(np.median(times))


def _map_and_search(x: np.ndarray, width: int, sizes: list[int], surrogates: int) -> None:
    from modalinfo.information import select_inputs, transfer_entropy_map
    from modalinfo.telemetry import ModalLog

    for M in sizes:
        log = ModalLog(x[:2000, :M], modes=list(range(2, 2 + M)), rate=2000.0)
        t0 = time.process_time()
        res = transfer_entropy_map(log, lags=2, history=1, n_surrogates=surrogates, seed=0,
                                   candidates="radial", radial_width=width, max_seconds=1e5)
        cpu = time.process_time() - t0
        cells = int(np.count_nonzero(~np.isnan(res.pvalue)))
        print(f"map: {M} modes x 2000 frames, lags 1..2, {surrogates} surrogates, radial "
              f"width {width}: {cells} cells ({cells / (M * (M - 1) * 2):.3f} of the full "
              f"map's {M * (M - 1) * 2}) in {cpu:.1f} s CPU (estimate checked before work "
              f"{res.estimated_seconds:.0f} s); {len(res.links())} significant links; load "
              f"{os.getloadavg()[0]:.1f}", flush=True)
    try:
        transfer_entropy_map(log, lags=2, history=1, n_surrogates=surrogates, seed=0,
                             max_seconds=1.0)
    except ValueError as err:
        print(f"unrestricted map refused: {err}", flush=True)
    M = x.shape[1]
    full_log = ModalLog(x, modes=list(range(2, 2 + M)), rate=2000.0)
    target = f"Z{min(500, M + 1)}"
    t0 = time.process_time()
    sel = select_inputs(full_log, target, horizon=2, max_lag=10, n_surrogates=199,
                        intervals=False, seed=0, candidates="radial", radial_width=width)
    cpu = time.process_time() - t0
    print(f"select_inputs {target} (radial {width}): {sel.n_candidates} candidates, "
          f"{len(sel.inputs)} inputs in {cpu:.1f} s CPU: "
          f"{', '.join(s.label for s in sel.inputs)}", flush=True)


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--modes", type=int, default=1500)
    parser.add_argument("--frames", type=int, default=5000)
    parser.add_argument("--width", type=int, default=2)
    parser.add_argument("--cache", type=Path, default=Path("/tmp/infotime_cache"))
    parser.add_argument("--baseline-root", type=Path, default=Path("/work/main"))
    parser.add_argument("--profile", action="store_true")
    parser.add_argument("--skip-small", action="store_true")
    parser.add_argument("--skip-large", action="store_true")
    parser.add_argument("--skip-infomeasure", action="store_true")
    parser.add_argument("--skip-map", action="store_true")
    parser.add_argument("--small-sizes", default="27,184")
    parser.add_argument("--map-sizes", default=None,
                        help="comma list of mode counts for the map (default: --modes)")
    parser.add_argument("--map-surrogates", type=int, default=49)
    args = parser.parse_args(argv)
    print(f"load average {os.getloadavg()}, {time.strftime('%Y-%m-%d %H:%M:%S', time.gmtime())}"
          " UTC", flush=True)
    x = _log(args.modes, args.frames, args.cache)
    if not args.skip_small:
        _small(x, [int(v) for v in args.small_sizes.split(",")], args.baseline_root,
               args.cache)
    if not args.skip_map:
        sizes = ([int(v) for v in args.map_sizes.split(",")] if args.map_sizes
                 else [args.modes])
        _map_and_search(x, args.width, sizes, args.map_surrogates)
    if args.skip_large:
        return
    labels = [f"Z{j}" for j in range(2, 2 + args.modes)]
    mask = candidate_mask(labels, "radial", args.width)
    groups = np.unique(mask.T, axis=0).shape[0]
    print(f"large: {args.modes} modes x {args.frames} frames, radial width {args.width}: "
          f"{groups} candidate groups, {mask.sum(axis=0).mean():.0f} candidate modes per "
          f"target (of {args.modes}), x 10 lags", flush=True)
    pred = InfoPredictor(candidates="radial", radial_width=args.width)
    prof = cProfile.Profile() if args.profile else None
    t0 = time.process_time()
    w0 = time.perf_counter()
    if prof:
        prof.enable()
    pred.fit(x)
    if prof:
        prof.disable()
    cpu, wall = time.process_time() - t0, time.perf_counter() - w0
    k = pred.n_inputs_
    print(f"large fit: {cpu:.1f} s CPU ({wall:.1f} s wall), {cpu / args.modes * 1e3:.1f} ms "
          f"CPU per mode; inputs per model mean {k.mean():.2f}, max {k.max()}", flush=True)
    if prof:
        s = io.StringIO()
        pstats.Stats(prof, stream=s).sort_stats("tottime").print_stats(12)
        print(s.getvalue())
    if not args.skip_infomeasure:
        n = args.frames - 10 - 10 + 1
        per = _infomeasure_per_eval(n)
        m_per = mask.sum(axis=0).mean() * 10
        evals = m_per * (k.mean() + 1) * k.shape[0]  # per mode: every horizon's search
        print(f"infomeasure cmi(miller_madow) at n = {n}: {per * 1e3:.2f} ms per "
              f"evaluation; our search per mode does ~{evals:.0f} evaluations -> "
              f"infomeasure >= {per * evals:.1f} s per mode against our "
              f"{cpu / args.modes:.3f} s: ratio >= {per * evals / (cpu / args.modes):.0f}x",
              flush=True)


if __name__ == "__main__":
    main()
