"""An atomic write removes its own target's dead temporaries, not another target's (review33).

``files._clean_killed_writes`` (round 50 PART b, R20) says "Only this target's names of a
pid that no process of this host has are removed". Writing ``old.csv`` removed the dead
temporary ``.old.csv.bak.<pid>-<random>.tmp`` of the target ``old.csv.bak`` too: its
prefix ``.old.csv.`` matched and the staging rule also takes ``<name>.<pid>-<random>``.
Reference: the docstring, and the names ``atomic_write`` gives its temporaries
(``.<target name>.<pid>-<random>.tmp``); a dead pid is that of a child this test started
and reaped (``subprocess``).
"""

from __future__ import annotations

import subprocess
import sys

from modalinfo.common.files import atomic_write


def _dead_pid() -> int:
    proc = subprocess.Popen([sys.executable, "-c", "pass"])
    proc.wait()
    return proc.pid


def test_another_targets_dead_temporary_is_left(tmp_path, capsys):
    dead = _dead_pid()
    own = tmp_path / f".old.csv.{dead}-ab_c12xy.tmp"
    own.write_bytes(b"half a file")
    other = tmp_path / f".old.csv.bak.{dead}-ab_c12xy.tmp"  # old.csv.bak's temporary
    other.write_bytes(b"half another file")
    atomic_write(tmp_path / "old.csv", lambda fh: fh.write(b"new\n"), overwrite=False)
    assert not own.exists()
    assert other.exists()
    err = capsys.readouterr().err
    assert own.name in err and other.name not in err
    # old.csv.bak's own write removes it
    atomic_write(tmp_path / "old.csv.bak", lambda fh: fh.write(b"bak\n"), overwrite=False)
    assert not other.exists()
