"""Output folders for every command: the checks before any work, and the lock.

Part of the ground floor (:mod:`modalinfo.common`). ``modalinfo batch``, ``closedloop
sweep``, ``closedloop run --out`` and ``python -m paper_figures`` refuse an output the
same way, with the same words:

- :func:`check_room`: a folder this process can write in (a real test write) with a
  given number of bytes free;
- :func:`check_out_dir`: an output *folder* (new or existing) before any work, with
  :data:`MIN_FREE_BYTES` free;
- :func:`make_out_dir`: create it, refusing in one line (and leaving nothing) a folder
  the umask leaves this process unable to write in;
- :class:`OutputLock` and :func:`locked_out_dir`: one run per output folder;
- :func:`staging_prefix` and :func:`clean_staging`: the staging folders and temporary
  files a run killed outright (SIGKILL, power loss) leaves, removed by a later run once
  they provably belong to no live run, or named with the command that removes them.
"""

from __future__ import annotations

import contextlib
import json
import os
import socket
import time
from collections.abc import Iterator, Sequence
from pathlib import Path
from typing import Any

# the staging rules live with atomic_write, whose temporary files they clean too
from modalinfo.common.files import (  # noqa: F401 - re-exported names
    _umask,
    clean_staging,
    pid_alive,
    quoted,
    staging_prefix,
    writable_free_bytes,
)
from modalinfo.common.sizes import format_size

__all__ = [
    "MIN_FREE_BYTES",
    "OutputError",
    "OutputInUseError",
    "OutputLock",
    "check_out_dir",
    "check_room",
    "clean_staging",
    "pid_alive",
    "locked_out_dir",
    "make_out_dir",
    "staging_prefix",
]

#: Free space an output folder must have before a batch, a sweep or the paper's figures
#: start [bytes]: rows (~1 kB each), tables and plots of a large archive, or the figures
#: (PNG and PDF), JSON evaluations and reports (~10 MB), fit many times over.
MIN_FREE_BYTES = 64 * 2**20


class OutputError(ValueError):
    """An output location that cannot take a run's files (checked before any work)."""


class OutputInUseError(OutputError):
    """The output folder is locked by another running batch, sweep or figure run."""


def check_room(folder: Path, need_bytes: float, what: str) -> None:
    """Refuse a ``folder`` this process cannot write in, or with less than ``need_bytes`` free.

    Parameters
    ----------
    folder : pathlib.Path
        An existing folder.
    need_bytes : float
        Free space required [bytes].
    what : str
        What is written, starting the message (``"--out 'run.h5'"``).

    Raises
    ------
    OutputError
        Naming ``what``, the folder and the rule (sizes in binary units).
    """
    try:
        free = writable_free_bytes(folder)
    except OSError as exc:
        raise OutputError(f"{what}: cannot write in {quoted(folder)} "
                          f"({exc.strerror or exc})") from None
    if free < need_bytes:
        raise OutputError(f"{what}: about {format_size(need_bytes)} is needed, {quoted(folder)} "
                          f"has {format_size(free)} free")


def _existing_ancestor(path: Path) -> Path:
    path = Path(os.path.abspath(path))
    while not path.exists() and path != path.parent:
        path = path.parent
    return path


