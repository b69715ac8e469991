"""How much memory the machine has: the readings every guard rail refuses work against.

Part of the ground floor (:mod:`modalinfo.common`): closedloop's run estimate, the
command line's memory refusals, the estimators' work-array checks and the Dask
cluster's worker limits read memory here, once.
"""

from __future__ import annotations

import math
import os

__all__ = ["address_space_left_bytes", "available_memory_bytes", "free_memory_bytes",
           "machine_memory_bytes", "usable_memory_bytes"]


def available_memory_bytes() -> float:
    """Memory the machine has available [bytes]: ``MemAvailable`` of ``/proc/meminfo``.

    Free pages plus the page cache the kernel can drop; falls back to
    :func:`free_memory_bytes` where ``/proc/meminfo`` is missing or unreadable. The one
    reading behind closedloop's run estimate and the command line's memory refusals.
    """
    try:
        with open("/proc/meminfo", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("MemAvailable:"):
                    return float(line.split()[1]) * 1024.0
    except (OSError, ValueError, IndexError):
        pass
    return free_memory_bytes()


def free_memory_bytes() -> float:
    """Memory this process may use now [bytes]: free pages capped by its address space.

    The free physical pages (``os.sysconf``), capped by the address space the process
    may still map (:func:`address_space_left_bytes`); ``inf`` where neither is known.
    The measure the library's guard rails refuse work against before they allocate
    (closedloop's run estimate reads ``MemAvailable`` instead, a larger figure that
    counts reclaimable caches). The cap: under
    ``ulimit -v`` or ``resource.setrlimit(RLIMIT_AS)`` of 2 GB, ``Pupil(8000)`` (2.9
    GiB of grids), a theoretical K-L basis of 12,000 modes and the bootstrap indices of
    ``mutual_information_ci`` at n = 1e6 passed the free pages (12 GiB) and raised
    numpy's ``MemoryError`` (adversarial round 27 PART a).
    """
    try:
        free = float(os.sysconf("SC_AVPHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # not available on this platform
        free = math.inf
    return min(free, address_space_left_bytes())


def machine_memory_bytes() -> float:
    """Physical memory of this machine [bytes] (``os.sysconf``); ``inf`` where unknown.

    What a fractional Dask ``memory_limit`` is a fraction of.
    """
    try:
        return float(os.sysconf("SC_PHYS_PAGES") * os.sysconf("SC_PAGE_SIZE"))
    except (ValueError, OSError, AttributeError):  # pragma: no cover - exotic platforms
        return float("inf")


def address_space_limit_bytes() -> float:
    """Return the address-space limit of this process [bytes]: ``RLIMIT_AS``'s soft value.

    ``inf`` without a limit (or where unknown). Set by ``ulimit -v`` or a batch system,
    inherited by the processes it starts (a local Dask cluster's workers).
    """
    try:
        import resource

        soft, _ = resource.getrlimit(resource.RLIMIT_AS)
    except (ImportError, OSError, ValueError):  # not on this platform
        return math.inf
    if soft == resource.RLIM_INFINITY or soft <= 0:
        return math.inf
    return float(soft)


def address_space_left_bytes() -> float:
    """Address space this process may still map [bytes]: ``RLIMIT_AS`` less ``VmSize``.

    ``inf`` without a limit (or where unknown). A memory-mapped file counts here whole
    (``ulimit -v``, a batch system's cap), though its pages are not memory use.
    """
    soft = address_space_limit_bytes()
    if not math.isfinite(soft):
        return math.inf
    size = 0.0
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith("VmSize:"):
                    size = float(line.split()[1]) * 1024.0
    except (OSError, ValueError, IndexError):
        pass
    return max(0.0, float(soft) - size)


def usable_memory_bytes() -> float:
    """Bytes this process may still allocate [bytes], the smaller of two sides.

    The machine's (:func:`available_memory_bytes`) and the address-space limit's
    (:func:`address_space_left_bytes`, memory-mapped files included).

    What a refusal before work compares its estimate with (the command lines' memory
    checks, the AOT reader and ``closedloop``'s AOT export).
    """
    return min(available_memory_bytes(), address_space_left_bytes())
