"""Review 21: ``free_memory_bytes`` is capped by the address space left under RLIMIT_AS.

Reference: the operating system. A child process sets its ``RLIMIT_AS`` to its own
``VmSize`` (read from ``/proc/self/status`` by the test's code) plus 1 GiB; the address
space it may still map is then at most 1 GiB (its ``VmSize`` only grows), whatever the
machine's free pages, and more than 0.5 GiB (the child allocates nothing large between
the two reads).
"""

import subprocess
import sys

import pytest

from .._limits import capped_child

resource = pytest.importorskip("resource")

CHILD = capped_child(setup="from modalinfo.common.memory import free_memory_bytes",
                     headroom=2**30, body="print(free_memory_bytes())")


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc/self/status")
def test_free_memory_is_the_address_space_left_under_a_limit():
    out = subprocess.run([sys.executable, "-c", CHILD], capture_output=True, text=True,
                         timeout=120, check=True).stdout
    free = float(out)
    assert 2**29 < free <= 2**30
