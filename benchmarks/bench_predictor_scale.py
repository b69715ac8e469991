"""ARMA predictors at the scale of a 4-m telescope (issue 30, item 3, ARMA part).

Run::

    nice /work/main/.venv/bin/python benchmarks/bench_predictor_scale.py
        [--sizes 27,184,500,1500] [--aic-sizes 27,184] [--frames 10000]
        [--baseline OLD_ARMA.py | --baseline-rev REV] [--baseline-max-aic 184]
        [--sm-modes 3] [--sm-aic-modes 0] [--spread] [--cache DIR]

Data: one synthetic closed-loop log of ``max(sizes)`` Kolmogorov-correlated Zernike modes
(Z2 onwards, :func:`modalinfo.telemetry.synthetic.kaos_like`, seed 0: von Karman
turbulence through the KAOS-like integrator loop), ``--frames`` frames; a size ``M`` takes
its first ``M`` modes. ``--cache DIR`` keeps the generated log as ``.npy`` (generation is
~2 min at 1,500 modes on a loaded machine).

Timed (median of ``--repeats`` runs, CPU-bound, single-threaded BLAS):

1. ``ARMAPredictor(order=(2, 3)).fit`` (the ``arma`` preset) at every ``--sizes``.
2. The ``arma-aic`` preset's fit (p, q <= 5 by AIC) at every ``--aic-sizes``.
3. With ``--baseline-rev REV`` (a git revision of this repository: its
   ``modalinfo/forecast/arma.py`` and ``_kernels.py``, the module importing that
   revision's kernels) or ``--baseline FILE`` (an earlier ``arma.py`` alone, which then
   runs on this tree's kernels), the same fits by that module in the same run:
   before/after ratio, whether the fitted parameters (and the AIC table) are
   bit-identical and, if not, the largest differences (coefficients, relative sigma^2
   and criterion) and the number of modes whose AIC orders differ
   (``--baseline-max-aic``: AIC baseline only up to that many modes, it is the slow one;
   ``--aic-every k``: the AIC rows fit every k-th mode, a sample spread over the whole
   log, e.g. 300 of 1,500 with k = 5).
   ``--spread`` (with a baseline): the baseline also fits the AIC rows' data perturbed by
   one ulp (``numpy.nextafter`` upwards) and, if it has ``_SharedRegressions``, with every
   Hannan-Rissanen start scaled by ``1 + 1e-12`` (both untimed); the largest change of
   any candidate's criterion is the search's own numerical spread, and the order rule of
   issue 30 (aic3) is printed against it: the selected orders equal on >= 99 % of the modes, every
   difference's gap in the baseline's own table beside the spread, and the mean signed
   criterion change (this tree minus the baseline) per candidate order.
4. statsmodels' ``ARIMA(order=(2, 0, 3)).fit()`` per mode on the first ``--sm-modes``
   modes, and (``--sm-aic-modes``) ``arma_order_select_ic(max_ar=5, max_ma=5,
   ic="aic")`` per mode: our cost per mode against theirs, same run.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import functools  # noqa: E402
import importlib.util  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402
from pathlib import Path  # noqa: E402

import numpy as np  # noqa: E402
from _common import timed  # noqa: E402

from modalinfo.forecast.presets import make_predictor  # noqa: E402
from modalinfo.telemetry.synthetic import kaos_like  # noqa: E402

_KEYS = ("mu", "phi", "theta", "orders", "sigma2", "criterion")


def _log(n_modes: int, n_frames: int, cache: Path | None) -> np.ndarray:
    path = None if cache is None else cache / f"kaos_like_{n_modes}x{n_frames}.npy"
    if path is not None and path.exists():
        return np.load(path)
    if cache is not None:  # a cached log of more modes holds these as its first columns
        for other in sorted(cache.glob(f"kaos_like_*x{n_frames}.npy")):
            if int(other.name.split("_")[2].split("x")[0]) >= n_modes:
                return np.ascontiguousarray(np.load(other, mmap_mode="r")[:, :n_modes])
    t0 = time.perf_counter()
    x = np.asarray(kaos_like(n_frames=n_frames, modes=list(range(2, 2 + n_modes)),
                             seed=0).coeffs, dtype=float)
    print(f"generated {n_modes} modes x {n_frames} frames in {time.perf_counter() - t0:.1f} s")
    if path is not None:
        cache.mkdir(parents=True, exist_ok=True)
        np.save(path, x)
    return x


def _load_baseline(path: str):
    spec = importlib.util.spec_from_file_location("arma_baseline", path)
    module = importlib.util.module_from_spec(spec)
    sys.modules["arma_baseline"] = module  # dataclasses look their module up
    spec.loader.exec_module(module)
    return module.ARMAPredictor


def _baseline_from_rev(rev: str):
    """``arma.py`` and its kernels at git revision ``rev``, in a temporary directory."""
    root = Path(__file__).resolve().parent.parent
    folder = Path(tempfile.mkdtemp(prefix="arma_baseline_"))

    def show(name: str) -> str:
        return subprocess.run(["git", "-C", str(root), "show", f"{rev}:{name}"], check=True,
                              capture_output=True, text=True).stdout

    (folder / "arma_baseline_kernels.py").write_text(show("modalinfo/forecast/_kernels.py"))
    arma = show("modalinfo/forecast/arma.py").replace(
        "from modalinfo.forecast._kernels import", "from arma_baseline_kernels import")
    (folder / "arma_baseline.py").write_text(arma)
    sys.path.insert(0, str(folder))
    return _load_baseline(str(folder / "arma_baseline.py"))


_median_time = functools.partial(timed, cpu=True, warm=False)  # every call timed


def _identical(a: dict, b: dict) -> bool:
    for key in _KEYS:
        if (a[key] is None) != (b[key] is None):
            return False
        if a[key] is not None and not np.array_equal(a[key], b[key], equal_nan=True):
            return False
    return True


def _differences(a: dict, b: dict) -> str:
    """Largest differences between two fits' parameters (when not bit-identical)."""
    out = []
    for key in ("phi", "theta"):
        if a[key].shape == b[key].shape:
            out.append(f"{key} {np.abs(a[key] - b[key]).max(initial=0.0):.1e}")
    out.append(f"sigma2 rel {np.abs(a['sigma2'] / b['sigma2'] - 1).max():.1e}")
    if a["criterion"] is not None:
        out.append(f"criterion rel {np.nanmax(np.abs(a['criterion'] / b['criterion'] - 1)):.1e}")
        # how near a flip the baseline's choice was: best-vs-second AIC, closest mode
        table = np.sort(b["criterion"].reshape(b["criterion"].shape[0], -1), axis=1)
        out.append(f"closest best-vs-second criterion {np.nanmin(table[:, 1] - table[:, 0]):.3g}")
    out.append(f"orders differ on {int((a['orders'] != b['orders']).any(axis=1).sum())} modes")
    return ", ".join(out)


