"""Round 4 of issue 27's adversarial inputs (closedloop side): the ones that failed, fixed.

The full list of inputs tried (id | input | expected | observed | verdict | fix) is in
docs/ADVERSARIAL.md, section "Round 4, issue 27".

References: the command-line contract of the README and ``modalinfo.common.cli``
(Ctrl-C: one line ``PROG: interrupted`` on stderr and exit 130, the shell's 128 + SIGINT;
bad input: one line, exit 2, nothing written); a real SIGINT delivered by the kernel
(``os.kill``) at the moment the command first imports NumPy, the seconds-long part of
its start-up.
"""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]

#: a ``sitecustomize`` (imported by ``site`` before ``-m`` runs anything) that sends the
#: process a real SIGINT when NumPy is first imported: a Ctrl-C during the start-up
_TRIP = """\
import os, signal, sys

class _CtrlCOnNumpy:
    def find_spec(self, name, path=None, target=None):
        if name == "numpy":
            sys.meta_path.remove(self)
            os.kill(os.getpid(), signal.SIGINT)
        return None

sys.meta_path.insert(0, _CtrlCOnNumpy())
"""


def ctrl_c_while_importing(tmp_path: Path, argv: list[str]) -> subprocess.CompletedProcess:
    """Run ``python ARGV`` with a Ctrl-C at its first NumPy import; return the process."""
    (tmp_path / "sitecustomize.py").write_text(_TRIP)
    env = dict(os.environ, PYTHONPATH=f"{tmp_path}{os.pathsep}{ROOT}")
    return subprocess.run([sys.executable, *argv], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=120)


@pytest.mark.parametrize("argv, line", [
    (["-m", "closedloop", "config", "--preset", "table1"], "closedloop: interrupted\n"),
    (["-m", "modalinfo", "info", "nonesuch.npz"], "modalinfo: interrupted\n"),
    (["-m", "paper_figures", "--only", "1", "--out", "pf"],
     "python -m paper_figures: interrupted\n"),
])
def test_ctrl_c_while_the_package_imports_is_one_line_and_130(tmp_path, argv, line):
    # x01 (round 3's x06): `closedloop/__init__.py` imported NumPy, SciPy and numba
    # before `__main__` could catch anything: a KeyboardInterrupt traceback
    done = ctrl_c_while_importing(tmp_path, argv)
    assert (done.returncode, done.stderr) == (130, line)
    assert not (tmp_path / "pf").exists()


def test_the_console_script_answers_ctrl_c_while_importing_too(tmp_path):
    # the `closedloop` console script (pip's wrapper: `from closedloop.cli import main`)
    (tmp_path / "closedloop").write_text(
        "import sys\nfrom closedloop.cli import main\nsys.exit(main())\n")
    done = ctrl_c_while_importing(tmp_path, [str(tmp_path / "closedloop"), "config"])
    assert (done.returncode, done.stderr) == (130, "closedloop: interrupted\n")


def test_imported_as_a_library_ctrl_c_stays_the_callers(tmp_path):
    # `import closedloop` in a user's script: the KeyboardInterrupt is not swallowed
    done = ctrl_c_while_importing(tmp_path, ["-c", "import closedloop; print('imported')"])
    assert done.returncode != 0 and "KeyboardInterrupt" in done.stderr
    assert "imported" not in done.stdout


@pytest.mark.parametrize("n", [451, 10**6])
def test_est_variant_beyond_ten_times_the_design_is_refused(n):
    # a05: est_mcao_variant(10**6) raised numpy's MemoryError (a 116 TiB actuator mask)
    from closedloop import presets

    with pytest.raises(ValueError, match=r"`ground_subapertures` must be <= 450"):
        presets.est_mcao_variant(n)


def test_an_unknown_key_of_an_actuator_dm_lists_the_kinds_options_too(tmp_path):
    # k33: `dms[0].pitch` on dkist-scao listed "altitude, diameter, kind, n_modes" as the
    # allowed keys, as if n_actuators, coupling and threshold (the preset's own) were not
    import json

    from closedloop import presets
    from closedloop.config import load_config, save_config

    path = save_config(presets.get("dkist-scao"), tmp_path / "dk.json") or tmp_path / "dk.json"
    data = json.loads(path.read_text())
    data["dms"][0]["pitch"] = 0.1
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=r"unknown key `dms\[0\]\.pitch` in the config; allowed "
                                         r"keys there: altitude, coupling, diameter, kind, "
                                         r"n_actuators, n_modes, threshold\."):
        load_config(path)
    # a Zernike DM's table has no such options: the list stays its own
    data["dms"][0] = {"altitude": 0.0, "n_modes": 20, "coupling": 0.3}
    path.write_text(json.dumps(data))
    with pytest.raises(ValueError, match=r"allowed keys there: altitude, diameter, kind, "
                                         r"n_modes\."):
        load_config(path)
