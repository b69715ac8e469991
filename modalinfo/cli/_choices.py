"""Command-line choices read from a registry when they are first needed.

``--estimator`` and ``--method`` offer the registered MI methods
(:mod:`modalinfo.information.methods`): a method registered before the parser runs is
a valid choice. The registry is imported on the first membership test or listing (a
value given, ``--help``, an error), not when the parser is built: importing
``modalinfo.information`` costs about a second that ``modalinfo info`` need not pay.
"""

from __future__ import annotations

from collections.abc import Iterator

__all__ = ["MIMethodChoices"]


class MIMethodChoices:
    """The registered MI method names, for ``argparse``'s ``choices=`` (give a ``metavar``).

    Parameters
    ----------
    needs : {None, "cmi", "entropy"}
        A capability every listed method has (None: every method).
    """

    def __init__(self, needs: str | None = None):
        self.needs = needs

    def _names(self) -> tuple[str, ...]:
        from modalinfo.information.methods import MethodNames

        return tuple(MethodNames(self.needs))

    def __contains__(self, value: object) -> bool:
        return value in self._names()

    def __iter__(self) -> Iterator[str]:
        return iter(self._names())
