r"""The note of removed staging names its folder in the shown form (review30, round 30 S10).

Fixes 47-b quoted ``clean_staging``'s folder through ``quoted`` (``ls -b``'s form: a
backslash written ``\\``); test_staging_left12.py's folders hold no backslash, so a
planted ``'{folder}'`` passed. Reference: the ``ls -b`` form written by hand and a dead
pid (a child exited and reaped, as test_staging_left12.py's fixture).
"""

from __future__ import annotations

import subprocess
import sys

import pytest

from modalinfo.common.folders import clean_staging, pid_alive


def test_removed_staging_names_a_backslash_folder_shown(tmp_path, capsys):
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    if pid_alive(child.pid):
        pytest.skip("the pid was reused at once")
    folder = tmp_path / "d\\e"
    folder.mkdir()
    dead = folder / f".out.partial-{child.pid}-k3j_x9ab"
    dead.mkdir()
    assert clean_staging(folder, ".out.partial-", command="prog") == [dead.name]
    (line,) = capsys.readouterr().err.splitlines()
    assert line == (f"prog: removed 1 staging item(s) of runs that ended without cleaning "
                    f"up (killed) in '{tmp_path}/d\\\\e': {dead.name}")