def check_out_dir(out_dir: Path, flag: str = "output directory", *,
                  parents: bool = False) -> Path:
    """Check an output folder before any work; return the existing folder that will hold it.

    Parameters
    ----------
    out_dir : pathlib.Path
        The output folder; it may not exist yet.
    flag : str
        The option named in the message (``"--out"``).
    parents : bool
        Whether missing parents are created too (then the nearest existing ancestor is
        checked); otherwise the parent of a new ``out_dir`` must exist.

    Returns
    -------
    pathlib.Path
        ``out_dir`` when it exists, else the existing folder it will be created in.

    Raises
    ------
    OutputError
        ``out_dir`` or the folder to hold it is not a folder (or is missing), cannot be
        written in, or has less than :data:`MIN_FREE_BYTES` free.
    """
    out_dir = Path(out_dir)
    try:
        out_dir.stat()
    except (FileNotFoundError, NotADirectoryError):
        pass  # a new folder, or a file on the way: the checks below say which
    except OSError as exc:
        # a name too long, a symlink loop: no folder can be made there (audit 10-env:
        # paper_figures reported ENAMETOOLONG as a failure, exit 1, not a refusal)
        raise OutputError(f"{flag} {quoted(out_dir)}: {exc.strerror or exc}") from None
    if out_dir.exists() and not out_dir.is_dir():
        raise OutputError(f"{flag} {quoted(out_dir)} exists and is not a directory")
    if out_dir.is_dir():
        base = out_dir
    else:
        base = _existing_ancestor(out_dir) if parents else out_dir.parent
    if not base.is_dir():
        what = "is not a directory" if base.exists() else "does not exist"
        raise OutputError(f"{flag} {quoted(out_dir)}: {quoted(base)} {what}")
    check_room(base, MIN_FREE_BYTES, f"{flag} {quoted(out_dir)}")
    return base


def _remove_new(created: Sequence[Path]) -> None:
    """Remove folders this process created (innermost first), if still empty.

    A folder made under umask 777 is mode 000, and its parent (made too) lets nobody
    unlink in it: each is given back its owner's rights first.
    """
    for folder in created:
        with contextlib.suppress(OSError):
            folder.chmod(0o700)
    remove_empty(created)


def remove_empty(created: Sequence[Path]) -> None:
    """Remove folders this process created, innermost first, only those left empty.

    A rollback's last step: another process may have written into a folder made here
    meanwhile (two ``forecast --out`` runs into one new folder, round 44 PART b, d08),
    and its files stay with their folder. Rights are not touched (:func:`_remove_new`
    does that for a folder this process could never write in).
    """
    for folder in created:
        with contextlib.suppress(OSError):
            folder.rmdir()


def make_out_dir(out_dir: Path, flag: str = "--out", *, parents: bool = True) -> list[Path]:
    """Create an output folder and make sure this process can write in it.

    Parameters
    ----------
    out_dir : pathlib.Path
        The folder; it may exist.
    flag : str
        The option starting the message (``"--out"``).
    parents : bool
        Create missing parents too (else the parent must exist).

    Returns
    -------
    list of pathlib.Path
        The folders created here, innermost first (empty if ``out_dir`` existed).

    Raises
    ------
    OutputError
        The new folder cannot be written in (a real test write): under ``umask 777`` a
        process without root's capabilities got "[Errno 13] Permission denied" on a
        temporary name and ``forecast`` left the empty mode-000 folder behind
        (adversarial round 18 PART b, H14 / H15). The folders created here are removed
        again, and the message names the umask and the remedy.
    """
    out_dir = Path(out_dir)
    created = []
    missing = Path(os.path.abspath(out_dir))
    while not missing.exists():
        created.append(missing)
        missing = missing.parent
    try:
        out_dir.mkdir(parents=parents, exist_ok=True)
        writable_free_bytes(out_dir)
    except OSError as exc:
        # os.path.exists: False, not EACCES, for a folder inside a mode-000 one
        made = [f for f in created if os.path.exists(f)]  # outermost last
        _remove_new(created)
        if isinstance(exc, PermissionError) and made:
            mask = _umask()
            shown = out_dir if made[-1] == created[0] else made[-1]  # as the user typed it
            with contextlib.suppress(ValueError):  # a parent of --out: relative, if inside
                relative = os.path.relpath(shown)
                shown = shown if relative.startswith("..") else relative
            raise OutputError(
                f"{flag}: cannot write into {quoted(shown)} it just created: the umask "
                f"{mask:03o} leaves it mode {0o777 & ~mask:03o}, no permission for its "
                "owner; set umask 022 (or 077 for private files) and run again") from None
        raise OutputError(f"{flag} {quoted(out_dir)}: cannot "
                          f"{'write in' if out_dir.is_dir() else 'create'} it "
                          f"({exc.strerror or exc})") from None
    return created


