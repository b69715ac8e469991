"""The ``info`` predictor on table1-wind POL telemetry: offline forecast gains and in the loop.

Run: nice /work/main/.venv/bin/python benchmarks/bench_info_predictor.py
     [--duration 2.5] [--modes-per-dm 14] [--loop-duration 0.4] [--seed 0]
     [--skip-offline] [--skip-loop] [--shipped] [--predictors info,info-nn,...]

1. Offline (issue 21 must-show). One no-prediction ``closedloop`` run of the preset
   ``table1-wind`` (``--duration`` s of simulated time, seed 0); the POL coefficients of
   the first ``--modes-per-dm`` modes of each DM side by side (Z2..Z15 of the ground
   WFS's DM, then of the upper one: 28 series, so that the other WFS's modes are
   candidates) after the loop closure and 15 ms, the first 2/3 for training and the
   rest for a rolling-origin evaluation (:func:`modalinfo.forecast.evaluate`, horizons
   1-10, no refit). Predictors: ``info`` (the preset: CMI-selected sparse direct LS,
   lags 0..9, extended-BIC stop), ``info-nn`` (the preset: ``info`` plus random tanh
   features of its inputs, :class:`modalinfo.forecast.InfoNNPredictor`), the full
   VAR (the ``multivariate`` preset, VAR(4):
   every mode at every lag; on all 184 modes it would need 7364 training frames under
   the 10-rows-per-coefficient rule, hence the subset), ARMA(2,3) and ARMA with AIC
   orders; persistence is the baseline of the gains. Reported: whole-wavefront gain
   over persistence per horizon (RMSE ratio), the number of inputs per mode and horizon
   (``info``: mean of ``n_inputs_``; VAR: order x modes; ARMA: p + q past values and
   innovations), the fit time, and the cost per ``update`` (median over 200 frames of
   one call that returns the forecasts of every mode at horizons 1..10).
2. In the loop: ``table1-wind`` for ``--loop-duration`` s with ``none``, ``info``,
   ``arma``, ``arma-aic`` and the ``oracle`` on one atmosphere (seed 0, one
   ``LoopModel``), the trained predictors fitted on the no-prediction run's POL after
   its loop closure and 15 ms (:func:`closedloop.run_trained`); SR peak mean and
   corrected-FoV diameter from :meth:`closedloop.SimulationResult.summary`.

Single-threaded BLAS (set before numpy is imported), as the other benchmarks.
"""

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402

from modalinfo.forecast import (  # noqa: E402
    ARMAPredictor,
    InfoNNPredictor,
    InfoPredictor,
    MultivariatePredictor,
    evaluate,
)

HORIZONS = range(1, 11)
LOOP_PREDICTORS = ("none", "info", "arma", "arma-aic", "oracle")


def run_trained(config, duration: float, names, *, seed: int = 0) -> dict:
    """One closed-loop run per predictor name, trained ones fitted on the ``none`` run."""
    import closedloop
    from closedloop.simulation import LoopModel

    model = LoopModel(config)
    results = {"none": closedloop.simulate(config, duration, seed=seed, model=model)}
    for name in names:
        if name != "none":
            results[name] = closedloop.run_trained(config, name, duration, seed=seed,
                                                   reference=results["none"], model=model)
    return results


def _update_cost(pred, data: np.ndarray, n: int = 200) -> float:
    """Median time of one ``update`` [s] over ``n`` frames after a reset."""
    pred.reset()
    times = np.empty(n)
    for i in range(n):
        t0 = time.perf_counter()
        pred.update(data[i])
        times[i] = time.perf_counter() - t0
    return float(np.median(times))


def _n_inputs(name: str, pred, n_modes: int) -> float:
    if isinstance(pred, InfoPredictor):
        return float(np.mean(pred.n_inputs_))
    if isinstance(pred, MultivariatePredictor):
        return float(pred.order * n_modes)
    if isinstance(pred, ARMAPredictor):
        return float(np.mean(np.sum(pred.orders_, axis=1)))
    return 1.0  # persistence: the last value


#: offline predictors: key (``--predictors``) -> (table label, factory)
OFFLINE = {
    "info": ("info", InfoPredictor),
    "info-nn": ("info-nn", InfoNNPredictor),
    "var": ("full VAR(4)", lambda: MultivariatePredictor(order=4)),
    "arma": ("ARMA(2,3)", lambda: ARMAPredictor(order=(2, 3))),
    "arma-aic": ("ARMA (AIC)", lambda: ARMAPredictor(order="aic")),
}


def _make(names) -> dict:
    return {OFFLINE[k][0]: OFFLINE[k][1]() for k in names}


