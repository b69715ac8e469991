"""Round 35 PART b, BS10: ``--set forecast.train=1e3`` is refused saying counts are integers.

Reference: the parameter's documented forms - a fraction in (0, 1) or a number of frames
>= 2 (``modalinfo forecast --train``); '1e3' is read as the float 1000.0, which was refused
"forecast.train must be < 1.0", as if a count of frames were not allowed.
"""

import pytest

from modalinfo.cli import main


@pytest.mark.parametrize("value, words", [
    ("1e3", "got 1000.0 (write 1000 for 1000 frames)"),
    ("2.5", "written as an integer; got 2.5"),
])
def test_a_float_count_of_frames_is_refused_naming_the_integer(tmp_path, capsys, helpers,
                                                                value, words):
    helpers.write_archive(tmp_path, n_good=1, corrupt=False)
    out = tmp_path / "out"
    code = main(["batch", str(tmp_path), "--analyses", "forecast", "--set",
                 f"forecast.train={value}", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1, err
    assert "forecast.train must be a fraction in (0, 1) or a number of frames >= 2" in err
    assert words in err and "must be < 1.0" not in err
    assert not out.exists()
