"""The time estimate's science pass: its cost per field direction scales with the pupil's pixels.

Reference: the pupil the science kernel visits, counted on the simulator's own grid
(``Geometry(config).disc_and_hole()[0].sum()``, the disc of ``n_pixels`` samples;
table1 has no obscuration), against the increment of the estimate's
``seconds_per_frame`` when only ``field.n_points`` changes: the work model in
``closedloop.resources`` ("time per frame = SECONDS_PER_FRAME + sum of FRAME_RATES[term]
x work") counts, per direction, every pupil pixel on every plane (the ``science``
term, ``planes x pupil pixels``), and nothing else in it depends on the number of
directions. The disc's count and ``pi N^2 / 4`` differ by 0.35 % at N = 64
(3228 and 3217); the tolerance is 2 %. A pupil area taken as ``pi N^2`` (N read as a
radius) is 4 times off.
"""

import dataclasses

import pytest

from closedloop import presets
from closedloop.optics.geometry import Geometry
from closedloop.resources import FRAME_RATES, estimate


def test_seconds_per_direction_are_the_pupil_pixels_on_every_plane():
    base = presets.get("table1")
    rows = []
    for n in (3, 5):
        config = base.replace(field=dataclasses.replace(base.field, n_points=n))
        geometry = Geometry(config)
        rows.append((n * n, estimate(config, 0.01).seconds_per_frame, len(geometry.planes),
                     int(geometry.disc_and_hole()[0].sum())))
    (n1, s1, planes, pixels), (n2, s2, planes2, pixels2) = rows
    assert (planes, pixels) == (planes2, pixels2)
    per_pixel = (s2 - s1) / ((n2 - n1) * planes * FRAME_RATES["science"])
    assert per_pixel == pytest.approx(pixels, rel=0.02)
