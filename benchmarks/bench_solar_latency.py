"""The correlation time of table1-solar's WFSs on this machine: CPU time against wall time.

What :func:`closedloop.studies.solar.solar_latency` feeds the latency model: one frame's
shift measurement (SDF + 2QI, the sensor's search range) of every valid subaperture and
the tracker image of each correlating WFS, timed in CPU seconds of this process, beside
the same batches timed in wall seconds (which a shared machine's load inflates), and the
delay each RTC preset gives.

    PYTHONPATH=. python benchmarks/bench_solar_latency.py [--repeats 5]
"""

from __future__ import annotations

import argparse
import os
import time


def main(argv=None) -> int:
    """Print the per-WFS CPU and wall times and the delay of each RTC preset."""
    ap = argparse.ArgumentParser(prog="bench_solar_latency")
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args(argv)
    from closedloop import presets
    from closedloop.simulation import LoopModel
    from closedloop.studies import solar

    cfg = presets.get("table1-solar")
    model = LoopModel(cfg)
    sizes = solar.correlating_wfs_sizes(cfg, model)
    print(f"load average at start {os.getloadavg()[0]:.1f} on {os.cpu_count()} cores")
    for i, n, px in sizes:
        cpu = [solar.correlation_compute_time(n + 1, px, repeats=args.repeats)
               for _ in range(3)]
        wall = [solar.correlation_compute_time(n + 1, px, repeats=args.repeats,
                                               clock=time.perf_counter) for _ in range(3)]
        print(f"WFS {i}: {n} subapertures + tracker, {px}x{px} px: CPU {min(cpu) * 1e3:.2f}-"
              f"{max(cpu) * 1e3:.2f} ms ({min(cpu) / (n + 1) * 1e6:.0f} us per image), wall "
              f"{min(wall) * 1e3:.1f}-{max(wall) * 1e3:.1f} ms")
    compute = solar.correlating_compute_time(cfg, model, repeats=args.repeats)
    print(f"one frame, both WFSs: {compute * 1e3:.2f} ms of CPU")
    for name in solar.RTC_PRESETS:
        try:
            _, delay = solar.solar_latency(cfg, rtc=name, compute_time=compute)
            print(f"  {name}: delay {delay * 1e3:.3f} ms")
        except ValueError as exc:
            print(f"  {name}: refused: {str(exc).splitlines()[0]}")
    print(f"load average at end {os.getloadavg()[0]:.1f}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
