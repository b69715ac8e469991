"""Round 18 PART b D29: ``convert`` to a .npy name says why NPY is refused.

Reference: the documented formats (``modalinfo.io.formats.FORMATS``: NPY is read-only,
one bare array holds no rate, modes or units) and NumPy's own formats (.npz is its
archive of several arrays, read back here with ``numpy.load``).
The refusal names NPY as read-only and the remedy, .npz; following it works.
"""

import numpy as np

from modalinfo.cli import main


def test_convert_to_npy_names_the_reason_and_remedy(tmp_path, capsys):
    src = tmp_path / "s.npy"
    np.save(src, np.random.default_rng(0).normal(size=(50, 3)))
    assert main(["convert", str(src), str(tmp_path / "o.npy"), "--quiet"]) == 2
    err = capsys.readouterr().err
    assert "NPY is read-only" in err and ".npz" in err and "cannot tell" not in err
    assert len(err.strip().splitlines()) == 1
    assert not (tmp_path / "o.npy").exists()
    assert main(["convert", str(src), str(tmp_path / "o.npz"), "--quiet"]) == 0
    assert np.array_equal(np.load(tmp_path / "o.npz")["coefficients"], np.load(src))
