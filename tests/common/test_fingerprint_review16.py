"""The source fingerprint of task keys changes with the Python version (review16, R16-M3).

Reference: the language's own documentation - ``ast.dump``'s output format is not
promised stable across Python minor versions (the ``ast`` module's docs: node classes
and fields change between 3.x releases), so a fingerprint of ASTs must name the minor
version it was made with. Two interpreters that differ only in the minor version (3.11
and 3.12, here a fake ``sys``) must give two fingerprints; the same version, one. A
planted bug that keyed the major version twice (``{sys.version_info[0]}`` for the
minor) escaped every test before this file.
"""

from __future__ import annotations

import types

from modalinfo.common.tasks import keys


def _fingerprint(monkeypatch, version: tuple[int, int, int]) -> str:
    monkeypatch.setattr(keys, "sys", types.SimpleNamespace(version_info=version))
    # the digest of each module is not what this test is about: a cheap constant keeps
    # it fast (the real one parses 2.4 MB of sources)
    monkeypatch.setattr(keys, "_code_digest", lambda data: b"same")
    return keys.source_fingerprint.__wrapped__()


def test_the_minor_python_version_is_part_of_the_fingerprint(monkeypatch):
    a = _fingerprint(monkeypatch, (3, 11, 0))
    b = _fingerprint(monkeypatch, (3, 12, 0))
    assert a != b
    # a patch release does not change ast.dump's form: same fingerprint
    assert _fingerprint(monkeypatch, (3, 11, 9)) == a
