"""The package's one way to catch warnings: :func:`catching_warnings`.

``warnings.catch_warnings`` swaps the process's filter list and ``showwarning`` on entry
and puts back what it saw on exit; two threads doing so interleave, and the one that
exits last restores the other's temporary filter for good (adversarial round 9: four
threads fitting neural-net predictors left ``always ConvergenceWarning`` installed, four
computing BCa intervals ``ignore DegenerateDataWarning``). Every such block of the
package holds one process-wide lock, so they follow each other. A block of the caller's
own code in another thread can still interleave with one of ours: that is Python's rule
before 3.14 (context-aware warnings), not ours to change.
"""

from __future__ import annotations

import contextlib
import threading
import warnings
from collections.abc import Iterator

__all__ = ["catching_warnings"]

_LOCK = threading.RLock()


@contextlib.contextmanager
def catching_warnings(*, record: bool = False) -> Iterator[list | None]:
    """``warnings.catch_warnings(record=record)`` held under the package's warnings lock."""
    with _LOCK, warnings.catch_warnings(record=record) as caught:
        yield caught
