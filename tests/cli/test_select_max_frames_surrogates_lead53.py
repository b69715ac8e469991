"""``select --max-frames``' advice covers the surrogates' rows too (review29, stop 53).

Found by review29 (docs/MUTATION.md round 29, "Found, not fixed" 1): the refusal of fixes
45-c (T74) advised "give --max-frames 22 or more" from the lagged pairs alone, but with the
default ``--surrogates 199`` every count from 22 to 220 was refused next by the surrogates'
rule ("199 circular shifts ... do not fit in 20 rows"). Reference: the command itself -
the advised count must run (exit 0) and one frame fewer must be refused (exit 2), whichever
rule refuses it; and the circular-shift arithmetic by hand for lags up to
``max_lag - 1 + horizon`` = 2: a shift k of n rows is admissible when
``min(2k mod n, n - 2k mod n) >= 2 (1 + 2) = 6``. For odd n each residue 0-5, n-5..n-1 of
2k has one k (k = 0 is not a shift): 10 of the n - 1 shifts excluded, n - 11 left (209 rows:
198, too few); for even n only the even residues occur, 0 once (k = n / 2) and 2, 4, n-4,
n-2 twice: 9 excluded, n - 10 left (210 rows: 200). So 210 rows, and 210 + horizon +
max_lag - 1 = 212 frames.
"""

import pytest

from .conftest import exit_code, write_small_log


# the small log's persistent modes warn on their effective samples (an error under the
# suite's filters); the frame-count rules are under test here
@pytest.mark.filterwarnings("ignore::modalinfo.information.methods.BiasRuleWarning")
def test_the_advised_count_runs_and_one_fewer_is_refused(tmp_path, capsys):
    log = write_small_log(tmp_path / "log.npz", 400)
    argv = ["select", log, "--target", "Z2", "--max-lag", "2", "--no-intervals"]
    assert exit_code([*argv, "--max-frames", "100"]) == 2
    err = capsys.readouterr().err
    assert "--surrogates 199" in err and "give --max-frames " in err
    advised = int(err.split("give --max-frames ")[1].split()[0])
    assert advised == 212  # the arithmetic by hand in the module docstring
    code = exit_code([*argv, "--max-frames", str(advised)])
    assert code == 0, capsys.readouterr().err
    capsys.readouterr()
    assert exit_code([*argv, "--max-frames", str(advised - 1)]) == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1


def test_least_surrogate_rows_is_the_search_over_the_lattice():
    # the closed form against the admissible shifts counted one by one (the lattice of
    # spacing 1 holds every spacing's: surrogate_shifts refuses iff it is too small)
    from modalinfo.information.resampling import _lattice, least_surrogate_rows

    for s in (1, 2, 3, 8, 9, 199, 200):
        for lag in (0, 1, 2, 7):
            least = least_surrogate_rows(s, lag)
            assert _lattice(least, 1, lag).size >= s > _lattice(least - 1, 1, lag).size
    assert least_surrogate_rows(10**12, 3) == 10**12 + 14  # no array of that size
