"""Memory estimated before the work against the measured peak RSS at many sizes (left19-ci).

Reference: the kernel's peak resident set of each child process (``os.wait4`` ->
``ru_maxrss``), not the code's own accounting. Every command that estimates its memory
before working is run at several sizes, each in a fresh process under ``nice``:

- ``closedloop run --preset P --duration D``: the estimate is
  ``closedloop.resources.estimate(config, D).peak_bytes`` (what ``closedloop config
  --estimate`` prints), which includes the interpreter (``BASELINE_BYTES``): compared
  with the whole peak;
- ``modalinfo synth``, ``select``, ``forecast``, ``reorder``: their estimates are the
  ``need`` passed to ``modalinfo.cli.shared.check_memory`` (the largest of a run's calls,
  captured by a wrapper in the child; the analysis only, no interpreter). They are
  compared with the child's peak minus its resident size just before the command ran
  (``net``) and with the growth of the peak over the command's smallest size
  (``growth``, which removes the lazily imported libraries too). ``batch`` estimates
  nothing before its work (Dask workers have their own ``--memory-limit``).

An estimate more than 1 MiB (page noise) below ``growth`` (below the whole peak for
``closedloop``) is an under-estimate: a run the check lets through may still be killed.
Printed as a Markdown table (sizes in MiB).

    OPENBLAS_NUM_THREADS=1 PYTHONPATH=. python benchmarks/bench_estimates_left19.py \\
        --work /tmp/est --only synth,select,forecast,reorder,closedloop
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MIB = 2.0 ** 20

#: the child: wrap every module's ``check_memory``, run the command line, report
DRIVER = r"""
import json, os, sys, importlib, pkgutil
import modalinfo.cli as cli, modalinfo.cli.shared as shared
for m in pkgutil.iter_modules(cli.__path__):
    importlib.import_module("modalinfo.cli." + m.name)
need = [0.0]
orig = shared.check_memory
def wrapped(n, what, fix):
    need[0] = max(need[0], float(n))
    return orig(n, what, fix)
for name, mod in list(sys.modules.items()):
    if name.startswith("modalinfo.cli") and getattr(mod, "check_memory", None) is orig:
        mod.check_memory = wrapped
def rss():
    for line in open("/proc/self/status"):
        if line.startswith("VmRSS:"):
            return float(line.split()[1]) * 1024
start = rss()
sys.argv = ["modalinfo"] + sys.argv[1:]
try:
    code = cli.main()
except SystemExit as e:
    code = e.code