def _spread(make_old, data: np.ndarray, fitted: dict) -> float:
    """The baseline's own spread: largest criterion change under 1 ulp of the data or a
    ``1 + 1e-12`` scaling of every Hannan-Rissanen start (untimed refits)."""
    crit = fitted["criterion"]
    bumped = make_old().fit(np.nextafter(data, np.inf)).params_["criterion"]
    widths = [float(np.nanmax(np.abs(bumped - crit)))]
    module = sys.modules[type(make_old()).__module__]
    shared = getattr(module, "_SharedRegressions", None)
    if shared is not None:
        solve = shared.solve
        shared.solve = lambda self, p, q: tuple(c * (1 + 1e-12) for c in solve(self, p, q))
        try:
            started = make_old().fit(data).params_["criterion"]
        finally:
            shared.solve = solve
        widths.append(float(np.nanmax(np.abs(started - crit))))
    print("  spread: 1 ulp of the data " + f"{widths[0]:.3g}" + (
        f", Hannan-Rissanen starts x (1 + 1e-12) {widths[1]:.3g}" if len(widths) > 1 else ""))
    return max(widths)


def _order_rule(new: dict, old: dict, spread: float) -> str:
    """The order rule (issue 30, aic3): selections, their gaps and the mean change."""
    crit_new, crit_old = new["criterion"], old["criterion"]
    n_modes = crit_old.shape[0]
    differ = np.flatnonzero((new["orders"] != old["orders"]).any(axis=1))
    lines = [f"  order rule: spread (largest |change| of a criterion, above) "
             f"{spread:.3g}; orders equal on {n_modes - differ.size}/{n_modes} modes "
             f"({100 * (1 - differ.size / n_modes):.1f} %, rule >= 99 %)"]
    for m in differ:
        o_new = tuple(int(i) for i in new["orders"][m])
        o_old = tuple(int(i) for i in old["orders"][m])
        gap = crit_old[m][o_new] - crit_old[m][o_old]
        lines.append(f"    mode {m}: {o_old} -> {o_new}, gap in the baseline's table "
                     f"{gap:.3g} ({'within' if gap <= spread else 'BEYOND'} the spread "
                     f"{spread:.3g})")
    mean = np.nanmean(crit_new - crit_old, axis=0)
    worst = tuple(int(i) for i in np.unravel_index(np.nanargmax(mean), mean.shape))
    lines.append(f"  mean criterion change per candidate (this tree - baseline): largest "
                 f"{mean[worst]:.3g} at {worst} ({'within' if mean[worst] <= spread else 'BEYOND'}"
                 f" the spread)")
    return "\n".join(lines)


