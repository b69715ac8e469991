"""Stable keys of tasks and the specs that carry them."""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from typing import Any

__all__ = ["TaskSpec", "canonical_json", "package_version", "task_key"]


def canonical_json(value: Any) -> str:
    """JSON with sorted keys and no spaces: the same value always gives the same text."""
    return json.dumps(value, sort_keys=True, separators=(",", ":"), allow_nan=True)


def package_version() -> str:
    """Version of the installed modalinfo (``modalinfo.__version__``)."""
    import modalinfo

    return str(modalinfo.__version__)


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
