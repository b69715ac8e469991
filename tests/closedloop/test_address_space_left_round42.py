"""Round 42 PART b of issue 27 (S13, S15, S17): a run is checked against the address space LEFT.

docs/ADVERSARIAL.md, "Round 42 PART b, issue 27": under ``ulimit -v 560 MiB``
``closedloop run --preset table1`` (estimated peak 392 MiB) passed the memory check and
ended in a ``SystemError`` traceback in the mirrors' build; kaos (349 MiB) and
dkist-scao (806 MiB under 850 MiB) ran out of memory after the check. The estimate is
resident memory (``BASELINE_BYTES`` + the parts) and was compared with the whole limit,
while the process had already mapped ~570 MiB of address space before the first part.

Reference: what a run still has to allocate (its parts, the estimate less the
interpreter's baseline) cannot be mapped beyond what the limit leaves (RLIMIT_AS less
VmSize); the address space left is the one the test states (``monkeypatch`` of
``address_space_left_bytes``), not one read by the code under test.
"""

from __future__ import annotations

import pytest

from closedloop import presets
from closedloop.resources import (
    ADDRESS_SPACE_SLACK,
    BASELINE_BYTES,
    ResourceError,
    check_resources,
    estimate,
)


@pytest.mark.parametrize("refused", [True, False])
def test_parts_are_checked_against_the_space_left(monkeypatch, refused):
    config = presets.kaos()
    need = estimate(config, 0.01).peak_bytes
    parts = need - BASELINE_BYTES
    # the limit is far above the whole estimate; what is left of it holds half the
    # parts (refused), or the parts, the slack and 1 MiB more (passes)
    left = parts / 2 if refused else parts + ADDRESS_SPACE_SLACK + 2**20
    monkeypatch.setattr("modalinfo.common.memory.address_space_limit_bytes",
                        lambda: 10 * need)
    monkeypatch.setattr("modalinfo.common.memory.address_space_left_bytes", lambda: left)
    if not refused:
        assert check_resources(config, 0.01, limit=10 * need).peak_bytes == need
        return
    with pytest.raises(ResourceError, match=r"RLIMIT_AS.* leaves "):
        check_resources(config, 0.01, limit=10 * need)
