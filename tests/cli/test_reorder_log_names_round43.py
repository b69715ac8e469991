"""``reorder`` on an ANSI / Fringe log names each ordered mode in the log's own labels too.

Round 43 PART b, c22 / c23 (wrong forms): the table of ``reorder s_ansi.npz`` lists the
Zernike basis's Noll labels (Z3, Z2, Z6 ...) with no word that the file calls those modes
A1, A2, A3 ...; ``forecast --modes`` / ``select --target`` on that file take its own names.

References: the ANSI Z80.28 / OSA and Wyant's Fringe tables by hand (Noll Z3 = (1, -1) =
A1 = F3, Z4 = (2, 0) = A4 = F4, Z5 = (2, -2) = A3 = F6, Z6 = (2, 2) = A5 = F5, Z11 = (4, 0) =
A12 = F9), and the data: each printed pair ``Zn = Xk`` names one column, checked by the
column ``Xk`` of the converted file being the Noll file's column ``Zn`` bit for bit.
"""

import re

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import load, save
from modalinfo.telemetry import ModalLog

HAND = {"ansi": {"Z3": "A1", "Z4": "A4", "Z5": "A3", "Z6": "A5", "Z11": "A12"},
        "fringe": {"Z3": "F3", "Z4": "F4", "Z5": "F6", "Z6": "F5", "Z11": "F9"}}


@pytest.fixture
def noll_path(tmp_path):
    rng = np.random.default_rng(3)
    # distinct variances: the variance order is Z11, Z6, Z5, Z4, Z3, Z2 ... (no ties)
    coeffs = rng.standard_normal((500, 10)) * np.linspace(0.2, 2.0, 10)
    return save(ModalLog(coeffs, rate=1000.0, modes=list(range(2, 12)), units="rad"),
                tmp_path / "noll.npz")


def _pairs(out: str) -> dict:
    line = next(x for x in out.splitlines() if x.startswith("modes are named in Noll"))
    return dict(re.findall(r"(Z\d+) = ([AF]\d+)", line))


@pytest.mark.parametrize("convention", ["ansi", "fringe"])
def test_c22_c23_log_names_beside_noll(noll_path, tmp_path, capsys, convention):
    other = tmp_path / f"{convention}.npz"
    assert main(["convert", str(noll_path), str(other), "--convention", convention,
                 "--quiet"]) == 0
    capsys.readouterr()
    assert main(["reorder", str(other), "--method", "variance"]) == 0
    pairs = _pairs(capsys.readouterr().out)
    assert len(pairs) == 10
    for noll, own in HAND[convention].items():
        assert pairs[noll] == own
    noll_log, own_log = load(noll_path), load(other)
    for noll, own in pairs.items():
        i = noll_log.modes.index(int(noll[1:]))
        k = own_log.modes.index(int(own[1:]))
        np.testing.assert_array_equal(own_log.coeffs[:, k], noll_log.coeffs[:, i])


def test_noll_log_has_no_names_line(noll_path, capsys):
    assert main(["reorder", str(noll_path), "--method", "variance"]) == 0
    assert "modes are named in Noll" not in capsys.readouterr().out
