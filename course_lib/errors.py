"""Named exceptions of ``course_lib`` and the small input checks that raise them; every message names
the offending input and its value, so a student learns *which* argument is wrong and *why*.
"""

from __future__ import annotations

import difflib
import functools
import inspect
import numbers
import warnings
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np

__all__ = ["CourseLibError", "UnreachableError", "ConvergenceError", "SingularJacobianError",
           "InvalidGeometryError", "InvalidArgumentError", "require_positive", "require_finite",
           "require_broadcast", "require_choice", "report_unreachable", "failure_policy", "FAILURE_POLICIES",
           "older_failure_keywords", "known_keywords"]

#: What a call does where it fails (no assembly, a singular Jacobian): raise the named error, or give NaN.
FAILURE_POLICIES = ("raise", "nan")


class CourseLibError(Exception):
    """Base class of every error raised on purpose by ``course_lib``."""


class InvalidGeometryError(CourseLibError, ValueError):
    """A length, angle, time, branch or mode label that makes no sense (and, as the base of
    :class:`InvalidArgumentError`, any other argument that does)."""


class InvalidArgumentError(InvalidGeometryError):
    """An argument that is not geometry makes no sense: a tolerance, a figure size, a dpi, a frame count,
    a callback, a failure policy.  A subclass of ``InvalidGeometryError``, so code written to catch that
    (before this class existed) still catches every misuse.

    >>> issubclass(InvalidArgumentError, InvalidGeometryError), issubclass(InvalidArgumentError, ValueError)
    (True, True)
    """


class UnreachableError(CourseLibError, ValueError):
    """The mechanism cannot be assembled for this input (no real solution); ``mask``, for arrays, is True
    at the entries that cannot."""

    def __init__(self, message: str, mask: np.ndarray | None = None):
        super().__init__(message)
        self.mask = mask


class SingularJacobianError(CourseLibError, ArithmeticError):
    """A Jacobian is singular (the core's rule, σ_min(J̃) < SINGULAR) or ill-conditioned (Newton's step test,
    ``newton.ill_conditioned``; the message says which), so a Newton step (or a rate) is undefined there.
    ``x``: the unknowns where it is (Newton's iterate, or the position found), None where not at hand;
    ``condition_number``: J's, where computed (inf when exactly singular)."""

    def __init__(self, message: str, x: Any = None, condition_number: float = np.inf):
        super().__init__(message)
        self.x = x
        self.condition_number = condition_number


class ConvergenceError(CourseLibError, RuntimeError):
    """An iteration stopped without converging; ``.result`` holds what it did."""

    def __init__(self, message: str, result: Any = None):
        super().__init__(message)
        self.result = result


def _numbers(name: str, value: Any, what: str) -> np.ndarray:
    """``value`` as a float array, or a named error: text, True/False, complex values and None are
    not numbers here, even where numpy would convert them ('90' is not 90 rad)."""
    problem = None
    if isinstance(value, str | bytes | bool | np.bool_) or value is None:
        problem = type(value).__name__
    elif isinstance(value, np.ma.MaskedArray):  # numpy would compute its masked entries too
        problem = "a masked array: its masked entries would be computed too; give the values to use"
    else:
        try:
            array = np.asarray(value)
        except (TypeError, ValueError):  # ragged nesting
            array, problem = np.zeros(0), "a ragged sequence"
        kind = array.dtype.kind
        if kind == "O" and all(isinstance(e, numbers.Real) and not isinstance(e, bool | np.bool_)
                               for e in array.ravel().tolist()):
            kind = "f"
        if kind not in "iuf":
            problem = {"b": "True/False", "c": "complex", "U": "text", "S": "text"}.get(
                kind, "something that is not a number")
    if problem is not None:
        raise InvalidGeometryError(f"{name} must be {what}; got {value!r} ({problem})")
    return np.asarray(value, dtype=float)


