"""The ground floor's output-folder rules (``modalinfo.common.folders``), one check for all.

References: the file system itself (a file where a folder is wanted, a missing parent,
a disk reported nearly full by a replaced ``shutil.disk_usage``, the folders a run
creates and must remove again), and Dask's own size formatter
``dask.utils.format_bytes`` for the sizes the messages state (binary units).
"""

import shutil
from collections import namedtuple

import pytest

from modalinfo.common.folders import (
    MIN_FREE_BYTES,
    OutputError,
    OutputInUseError,
    OutputLock,
    check_out_dir,
    check_room,
    locked_out_dir,
)

dask_utils = pytest.importorskip("dask.utils")


def test_check_out_dir_new_existing_and_nested(tmp_path):
    assert check_out_dir(tmp_path) == tmp_path  # an existing folder holds itself
    assert check_out_dir(tmp_path / "new") == tmp_path  # a new one: its parent
    with pytest.raises(OutputError, match="does not exist"):
        check_out_dir(tmp_path / "a" / "b")  # parents are not created by default
    assert check_out_dir(tmp_path / "a" / "b", parents=True) == tmp_path


def test_check_out_dir_refuses_files(tmp_path):
    a_file = tmp_path / "f.txt"
    a_file.write_text("mine")
    with pytest.raises(OutputError, match=r"--out '.*f\.txt' exists and is not a directory"):
        check_out_dir(a_file, "--out")
    for parents in (False, True):
        with pytest.raises(OutputError, match=r"f\.txt' is not a directory"):
            check_out_dir(a_file / "sub" / "deeper" if parents else a_file / "sub",
                          parents=parents)
    assert a_file.read_text() == "mine"


def test_free_space_is_named_in_binary_units(tmp_path, monkeypatch):
    usage = namedtuple("usage", "total used free")
    free = MIN_FREE_BYTES - 1
    monkeypatch.setattr(shutil, "disk_usage", lambda _: usage(10**9, 10**9 - free, free))
    with pytest.raises(OutputError) as info:
        check_out_dir(tmp_path / "out", "--out")
    assert (f"about {dask_utils.format_bytes(MIN_FREE_BYTES)} is needed, '{tmp_path}' has "
            f"{dask_utils.format_bytes(free)} free") in str(info.value)
    check_room(tmp_path, free, "x")  # exactly what is free: accepted
    with pytest.raises(OutputError) as info:
        check_room(tmp_path, free + 1, "x")  # one byte more: refused
    assert str(info.value).startswith(f"x: about {dask_utils.format_bytes(free + 1)} is needed")


def test_locked_out_dir_removes_only_what_it_created(tmp_path):
    out = tmp_path / "a" / "b"
    with locked_out_dir(out, "test", marker=None, parents=True) as held:
        assert (held / OutputLock.NAME).is_file()
        with pytest.raises(OutputInUseError, match=r"^--out output directory .* in use by test"):
            with locked_out_dir(out, "other", marker=None, flag="--out"):
                pass
    assert not (tmp_path / "a").exists()  # both created folders removed, being empty
    with locked_out_dir(out, "test", marker=None, parents=True):
        (out / "kept.txt").write_text("result")
    assert (out / "kept.txt").is_file() and not (out / OutputLock.NAME).exists()


def test_locked_out_dir_refuses_a_foreign_folder(tmp_path):
    (tmp_path / "notes.txt").write_text("someone else's")
    with pytest.raises(OutputError, match="holds no earlier batch or sweep"):
        with locked_out_dir(tmp_path, "modalinfo batch"):
            pass
    assert not (tmp_path / OutputLock.NAME).exists()
    (tmp_path / "rows").mkdir()  # an earlier run's marker: accepted
    with locked_out_dir(tmp_path, "modalinfo batch") as held:
        assert held == tmp_path


# Audit 10-env: a name longer than NAME_MAX and a symlink loop reached paper_figures as
# OSError (exit 1, "failure while computing"); no folder can be made there, so it is a
# refusal before any work. Reference: POSIX errno ENAMETOOLONG / ELOOP from stat(2).
def test_out_dir_too_long_or_looping_is_refused(tmp_path):
    from modalinfo.common.folders import OutputError, check_out_dir

    with pytest.raises(OutputError, match="--out .*(too long|symbolic links)"):
        check_out_dir(tmp_path / ("x" * 300), "--out")
    (tmp_path / "a").symlink_to(tmp_path / "b")
    (tmp_path / "b").symlink_to(tmp_path / "a")
    with pytest.raises(OutputError, match="--out .*symbolic links"):
        check_out_dir(tmp_path / "a", "--out", parents=True)
