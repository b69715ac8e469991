"""Round 12 PART b's refusals at their edges (review12, round 12).

References (outside the code): POSIX errno values (``ENOMEM``: the kernel could not
allocate memory, whatever the C library's message says in the user's locale;
``ENOSPC``: the disk is full, not memory) and the paths each test writes (a log two
folders deep inside ``--out`` is inside the output directory as much as one directly
in it).
"""

from __future__ import annotations

import errno

import pytest

from modalinfo.batch.manifest import collect_logs
from modalinfo.common.startup import memory_refusal

from .conftest import write_small_log


def test_a_log_nested_inside_the_output_is_refused(tmp_path):
    out = tmp_path / "out"
    (out / "rows" / "old").mkdir(parents=True)
    inside = write_small_log(out / "rows" / "old" / "extra.npz", 50)
    outside = write_small_log(tmp_path / "c.npz", 50)
    with pytest.raises(ValueError, match="inside the output directory"):
        collect_logs([str(inside), str(outside)], exclude=[out])
    manifest = tmp_path / "m.csv"
    manifest.write_text(f"path\n{inside}\n{outside}\n")
    with pytest.raises(ValueError, match="inside the output directory"):
        collect_logs([str(manifest)], exclude=[out])


def test_memory_is_told_by_errno_not_by_the_message(capsys):
    # a French libc: "Impossible d'allouer de la memoire"
    assert memory_refusal("modalinfo", OSError(errno.ENOMEM, "Impossible d'allouer")) == 2
    assert capsys.readouterr().err.count("\n") == 1
    with pytest.raises(OSError, match="No space left"):
        memory_refusal("modalinfo", OSError(errno.ENOSPC, "No space left on device"))