def require_positive(name: str, value: float, allow_zero: bool = False) -> float:
    """Return ``value`` as a float if it is a finite length > 0 (or >= 0), else raise.

    >>> require_positive("l5", 0.0, allow_zero=True)
    0.0
    """
    array = _numbers(name, value, "a number (a length in metres)")
    if array.ndim:
        raise InvalidGeometryError(f"{name} must be one number (a length in metres); got {value!r}")
    number = float(array)
    if not (np.isfinite(number) and (number >= 0 if allow_zero else number > 0)):
        kind = "non-negative" if allow_zero else "positive"
        raise InvalidGeometryError(f"{name} must be a {kind}, finite length in metres; got {value!r}")
    return number


def require_finite(name: str, value: Any, unit: str = "", allow_nan: bool = False) -> np.ndarray:
    """Return ``value`` as a float array if every entry is a finite number (or NaN, with ``allow_nan``:
    an unassembled entry), else raise.

    >>> require_finite("theta2", [0.0, 1.0]).tolist(), require_finite("q", [np.nan], allow_nan=True).tolist()
    ([0.0, 1.0], [nan])
    """
    suffix = f" in {unit}" if unit else ""
    array = _numbers(name, value, "a number or array of numbers" + suffix)
    finite = np.isfinite(array) | (np.isnan(array) if allow_nan else False)
    if not np.all(finite):
        bad = np.flatnonzero(~finite)
        where = f" (entry {bad[0]} of {array.size})" if array.ndim else ""
        raise InvalidGeometryError(f"{name} must be finite{suffix}; got {array.ravel()[bad[0]]}{where}")
    return array


def require_broadcast(**arrays: Any) -> list[np.ndarray]:
    """The named arrays broadcast to one shape, or ``InvalidGeometryError`` naming them and their shapes.

    >>> [a.shape for a in require_broadcast(theta2=np.zeros(3), omega2=1.0)]
    [(3,), (3,)]
    """
    try:
        return np.broadcast_arrays(*(np.asarray(value, dtype=float) for value in arrays.values()))
    except ValueError:
        shapes = ", ".join(f"{name} of shape {np.shape(value)}" for name, value in arrays.items())
        raise InvalidGeometryError(f"the inputs must broadcast to one shape; got {shapes}") from None


def require_choice(name: str, value: Any, choices: Iterable[Any], error: type | None = None) -> Any:
    """Return ``value`` if it is one of ``choices``, else raise ``error`` naming the valid ones
    (``InvalidGeometryError`` by default: a branch or mode label; ``InvalidArgumentError`` for a policy).

    >>> require_choice("branch", "open", ("open", "crossed"))
    'open'
    """
    choices = tuple(choices)
    if not any(value == choice and type(value) is not bool for choice in choices):
        listed = ", ".join(repr(choice) for choice in choices)
        raise (error or InvalidGeometryError)(f"{name} must be one of {listed}; got {value!r}")
    return value


#: The older spellings of ``on_failure=``, accepted with a ``DeprecationWarning`` until this version.
OLDER_FAILURE_KEYWORDS = ("on_unreachable", "on_singular")
OLDER_FAILURE_REMOVED_IN = "2.0.0"


def failure_policy(on_failure: str | None = None) -> str:
    """The one failure policy of a call: ``on_failure`` = "raise" (the default, None) or "nan".

    >>> failure_policy(), failure_policy("nan")
    ('raise', 'nan')
    """
    return "raise" if on_failure is None else require_choice("on_failure", on_failure, FAILURE_POLICIES,
                                                             InvalidArgumentError)


