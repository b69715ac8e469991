"""CPU of the lag-1 autocorrelation of every column, per-column loop vs one vectorised call.

Issue 27, left30-twins: ``modalinfo._stats.lag1_autocorrelations`` replaced a per-column
Python loop over the 1-D estimator (``spread_at_split``, ``variance_steps``, the shuffle
rule) and an inline copy (``_scale_shift``). Times, on an AR(1) log of ``--frames`` x
``--modes`` (rho 0.9, seed 30), the median CPU time (``time.process_time``, one untimed
call first) of

- ``loop``: c78d7229's 1-D arithmetic (written out below), once per column;
- ``columns``: ``lag1_autocorrelations`` on the whole log (when the tree has it);
- ``spread_at_split``: the quality pass's spread rule at the middle frame, which held the
  loop (run this script with ``PYTHONPATH`` on the old and the new tree to compare).

Run: PYTHONPATH=. python benchmarks/bench_lag1_left30.py [--frames 10000 --modes 2000]
"""

import numpy as np
from _common import ar1_log, cpu_median, int_options

import modalinfo
from modalinfo import _stats


def _loop(x: np.ndarray) -> np.ndarray:
    """c78d7229's ``lag1_autocorrelation``, one column at a time."""
    out = np.empty(x.shape[1])
    for j in range(x.shape[1]):
        a = x[:, j]
        scale = float(np.max(np.abs(a)))
        d = a / scale
        d = d - d.mean()
        power = float(d @ d)
        out[j] = float(d[1:] @ d[:-1]) / power
    return out


def main() -> None:
    args = int_options(__doc__, frames=10_000, modes=2000, repeats=3).parse_args()
    x = ar1_log(args.frames, args.modes, 30)
    print(f"modalinfo from {modalinfo.__file__}; {args.frames} x {args.modes}, "
          f"median CPU of {args.repeats}")
    print(f"loop             {cpu_median(lambda: _loop(x), args.repeats):8.3f} s")
    if hasattr(_stats, "lag1_autocorrelations"):
        t = cpu_median(lambda: _stats.lag1_autocorrelations(x), args.repeats)
        diff = np.max(np.abs(_stats.lag1_autocorrelations(x) - _loop(x)))
        print(f"columns          {t:8.3f} s  (largest difference from the loop {diff:.1e})")
    t = cpu_median(lambda: _stats.spread_at_split(x, args.frames // 2), args.repeats)
    print(f"spread_at_split  {t:8.3f} s")


if __name__ == "__main__":
    main()
