"""An OrderingResult read back from JSON is the one written, or refused (audit 10,
feedback, rows js-labels-edited, js-order-dup, js-order-float, js-mi-short,
js-basis-labels-short).

Reference: the round trip (the object written is the object read, ``==``) and the
definition of the fields: ``labels`` is ``basis_labels`` taken in ``order``, ``order`` a
permutation of the basis's indices, every per-mode array one value per mode. A file
contradicting them (edited by hand, damaged) was rebuilt as given: labels reversed by
hand were shown while the curves followed ``order``; order 2.5 became 2.
"""

import json

import numpy as np
import pytest

from modalinfo.bases import Pupil, ZernikeBasis
from modalinfo.ordering import OrderingResult, order_modes
from modalinfo.telemetry import ModalLog


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    rng = np.random.default_rng(5)
    log = ModalLog(rng.standard_normal((300, 6)) * np.arange(1.0, 7.0), rate=500.0)
    result = order_modes(log, ZernikeBasis(Pupil(16), modes=range(2, 8)), "variance")
    path = tmp_path_factory.mktemp("ord") / "o.json"
    result.to_json(path)
    return result, json.loads(path.read_text())


def test_round_trip_is_the_object(written, tmp_path):
    result, data = written
    assert OrderingResult.from_dict(data) == result


@pytest.mark.parametrize("edit, match", [
    (lambda d: d.__setitem__("labels", d["labels"][::-1]), "labels"),
    (lambda d: d.__setitem__("order", d["order"][:-1] + d["order"][:1]), "permutation"),
    (lambda d: d.__setitem__("order", [v + 0.5 for v in d["order"]]), "list of ints"),
    (lambda d: d.__setitem__("scores", d["scores"][:-2]), "scores"),
    (lambda d: d.__setitem__("basis_labels", d["basis_labels"][:-1]), "permutation"),
])
def test_contradicting_fields_refused(written, tmp_path, edit, match):
    _, data = written
    edited = json.loads(json.dumps(data))
    edit(edited)
    path = tmp_path / "edited.json"
    path.write_text(json.dumps(edited))
    with pytest.raises(ValueError, match=match):
        OrderingResult.from_json(path)
