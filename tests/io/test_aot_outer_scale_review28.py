"""An AOT file's ``LAYERS_L0`` read only where the docstring promises (review28, round 28).

``modalinfo.io.aot._atmosphere_outer_scale`` promises: the FIRST atmosphere's layers;
nothing without positive outer scales; nothing for Cn2 weights that are not weights
(negative). Planted bugs R28-A1 (a zero outer scale read as one), R28-A2 (a negative
weight accepted), R28-A3 (the last atmosphere read) escaped ``test_aot_outer_scale.py``.
References: the ``LAYERS_L0`` / ``LAYERS_WEIGHT`` images written with ``aotpy`` alone
(``_write`` of ``test_aot_outer_scale.py``, a second atmosphere added here) and the
reader's docstring.
"""

from __future__ import annotations

import numpy as np
import pytest

aotpy = pytest.importorskip("aotpy")

from modalinfo.io import load  # noqa: E402

from .test_aot_outer_scale import _write  # noqa: E402


def test_a_zero_outer_scale_is_not_recorded(tmp_path):
    """R28-A1: 0 m is no outer scale (the rule: positive rows only)."""
    log = load(_write(tmp_path / "z.fits", [0.0, 0.0]))
    assert "outer_scale" not in log.metadata
    assert "atmosphere_layers" not in log.metadata


def test_a_negative_cn2_weight_is_not_recorded(tmp_path):
    """R28-A2: weights (-0.5, 1.5) sum to 1 but are no Cn2 profile."""
    log = load(_write(tmp_path / "n.fits", [20.0, 50.0], weights=(-0.5, 1.5)))
    assert "atmosphere_layers" not in log.metadata
    assert "outer_scale" not in log.metadata


def test_the_first_atmosphere_is_read(tmp_path, monkeypatch):
    """R28-A3: of two atmospheres (20 m, then 50 m), the first one's outer scale."""
    second = aotpy.AtmosphericParameters(
        uid="ATM2", wavelength=5e-7, r0=[0.1],
        layers_relative_weight=aotpy.Image("w2", np.array([[0.7, 0.3]])),
        layers_l0=aotpy.Image("l02", np.array([[50.0, 50.0]]), unit="m"))
    system = aotpy.AOSystem

    def two_atmospheres(**kwargs):  # the helper's system, a second atmosphere after its own
        kwargs["atmosphere_params"] = [*kwargs["atmosphere_params"], second]
        return system(**kwargs)

    monkeypatch.setattr(aotpy, "AOSystem", two_atmospheres)
    path = _write(tmp_path / "f.fits", [20.0, 20.0])
    monkeypatch.undo()  # the reader's own AOSystem
    log = load(path)
    assert log.metadata["outer_scale"] == 20.0
