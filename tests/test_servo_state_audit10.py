"""A LoopBandwidth with an undefined (NaN) bandwidth equals its pickle (audit 10-state).

Reference: round trips and Python's hash contract. ``closed_loop_bandwidth`` reports NaN
where a curve never crosses its level below Nyquist; ``hash(nan)`` and ``nan == nan``
follow the object's identity, so the pickled record compared unequal before the fix.
"""

import math
import pickle

from modalinfo.servo import LoopBandwidth


def test_nan_bandwidth_round_trip():
    b = LoopBandwidth(rejection_0db=math.nan, closed_loop_3db=120.0,
                      max_amplification=math.nan)
    q = pickle.loads(pickle.dumps(b))
    assert b == q and hash(b) == hash(q)
    assert b != LoopBandwidth(rejection_0db=math.nan, closed_loop_3db=121.0,
                              max_amplification=math.nan)