class OutputLock:
    """Exclusive use of an output folder by one batch, sweep or figure run (a context manager).

    The lock is the file ``<out>/.lock`` holding JSON ``{"pid", "host", "started",
    "command"}``; it is created complete or not at all (written to a temporary file,
    then hard-linked to its name, which fails if the name exists), so two runs
    starting together cannot both hold it. A lock whose holder is a dead process on
    this host is stale and taken over; a lock held by a live process, or by a
    process on another host (which cannot be checked from here), raises
    :class:`OutputInUseError` naming the holder and the file to remove if that run is
    known to be over.

    Parameters
    ----------
    out_dir : str or os.PathLike
        An existing directory.
    command : str
        What holds the lock (``"modalinfo batch"``), recorded in the file.
    """

    NAME = ".lock"

    def __init__(self, out_dir: str | os.PathLike, command: str = "modalinfo batch") -> None:
        self.path = Path(out_dir) / self.NAME
        self.command = command
        self.held = False

    def _holder(self) -> dict | None:
        """Return the lock file's content; None when absent; {} when unreadable."""
        try:
            text = self.path.read_text(encoding="utf-8")
        except FileNotFoundError:
            return None
        except OSError:
            return {}
        try:
            data = json.loads(text)
        except ValueError:
            return {}
        return data if isinstance(data, dict) else {}

    def _stale(self, holder: dict) -> bool:
        pid = holder.get("pid")
        if holder.get("host") != socket.gethostname() or not isinstance(pid, int):
            return False
        if pid == os.getpid():
            return False
        if not pid_alive(pid):
            return True
        # a live process with the holder's pid that started after the lock was written
        # is another process that reused the pid (pid 1 was refused as "in use by
        # modalinfo batch (pid 1)": adversarial round 15 PART b, F10)
        started, began = holder.get("started"), _process_start_time(pid)
        return (isinstance(started, (int, float)) and began is not None
                and began > started + _START_SLACK)

    def acquire(self) -> OutputLock:
        """Take the lock (taking over a stale one); raise OutputInUseError if held."""
        from modalinfo.common.tasks.keys import canonical_json

        info = canonical_json({"pid": os.getpid(), "host": socket.gethostname(),
                               "started": time.time(), "command": self.command})
        tmp = self.path.with_name(f".lock.{os.getpid()}.{time.monotonic_ns()}.tmp")
        try:
            # written inside the try: a failed write (`ulimit -f 0`: EFBIG) left the empty
            # `.lock.<pid>.<ns>.tmp`, and with it paper_figures' new folder "as it was"
            # (adversarial round 50 PART b, R90)
            tmp.write_text(info, encoding="utf-8")
            for _ in range(3):  # a stale lock removed by us (or another taker) in between
                try:
                    os.link(tmp, self.path)
                    self.held = True
                    return self
                except FileExistsError:
                    pass
                holder = self._holder()
                if holder is None:
                    continue  # released between our link and our read: try again
                if not self._stale(holder):
                    who = (f"{holder.get('command', 'a run')} (pid {holder.get('pid')} on "
                           f"{holder.get('host')})" if holder else "another run")
                    raise OutputInUseError(
                        f"output directory {quoted(self.path.parent)} is in use by {who}; "
                        f"wait for it to finish, or remove {quoted(self.path)} if it is no "
                        "longer running")
                # stale: remove it only if it is still the same dead holder's file
                with contextlib.suppress(FileNotFoundError):
                    if self._holder() == holder:
                        self.path.unlink()
            raise OutputInUseError(f"output directory {quoted(self.path.parent)}: could not take "
                                   f"the lock {quoted(self.path)} (others keep taking it)")
        finally:
            with contextlib.suppress(OSError):
                tmp.unlink()

    def release(self) -> None:
        """Remove the lock file if this process holds it."""
        if self.held:
            holder = self._holder()
            if holder and holder.get("pid") == os.getpid():
                with contextlib.suppress(FileNotFoundError):
                    self.path.unlink()
            self.held = False

    def __enter__(self) -> OutputLock:
        return self.acquire()

    def __exit__(self, *exc: Any) -> None:
        self.release()


