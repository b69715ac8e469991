"""Stable keys of tasks and the specs that carry them."""

from __future__ import annotations

import ast
import functools
import hashlib
import json
import sys
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


def _code_digest(data: bytes) -> bytes:
    """SHA-256 of what a module's source means to the interpreter, not of its layout.

    The abstract syntax tree of ``data`` with every docstring (a string-constant first
    statement of a module, class or function body) removed, dumped by ``ast.dump``
    without positions: comments, blank lines, line breaks inside brackets, a docstring's
    text and everything a comment or docstring edit moves (line numbers) are left out,
    while any change of a name, operator, constant or statement (``0.9`` to ``0.91``) or
    of any other string changes the dump. The AST rather than compiled bytecode: a code
    object holds line numbers (``co_firstlineno``, its line table) that every added
    comment line shifts, and its docstrings as constants, whose removal depends on the
    Python version's bytecode. Source that does not parse contributes its bytes.
    """
    try:
        tree = ast.parse(data)
    except (SyntaxError, ValueError):
        return b"bytes:" + hashlib.sha256(data).digest()
    for node in ast.walk(tree):
        body = getattr(node, "body", None)
        if (isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef))
                and body and isinstance(body[0], ast.Expr)
                and isinstance(body[0].value, ast.Constant)
                and isinstance(body[0].value.value, str)):
            node.body = body[1:] or [ast.Pass()]
    return b"ast:" + hashlib.sha256(ast.dump(tree).encode()).digest()


@functools.cache
def source_fingerprint() -> str:
    """SHA-256 of the code of the installed ``modalinfo`` and ``closedloop``.

    Each ``*.py`` file under the two packages, in sorted order of its path relative to
    the package's folder, contributes that path and the digest of its syntax tree less
    docstrings (``_code_digest``): an edit of a comment or docstring keeps the
    fingerprint (a resumed batch or sweep keeps its rows), any change of the code
    changes it (rows of other code are run again). The Python version is part of it
    (``ast.dump``'s form may change between versions). Computed once per process:
    about 2.4 MB parsed, 1.4 s of CPU on this shared machine (left15-misc; hashing the
    bytes took 0.02 s), in the main process of a batch or sweep only.
    A package that cannot be found contributes its name only.
    """
    import importlib.util

    digest = hashlib.sha256()
    digest.update(f"python {sys.version_info[0]}.{sys.version_info[1]}\n".encode())
    for name in ("modalinfo", "closedloop"):
        digest.update(f"package {name}\n".encode())
        spec = importlib.util.find_spec(name)
        if spec is None or not spec.submodule_search_locations:
            continue
        root = Path(next(iter(spec.submodule_search_locations)))
        for path in sorted(root.rglob("*.py"), key=lambda q: q.relative_to(root).as_posix()):
            digest.update(f"{path.relative_to(root).as_posix()}\n".encode())
            digest.update(_code_digest(path.read_bytes()))
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
