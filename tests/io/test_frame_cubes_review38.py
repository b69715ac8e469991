"""NPZ files of frame cubes: integer pixels, and more than one cube (mutation round 38).

References: the arrays written here with ``numpy.savez`` (their names, dtypes and shapes,
as numpy reports them); the refusal names the first cube by name (sorted), its dtype
and shape, and counts the others (fix56-c). Each test names the plant of
docs/MUTATION.md's round 38 it fails with.
"""

import numpy as np

from modalinfo.cli import main


def test_npz_of_two_uint16_cubes_is_named_as_images(tmp_path, capsys):
    """R38-NP3 (an integer cube), R38-NP4 (the second cube counted)."""
    path = tmp_path / "camera.npz"
    rng = np.random.default_rng(38)
    a = (rng.random((20, 8, 12)) * 4000).astype(np.uint16)
    np.savez(path, wfs=a, science=a[:, :4, :6].copy(), exposure=np.ones(20))
    assert main(["info", str(path)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1
    assert "'science' is a 3-D uint16 array of shape (20, 4, 6) (and 1 more 3-D)" in err
    assert "cube of images (20 frames of 4 x 6 pixels" in err
