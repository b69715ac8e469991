"""ModalLog subclasses, older pickles and numpy-integer seeds (adversarial round 23 PART a).

Reference: round trips. A log copied by ``pickle`` or ``copy.deepcopy``, or sliced, must
hold the same coefficients, rate and modes as the original (``numpy.array_equal`` on the
values the caller passed); a subclass's own attributes must survive the round trip; a
pickle of the layout Python writes for a ``__slots__`` class without ``__getstate__``
(``(None, {slot: value})``, what ModalLog pickles were before 2026-11-22) must load. A
seed given as ``numpy.int64`` must draw the same numbers as the same ``int`` (the
generator is seeded by value) and be recorded as that int in the metadata.
"""

from __future__ import annotations

import copy
import pickle

import numpy as np
import pytest

from modalinfo.telemetry import ModalLog
from modalinfo.telemetry.synthetic import Layer, closed_loop_log, kaos_like, open_loop_log

COEFFS = np.arange(40.0).reshape(20, 2)


class SlottedLog(ModalLog):
    __slots__ = ("site",)


class PlainLog(ModalLog):
    pass


@pytest.mark.parametrize("cls", [SlottedLog, PlainLog])
def test_subclass_pickle_and_deepcopy_keep_values_and_attributes(cls):
    log = cls(COEFFS, rate=100.0, modes=[2, 3])
    log.site = "La Palma"
    for other in (pickle.loads(pickle.dumps(log)), copy.deepcopy(log)):
        assert type(other) is cls
        assert np.array_equal(other.coeffs, COEFFS)
        assert other.rate == 100.0 and list(other.modes) == [2, 3]
        assert other.site == "La Palma"


def test_subclass_slices_and_selects():
    log = SlottedLog(COEFFS, rate=100.0, modes=[2, 3])
    assert np.array_equal(log[5:10].coeffs, COEFFS[5:10])
    assert np.array_equal(log.select(modes=[3]).coeffs, COEFFS[:, 1:])


def test_pickle_without_getstate_layout_loads():
    log = ModalLog(COEFFS, rate=100.0, modes=[2, 3])
    old = (None, {name: getattr(log, name) for name in ModalLog.__slots__})
    back = ModalLog.__new__(ModalLog)
    back.__setstate__(old)
    assert back == log


def test_numpy_integer_seed_is_the_int_seed():
    layer = Layer(r0=0.15, wind_speed=10.0)
    kw = dict(n_frames=64, rate=1000.0, diameter=8.0, layers=layer)
    a = open_loop_log([2, 3], seed=np.int64(3), **kw)
    b = open_loop_log([2, 3], seed=3, **kw)
    assert np.array_equal(a.coeffs, b.coeffs)
    assert a.metadata["seed"] == 3
    k = kaos_like(200, seed=np.int32(1))
    assert np.array_equal(k.coeffs, kaos_like(200, seed=1).coeffs) and k.metadata["seed"] == 1
    c = closed_loop_log(b, gain=0.3, noise_rms=0.1, seed=np.uint8(2))
    assert np.array_equal(c.coeffs, closed_loop_log(b, gain=0.3, noise_rms=0.1, seed=2).coeffs)
