"""How much memory the machine has: the readings every guard rail refuses work against.

Part of the ground floor (:mod:`modalinfo.common`): closedloop's run estimate, the
command line's memory refusals, the estimators' work-array checks and the Dask
cluster's worker limits read memory here, once.
"""

from __future__ import annotations

import math
import os

__all__ = ["BLAS_BUFFER_BYTES", "address_space_left_bytes", "available_memory_bytes",
           "blas_buffers_bytes", "data_left_bytes",
           "data_limit_bytes", "free_memory_bytes", "machine_memory_bytes",
           "memory_limits_text", "usable_memory_bytes"]


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
    may still map (:func:`address_space_left_bytes`) and by the data-segment limit's
    room (:func:`data_left_bytes`); ``inf`` where none is known.
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
    return min(free, address_space_left_bytes(), data_left_bytes())


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
    return _soft_limit("RLIMIT_AS")


def address_space_left_bytes() -> float:
    """Address space this process may still map [bytes]: ``RLIMIT_AS`` less ``VmSize``.

    ``inf`` without a limit (or where unknown). A memory-mapped file counts here whole
    (``ulimit -v``, a batch system's cap), though its pages are not memory use.
    """
    soft = address_space_limit_bytes()
    if not math.isfinite(soft):
        return math.inf
    return max(0.0, soft - _status_bytes("VmSize"))


def usable_memory_bytes() -> float:
    """Bytes this process may still allocate [bytes], the smaller of two sides.

    The machine's (:func:`available_memory_bytes`) and the process limits': the
    address space's (:func:`address_space_left_bytes`, memory-mapped files included)
    and the data segment's (:func:`data_left_bytes`, ``ulimit -d``).

    What a refusal before work compares its estimate with (the command lines' memory
    checks, the AOT reader and ``closedloop``'s AOT export).
    """
    return min(available_memory_bytes(), address_space_left_bytes(), data_left_bytes())


def _soft_limit(name: str) -> float:
    """Return the soft value of ``resource.<name>`` [bytes]; ``inf`` without one or unknown."""
    try:
        import resource

        soft, _ = resource.getrlimit(getattr(resource, name))
    except (ImportError, AttributeError, OSError, ValueError):  # not on this platform
        return math.inf
    if soft == resource.RLIM_INFINITY or soft <= 0:
        return math.inf
    return float(soft)


def _status_bytes(key: str) -> float:
    """Return a ``kB`` line of ``/proc/self/status`` (``VmSize``, ``VmData``) [bytes], 0 unknown."""
    try:
        with open("/proc/self/status", encoding="ascii") as fh:
            for line in fh:
                if line.startswith(key + ":"):
                    return float(line.split()[1]) * 1024.0
    except (OSError, ValueError, IndexError):
        pass
    return 0.0


def data_limit_bytes() -> float:
    """Return the data-segment limit of this process [bytes]: ``RLIMIT_DATA``'s soft value.

    ``inf`` without a limit. Set by ``ulimit -d`` or a batch system; on Linux (4.7 on) it
    caps the heap and every private writable mapping, so NumPy's large arrays too: under
    ``ulimit -d 3000000`` (2.9 GiB) ``closedloop run --preset est-mcao`` (estimate 6.36
    GiB) passed the address-space check, built for 18 s of CPU and then ran out of
    memory, and ``modalinfo info`` of a 430 kB log said "use a smaller log"
    (adversarial round 50 PART b, R03, R05).
    """
    return _soft_limit("RLIMIT_DATA")


def data_left_bytes() -> float:
    """Room left under ``RLIMIT_DATA`` [bytes]: the limit less ``VmData``; ``inf`` without one.

    ``VmData`` is the figure Linux checks the limit against (the heap and the private
    writable mappings); read-only file mappings (a memory-mapped log) do not count.
    """
    soft = data_limit_bytes()
    if not math.isfinite(soft):
        return math.inf
    return max(0.0, soft - _status_bytes("VmData"))


def memory_limits_text() -> str:
    """Name the process memory limits set, with their values; ``""`` when none is.

    ``"the address-space limit (ulimit -v, RLIMIT_AS) is 1.00 GiB"``, the data-segment
    limit (``ulimit -d``) likewise, joined by "and": what an out-of-memory line says
    besides "use a smaller log".
    """
    from modalinfo.common.sizes import format_size

    parts = []
    for label, limit in (("address-space limit (ulimit -v, RLIMIT_AS)",
                          address_space_limit_bytes()),
                         ("data-segment limit (ulimit -d, RLIMIT_DATA)", data_limit_bytes())):
        if math.isfinite(limit):
            parts.append(f"the {label} is {format_size(limit)}")
    return " and ".join(parts)


#: Address space OpenBLAS maps on its first level-3 call (a matrix product of 128 x 128
#: or more), once per library: 32.2-32.7 MiB of ``VmSize`` measured (OpenBLAS 0.3.31,
#: numpy's scipy-openblas64 and SciPy's own copy, each its own buffer; round 50 PART b,
#: fix50-d). Not memory used (its pages are touched as needed), but counted by
#: ``ulimit -v`` and ``ulimit -d``.
BLAS_BUFFER_BYTES = 32 * 2**20 + 2**19


def blas_buffers_bytes() -> float:
    """Address space the BLAS libraries may still map [bytes]: numpy's and SciPy's buffers.

    What an estimate of arrays leaves out under an address-space or data limit: a
    ``convert`` admitted with 14 MiB to spare died in OpenBLAS ("Memory allocation
    still failed after 10 retries", exit 1) at its first matrix product. Counted
    whether or not the buffers are mapped already (no portable way to tell): the
    refusals under such a limit err by at most this much on the safe side.
    """
    return 2.0 * BLAS_BUFFER_BYTES

