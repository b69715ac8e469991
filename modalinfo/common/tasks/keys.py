"""Stable keys of tasks and the specs that carry them."""

from __future__ import annotations

import functools
import hashlib
import json
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

__all__ = ["TaskSpec", "canonical_json", "package_version", "source_fingerprint", "task_key"]


def canonical_json(value: Any) -> str:
    """JSON with sorted keys and no spaces: the same value always gives the same text."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), allow_nan=True)


def package_version() -> str:
    """Version of the installed code: ``modalinfo.__version__`` and its source fingerprint.

    ``"<__version__>+src.<12 hex digits>"``: the digits are ``source_fingerprint()``,
    which changes with any change of the code of ``modalinfo`` or ``closedloop``. The
    version number alone stayed "0.1.0" over hundreds of commits, so a batch or sweep
    folder written by an older checkout was resumed by a newer one with the old rows
    reused under the same keys: a table mixing two versions' numbers (a quality rule's
    ``k`` 5.21 beside 5.27) and columns, without a word (adversarial round 15 PART b,
    O01, O02, O05). With the fingerprint in every task key, rows of another build are
    not reused (they stay in ``rows/``, outside the table) and are run again.
    """
    import modalinfo

    return f"{modalinfo.__version__}+src.{source_fingerprint()[:12]}"


@functools.cache
def source_fingerprint() -> str:
    """SHA-256 of the Python sources of the installed ``modalinfo`` and ``closedloop``.

    Each ``*.py`` file under the two packages, in sorted order of its path relative to
    the package's folder, contributes that path and its bytes; computed once per
    process (about 2 MB read). A package that cannot be found contributes its name only.
    """
    import importlib.util

    digest = hashlib.sha256()
    for name in ("modalinfo", "closedloop"):
        digest.update(f"package {name}\n".encode())
        spec = importlib.util.find_spec(name)
        if spec is None or not spec.submodule_search_locations:
            continue
        root = Path(next(iter(spec.submodule_search_locations)))
        for path in sorted(root.rglob("*.py"), key=lambda q: q.relative_to(root).as_posix()):
            digest.update(f"{path.relative_to(root).as_posix()}\n".encode())
            digest.update(hashlib.sha256(path.read_bytes()).digest())
    return digest.hexdigest()


def task_key(*parts: Any) -> str:
    """Stable key of a task: SHA-256 of the canonical JSON of ``parts`` and the version.

    Parameters
    ----------
    *parts
        JSON-able values identifying the work (e.g. input SHA-256, analysis name,
        parameters, hints).

    Returns
    -------
    str
        64 hexadecimal digits.
    """
    text = canonical_json([package_version(), *parts])
    return hashlib.sha256(text.encode()).hexdigest()


@dataclass(frozen=True)
class TaskSpec:
    """One unit of work.

    Attributes
    ----------
    key : str
        Stable identifier (see :func:`task_key`); also the row's file name.
    payload : dict
        JSON-able argument of the task function.
    labels : dict
        Scalar columns copied into the row, ok or error (e.g. ``path``, ``analysis``,
        ``sha256``, ``params``), so an error row names its input.
    """

    key: str
    payload: dict
    labels: dict = field(default_factory=dict)
