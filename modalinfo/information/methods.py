"""The one registry of mutual-information methods: one :class:`MIMethod` record per name.

A method is everything the package asks of an estimator under one ``method=`` name:
the MI engine (``fit(x)`` / ``score(y)``), the 1-D entropy, the conditional MI of
multivariate groups, its bias rule and its capabilities. Every module that dispatches
on ``method=`` reads the record: :func:`~modalinfo.information.mutual_information`,
:class:`~modalinfo.information.MutualInformation` and
:func:`~modalinfo.information.entropy` (engine, entropy),
:func:`~modalinfo.information.conditional_mutual_information` and transfer entropy
(cmi, bias rule), the intervals (``bootstrap``), the input selection and the transfer
map (``gaussian_closed_form``), the orderings and the command line (the names).

Each built-in method registers itself at the end of its own module (``kde.py``,
``histogram.py``, ``ksg.py``, ``gaussian.py``), which the package's ``__init__``
imports. A new method is one module that defines its functions and calls
:func:`register_method`; once it is imported, ``method="<name>"`` works everywhere and
the command line offers it (docs/ARCHITECTURE.md, "To add an MI method").
"""

from __future__ import annotations

from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any

from modalinfo.common.validation import check_choice

__all__ = [
    "BiasRuleWarning",
    "CMI_METHODS",
    "METHODS",
    "MIMethod",
    "MethodNames",
    "check_bootstrappable",
    "get_method",
    "register_method",
    "unregister_method",
]


class BiasRuleWarning(UserWarning):
    """An estimate was switched (or kept) where the estimator's bias swamps it.

    Defined here, the registry's floor, so that the MI, entropy and CMI functions warn
    with one class (re-exported by ``modalinfo.information.conditional``).
    """


@dataclass(frozen=True)
class MIMethod:
    """Everything the package asks of one MI estimator, under one name.

    Attributes
    ----------
    name : str
        The ``method=`` name (non-empty, no spaces; a command-line choice).
    engine : callable
        ``engine(**options)`` returns an object with ``fit(x)`` (x a validated,
        non-constant float array of shape (n,); returns the object) and ``score(y)``
        (y of the same length, non-constant) giving I(x; y) in nats. Its keyword
        parameters are the method's MI options: any other is refused by name.
    entropy : callable or None
        ``entropy(x, **options)``: differential entropy [nats] of a validated,
        non-constant sample of shape (n,). None: :func:`~modalinfo.information.entropy`
        refuses the method.
    cmi : callable or None
        ``cmi(x, y, z, **options)``: I(X; Y | Z) [nats] of float arrays of shapes
        (n, dx), (n, dy), (n, dz) (C-contiguous, no constant column, dx, dy >= 1,
        dz >= 0). None: not a conditional estimator (refused by the CMI functions,
        the transfer entropy, the selection and the transfer map).
    bias_rule : callable or None
        ``bias_rule(n, d, options)``: a sentence naming the rule and the numbers when
        the CMI over n samples and d columns is biased beyond use, else None (see
        :func:`~modalinfo.information.bias_rule`). None: no rule.
    bootstrap : str or None
        None if the estimates may be bootstrapped; else why not (a clause, for the
        error message of the intervals): resamples repeat rows, which a
        nearest-neighbour estimator sees as zero distances.
    gaussian_closed_form : bool
        True if the CMI is the Gaussian CMI of the values' sample covariance, so that
        the input selection and the transfer-entropy map may score every candidate by
        partial correlations and least-squares residuals instead of calling ``cmi``.
    summary : str
        One line for listings.
    """

    name: str
    engine: Callable[..., Any]
    entropy: Callable[..., float] | None = None
    cmi: Callable[..., float] | None = None
    bias_rule: Callable[[int, int, dict], str | None] | None = None
    bootstrap: str | None = None
    gaussian_closed_form: bool = False
    summary: str = ""

    def __post_init__(self) -> None:
        if not isinstance(self.name, str) or not self.name or self.name != self.name.strip() \
                or any(c.isspace() for c in self.name):
            raise ValueError(f"`name` must be a non-empty string without spaces; "
                             f"got {self.name!r}.")
        if not callable(self.engine):
            raise TypeError(f"`engine` of MI method {self.name!r} must be callable; "
                            f"got {type(self.engine).__name__}.")
        for field in ("entropy", "cmi", "bias_rule"):
            value = getattr(self, field)
            if value is not None and not callable(value):
                raise TypeError(f"`{field}` of MI method {self.name!r} must be callable or "
                                f"None; got {type(value).__name__}.")
        if self.bootstrap is not None and not isinstance(self.bootstrap, str):
            raise TypeError(f"`bootstrap` of MI method {self.name!r} must be None or a "
                            f"reason (str); got {type(self.bootstrap).__name__}.")