def _rows(x, sizes, label, make, make_old, repeats, baseline_max=None, every=1,
          spread=False):
    out = {}
    for m in sizes:
        data = np.ascontiguousarray(x[:, ::every][:, :m])
        t_new, fit_new = _median_time(lambda d=data: make().fit(d), repeats)
        line = f"{label:10s} {m:5d} modes: {t_new:8.2f} s  ({t_new / m * 1e3:7.2f} ms/mode)"
        if make_old is not None and (baseline_max is None or m <= baseline_max):
            t_old, fit_old = _median_time(lambda d=data: make_old().fit(d), repeats)
            same = _identical(fit_new.params_, fit_old.params_)
            line += (f" | baseline {t_old:8.2f} s ({t_old / m * 1e3:7.2f} ms/mode), "
                     f"ratio {t_old / t_new:5.2f}x, "
                     + ("bit-identical" if same
                        else _differences(fit_new.params_, fit_old.params_)))
            if spread and fit_old.params_["criterion"] is not None:
                line += "\n" + _order_rule(fit_new.params_, fit_old.params_,
                                           _spread(make_old, data, fit_old.params_))
        print(line, flush=True)
        out[m] = t_new / m
    return out


def _statsmodels(x, n_sm, n_sm_aic):
    from statsmodels.tsa.arima.model import ARIMA
    from statsmodels.tsa.stattools import arma_order_select_ic

    per_mode = {}
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        if n_sm:
            t0 = time.process_time()
            for m in range(n_sm):
                ARIMA(x[:, m], order=(2, 0, 3)).fit()
            per_mode["arma"] = (time.process_time() - t0) / n_sm
            print(f"statsmodels ARIMA(2,0,3).fit: {per_mode['arma']:.3f} s/mode "
                  f"({n_sm} modes)", flush=True)
        if n_sm_aic:
            t0 = time.process_time()
            for m in range(n_sm_aic):
                arma_order_select_ic(x[:, m], max_ar=5, max_ma=5, ic="aic")
            per_mode["aic"] = (time.process_time() - t0) / n_sm_aic
            print(f"statsmodels arma_order_select_ic(5, 5, aic): {per_mode['aic']:.2f} "
                  f"s/mode ({n_sm_aic} modes)", flush=True)
    return per_mode


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", default="27,184,500,1500")
    parser.add_argument("--aic-sizes", default="27,184")
    parser.add_argument("--frames", type=int, default=10_000)
    parser.add_argument("--repeats", type=int, default=1)
    parser.add_argument("--baseline", default=None,
                        help="an earlier arma.py (runs on this tree's kernels)")
    parser.add_argument("--baseline-rev", default=None,
                        help="a git revision: its arma.py with its own kernels")
    parser.add_argument("--baseline-max-aic", type=int, default=None)
    parser.add_argument("--aic-every", type=int, default=1,
                        help="AIC rows fit every k-th mode (a sample spread over the log)")
    parser.add_argument("--sm-modes", type=int, default=3)
    parser.add_argument("--sm-aic-modes", type=int, default=0)
    parser.add_argument("--spread", action="store_true",
                        help="the AIC rows' order rule against the baseline's 1-ulp spread")
    parser.add_argument("--cache", type=Path, default=None)
    args = parser.parse_args(argv)
    sizes = [int(s) for s in args.sizes.split(",") if s]
    aic_sizes = [int(s) for s in args.aic_sizes.split(",") if s]
    x = _log(max(sizes + [m * args.aic_every for m in aic_sizes]), args.frames, args.cache)
    old = (_baseline_from_rev(args.baseline_rev) if args.baseline_rev is not None
           else None if args.baseline is None else _load_baseline(args.baseline))
    make_old = (None if old is None else lambda: old(order=(2, 3)))
    make_old_aic = (None if old is None else lambda: old(order="aic"))
    # compile the kernels (this tree's and the baseline's) outside the timings
    make_predictor("arma").fit(x[:2000, :2])
    if aic_sizes:
        make_predictor("arma-aic").fit(x[:2000, :2])
    if make_old is not None:
        make_old().fit(x[:2000, :2])
        if aic_sizes:
            make_old_aic().fit(x[:2000, :2])
    print(f"## ARMA fits, {args.frames} frames, CPU time (process_time), "
          f"median of {args.repeats}; load average {os.getloadavg()}", flush=True)
    fixed = _rows(x, sizes, "ARMA(2,3)", lambda: make_predictor("arma"), make_old,
                  args.repeats)
    aic = _rows(x, aic_sizes, "arma-aic", lambda: make_predictor("arma-aic"), make_old_aic,
                args.repeats, args.baseline_max_aic, args.aic_every, args.spread)
    sm = _statsmodels(x, args.sm_modes, args.sm_aic_modes)
    if "arma" in sm:
        for m, t in fixed.items():
            print(f"ARMA(2,3) at {m} modes: {sm['arma'] / t:6.0f}x statsmodels per mode")
    if "aic" in sm:
        for m, t in aic.items():
            print(f"arma-aic at {m} modes: {sm['aic'] / t:6.0f}x statsmodels per mode")


if __name__ == "__main__":
    main()