#: Seconds of doubt between a process's start time (clock ticks since boot, rounded,
#: and the boot time in whole seconds) and the ``started`` its lock records.
_START_SLACK = 5.0


def _process_start_time(pid: int) -> float | None:
    """Return when process ``pid`` of this host started [Unix s], or None if unknown.

    From Linux's ``/proc/<pid>/stat`` (field 22, clock ticks after boot) and the boot
    time of ``/proc/stat`` (``btime``); None elsewhere or when unreadable.
    """
    try:
        with open(f"/proc/{int(pid)}/stat", encoding="ascii", errors="replace") as fh:
            fields = fh.read().rsplit(")", 1)[1].split()
        ticks = int(fields[19])  # field 22 of the line; fields[0] is field 3 (state)
        with open("/proc/stat", encoding="ascii") as fh:
            boot = next(int(line.split()[1]) for line in fh if line.startswith("btime "))
        return boot + ticks / os.sysconf("SC_CLK_TCK")
    except (OSError, ValueError, IndexError, StopIteration):
        return None


def _check_foreign(out_dir: Path, marker: str, also: Sequence[str] = ()) -> None:
    """Refuse a non-empty directory that holds no earlier run (no ``marker``, no ``also``)."""
    others = [p for p in out_dir.iterdir() if not p.name.startswith(OutputLock.NAME)]
    if others and not any((out_dir / m).is_dir() for m in (marker, *also)):
        raise OutputError(f"output directory {quoted(out_dir)} is not empty and holds no "
                          f"earlier batch or sweep (no {marker}/); choose a new or empty "
                          "directory")


@contextlib.contextmanager
def locked_out_dir(out_dir: Path, command: str, *, marker: str | None = "rows",
                   also: Sequence[str] = (), parents: bool = False,
                   flag: str | None = None) -> Iterator[Path]:
    """Create ``out_dir`` if needed, take its :class:`OutputLock`; yield ``out_dir``.

    Parameters
    ----------
    out_dir : pathlib.Path
        The output folder.
    command : str
        What holds the lock (recorded in the lock file).
    marker : str or None
        A subfolder an earlier run of the same kind leaves (``"rows"``): a non-empty
        folder without it is refused as someone else's. None: no such check.
    also : sequence of str
        Other subfolders that only a run of the same kind writes (a sweep's ``runs/``):
        a folder holding one of them is not refused either. A sweep interrupted before
        its first row leaves ``runs/`` alone (its empty ``rows/`` removed on leaving, a
        worker still saving a run), and the next sweep must resume there (Leftovers
        16-dask, sweep #11).
    parents : bool
        Create missing parents too (else the parent must exist).
    flag : str, optional
        The option starting the message of :class:`OutputInUseError` (``"--out"``).

    On leaving, the lock is released and the folders created here are removed again
    if the run left them empty (with ``marker``: holding no row), so a run that failed
    at its start leaves nothing behind; a folder holding anything else keeps its
    ``marker`` (a batch interrupted before its first row leaves ``hashes.json``), so
    the next run resumes there.
    """
    out_dir = Path(out_dir)
    created = make_out_dir(out_dir, flag or "--out", parents=parents)
    try:
        try:
            lock = OutputLock(out_dir, command).acquire()
        except OutputInUseError as exc:
            if flag is None:
                raise
            raise OutputInUseError(f"{flag} {exc}") from None
        try:
            if marker is not None:
                _check_foreign(out_dir, marker, also)
            yield out_dir
        finally:
            lock.release()
    finally:
        ours = [out_dir / m for m in (marker, *also)] if created and marker else []
        try:  # anything else left (a batch's hashes.json): the marker stays with it,
            # or the folder is refused as foreign by the next run (Leftovers 17-sigint)
            left = [p for p in out_dir.iterdir() if not p.name.startswith(OutputLock.NAME)
                    and (p not in ours or any(p.iterdir()))]
        except OSError:
            left = []
        remove_empty(([] if left else ours) + created)
