"""reorder's JSON says which order its scores are in (fix55-c; round 54 PART b, T02).

Reference: ``json.load`` of the file written by ``modalinfo reorder --out``, and numpy on
the log: a variance order's score of a mode is its mean square (the modes of ``synth``
are the basis's modes, rad), so ``scores_by_label[label]`` must equal numpy's mean of
that column squared, whatever rank the mode has; the file still reads back with
``OrderingResult.from_json`` (format unchanged, the new keys derived).
"""

import json

import numpy as np
import pytest

from modalinfo.cli import main
from modalinfo.io import load
from modalinfo.ordering.result import OrderingResult


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    folder = tmp_path_factory.mktemp("ro")
    log = folder / "s.npz"
    assert main(["synth", str(log), "--frames", "400", "--seed", "3", "--quiet"]) == 0
    out = folder / "ro.json"
    assert main(["reorder", str(log), "--method", "variance", "--resamples", "0",
                 "--out", str(out), "--quiet"]) == 0
    return log, out


def test_scores_keyed_by_label_are_the_modes_mean_squares(written):
    log_path, out = written
    with open(out, encoding="utf-8") as fh:
        data = json.load(fh)
    log = load(log_path)
    by_label = dict(zip(log.labels, np.mean(np.asarray(log.coeffs) ** 2, axis=0), strict=True))
    assert data["score_order"].startswith("basis_labels")
    assert list(data["scores_by_label"]) == data["basis_labels"]
    for label, score in data["scores_by_label"].items():
        assert score == pytest.approx(by_label[label], rel=1e-12)
    # the first step's mode has the largest score: the keyed scores and the step order agree
    first = data["labels"][0]
    assert data["scores_by_label"][first] == max(data["scores_by_label"].values())
    # the steps' order is not the basis's here (else the test could not tell them apart)
    assert data["labels"] != data["basis_labels"]


def test_the_file_reads_back_unchanged(written):
    _, out = written
    back = OrderingResult.from_json(out)
    with open(out, encoding="utf-8") as fh:
        data = json.load(fh)
    assert data["format"] == "modalinfo.OrderingResult/1"
    np.testing.assert_array_equal(back.scores, np.asarray(data["scores"]))
    assert back.to_dict()["scores_by_label"] == data["scores_by_label"]


def test_no_scores_no_keyed_scores(tmp_path, written):
    log_path, _ = written
    out = tmp_path / "std.json"
    assert main(["reorder", str(log_path), "--method", "standard", "--out", str(out),
                 "--quiet"]) == 0
    with open(out, encoding="utf-8") as fh:
        data = json.load(fh)
    assert data["scores"] is None and "scores_by_label" not in data