#: name -> record, in registration order.
_REGISTRY: dict[str, MIMethod] = {}
#: The built-in names in the order the package has always listed them (messages,
#: command-line help); other methods follow in registration order.
_BUILTIN_ORDER = ("kde", "histogram", "ksg", "gaussian")


def register_method(method: MIMethod, *, replace: bool = False) -> MIMethod:
    """Register an MI method under ``method.name``.

    Parameters
    ----------
    method : MIMethod
        The record.
    replace : bool
        Allow replacing a registered method of the same name (default: refused).

    Returns
    -------
    MIMethod
        ``method``, so a module can keep it (``METHOD = register_method(...)``).

    Raises
    ------
    TypeError
        If ``method`` is not an :class:`MIMethod`.
    ValueError
        If the name is registered already and ``replace`` is False.
    """
    if not isinstance(method, MIMethod):
        raise TypeError(f"`method` must be an MIMethod record; got {type(method).__name__}.")
    if method.name in _REGISTRY and not replace:
        raise ValueError(f"`method` name {method.name!r} is registered already; pass "
                         "replace=True to replace it or choose another name.")
    _REGISTRY[method.name] = method
    return method


def unregister_method(name: str) -> MIMethod:
    """Remove the method ``name`` from the registry and return its record.

    Raises
    ------
    ValueError
        If no method of that name is registered.
    """
    record = get_method(name)
    del _REGISTRY[record.name]
    return record


def _ordered() -> list[MIMethod]:
    # one snapshot (a C-level copy, atomic under the GIL): another thread registering a
    # method while this one iterates would raise "dictionary changed size during iteration"
    registry = dict(_REGISTRY)
    first = [registry[n] for n in _BUILTIN_ORDER if n in registry]
    return first + [m for n, m in registry.items() if n not in _BUILTIN_ORDER]


def get_method(name: Any, argument: str = "method", needs: str | None = None) -> MIMethod:
    """Return the record of the registered method ``name``.

    Parameters
    ----------
    name : str
        Method name.
    argument : str
        Name of the caller's argument, for the error message.
    needs : {None, "entropy", "cmi"}
        A capability the method must have (its record field is not None).

    Raises
    ------
    ValueError
        If ``name`` is not a registered method with that capability (the message
        names the argument and lists the methods that qualify).
    """
    check_choice(name, argument, MethodNames(needs))
    return _REGISTRY[name]


class MethodNames(Sequence):
    """Live, read-only tuple-like view of the registered method names.

    Iterates, indexes, tests membership and compares equal to the tuple of the names
    at the time of the call, so ``METHODS`` imported once sees methods registered later.

    Parameters
    ----------
    needs : str or None
        A record field that must be set (``"cmi"``, ``"entropy"``) for a name to be
        listed; None lists every method.
    """

    def __init__(self, needs: str | None = None):
        self._needs = needs

    def _names(self) -> tuple[str, ...]:
        return tuple(m.name for m in _ordered()
                     if self._needs is None or getattr(m, self._needs) is not None)

    def __getitem__(self, index):
        return self._names()[index]

    def __len__(self) -> int:
        return len(self._names())

    def __iter__(self) -> Iterator[str]:
        return iter(self._names())

    def __contains__(self, value: object) -> bool:
        return value in self._names()

    def __eq__(self, other: object) -> bool:
        if isinstance(other, MethodNames):
            return self._names() == other._names()
        return self._names() == other

    # unhashable, as a list: the names change with register_method, and a hash that
    # changes lost the view from the dicts and sets it was put in (audit 10-state,
    # row hash-METHODS)
    __hash__ = None  # type: ignore[assignment]

    def __repr__(self) -> str:
        return repr(self._names())


#: Names accepted by ``method=`` of the MI and entropy functions (live view).
METHODS = MethodNames()
#: Names accepted by ``method=`` of the conditional-MI functions (live view).
CMI_METHODS = MethodNames("cmi")


def check_bootstrappable(name: Any, needs: str | None = None) -> MIMethod:
    """Return the record of ``name``, or raise ``ValueError`` if it may not be bootstrapped.

    The message names the argument, the reason (:attr:`MIMethod.bootstrap`) and the
    registered methods (with the capability ``needs``, as :func:`get_method`) that may be.
    """
    record = get_method(name, needs=needs)
    if record.bootstrap is not None:
        ok = [repr(m.name) for m in _ordered() if m.bootstrap is None
              and (needs is None or getattr(m, needs) is not None)]
        alt = ", ".join(ok[:-1]) + f" or {ok[-1]}" if len(ok) > 1 else "".join(ok)
        raise ValueError(f"`method`={name!r} cannot be bootstrapped: {record.bootstrap}; "
                         f"use {alt}.")
    return record
