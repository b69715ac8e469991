"""The documentation site builds without a warning, and its examples run.

References: Sphinx itself (``-W -n``: every warning, including every unresolved
cross-reference, is an error; a fresh build with ``-E`` into a temporary directory),
and the examples' own documented outputs: the tour prints Noll's Delta_21 = 0.0208
(Noll 1976, Table IV) and the MI of a Gaussian pair with rho = 0.6, -0.5 ln(1 - 0.36)
= 0.223 nats, estimated within the estimator's bias (+-0.03 nats at n = 10 000).
"""

from __future__ import annotations

import math
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


def _env() -> dict:
    env = dict(os.environ)
    env["PYTHONPATH"] = str(ROOT) + os.pathsep + env.get("PYTHONPATH", "")
    return env


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def test_site_builds_without_warnings(tmp_path):
    pytest.importorskip("sphinx")
    proc = subprocess.run(
        [sys.executable, "-m", "sphinx", "-E", "-W", "-n", "--keep-going", "-q",
         "-b", "html", "-d", str(tmp_path / "doctrees"), str(ROOT / "docs"),
         str(tmp_path / "html")],
        capture_output=True, text=True, cwd=ROOT, env=_env(),
    )
    assert proc.returncode == 0, proc.stderr[-4000:]
    assert (tmp_path / "html" / "api" / "generated" / "modalinfo.telemetry.ModalLog.html").is_file()


def test_tour_example_runs():
    proc = subprocess.run([sys.executable, "docs/examples/tour.py"], capture_output=True,
                          text=True, cwd=ROOT, env=_env())
    assert proc.returncode == 0, proc.stderr[-4000:]
    numbers = [float(line) for line in proc.stdout.splitlines() if _is_number(line)]
    # printed alone, in order: Delta_21, modes to reach 1e-4 waves^2, the KDE MI, the KSG MI
    assert numbers[0] == pytest.approx(0.0208, abs=5e-5)  # Noll's Delta_21
    assert numbers[2] == pytest.approx(-0.5 * math.log(1 - 0.36), abs=0.03)


@pytest.mark.slow
def test_simulator_example_runs():
    proc = subprocess.run([sys.executable, "docs/examples/simulator.py", "0.05"],
                          capture_output=True, text=True, cwd=ROOT, env=_env())
    assert proc.returncode == 0, proc.stderr[-4000:]
    peak = float(proc.stdout.split()[0])
    assert 0.0 < peak <= 1.0  # a Strehl ratio