def older_failure_keywords(function):
    """A call's ``on_unreachable=`` or ``on_singular=`` (the older spellings of ``on_failure=``) read as
    ``on_failure=``, with a ``DeprecationWarning`` naming the removal version; two that disagree are refused.

    >>> import warnings
    >>> @older_failure_keywords
    ... def solve(x, *, on_failure=None):
    ...     return failure_policy(on_failure)
    >>> with warnings.catch_warnings(record=True) as caught:
    ...     warnings.simplefilter("always")
    ...     solve(1.0, on_unreachable="nan"), caught[0].category.__name__
    ('nan', 'DeprecationWarning')
    """

    @functools.wraps(function)
    def call(*args, **kwargs):
        older = {name: kwargs.pop(name) for name in OLDER_FAILURE_KEYWORDS if name in kwargs}
        if older:
            warnings.warn(f"{', '.join(older)}= is the older spelling of on_failure= and goes in course_lib "
                          f"{OLDER_FAILURE_REMOVED_IN}: write on_failure={next(iter(older.values()))!r}",
                          DeprecationWarning, stacklevel=2)
            given = dict(older)
            if kwargs.get("on_failure") is not None:
                given = {"on_failure": kwargs["on_failure"]} | older
            for name, value in given.items():
                require_choice(name, value, FAILURE_POLICIES)
            if len(set(given.values())) > 1:
                shown = ", ".join(f"{name}={value!r}" for name, value in given.items())
                raise InvalidArgumentError(f"on_failure and its older spelling disagree: give one; "
                                           f"got {shown}")
            kwargs["on_failure"] = next(iter(given.values()))
        return function(*args, **kwargs)

    return call


def known_keywords(function):
    """A call's misspelt keyword (``unknown=`` for ``unknowns=``) refused by ``InvalidArgumentError``
    naming it and the keyword it is closest to, instead of Python's bare ``TypeError``.

    >>> @known_keywords
    ... def solve(inputs, *, guess=None):
    ...     return guess
    >>> try:
    ...     solve(1.0, guesses=2.0)
    ... except InvalidArgumentError as error:
    ...     print(error)
    solve takes no keyword guesses= (did you mean guess=?); it takes inputs, guess
    """
    parameters = inspect.signature(function).parameters
    taken = [name for name, p in parameters.items() if name != "self"
             and p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY)]
    known, anything = frozenset(taken), any(p.kind is p.VAR_KEYWORD for p in parameters.values())
    called = function.__qualname__.split(".")[0] if function.__name__ == "__init__" else function.__name__

    @functools.wraps(function)
    def call(*args, **kwargs):
        if not anything and not known.issuperset(kwargs):
            wrong = next(name for name in kwargs if name not in known)
            close = difflib.get_close_matches(wrong, taken, n=1, cutoff=0.6) or [
                name for name in taken if wrong.startswith(name) or name.startswith(wrong)][:1]
            hint = f" (did you mean {close[0]}=?)" if close else ""
            who = type(args[0]).__name__ if function.__name__ == "__init__" and args else called
            raise InvalidArgumentError(f"{who} takes no keyword {wrong}={hint}; "
                                       f"it takes {', '.join(taken)}")
        return function(*args, **kwargs)

    return call


def report_unreachable(bad: np.ndarray, inputs: Mapping[str, Any], what: str, on_failure: str = "raise"
                       ) -> None:
    """Raise ``UnreachableError`` if any entry of the boolean mask ``bad`` is set, naming the ``inputs``
    (arrays broadcastable to ``bad``) at the first bad entry, and for arrays how many are bad.  With
    ``on_failure="nan"`` nothing is raised (the caller fills NaN).

    >>> try:
    ...     report_unreachable(np.array([False, True]), {"theta2": [0.1, 2.0]}, "the loop cannot close")
    ... except UnreachableError as err:
    ...     print(err)
    the loop cannot close at theta2=2 (1 of 2 inputs unreachable, first at index 1)
    """
    require_choice("on_failure", on_failure, FAILURE_POLICIES)
    bad = np.asarray(bad, dtype=bool)
    if on_failure == "nan" or not bad.any():
        return
    first = int(np.flatnonzero(bad)[0])
    index = np.unravel_index(first, bad.shape) if bad.ndim else ()
    values = [f"{name}={np.broadcast_to(np.asarray(value, dtype=float), bad.shape)[index]:.6g}"
              for name, value in inputs.items()]
    message = f"{what} at {', '.join(values)}"
    if bad.ndim:
        message += f" ({int(bad.sum())} of {bad.size} inputs unreachable, first at index {first})"
    raise UnreachableError(message, mask=bad)
