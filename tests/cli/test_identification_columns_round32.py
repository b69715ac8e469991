"""Round 32 PART b (issue 27): a file's mode identification follows its columns.

docs/ADVERSARIAL.md, "Round 32 PART b, issue 27", b12 / b53: ``closedloop export`` ->
``modalinfo convert r.fits out.fits --loop dm0.pol --convention ansi`` (or fringe) ->
``modalinfo info out.fits`` printed "the file's modes against our Zernikes" with
column 1 = Z2 (1,1), the file's column order, while column 1 held A1 = Z3 (1,-1):
``metadata["modes_identification"]`` was carried unchanged through the reordering.

Reference: mode images written here from Noll's (1976) closed forms of Z2-Z7 (x along
columns, y along rows); the ANSI / OSA index of each (n, m) from the published
single-index table (ANSI j = (n (n + 2) + m) / 2): Noll 2, 3, 4, 5, 6, 7 are
(1,1), (1,-1), (2,0), (2,-2), (2,2), (3,-1) = ANSI 2, 1, 4, 3, 5, 7.
"""

from __future__ import annotations

import numpy as np

from modalinfo.bases.identify import ZernikeIdentification, identify_zernike
from modalinfo.cli import main
from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog

from .conftest import exit_code

#: ANSI index of Noll 2..7 (published table)
ANSI_OF_NOLL = {2: 2, 3: 1, 4: 4, 5: 3, 6: 5, 7: 7}


def _noll_images(n: int = 48) -> np.ndarray:
    c = (np.arange(n) - (n - 1) / 2) / (n / 2)
    x, y = np.meshgrid(c, c)  # x along columns, y along rows
    r2 = x**2 + y**2
    imgs = np.array([2 * x, 2 * y, np.sqrt(3) * (2 * r2 - 1), np.sqrt(6) * 2 * x * y,
                     np.sqrt(6) * (x**2 - y**2), np.sqrt(8) * (3 * r2 - 2) * y])
    return np.where(r2 <= 1, imgs, 0.0)


def _log() -> ModalLog:
    ident = identify_zernike(_noll_images())
    assert list(ident.noll) == [2, 3, 4, 5, 6, 7] and ident.is_standard  # precondition
    x = np.random.default_rng(32).normal(size=(200, 6)) * np.arange(1, 7)
    return ModalLog(x, rate=1000.0, modes=[2, 3, 4, 5, 6, 7], units="rad",
                    metadata={"modes_identification": ident.to_dict()})


def _ident(log: ModalLog) -> ZernikeIdentification:
    return ZernikeIdentification.from_dict(log.metadata["modes_identification"])


def test_convention_change_and_selection_carry_the_identification():
    log = _log()
    ansi = log.to_convention("ansi")
    noll_of_column = [k for a in ansi.modes for k, v in ANSI_OF_NOLL.items() if v == a]
    assert list(_ident(ansi).noll) == noll_of_column == [3, 2, 5, 4, 6, 7]
    picked = log.select(modes=[6, 2])
    assert list(_ident(picked).noll) == [6, 2]
    np.testing.assert_array_equal(picked.coeffs, log.coeffs[:, [4, 0]])
    assert list(_ident(log.drop_modes([4])).noll) == [2, 3, 5, 6, 7]


def test_info_after_convert_names_each_column(tmp_path, capsys):
    save(_log(), tmp_path / "in.npz")
    assert exit_code(["convert", tmp_path / "in.npz", tmp_path / "out.npz",
                      "--convention", "ansi", "--quiet"]) == 0
    capsys.readouterr()
    assert main(["info", str(tmp_path / "out.npz"), "--quiet"]) == 0
    text = capsys.readouterr().out
    rows = text.split("against our Zernikes")[1].splitlines()[2:8]
    assert [int(r.split()[1]) for r in rows] == [3, 2, 5, 4, 6, 7]
    out = load(tmp_path / "out.npz")
    assert [ANSI_OF_NOLL[j] for j in [3, 2, 5, 4, 6, 7]] == list(out.modes)
