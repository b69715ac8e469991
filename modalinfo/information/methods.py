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

import math
import numbers
from collections.abc import Callable, Iterator, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from modalinfo.common.validation import as_scalar, check_choice

__all__ = [
    "BiasRuleWarning",
    "CMI_METHODS",
    "ENTROPY_FEWEST",
    "METHODS",
    "MIMethod",
    "MethodNames",
    "call_bias_rule",
    "check_bootstrappable",
    "check_deterministic",
    "check_plugin_value",
    "get_method",
    "is_plugin",
    "option_alias_hint",
    "read_only",
    "register_method",
    "unregister_method",
    "warn_few_entropy_samples",
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
#: the package's own record of each built-in name, restored when a replacement is removed
_BUILTINS: dict[str, MIMethod] = {}


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
    if method.name in _BUILTIN_ORDER and method.name not in _BUILTINS:
        # the first record of a built-in name is the package's own, registered when its
        # module is imported: kept aside so that removing a replacement restores it
        _BUILTINS[method.name] = method
    _REGISTRY[method.name] = method
    return method


def unregister_method(name: str) -> MIMethod:
    """Remove the method ``name`` from the registry and return its record.

    A record that replaced a built-in (``register_method(..., replace=True)``) is
    removed and the built-in is registered again; the built-in record itself is removed
    for the process (adversarial round 45 PART a, R20: removing a replacement of
    ``gaussian`` removed ``gaussian``, and ``select_inputs`` called without ``method``
    was refused).

    Raises
    ------
    ValueError
        If no method of that name is registered.
    """
    record = get_method(name)
    builtin = _BUILTINS.get(record.name)
    if builtin is not None and record is not builtin:
        _REGISTRY[record.name] = builtin
    else:
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
    if (needs is not None and isinstance(name, str) and name in _REGISTRY
            and getattr(_REGISTRY[name], needs) is None):
        # a registered method without the capability: say so, not "must be one of" the
        # others as if the name were unknown (round 13, rows te-reg-*)
        able = ", ".join(repr(n) for n in MethodNames(needs))
        raise ValueError(f"`{argument}`={name!r} is registered with no `{needs}` "
                         f"function (MIMethod({needs}=...)); methods with one: {able}.")
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

    def refusal(self, name: Any, argument: str) -> str | None:
        """Return the refusal of a built-in ``name`` unregistered in this process, else None.

        ``check_choice`` (modalinfo.common.validation) raises it instead of "must be
        one of" the others, which a caller relying on a function's default method never
        passed (round 45 PART a, R31 / R32).
        """
        if isinstance(name, str) and name in _BUILTINS and name not in _REGISTRY:
            return (f"`{argument}`={name!r}: the built-in method {name!r} was unregistered "
                    "in this process (unregister_method); re-register it with "
                    f"register_method(modalinfo.information.{name}.METHOD).")
        return None

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


#: a plug-in's MI or CMI below 0 by more than this [nats] is refused: neither is ever
#: negative, and a bias correction's undershoot stays within it at the sample sizes the
#: package accepts (the 0.05 nats of the convergence rules, ``convergence._TOL_NATS``)
NEGATIVE_TOLERANCE = 0.05


#: Fewest samples of a built-in entropy estimate with its rule-chosen resolution, the
#: measured bias below it and its sign: below, its small-sample bias on normal samples
#: is above ``NEGATIVE_TOLERANCE`` (0.05 nats, the convergence rules' tolerance).
#: Measured, mean - 0.5 ln(2 pi e) (s.e.): the KDE over 60 seeds (100 at n = 25),
#: +0.140 (0.031) at n = 10, +0.062 (0.016) at 25, +0.038 (0.019) at 30 (round 48 PART a,
#: S19); the histogram (``bins`` the rule, uniform, Miller-Madow) over 200 seeds,
#: -0.289 (0.019) at n = 10, -0.126 (0.011) at 25, -0.066 (0.009) at 40, -0.045 (0.008)
#: at 50, -0.012 (0.006) at 100 (fixes 48-e). Not KSG (Kozachenko-Leonenko, k = 3): at
#: most -0.039 (0.014) over 200 seeds at n = 10-300, within the tolerance.
ENTROPY_FEWEST = {"kde": (30, "+0.14 at n = 10, +0.06 at 25", "upwards"),
                  "histogram": (50, "-0.29 at n = 10, -0.13 at 25, -0.07 at 40",
                                "downwards")}


def warn_few_entropy_samples(method: str, n: int, stacklevel: int) -> bool:
    """Warn (BiasRuleWarning) below ``ENTROPY_FEWEST[method]`` samples; return whether.

    The one small-sample rule of the entropy estimates with their rule-chosen resolution
    (the KDE's bandwidth, the histogram's bins); ``stacklevel`` counts from the caller.
    """
    from modalinfo.common.quiet import warn

    fewest, measured, sign = ENTROPY_FEWEST[method]
    if n >= fewest:
        return False
    warn(f"entropy with method={method!r} on n = {n} samples, below the rule n >= "
         f"{fewest}: its small-sample bias is above {NEGATIVE_TOLERANCE:g} nats there "
         f"({measured} on normal samples), so the estimate is biased {sign}; use more "
         "samples", BiasRuleWarning, stacklevel=stacklevel + 1)
    return True


#: Keywords that reach an estimator's options (``**options``) but name a parameter of
#: the calling function under the name another function of the package gives the same
#: concept (adversarial round 28 PART a: ``level=`` on ``mutual_information_ci`` was
#: refused as "method='histogram' does not accept option(s) level", which reads as a
#: fault of the estimator). :func:`option_alias_hint` names the parameter meant.
OPTION_ALIASES = {
    "level": "the confidence level of the interval functions is `confidence_level`",
    "confidence": "the confidence level of the interval functions is `confidence_level`",
    "n_permutations": "the number of null draws is `n_surrogates` in the conditional "
                      "tests, select_inputs and transfer_entropy_map (`n_permutations` "
                      "in mutual_information_permutation_test)",
    "n_surrogates": "the number of null draws is `n_permutations` in "
                    "mutual_information_permutation_test (`n_surrogates` in the "
                    "conditional tests, select_inputs and transfer_entropy_map)",
    "n_bootstrap": "the number of bootstrap resamples is `n_resamples`",
    "rng": "a random generator or seed is passed as `seed`",
    "random_state": "a random generator or seed is passed as `seed`",
    "lags": "transfer_entropy takes one lag as `lag` (transfer_entropy_map takes `lags`)",
    "lag": "transfer_entropy_map takes its lags as `lags` (transfer_entropy takes `lag`)",
}


def option_alias_hint(unknown: Sequence[str]) -> str:
    """Sentence naming the parameter meant by unknown options that are known aliases.

    Parameters
    ----------
    unknown : sequence of str
        Options an estimator refused.

    Returns
    -------
    str
        ``""`` when none is in ``OPTION_ALIASES``, else ``" (`level` is not an
        estimator option: the confidence level ... is `confidence_level`)"``, to append
        to the one-line refusal.
    """
    said = [f"`{name}` is not an estimator option: {OPTION_ALIASES[name]}"
            for name in unknown if name in OPTION_ALIASES]
    return f" ({'; '.join(said)})" if said else ""


def is_plugin(name: Any) -> bool:
    """Tell whether ``name`` is a method registered from outside the package (a plug-in)."""
    return name not in _BUILTIN_ORDER


def check_option_values(fn: Callable[..., Any], n: int, shapes: Sequence[Any],
                        options: dict[str, Any]) -> None:
    """Check a built-in estimator's option values where its answer needs no estimate.

    The built-in estimators check their options' values (``k >= 1``, ``bins >= 1``, a
    positive ``bandwidth``) where they meet the data, so a shortcut that answers without
    them (0.0 for a constant x or y, ``-inf`` for the entropy of a constant) accepted
    ``k=0`` (round 17). This runs ``fn`` once on a fixed standard-normal probe of the
    caller's sample size, whose result is discarded; an invalid value raises the
    estimator's own ``ValueError`` / ``TypeError`` naming the option.

    Parameters
    ----------
    fn : callable
        The estimator, ``fn(*arrays, **options)``.
    n : int
        Number of samples of the caller's data (some options are checked against it).
    shapes : sequence of int or tuple
        Column counts of the probe arrays, ``(n, c)`` each; ``()`` for a 1-D ``(n,)``.
    options : dict
        The options to check.
    """
    rng = np.random.default_rng(0)
    fn(*(rng.standard_normal((n,) + ((c,) if isinstance(c, int) else tuple(c)))
         for c in shapes), **options)


def read_only(a: np.ndarray) -> np.ndarray:
    """Return a read-only view of ``a``, what a plug-in gets: it cannot change the caller's data.

    A plug-in engine that wrote into its argument (``x *= 2``) changed the caller's
    array (adversarial round 13, row mi-reg-mutm); through this view numpy refuses the
    write with "assignment destination is read-only".
    """
    view = a.view()
    view.flags.writeable = False
    return view


def check_plugin_value(value: Any, who: str, *, allow_nan: bool = False,
                       signed: bool = False) -> float:
    """Return a plug-in's estimate as a float, or raise naming ``who`` and what was wrong.

    Parameters
    ----------
    value : object
        What the plug-in returned (an MI, a CMI or an entropy, in nats).
    who : str
        The plug-in and the call, for the message (``"method='mine': its engine's score()"``).
    allow_nan : bool
        Let NaN through (the orderings read NaN as "this candidate cannot be scored").
    signed : bool
        The quantity may be negative (a differential entropy); else a value below
        ``-NEGATIVE_TOLERANCE`` nats is refused.

    Raises
    ------
    TypeError
        Not a real number: a string, a bool, a complex, a list or an array of size > 1
        (round 13, rows ord-est-str, ord-est-bool, ord-est-list, mi-reg-strm).
    ValueError
        Infinite, NaN (unless ``allow_nan``) or negative beyond the tolerance.
    """
    value = as_scalar(value)
    if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real):
        raise TypeError(f"{who} must return a real number (nats); got {value!r}.")
    v = float(value)
    if math.isnan(v):
        if allow_nan:
            return v
        raise ValueError(f"{who} returned NaN: an estimate must be a finite number of nats.")
    if math.isinf(v):
        raise ValueError(f"{who} returned {v}: an estimate must be a finite number of nats.")
    if not signed and v < -NEGATIVE_TOLERANCE:
        raise ValueError(f"{who} returned {v:.4g} nats: a mutual information is never "
                         f"negative (more than {NEGATIVE_TOLERANCE} nats below 0 is not a "
                         "bias correction's undershoot).")
    return v


