"""Archives holding several instruments' logs (adversarial round 29 PART b, issue 27).

References: the arrays written with numpy and astropy themselves (``A`` and
``B = 3 A + 1``, so which one was read is visible in its values), and the rule the HDF5
reader already follows for the same question: several candidate coefficient arrays are
refused, or the one read is named in ``metadata``. An NPZ holding ``coeffs`` and
``coefficients`` read ``coefficients`` without a word (M13); a FITS file holding two
binary tables (``WFS1``, ``WFS2``) read the first without a word (M33), although two
images were named.
"""

from __future__ import annotations

import numpy as np
import pytest

from modalinfo.io import LogFormatError, load

RNG = np.random.default_rng(29)
A = RNG.standard_normal((300, 4)) * 0.1
B = 3 * A + 1


@pytest.mark.parametrize("names", [("coeffs", "coefficients"), ("data", "zernike")])
def test_an_npz_with_two_coefficient_names_is_refused_naming_both(tmp_path, names):
    path = tmp_path / "two.npz"
    np.savez(path, **{names[0]: A, names[1]: B})
    with pytest.raises(LogFormatError, match="2 arrays named as coefficients") as info:
        load(path, rate=1000.0)
    assert all(n in str(info.value) for n in names) and "--dataset" in str(info.value)
    # the choice the refusal asks for reads that array, bit for bit
    chosen = load(path, rate=1000.0, dataset=names[1])
    np.testing.assert_array_equal(chosen.coeffs, B)
    assert chosen.metadata["source_dataset"] == names[1]


def test_an_npz_coefficient_array_beside_other_arrays_is_named(tmp_path):
    path = tmp_path / "cs.npz"
    np.savez(path, coeffs=A, slopes=RNG.standard_normal((300, 8)))
    log = load(path, rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, A)
    assert log.metadata["source_dataset"] == "coeffs"


def test_two_fits_tables_name_the_one_read(tmp_path):
    from astropy.io import fits
    from astropy.table import Table

    names = [f"Z{j}" for j in range(2, 6)]
    path = tmp_path / "tabs.fits"
    fits.HDUList([fits.PrimaryHDU(), fits.BinTableHDU(Table(A, names=names), name="WFS1"),
                  fits.BinTableHDU(Table(B, names=names), name="WFS2")]).writeto(path)
    log = load(path, rate=1000.0)
    np.testing.assert_array_equal(log.coeffs, A)
    assert log.metadata["source_hdu"].startswith("HDU 1 (WFS1), the first of 2 tables")
    np.testing.assert_array_equal(load(path, rate=1000.0, dataset="WFS2").coeffs, B)
    # one table: nothing to choose, nothing said
    one = tmp_path / "one.fits"
    fits.HDUList([fits.PrimaryHDU(), fits.BinTableHDU(Table(A, names=names))]).writeto(one)
    assert "source_hdu" not in load(one, rate=1000.0).metadata


@pytest.mark.parametrize("key", ["wfs", "loop", "night"])
def test_a_key_column_beside_zernike_columns_is_refused_in_a_csv(tmp_path, key):
    # two WFSs' rows interleaved with a key column: read before as one 11-"mode" series
    # of twice the frames ('wfs' a mode with lag-1 ACF -1), labels convention, no word
    path = tmp_path / f"{key}.csv"
    names = [f"Z{j}" for j in range(2, 6)]
    rows = [",".join([*names, key])]
    for a, b in zip(A, B, strict=True):
        rows.append(",".join([*map(repr, a.tolist()), "1"]))
        rows.append(",".join([*map(repr, b.tolist()), "2"]))
    path.write_text("\n".join(rows) + "\n")
    with pytest.raises(LogFormatError, match=rf"column\(s\) '{key}' are not modes beside 4 "
                                             r"noll mode columns"):
        load(path, rate=1000.0)
    # the same rows of one instrument without the key read as their values (numpy)
    one = tmp_path / "one.csv"
    lines = [",".join(names)] + [",".join(map(repr, a.tolist())) for a in A]
    one.write_text("\n".join(lines) + "\n")
    np.testing.assert_array_equal(load(one, rate=1000.0).coeffs, A)


def test_a_key_column_in_a_fits_table_is_refused(tmp_path):
    from astropy.io import fits
    from astropy.table import Table

    table = Table(A, names=[f"Z{j}" for j in range(2, 6)])
    table["WFS"] = np.ones(len(A), dtype=np.int16)
    path = tmp_path / "key.fits"
    fits.HDUList([fits.PrimaryHDU(), fits.BinTableHDU(table)]).writeto(path)
    with pytest.raises(LogFormatError, match=r"column\(s\) 'WFS' are not modes"):
        load(path, rate=1000.0)