def _table(preds: dict, data: np.ndarray, n_train: int) -> None:
    """Evaluate, fit-time and update-cost table of ``preds`` on ``data``."""
    t0 = time.perf_counter()
    ev = evaluate(preds, data, train=n_train, horizons=HORIZONS)
    print(f"evaluation: {time.perf_counter() - t0:.0f} s (train {n_train} frames, test "
          f"{data.shape[0] - n_train})", flush=True)
    rows = []
    for name, proto in [("persistence", None), *preds.items()]:
        if proto is None:
            from modalinfo.forecast import PersistencePredictor

            proto = PersistencePredictor()
        pred = proto.clone(horizon=max(HORIZONS))
        t0 = time.perf_counter()
        pred.fit(data[:n_train])
        fit_s = time.perf_counter() - t0
        cost = _update_cost(pred, data[n_train:])
        i = ev.names.index(name)
        extra = (f" (network on in {np.mean(pred.n_active_):.2f} of the models)"
                 if isinstance(pred, InfoNNPredictor) else "")
        rows.append((name + extra, ev.gain_wavefront[i], _n_inputs(name, pred, data.shape[1]),
                     fit_s, cost))
    hs = list(HORIZONS)
    print("\n| predictor | " + " | ".join(f"h={h}" for h in hs)
          + " | inputs per mode | fit [s] | update [ms] |")
    print("|---|" + "---|" * len(hs) + "---|---|---|")
    for name, gains, n_in, fit_s, cost in rows:
        print(f"| {name} | " + " | ".join(f"{g:.3f}" for g in gains)
              + f" | {n_in:.1f} | {fit_s:.2f} | {1e3 * cost:.3f} |", flush=True)


def shipped(names) -> None:
    """The offline table on the shipped logs (train on the first half, as the CLI)."""
    from pathlib import Path

    from modalinfo.io import load

    data_dir = Path(__file__).resolve().parent.parent / "data"
    for log_name in ("kaos_like_closed_loop", "kaos_closedloop"):
        log = load(data_dir / f"{log_name}.npz")
        data = np.ascontiguousarray(np.asarray(log.coeffs, dtype=float))
        print(f"\n{log_name}: {data.shape}", flush=True)
        _table(_make(names), data, data.shape[0] // 2)


def offline(duration: float, seed: int, per_dm: int, names=tuple(OFFLINE)) -> None:
    from closedloop import presets
    from closedloop.control.predictors import training_data

    config = presets.get("table1-wind")
    t0 = time.perf_counter()
    res = run_trained(config, duration, ("none",), seed=seed)["none"]
    pol = training_data(res)  # POL of both DMs after the loop closure and 15 ms
    n0 = res.config.dms[0].n_modes
    pol = np.ascontiguousarray(np.hstack([pol[:, :per_dm], pol[:, n0 : n0 + per_dm]]))
    print(f"table1-wind no-prediction run, {duration} s, seed {seed}: POL {pol.shape} "
          f"({time.perf_counter() - t0:.0f} s)", flush=True)
    n_train = (2 * pol.shape[0]) // 3
    _table(_make(names), pol, n_train)


def in_loop(duration: float, seed: int) -> None:
    from closedloop import presets

    config = presets.get("table1-wind")
    t0 = time.perf_counter()
    results = run_trained(config, duration, LOOP_PREDICTORS, seed=seed)
    print(f"\nin the loop: table1-wind, {duration} s, seed {seed} "
          f"({time.perf_counter() - t0:.0f} s)")
    print("| predictor | SR peak (mean after closure) | SR field mean | corrected FoV d ['] |")
    print("|---|---|---|---|")
    for name, r in results.items():
        s = r.summary()
        print(f"| {name} | {s['strehl_peak_mean']:.3f} | {s['strehl_field_mean']:.3f} | "
              f"{s['corrected_fov_diameter_arcmin']:.2f} |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--duration", type=float, default=2.5)
    parser.add_argument("--modes-per-dm", type=int, default=14)
    parser.add_argument("--loop-duration", type=float, default=0.4)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--skip-offline", action="store_true")
    parser.add_argument("--skip-loop", action="store_true")
    parser.add_argument("--shipped", action="store_true",
                        help="also the offline table on the two shipped logs")
    parser.add_argument("--predictors", default=",".join(OFFLINE),
                        help=f"offline predictors, from {', '.join(OFFLINE)}")
    args = parser.parse_args()
    names = [n.strip() for n in args.predictors.split(",")]
    for n in names:
        if n not in OFFLINE:
            parser.error(f"--predictors: unknown {n!r}; choose from {', '.join(OFFLINE)}")
    if args.shipped:
        shipped(names)
    if not args.skip_loop:
        in_loop(args.loop_duration, args.seed)
    if not args.skip_offline:
        offline(args.duration, args.seed, args.modes_per_dm, names)


if __name__ == "__main__":
    main()