def check_deterministic(first: float, again: float, who: str) -> None:
    """Refuse a plug-in whose two scores of the same data differ (round 13, ord-est-random).

    The orderings compare candidates' scores and the intervals resample them: an
    estimator that draws unseeded noise changes the answer at every call.
    """
    if first != again and not (math.isnan(first) and math.isnan(again)):
        raise ValueError(f"{who} is not deterministic: the same data scored {first:.6g} and "
                         f"{again:.6g} nats; seed its randomness (the package's resampling "
                         "compares scores).")


def call_bias_rule(record: MIMethod, n: int, d: int, options: dict) -> str | None:
    """Call the record's ``bias_rule(n, d, options)``: None, or the sentence it returned.

    Raises
    ------
    TypeError
        The rule returned something else than None or a non-empty string (a plug-in's
        rule returning 5 was printed as the warning "5; returning the Gaussian-copula
        CMI instead", round 13, row cmi-reg-biasrule-int).
    """
    if record.bias_rule is None:
        return None
    why = record.bias_rule(n, d, options)
    if why is not None and not (isinstance(why, str) and why.strip()):
        raise TypeError(f"the bias_rule of MI method {record.name!r} must return None or a "
                        f"sentence (str) saying why the estimate is biased; got {why!r}.")
    return why
