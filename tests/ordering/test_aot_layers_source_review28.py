"""The AOT reader's ``atmosphere_layers`` beside a config without layers (review28, round 28).

``compare._layers_source``: "the closedloop config, else the AOT reader's
``atmosphere_layers``": a config dict that has no ``layers`` (a file's other settings)
must not hide the AOT layers. Planted bug R28-O1 (any config dict taken) escaped
``tests/io/test_aot_outer_scale.py``, whose logs carry no config. Reference: the
Cn2-weighted mean of the outer scales written here, by hand: (0.7 * 20 + 0.3 * 50) / 1
= 29 m.
"""

import numpy as np

from modalinfo.ordering.compare import kl_geometry_assumption
from modalinfo.telemetry import ModalLog


def test_layers_read_beside_a_config_without_layers():
    layers = [{"outer_scale": 20.0, "cn2_weight": 0.7}, {"outer_scale": 50.0, "cn2_weight": 0.3}]
    log = ModalLog(np.random.default_rng(0).standard_normal((50, 5)), rate=1000.0,
                   modes=list(range(2, 7)), units="rad",
                   metadata={"config": {"seed": 1}, "atmosphere_layers": layers})
    note = kl_geometry_assumption(log)
    mean = (0.7 * 20.0 + 0.3 * 50.0) / (0.7 + 0.3)
    assert note is not None and "20, 50 m" in note and f"{mean:.4g} m" in note
