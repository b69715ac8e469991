"""The address space left must hold the parts AND the allocator's slack (review27).

Planted bug of review27 (docs/MUTATION.md, round 27) that the round-42 file let through:
``ADDRESS_SPACE_SLACK`` dropped from the comparison (its cases were half the parts,
refused either way, and the parts + slack + 1 MiB, accepted either way). Reference: the
measurement the constant records (round 42 PART b, S17: kaos, 15 MiB of parts, ran out
of memory in its set-up with 17 MiB of ``ulimit -v`` left, and ran with 28), i.e. room
for the parts alone is not enough; the space left is the test's (``monkeypatch``).
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


def test_room_for_the_parts_but_not_the_slack_is_refused(monkeypatch):
    config = presets.kaos()
    need = estimate(config, 0.01).peak_bytes
    parts = need - BASELINE_BYTES
    left = parts + ADDRESS_SPACE_SLACK / 2  # S17: 17 MiB left for 15 MiB of parts failed
    monkeypatch.setattr("modalinfo.common.memory.address_space_limit_bytes",
                        lambda: 10 * need)
    monkeypatch.setattr("modalinfo.common.memory.address_space_left_bytes", lambda: left)
    with pytest.raises(ResourceError, match=r"for the allocator"):
        check_resources(config, 0.01, limit=10 * need)
