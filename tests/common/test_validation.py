"""Tests of modalinfo.common.validation: masked arrays are refused, not unmasked silently.

Reference: NumPy's documented behaviour, ``np.asarray(masked)`` returns the data with
the mask dropped; the MI of a pair is computed here on the unmasked samples with the
same estimator (a round trip), so a mask that reached the estimator would show.
Adversarial round 5, row a01: ``mutual_information`` of a half-masked array used all
of it. The log-rate rule: the range ``--rate`` documents in the README, 1 mHz - 1 MHz,
bounds included (adversarial round 6, row b01).
"""

import numpy as np
import pytest

from modalinfo.common.validation import as_float_array, log_rate_problem
from modalinfo.forecast import LinearPredictor
from modalinfo.information import mutual_information
from modalinfo.telemetry import ModalLog


@pytest.fixture(scope="module")
def pair():
    rng = np.random.default_rng(0)
    x = rng.standard_normal(500)
    return x, 0.6 * x + 0.8 * rng.standard_normal(500)


def test_a_masked_value_is_refused_naming_the_argument(pair):
    x, y = pair
    masked = np.ma.masked_array(x, mask=np.arange(500) < 3)
    with pytest.raises(ValueError, match="`x` is a masked array with 3 masked value"):
        mutual_information(masked, y)
    with pytest.raises(ValueError, match="`coeffs` is a masked array with 3 masked"):
        ModalLog(np.ma.column_stack([masked, y]), rate=100.0)
    with pytest.raises(ValueError, match="`history` is a masked array with 3 masked"):
        LinearPredictor().fit(np.ma.column_stack([masked, y]))


def test_a_masked_array_with_nothing_masked_is_its_data(pair):
    x, y = pair
    assert mutual_information(np.ma.masked_array(x), y) == mutual_information(x, y)
    out = as_float_array(np.ma.masked_array(x, mask=False), "x")
    assert type(out) is np.ndarray and np.array_equal(out, x)
    log = ModalLog(np.ma.column_stack([x, y]), rate=100.0)
    assert type(log.coeffs) is np.ndarray


def test_dropping_the_masked_samples_is_the_documented_way(pair):
    x, y = pair
    keep = np.arange(500) >= 3
    assert mutual_information(x[keep], y[keep]) != mutual_information(x, y)


@pytest.mark.parametrize("rate", [None, 1e-3, 2000.0, 1e6])
def test_a_rate_in_one_millihertz_to_one_megahertz_is_no_problem(rate):
    assert log_rate_problem(rate, False, "'a.npz'") is None


@pytest.mark.parametrize("rate, timestamps, source", [
    (float(np.nextafter(1e-3, 0.0)), True, "timestamps give"),
    (float(np.nextafter(1e6, np.inf)), False, "stored rate gives"),
    (2e-6, True, "timestamps give"), (1e300, False, "stored rate gives")])
def test_a_rate_outside_the_range_is_named_with_its_source(rate, timestamps, source):
    text = log_rate_problem(rate, timestamps, "'a.npz'")
    assert text.startswith(f"'a.npz': its {source} a frame rate of {rate:.3g} Hz, outside "
                           "0.001-1e+06 Hz")


# Audit 9 (inputs): NumPy's documented dtype kinds are the reference. timedelta64 is a
# subtype of np.integer, so durations passed the numeric check and were read as counts
# of their unit (ms as seconds); a 0/1 mask of floats is a mask, 0.5 or '1' is not.
@pytest.mark.parametrize("unit", ["timedelta64[ms]", "datetime64[ms]"])
def test_date_and_time_dtypes_are_refused_naming_the_argument(unit):
    values = np.arange(10).astype(unit)
    assert np.issubdtype(values.dtype, np.number) == (unit.startswith("timedelta"))
    with pytest.raises(TypeError, match="`t` must be a numeric array; got array of shape"):
        as_float_array(values, "t")


def test_a_mask_is_bool_or_zeros_and_ones():
    from modalinfo.common.validation import as_bool_mask

    mask = np.array([[0, 1], [1, 1]])
    assert as_bool_mask(mask.astype(np.float32), "mask").tolist() == mask.astype(bool).tolist()
    with pytest.raises(ValueError, match=r"`mask` must be boolean \(or numbers 0 and 1\); got 1 "):
        as_bool_mask(np.array([0.0, 0.5, 1.0]), "mask")
    with pytest.raises(TypeError, match="`mask` must be a numeric array"):
        as_bool_mask(np.array(["0", "1"]), "mask")
    with pytest.raises(TypeError, match="`mask` must be real"):
        as_bool_mask(np.array([1 + 1j, 0]), "mask")
