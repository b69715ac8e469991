"""Peak resident memory of assembling the Shack-Hartmann operators of a config (set-up only).

Builds the config's :class:`~closedloop.optics.geometry.Geometry` and mirrors (their mode
shapes), records the process's peak RSS (``ru_maxrss``), then builds every WFS through its
kind's record and records the peak again: the difference is what the WFS operators'
assembly (and each WFS's own interaction matrix and least-squares reconstructor) added
above the mirrors (a lower bound when the mirrors' own build peaked higher; the current
RSS after the mirrors is printed too: the peak above it is the assembly's). Prints one
JSON line with the peaks, the current RSS, the WFS build's CPU time, the kept CSR
operators' bytes and ``closedloop.resources.estimate``'s ``wfs_build`` part.

Usage (the published ``est-mcao``, ~3-4 GiB)::

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=$PWD python benchmarks/bench_est_wfs_memory.py
    ... --subapertures 16      # est_mcao_variant(16)
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import time

from closedloop import presets, resources
from closedloop.kinds import mirror_kind, sensor_kind
from closedloop.optics.geometry import Geometry


def _peak_gib() -> float:
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20


def _current_gib() -> float:
    """The process's resident memory now (``VmRSS`` of ``/proc/self/status``) [GiB]."""
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 2**20
    return float("nan")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--subapertures", type=int, default=presets.EST_SUBAPERTURES)
    args = ap.parse_args()
    config = presets.est_mcao_variant(args.subapertures)
    t0 = time.process_time()
    geometry = Geometry(config)
    dms = [mirror_kind(d.kind).build(geometry, i) for i, d in enumerate(config.dms)]
    dm_cpu = time.process_time() - t0
    before = _peak_gib()
    held = _current_gib()
    t0 = time.process_time()
    wfss = [sensor_kind(w.kind).build(geometry, j, dms[w.dm])
            for j, w in enumerate(config.wfss)]
    wfs_cpu = time.process_time() - t0
    after = _peak_gib()
    kept = sum(op.data.nbytes + op.indices.nbytes + op.indptr.nbytes
               for w in wfss for op in w.operators)
    est = resources.estimate(config, 0.04)
    print(json.dumps({
        "config": config.name, "load_average": round(os.getloadavg()[0], 1),
        "dm_cpu_s": round(dm_cpu, 1), "wfs_cpu_s": round(wfs_cpu, 1),
        "peak_rss_after_dms_gib": round(before, 3), "peak_rss_after_wfss_gib": round(after, 3),
        "rss_after_dms_gib": round(held, 3), "rss_after_wfss_gib": round(_current_gib(), 3),
        "wfs_assembly_gib": round(after - before, 3), "kept_operators_gib": round(kept / 2**30, 3),
        "estimate_wfs_build_gib": round(est.parts["wfs_build"] / 2**30, 3),
        "estimate_peak_gib": round(est.peak_bytes / 2**30, 3)}))


if __name__ == "__main__":
    main()
