"""``modalinfo select`` runs the outlier policy it names, as ``select_inputs`` (fix56-b).

References: the clean log's answer (the same AR(1) log before one frame of the target
is glitched by 100 standard deviations) for the glitched log's under the cleaning
policy, and ``select_inputs`` itself on the same array for each policy (the CLI must
give the API's answer: ``outliers="clip"`` for its default, ``outliers="warn"`` for
``--outliers warn``). The exact input set is ``m0[t]`` alone (AR(1) modes whose
innovations share a Kolmogorov covariance: fix54-b's generator, round 53's seeds).
Before fix56-b the command's default was ``--outliers warn``, whose stderr line said
"used as is" while ``select_inputs`` replaced the glitch beneath it, and ``--outliers
warn`` could not score the values as given (its answer was the cleaned one): the
default, the words and the warn tests fail on c423e5eb; the clean-log guard passes on
both. Seeds fixed: measured, the cleaned answers equal the clean ones to 5e-4 nats on
seeds 0-9, the as-given ones hold a false input (m0[t-1]) on all 10.
"""

import re
import warnings

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.information import select_inputs

from ._glitched_ar1 import noll_ar1 as _ar1

ARGS = ["--target", "0", "--max-lag", "2", "--surrogates", "19", "--no-intervals",
        "--rate", "1000", "--in-units", "rad"]


def _logs(folder, s: int) -> tuple[np.ndarray, np.ndarray]:
    y = _ar1(4000, 40, 54000 + s)
    g = y.copy()
    rng = np.random.default_rng(s + 999)
    g[rng.integers(10, 3990), 0] += 100 * y[:, 0].std() * rng.choice([-1, 1])
    np.save(folder / "clean.npy", y)
    np.save(folder / "glitch.npy", g)
    return y, g


def _api(data, s: int, **kw) -> list[tuple[int, int, float]]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # the OutlierWarning: said, tested in fix54-b's file
        r = select_inputs(data, 0, max_lag=2, n_surrogates=19, intervals=False, seed=s, **kw)
    return [(i.source, i.lag, round(float(i.gain), 4)) for i in r.inputs]


def _cli(capsys, path, s: int, *extra) -> tuple[list[tuple[int, int, float]], str]:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")  # the command's own run prints them on stderr
        assert main(["select", str(path), *ARGS, "--seed", str(s), *extra]) == 0
    out = capsys.readouterr()
    rows = re.findall(r"^\s*\d+\s+Z(\d+)\[t(?:-(\d+))?\]\s+([-\d.]+)", out.out, re.M)
    said = "\n".join([out.err, *(str(w.message) for w in caught)])
    return [(int(z) - 2, int(lag or 0), float(g)) for z, lag, g in rows], said


@pytest.mark.parametrize("s", [0, 1])
def test_the_default_cleans_as_the_api_does_and_says_so(tmp_path, capsys, s):
    y, g = _logs(tmp_path, s)
    api, clean = _api(g, s), _api(y, s)
    assert [(src, lag) for src, lag, _ in clean] == [(0, 0)]  # the exact input
    cli, err = _cli(capsys, tmp_path / "glitch.npy", s)
    assert [(src, lag) for src, lag, _ in cli] == [(src, lag) for src, lag, _ in api] == [(0, 0)]
    assert cli[0][2] == pytest.approx(api[0][2], abs=2e-4)
    assert cli[0][2] == pytest.approx(clean[0][2], abs=1e-3)
    assert "used as is" not in err  # before: "used as is" beside "were replaced"
    assert "clipped 1 outlier value(s)" in err


@pytest.mark.parametrize("s", [0, 1])
def test_outliers_warn_scores_the_values_as_given_as_the_api(tmp_path, capsys, s):
    _, g = _logs(tmp_path, s)
    given = _api(g, s, outliers="warn")
    assert len(given) >= 2  # the glitch's false input (the target's own lag 2)
    cli, err = _cli(capsys, tmp_path / "glitch.npy", s, "--outliers", "warn")
    assert [(src, lag) for src, lag, _ in cli] == [(src, lag) for src, lag, _ in given]
    assert [gain for *_, gain in cli] == pytest.approx([gain for *_, gain in given], abs=2e-4)
    assert "used as is" in err and "scored as given" in err


def test_select_help_names_clip_as_its_default(capsys):
    with pytest.raises(SystemExit):
        main(["select", "--help"])
    text = " ".join(capsys.readouterr().out.split())
    assert "clip (default: the search scores the cleaned values" in text
    assert "warn (default" not in text


def test_a_clean_log_gives_one_answer_under_every_policy(tmp_path, capsys):
    y, _ = _logs(tmp_path, 2)
    api = _api(y, 2)
    for policy in ((), ("--outliers", "warn"), ("--outliers", "clip")):
        cli, _ = _cli(capsys, tmp_path / "clean.npy", 2, *policy)
        assert [(src, lag) for src, lag, _ in cli] == [(src, lag) for src, lag, _ in api]
        assert [gain for *_, gain in cli] == pytest.approx([gain for *_, gain in api], abs=2e-4)
