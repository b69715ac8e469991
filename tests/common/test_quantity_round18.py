"""Round 18 PART a (issue 27): astropy Quantities, pandas nullable tables, repair notes.

References from outside the code: astropy's own unit conversion (``Quantity.to_value``)
says what number a Quantity stands for, so a Quantity whose unit would be dropped must
be refused naming that unit (a log of 1 um read as 1 "nm" is 1000x wrong; timestamps
of 1 ms read as 1 s give a rate 1000x wrong); pandas' ``DataFrame.to_numpy`` gives the
values of a nullable Float64 / Arrow table, which ``ModalLog`` must then hold exactly;
the position of each column's first and last finite value (counted by hand) says how
many values ``nonfinite='interpolate'`` holds constant rather than interpolates;
``numpy`` cannot allocate 2**70 frames, so ``kaos_like`` must refuse naming
``n_frames`` rather than raise OverflowError.
"""

import numpy as np
import pytest

from modalinfo.information import mutual_information
from modalinfo.telemetry import ModalLog, sampling_of
from modalinfo.telemetry.synthetic import kaos_like

u = pytest.importorskip("astropy.units")
pd = pytest.importorskip("pandas")

RNG = np.random.default_rng(18)
C = RNG.standard_normal((300, 3))


def test_log_in_um_is_refused_naming_the_unit():
    with pytest.raises(TypeError, match=r"`coeffs` is an astropy Quantity in um"):
        ModalLog(C * u.um, units="nm")


def test_timestamps_in_ms_are_refused_not_read_as_seconds():
    with pytest.raises(TypeError, match=r"`timestamps` is an astropy Quantity in ms"):
        ModalLog(C, timestamps=np.arange(300) * u.ms)
    with pytest.raises(TypeError, match=r"`times` is an astropy Quantity in ms"):
        sampling_of(np.arange(300) * u.ms)


def test_following_the_remedy_gives_astropys_number():
    t = np.arange(300) * u.ms
    log = ModalLog(C, timestamps=t.to_value("s"))
    assert log.rate == pytest.approx(1000.0, rel=1e-9)


def test_mi_array_quantity_refused_and_dimensionless_accepted():
    x = RNG.standard_normal(500)
    y = x + RNG.standard_normal(500)
    with pytest.raises(TypeError, match=r"`x` is an astropy Quantity in nm"):
        mutual_information(x * u.nm, y, method="gaussian")
    assert mutual_information(x * u.dimensionless_unscaled, y, method="gaussian") == (
        mutual_information(x, y, method="gaussian"))


def test_scalar_quantity_refusal_names_the_unit():
    with pytest.raises(TypeError, match=r"astropy Quantity \(1\.0 in kHz\)"):
        ModalLog(C, rate=1 * u.kHz)


def test_nullable_float64_table_is_read_with_na_as_nan():
    df = pd.DataFrame(C).astype("Float64")
    assert np.array_equal(ModalLog(df, modes=[2, 3, 4]).coeffs, df.to_numpy(dtype=float))
    df.iloc[3, 2] = pd.NA
    assert ModalLog(df, modes=[2, 3, 4], nonfinite="drop").n_frames == 299
    with pytest.raises(TypeError, match="dtype object"):
        ModalLog(pd.DataFrame(C.astype(str)), modes=[2, 3, 4])


def test_interpolate_says_how_many_values_it_held_constant():
    a = C.copy()
    a[:100, 1] = np.nan      # 100 before the first finite value
    a[150, 0] = np.nan       # 1 inside: interpolated
    a[-5:, 2] = np.nan       # 5 after the last finite value
    log = ModalLog(a, nonfinite="interpolate")
    assert "106 non-finite value(s)" in log.repairs[0]
    assert "105 of them held constant" in log.repairs[0]


def test_kaos_like_huge_n_frames_refused_naming_it():
    with pytest.raises(ValueError, match=r"`n_frames` = 1180591620717411303424 needs"):
        kaos_like(2**70, seed=0)
