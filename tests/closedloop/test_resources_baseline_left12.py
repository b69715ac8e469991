"""The memory model's baseline at a cap (Leftovers 12-cost, item 2).

Reference: the peak resident memory of a child ``simulate`` (``ru_maxrss``, one BLAS and
numba thread) less the run's own arrays (the estimate's parts, summed here from
``estimate``): for kaos 297-311 MB with numba's cache cold (its kernels compiled) in
round 12, 398 MB in audit 11-cost (414 MB peak; docs/ADVERSARIAL.md, "Leftovers
12-cost"). The baseline lies between the two measurements, not at half of them as the
200 MB before; a cap below it is one no run fits under, refused as such.
"""

from __future__ import annotations

import pytest

from closedloop import presets
from closedloop.resources import BASELINE_BYTES, ResourceError, check_resources, estimate


def test_the_baseline_lies_between_the_measured_interpreters():
    parts = estimate(presets.get("kaos"), 0.05).peak_bytes - BASELINE_BYTES
    assert 311e6 <= BASELINE_BYTES <= 414e6 - parts


def test_a_cap_the_interpreter_alone_exceeds_is_refused_as_such():
    # 300 MB: a run of kaos (16 MB of arrays) fitted by the old 200 MB baseline
    with pytest.raises(ResourceError, match="no run fits under this limit"):
        check_resources(presets.get("kaos"), 0.05, limit=300e6)