json.dump({"need": need[0], "start": start, "code": code}, open(os.environ["EST_OUT"], "w"))
sys.exit(code)
"""


def child(argv: list[str], cwd: Path, env: dict) -> tuple[float, float, int]:
    """Run ``argv`` under nice; return (peak RSS [bytes], seconds, exit code)."""
    t = time.perf_counter()
    p = subprocess.Popen(["nice", "-n", "10", *argv], cwd=cwd, env=env,
                         stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    _, status, usage = os.wait4(p.pid, 0)
    p.returncode = os.waitstatus_to_exitcode(status)
    err = p.stderr.read().decode(errors="replace").strip().splitlines()
    p.stderr.close()
    if p.returncode != 0:
        print(f"  (exit {p.returncode}: {err[-1] if err else ''})", file=sys.stderr)
    return usage.ru_maxrss * 1024.0, time.perf_counter() - t, p.returncode


def modalinfo_rows(cmd: str, sizes: list[int], work: Path, env: dict) -> list[dict]:
    py = sys.executable
    rows = []
    for frames in sizes:
        log = work / f"s{frames}.npz"
        if not log.exists() and cmd != "synth":
            subprocess.run([py, "-m", "modalinfo", "synth", str(log), "--frames", str(frames),
                            "--quiet"], cwd=work, env=env, check=True)
        tag = f"{cmd}{frames}"
        args = {
            "synth": ["synth", str(work / f"o_{tag}.npz"), "--frames", str(frames),
                      "--quiet", "--overwrite"],
            "select": ["select", str(log), "--target", "4", "--surrogates", "19"],
            "forecast": ["forecast", str(log), "--out", str(work / f"o_{tag}"), "--quiet",
                         "--overwrite"],
            "reorder": ["reorder", str(log), "--quiet", "--overwrite",
                        "--out", str(work / f"o_{tag}.json")],
        }[cmd]
        out = work / f"{tag}.json"
        peak, sec, code = child([py, "-c", DRIVER, *args], work, {**env, "EST_OUT": str(out)})
        got = json.loads(out.read_text()) if out.exists() else {"need": float("nan"),
                                                                  "start": float("nan")}
        rows.append({"command": f"modalinfo {cmd}", "size": f"{frames} frames",
                     "estimate": got["need"], "peak": peak, "net": peak - got["start"],
                     "seconds": sec, "code": code})
    # the smallest size that ran (a refused size, e.g. too few frames, is no baseline)
    ok = [r["peak"] for r in rows if r["code"] == 0]
    base = ok[0] if ok else float("nan")
    for r in rows:
        r["growth"] = r["peak"] - base if r["code"] == 0 else float("nan")
    return rows


def closedloop_rows(runs: list[tuple[str, float]], work: Path, env: dict) -> list[dict]:
    from closedloop import presets
    from closedloop.resources import estimate

    rows = []
    for preset, duration in runs:
        est = estimate(presets.get(preset), duration).peak_bytes
        peak, sec, code = child([sys.executable, "-m", "closedloop", "run", "--preset", preset,
                                 "--duration", str(duration), "--quiet"], work, env)
        rows.append({"command": f"closedloop run {preset}", "size": f"{duration:g} s",
                     "estimate": est, "peak": peak, "net": peak, "growth": peak,
                     "seconds": sec, "code": code})
    return rows


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--work", type=Path, required=True, help="scratch folder (created)")
    p.add_argument("--only", default="synth,select,forecast,reorder,closedloop")
    p.add_argument("--frames", default="200,1000,4000,16000,64000",
                   help="log sizes of synth and select")
    p.add_argument("--forecast-frames", default="3000,8000,16000,24000")
    p.add_argument("--reorder-frames", default="300,600,1200")
    p.add_argument("--closedloop", default="kaos:0.02,kaos:0.1,table1:0.05",
                   help="PRESET:DURATION pairs")
    a = p.parse_args()
    a.work.mkdir(parents=True, exist_ok=True)
    env = {**os.environ, "PYTHONPATH": str(ROOT), "OPENBLAS_NUM_THREADS": "1"}
    ints = lambda s: [int(v) for v in s.split(",")]  # noqa: E731
    print("| command | size | estimate | peak RSS | net | growth | estimate / growth | s |")
    print("|---|---|---|---|---|---|---|---|")
    for cmd in a.only.split(","):
        if cmd == "closedloop":
            runs = [(v.split(":")[0], float(v.split(":")[1])) for v in a.closedloop.split(",")]
            rows = closedloop_rows(runs, a.work, env)
        else:
            sizes = {"forecast": a.forecast_frames, "reorder": a.reorder_frames}.get(cmd,
                                                                                   a.frames)
            rows = modalinfo_rows(cmd, ints(sizes), a.work, env)
        for r in rows:
            if r["code"] != 0:
                print(f"| {r['command']} | {r['size']} | exit {r['code']} | | | | | |")
                continue
            ratio = r["estimate"] / r["growth"] if r["growth"] > 0 else float("inf")
            # page-granular noise of ~1 MiB is not an under-estimate
            flag = " **under**" if r["growth"] > r["estimate"] + MIB else ""
            print(f"| {r['command']} | {r['size']} | {r['estimate'] / MIB:.1f} | "
                  f"{r['peak'] / MIB:.0f} | {r['net'] / MIB:.1f} | {r['growth'] / MIB:.1f} | "
                  f"{ratio:.2f}{flag} | {r['seconds']:.0f} |", flush=True)


if __name__ == "__main__":
    main()
