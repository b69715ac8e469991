"""Lossless round trips of every writer/reader pair (NPZ, CSV, FITS, HDF5).

Reference: the log itself. Coefficients (float32 and float64, including
subnormals, signed zeros and extremes), timestamps or rate, modes, convention,
units, wavelength and arbitrary JSON metadata must come back bitwise / exactly
equal, for random logs drawn by hypothesis.
"""

from __future__ import annotations

import tempfile
from pathlib import Path

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from modalinfo.io import load, read_csv, read_fits, read_hdf5, read_npz, save
from modalinfo.telemetry import ModalLog

EXTENSIONS = (".npz", ".csv", ".fits", ".h5")

json_scalars = (
    st.none()
    | st.booleans()
    | st.integers(min_value=-(2**63), max_value=2**63)
    | st.floats(allow_nan=False, allow_infinity=False)
    | st.text(max_size=30)
)
metadata_strategy = st.dictionaries(
    st.text(max_size=12),
    st.recursive(
        json_scalars,
        lambda inner: (
            st.lists(inner, max_size=3) | st.dictionaries(st.text(max_size=5), inner, max_size=3)
        ),
        max_leaves=6,
    ),
    max_size=5,
)
label = st.text(
    alphabet=st.characters(blacklist_categories=("Cc", "Cs", "Zl", "Zp", "Zs", "Cf", "Co", "Cn")),
    min_size=1,
    max_size=8,
)


@st.composite
def logs(draw):
    n_frames = draw(st.integers(1, 30))
    n_modes = draw(st.integers(1, 5))
    dtype = draw(st.sampled_from([np.float32, np.float64]))
    width = 32 if dtype is np.float32 else 64
    coeffs = draw(
        hnp.arrays(
            dtype,
            (n_frames, n_modes),
            elements=st.floats(allow_nan=False, allow_infinity=False, width=width),
        )
    )
    convention = draw(st.sampled_from(["noll", "ansi", "fringe", "labels"]))
    if convention == "labels":
        modes = draw(st.lists(label, min_size=n_modes, max_size=n_modes, unique=True))
    else:
        modes = draw(st.lists(st.integers(1, 200), min_size=n_modes, max_size=n_modes, unique=True))
    time_kind = draw(st.sampled_from(["rate", "timestamps", "none"]))
    kwargs = {}
    if time_kind == "rate":
        kwargs["rate"] = draw(st.floats(min_value=1e-3, max_value=1e6))
        kwargs["start_time"] = draw(st.floats(min_value=-1e6, max_value=1e6))
    elif time_kind == "timestamps":
        start = draw(st.floats(min_value=-1e3, max_value=1e3))
        steps = draw(st.lists(st.floats(1e-4, 10.0), min_size=n_frames, max_size=n_frames))
        t = start + np.cumsum(steps)
        assume(np.all(np.diff(t) > 0))
        kwargs["timestamps"] = t
    units = draw(st.sampled_from(["rad", "nm", "um", "waves"]))
    wavelength = draw(st.none() | st.floats(min_value=1e-7, max_value=1e-4))
    return ModalLog(
        coeffs,
        modes=modes,
        convention=convention,
        units=units,
        wavelength=wavelength,
        metadata=draw(metadata_strategy),
        **kwargs,
    )


# rates span the whole accepted range (1 mHz - 1 MHz) on purpose: outside the wavefront
# sensors' 1 Hz - 100 kHz a log is built, written and read with a UserWarning (Leftovers
# 23-plaus), which is not what this round trip tests; drawn timestamps likewise (their
# median rate is warned on when the log is built, Leftovers 26-rate)
@pytest.mark.filterwarnings("ignore:`rate` = .* Hz is (below|above):UserWarning")
@pytest.mark.filterwarnings("ignore:`timestamps` give a frame rate of .* Hz:UserWarning")
# a drawn label or metadata text such as '00' or '=x' is written to CSV with the documented
# spreadsheet warning (read back as written, which is what this test checks); hypothesis
# drew label '00' in adversarial round 25 PART b and the test failed on the warning
@pytest.mark.filterwarnings("ignore:CSV .*text cell.* a spreadsheet would not show:UserWarning")
@settings(
    max_examples=40, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture]
)
@given(log=logs())
def test_round_trip_all_formats(log, assert_same_log):
    with tempfile.TemporaryDirectory() as tmp:
        for ext in EXTENSIONS:
            path = Path(tmp) / f"log{ext}"
            assert save(log, path) == path
            assert_same_log(log, load(path))


@pytest.mark.parametrize("ext", EXTENSIONS)
@pytest.mark.parametrize("dtype", [np.float32, np.float64])
def test_round_trip_special_values(tmp_path, ext, dtype, assert_same_log):
    info = np.finfo(dtype)
    x = np.array(
        [
            [0.0, -0.0, info.tiny, info.smallest_subnormal],
            [info.max, -info.max, info.eps, 1 / 3],
            [np.pi, -np.e, 1e-30 if dtype is np.float64 else 1e-20, 123456789.123],
        ],
        dtype=dtype,
    )
    log = ModalLog(
        x,
        rate=1234.5,
        modes=[4, 5, 6, 7],
        units="nm",
        wavelength=6.3e-7,
        metadata={
            "telescope": "LOST 4 m",
            "loop": "closed",
            "date": "2026-11-21",
            "note": "quote ' and \" and newline\n and é and \u2603",
            "n": 3,
            "ok": True,
        },
    )
    save(log, tmp_path / f"x{ext}")
    assert_same_log(log, load(tmp_path / f"x{ext}"))


@pytest.mark.parametrize(
    ("ext", "reader"),
    [(".npz", read_npz), (".csv", read_csv), (".fits", read_fits), (".h5", read_hdf5)],
)
def test_explicit_readers_and_fmt_override(tmp_path, ext, reader, assert_same_log):
    # ms apart: frame times below 10 Hz are warned (fixes 40-a)
    log = ModalLog(np.arange(12.0).reshape(4, 3), timestamps=[0.0, 5e-4, 7e-4, 2e-3], rate=None)
    path = save(log, tmp_path / "noext.bin", fmt=ext.strip(".").replace("h5", "hdf5"))
    assert_same_log(log, reader(path))
    assert_same_log(log, load(path))  # detected from content


def test_repairs_persist_in_metadata(tmp_path):
    x = np.ones((5, 2))
    x[2, 1] = np.nan
    log = ModalLog(x, rate=10.0, nonfinite="interpolate")
    back = load(save(log, tmp_path / "r.npz"))
    assert back.metadata["repairs"] == list(log.repairs)
    assert back.repairs == ()


def test_memmap_loads_keep_values(tmp_path, assert_same_log):
    log = ModalLog(np.random.default_rng(0).standard_normal((300, 4)), rate=100.0)
    for name in ("m.npz", "m.h5"):
        path = save(log, tmp_path / name)
        back = load(path, mmap=True)
        assert isinstance(back.coeffs, np.memmap)
        assert_same_log(log, back)
