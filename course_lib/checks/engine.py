"""The feedback engine every checker shares: :func:`reads` checks the task's arguments first
(:func:`task_argument`, :func:`task_possible`: a bad task raises), then a parser (:func:`vector`,
:func:`integer`, :func:`word`, :func:`fields`) reads the answer; :func:`diagnose` tries (candidate,
verdict) rules in order, the reference first, then known mistakes with their hints.  Sympy answers go to
:func:`judge_expression` (sympy is imported only to judge them)."""

import contextlib
import functools
import inspect
import io
import itertools
import pathlib
import re
import sys
import types
import warnings
from collections.abc import Callable, Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from ..errors import (
    CourseLibError,
    InvalidArgumentError,
    InvalidGeometryError,
    require_choice,
    require_finite,
)
from ..planar import wrap_angle

__all__ = ["ANGLE_TOL", "RELATIVE_TOL", "MOST_TYPED", "Precision", "FIGURES", "DECIMALS", "Feedback", "reads",
           "right", "wrong", "vector", "number", "integer", "word", "fields", "choice", "close", "near",
           "angles_close", "in_degrees", "diagnose", "first", "angle_verdict", "plain", "judge_expression",
           "as_expressions", "same_equations", "task_argument", "task_possible", "procedure", "solver_code"]

#: Absolute tolerance on angles (rad) and relative tolerance on other numbers, where a checker compares
#: computed quantities (not a student's rounded numbers: those are judged by a :class:`Precision`).
ANGLE_TOL = 1e-6
RELATIVE_TOL = 1e-6


#: The most numbers :meth:`Precision.typed` reads (each one is written up to 18 ways to count its digits).
MOST_TYPED = 10_000


def _integer_argument(name: str, value: Any, low: int, high: int) -> int:
    """``value`` as an int from ``low`` to ``high``, or :class:`InvalidArgumentError` naming ``name``
    (True/False, 4.5, "4" and None are not digit counts)."""
    whole = isinstance(value, int | np.integer) and not isinstance(value, bool | np.bool_)
    if not (whole and low <= value <= high):
        raise InvalidArgumentError(f"{name} must be a whole number (an int) from {low} to {high}; "
                                   f"got {value!r}")
    return int(value)


def _reals(value: Any) -> np.ndarray | None:
    """``value`` as a float array of its own shape, or None when it is not real numbers (a string, a bool,
    None, a complex number, a dict, a ragged list, …): text is never read as a number here."""
    if _not_a_number(value):
        return None
    try:
        array = np.asarray(value)
        if array.dtype.kind == "O":
            array = np.array([float(item) for item in array.ravel().tolist()]).reshape(array.shape)
        return array.astype(float) if array.dtype.kind in "iuf" else None
    except (TypeError, ValueError, OverflowError):
        return None


def _require_reals(name: str, value: Any) -> np.ndarray:
    """``value`` as a float array, or :class:`InvalidArgumentError` naming ``name`` and what it is."""
    array = _reals(value)
    if array is None:
        what = _not_a_number(value) or "something that is not real numbers"
        raise InvalidArgumentError(f"{name} must be a number or numbers; got {value!r}, {what}")
    return array


@dataclass(frozen=True)
class Precision:
    """The precision a task states, and the rule every numeric checker keeps: an answer is right when each
    number lies within half a unit of the last digit asked for (``digits`` significant figures, or ``digits``
    decimals with ``decimals=True``; angles always compared modulo 2π); an answer right only to fewer
    digits is told to give more, never sent to recheck its method.

    >>> FIGURES.agrees(0.5975, 0.59746), FIGURES.agrees(0.597, 0.59746), FIGURES.fewer(0.597, 0.59746)
    (True, False, 3)
    >>> str(DECIMALS), DECIMALS.agrees(3.7635 - 2 * np.pi, 3.76346, angles=True)
    ('4 decimals', True)

    ``digits`` is a whole number from 1 to 17 (a float64 holds no more) and ``decimals`` a bool; anything
    else is refused by name.  Only numbers agree: text such as "1" never does.

    >>> Precision(0)
    Traceback (most recent call last):
    ...
    course_lib.errors.InvalidArgumentError: digits must be a whole number (an int) from 1 to 17; got 0
    >>> FIGURES.agrees("1", 1.0), FIGURES.agrees(True, 1.0)
    (False, False)
    """

    digits: int = 4
    decimals: bool = False
    scale: float | None = None  # significant figures of this size for every entry (a vector's length)

    def __post_init__(self) -> None:
        object.__setattr__(self, "digits", _integer_argument("digits", self.digits, 1, 17))
        if not isinstance(self.decimals, bool | np.bool_):
            raise InvalidArgumentError(f"decimals must be True (count decimals) or False (count significant "
                                       f"figures); got {self.decimals!r}")
        object.__setattr__(self, "decimals", bool(self.decimals))
        if self.scale is not None:
            scale = _reals(self.scale)
            if scale is None or scale.ndim:
                raise InvalidArgumentError(f"scale must be None or one number (the size whose significant "
                                           f"figures count); got {self.scale!r}")
            object.__setattr__(self, "scale", float(scale))

    def __str__(self) -> str:
        return f"{self.digits} {'decimals' if self.decimals else 'significant figures'}"

    def _digits(self, digits: int | None) -> int:
        """The digits asked for: this precision's own, or ``digits`` (a checker asks for fewer, down to 2
        under what is asked for an angle in degrees, so -17 to 17)."""
        return self.digits if digits is None else _integer_argument("digits", digits, -17, 17)

    def unit(self, reference, digits: int | None = None) -> np.ndarray:
        """Half a unit of the last digit asked for, per entry of ``reference`` (with 2 % slack for a
        reference that lies on a rounding boundary).  An entry that is zero beside others (below 1e-9 of
        the largest: cos 90° in a rate vector) counts as one of the vector's size, so a rate computed from an
        input rounded as asked passes; a zero reference alone counts as one of size 1e-9.

        >>> FIGURES.unit([0.5, 120.0]).tolist(), DECIMALS.unit(2.5).tolist()
        ([5.1e-05, 0.051000000000000004], 5.1e-05)
        >>> FIGURES.unit([0.73, 0.0]).tolist()
        [5.1e-05, 5.1e-05]
        """
        digits = self._digits(digits)
        reference = np.abs(_require_reals("reference", reference))
        if self.decimals:
            return np.full(reference.shape, 0.51 * 10.0 ** -digits)
        size = reference if self.scale is None else np.full(reference.shape, abs(self.scale))
        largest = reference.max() if reference.size > 1 else 0.0
        if self.scale is None and np.isfinite(largest) and largest > 0:
            size = np.where(reference <= 1e-9 * largest, largest, reference)
        exponent = np.floor(np.log10(np.maximum(size, 1e-9)))
        return 0.51 * 10.0 ** (exponent - digits + 1)

    def agrees(self, value, reference, angles=False, digits: int | None = None) -> bool:
        """Whether ``value`` is ``reference`` to this precision; ``angles`` (one bool, or one per entry)
        marks the entries compared modulo 2π; None in a tuple ``reference`` stands for any value.  A
        ``value`` that is not numbers, or not of the reference's shape, does not agree.

        >>> FIGURES.agrees((0.5975, 9.0), (0.59746, None)), FIGURES.agrees([0.5975], 0.59746)
        (True, False)
        """
        digits = self._digits(digits)
        flags = np.asarray(angles)
        if flags.dtype.kind != "b":
            raise InvalidArgumentError(f"angles must be True/False, or one True/False per entry; "
                                       f"got {angles!r}")
        kept, shape = ..., None
        if isinstance(reference, tuple) and any(r is None for r in reference):
            kept, shape = [i for i, r in enumerate(reference) if r is not None], (len(reference),)
            reference = [reference[i] for i in kept]
        references = _require_reals("reference", reference)
        shape = references.shape if shape is None else shape
        values = _reals(value)
        if values is None or values.shape != shape or values[kept].shape != references.shape:
            return False
        if not np.all(np.isfinite(values[kept])):  # NaN or inf is nothing's value (and wraps to no angle)
            return False
        try:
            flags = np.broadcast_to(flags, shape)
        except ValueError:
            raise InvalidArgumentError(f"angles must be one True/False, or one per entry of the reference "
                                       f"(shape {shape}); got {angles!r}") from None
        gaps = values[kept] - references
        gaps = np.where(flags[kept], wrap_angle(gaps, nan_ok=True), gaps)
        return bool(np.all(np.abs(gaps) <= self.unit(references, digits)))

    def of_size(self, vector) -> "Precision":
        """The same digits, counted on the size of ``vector`` for each entry (a component that should be 0,
        as cos 90°, may then be any round-off).

        >>> FIGURES.of_size([0.0, 0.06]).agrees([1e-6, 0.06], [0.0, 0.06])
        True
        """
        array = _require_reals("vector", vector)
        if not np.all(np.isfinite(array)):
            raise InvalidArgumentError(f"vector must hold finite numbers (its size counts the digits); "
                                       f"got {_shown(vector)}")
        if not array.size:
            raise InvalidArgumentError(f"vector must hold at least one number (its size counts the digits); "
                                       f"got {vector!r}")
        return Precision(self.digits, self.decimals, float(np.abs(array).max()))

    def fewer(self, value, reference, angles=False) -> int:
        """The most digits, one or two fewer than asked (and at least 2), to which ``value`` is ``reference``;
        0 when it is not even that close."""
        return next((digits for digits in range(self.digits - 1, max(self.digits - 3, 1), -1)
                     if _try(lambda d=digits: self.agrees(value, reference, angles, d))), 0)

    def typed(self, value) -> int:
        """How many digits (significant figures, or decimals) the numbers in ``value`` were written with;
        at most :data:`MOST_TYPED` numbers (each is written up to 18 ways), more are refused by name.

        >>> FIGURES.typed([0.597, 12.5]), DECIMALS.typed(3.14)
        (3, 2)
        """
        try:  # the count first, before any per-number work
            count = value.size if isinstance(value, np.ndarray) else np.size(value)
        except (TypeError, ValueError):  # a ragged list: refused below, by what it is
            count = 0
        if count > MOST_TYPED:
            raise InvalidArgumentError(f"value must hold at most {MOST_TYPED} numbers to count their digits; "
                                       f"got {count} (shape {np.shape(value)})")
        numbers = _require_reals("value", value)
        if not np.all(np.isfinite(numbers)):
            raise InvalidArgumentError(f"value must hold finite numbers to count their digits; got "
                                       f"{_shown(value)}")
        least = 0 if self.decimals else 1  # 3.0 has 0 decimals; 0.5 has 1 significant figure, not 0

        def digits(number: float) -> int:
            written = ((n, f"{{:.{n}f}}" if self.decimals else f"{{:.{n - 1}e}}") for n in range(least, 18))
            return next((n for n, text in written if float(text.format(number)) == number), 17)
        return max((digits(number) for number in numbers.ravel().tolist() if number != 0), default=0)

    def more_digits(self, value, reference, angles=False) -> "Feedback | None":
        """"Give more digits" feedback when some entries of ``value`` were written with one or two fewer
        digits than asked and are ``reference`` to every digit written, while the entries written in full are
        right as asked; else None (a number written in full but off, or off in a digit written, is not a
        rounding).
        Each entry counts its own digits.

        >>> FIGURES.more_digits((1.535, 78.2), (1.5354, 78.18))
        ✘ Not yet: right to 3 significant figures; the task asks for 4 significant figures: give more digits.
        >>> FIGURES.more_digits((1.536, 78.2), (1.5354, 78.18)) is None  # 1.536 is written in full, and off
        True
        """
        kind = "decimals" if self.decimals else "significant figures"
        values = _reals(value)
        if values is not None and not np.all(np.isfinite(values)):
            return None  # NaN or inf is no rounding of anything
        references = (list(reference) if isinstance(reference, tuple | list)
                      or isinstance(reference, np.ndarray) and reference.ndim == 1 else None)
        if values is None or values.ndim != 1 or references is None or len(references) != values.size:
            typed = self.typed(value)  # (a lower bound: trailing zeros are not seen in a number)
            if typed < self.digits and (digits := self.fewer(value, reference, angles)) and typed <= digits:
                return wrong(f"right to {digits} {kind}; the task asks for {self}: give more digits.")
            return None
        typed = [self.typed(number) if number != 0 else self.digits for number in values.tolist()]
        short = {i for i, count in enumerate(typed) if count < self.digits}
        if not short:
            return None

        def only(kept):  # the reference with the other entries free
            return tuple(r if i in kept else None for i, r in enumerate(references))

        full = set(range(values.size)) - short
        if full and not self.agrees(value, only(full), angles):
            return None
        # each short entry right to one or two digits fewer, and to every digit it was written with; a
        # zero written as a small number is not a zero written short
        scale = float(np.max(np.abs(np.asarray(references, float)))) if references else 0.0
        if any(abs(float(references[i])) <= 1e-12 * scale for i in short):
            return None
        right_to = [self.fewer(value, only({i}), angles) for i in sorted(short)]
        if all(right_to) and all(typed[i] <= d for i, d in zip(sorted(short), right_to, strict=True)):
            return wrong(f"right to {min(right_to)} {kind}; the task asks for {self}: give more digits.")
        return None


#: The usual precisions: 4 significant figures, and 4 decimals (angles in radians, lengths in metres).
FIGURES, DECIMALS = Precision(4), Precision(4, decimals=True)


@dataclass(frozen=True)
class Feedback:
    """The verdict on one answer: ``ok`` and a message, shown as one line starting with ✔ or ✘.

    >>> Feedback(True, "Correct.")
    ✔ Correct.
    """

    ok: bool
    message: str

    def __str__(self) -> str:
        return ("✔ " if self.ok else "✘ ") + self.message

    __repr__ = __str__

    def __bool__(self) -> bool:
        return self.ok


def right(message: str = "Correct.") -> Feedback:
    return Feedback(True, message)


def wrong(message: str) -> Feedback:
    return Feedback(False, "Not yet: " + message)


def _shown(value: Any, most: int = 100) -> str:
    """``repr(value)``, cut to ``most`` characters (a task argument may be a large array)."""
    try:
        text = repr(value)
    except Exception:  # a repr that fails is still named by its type
        text = f"<{type(value).__name__}>"
    return text if len(text) <= most else text[:most - 1] + "…"


#: The words that may open a number's kind in :func:`task_argument`, and what they add to "a finite number".
_MODIFIERS = {"positive": "a positive, finite number", "nonzero": "a non-zero, finite number",
              "pair": "a pair of finite numbers"}


def _class_named(kind: type) -> str:
    """A class as its call, "FourBar(crank, coupler, rocker, ground)", or its bare name."""
    try:
        parameters = inspect.signature(kind).parameters
    except (TypeError, ValueError):  # a builtin such as str has no signature
        return kind.__name__
    return f"{kind.__name__}({', '.join(parameters)})"


def task_argument(name: str, value: Any, kind: Any) -> Any:
    """A task argument — what the instructor writes in the notebook (a linkage, a crank angle, a branch), not
    the student's answer — as the checker uses it, or :class:`InvalidArgumentError` naming ``name`` and
    showing ``value``.  ``kind`` says what it must be:

    * a class (``FourBar``, ``Saw``, …): an instance of it; ``bool``: True or False;
    * a tuple of choices: one of them (returned as that choice: 1.0 for the mode 1 is the int 1);
    * a unit ("rad", "rad/s", "m", "degrees", or "" for a pure number): one finite real number (a float),
      "positive …" or "nonzero …" one that is also > 0 or ≠ 0, "pair …" two of them (a float array).

    >>> task_argument("theta2", np.float64(0.5), "rad"), task_argument("mode", 1.0, (1, -1))
    (0.5, 1)
    >>> task_argument("theta2", "abc", "rad")
    Traceback (most recent call last):
    ...
    course_lib.errors.InvalidArgumentError: theta2 must be a finite number in rad; got 'abc'
    >>> task_argument("branch", "up", ("open", "crossed"))
    Traceback (most recent call last):
    ...
    course_lib.errors.InvalidArgumentError: branch must be one of 'open', 'crossed'; got 'up'
    """
    shown = _shown(value)
    if kind is bool:
        if not isinstance(value, bool | np.bool_):
            raise InvalidArgumentError(f"{name} must be True or False; got {shown}")
        return bool(value)
    if isinstance(kind, type):
        if not isinstance(value, kind):
            raise InvalidArgumentError(f"{name} must be a {_class_named(kind)}; got {shown}")
        return value
    if isinstance(kind, tuple):
        if isinstance(value, list | np.ndarray) and any(isinstance(choice, tuple) for choice in kind):
            value = tuple(np.asarray(value, dtype=object).tolist())  # a pair such as modes, as a tuple
        try:
            if isinstance(value, np.bool_) or isinstance(value, tuple) and any(
                    isinstance(entry, bool | np.bool_) for entry in value):
                raise InvalidGeometryError(f"{name} must be one of {kind}; got {shown}")  # True is not 1
            require_choice(name, value, kind)
            return next(choice for choice in kind if bool(choice == value))
        except (InvalidGeometryError, TypeError, ValueError) as error:  # ValueError: an array's truth value
            listed = ", ".join(map(repr, kind))
            raise InvalidArgumentError(f"{name} must be one of {listed}; got {shown}") from error
    words = str(kind).split(" ", 1)
    modifier = words[0] if words[0] in _MODIFIERS else ""
    unit = (words[1] if len(words) > 1 else "") if modifier else str(kind)
    what = _MODIFIERS.get(modifier, "a finite number") + (f" in {unit}" if unit else "")
    try:
        array = require_finite(name, value, unit)
    except InvalidGeometryError as error:  # text, None, NaN, inf, a bool, a complex number, …
        raise InvalidArgumentError(f"{name} must be {what}; got {shown}") from error
    if array.shape != ((2,) if modifier == "pair" else ()):
        raise InvalidArgumentError(f"{name} must be {what}; got {shown}")
    if modifier == "positive" and not array > 0 or modifier == "nonzero" and not array != 0:
        raise InvalidArgumentError(f"{name} must be {what}; got {shown}")
    return array.copy() if modifier == "pair" else float(array)


def task_possible(compute: Callable[[], Any], problem: str) -> Any:
    """``compute()``, the reference of a task, or :class:`InvalidArgumentError` "``problem``: no reference
    answer exists for this task" where the library refuses it (the mechanism cannot be assembled there, a
    singular Jacobian) or it is not finite numbers; ``problem`` names the task argument that makes it
    impossible.

    >>> task_possible(lambda: np.sqrt(-1.0), "no crank angle theta2")
    Traceback (most recent call last):
    ...
    course_lib.errors.InvalidArgumentError: no crank angle theta2: no reference answer exists for this task
    """
    try:
        with np.errstate(all="ignore"):
            value = compute()
    except (CourseLibError, ArithmeticError, ValueError) as error:
        raise InvalidArgumentError(f"{problem}: no reference answer exists for this task ({error})") from None
    if not _finite_leaves(value):
        raise InvalidArgumentError(f"{problem}: no reference answer exists for this task")
    return value


#: course_lib's own folder: the code of a call the student's function makes is found by its file
_LIBRARY = pathlib.Path(__file__).resolve().parent.parent


def solver_code(*machines: type) -> Callable[[types.CodeType], bool]:
    """Whether a code object is one of course_lib's solves (the core in ``mechanism/``, ``motion.py``,
    ``newton.py``, and the modules of ``machines``, e.g. FourBar's) — a property of a machine (its lengths
    ``l1``, …) and the special methods (building a machine, reading a Motion's value) excepted: what a
    procedure the task asks for must not call to get its answer."""
    files = {_LIBRARY / name for name in ("motion.py", "newton.py")}
    files |= {pathlib.Path(inspect.getfile(machine)).resolve() for machine in machines}
    getters = {member.fget.__code__ for machine in machines for member in vars(machine).values()
               if isinstance(member, property) and hasattr(member.fget, "__code__")}

    def solves(code: types.CodeType) -> bool:
        if code in getters or code.co_name.startswith("__"):
            return False
        path = pathlib.Path(code.co_filename)
        return path in files or path.parent == _LIBRARY / "mechanism"

    return solves


def allowing(solves: Callable[[types.CodeType], bool], *uses: Callable[[], Any]
             ) -> Callable[[types.CodeType], bool]:
    """``solves`` (a :func:`solver_code`) with the code that each of ``uses`` runs no longer counted as a
    solve: a call the task gives the student to use inside the procedure (``bench.loop_jacobian(θ3, θ4)``: J
    is given, the rates are asked), run once here with every function it enters recorded.  A solve the task
    asks the student not to use is still one: its own code is entered first, and it is not among those.

    >>> from course_lib.fourbar import FourBar
    >>> bar = FourBar(0.07, 0.20, 0.15, 0.25)
    >>> given = allowing(solver_code(FourBar), lambda: bar.loop_jacobian(0.3, 1.2))
    >>> given(FourBar.loop_jacobian.__code__), given(inspect.unwrap(FourBar.solve).__code__)
    (False, True)
    """
    ran: set[types.CodeType] = set()

    def record(frame, event, _):
        if event == "call":
            ran.add(frame.f_code)

    previous = sys.getprofile()
    sys.setprofile(record)
    try:
        for use in uses:
            use()
    finally:
        sys.setprofile(previous)
    return lambda code: code not in ran and solves(code)


#: Seconds one call of a student's function may take in :func:`procedure` before it is reported as a hang.
PROCEDURE_SECONDS = 5.0


def procedure(function: Any, calls: Sequence[tuple], solves: Callable[[types.CodeType], bool], called: str,
              parse: Callable[[Any], Any], given: str = "floats in radians, one call per instant"
              ) -> list | Feedback:
    """The results of the student's ``function`` at each argument tuple of ``calls``, each read by
    ``parse`` — or the feedback on the first call that raises, returns what ``parse`` refuses, or calls one
    of course_lib's solves (``solves`` of its code: the task asks for the work the solve would do).  What
    the function prints is not shown; ``called`` is how the student calls it, e.g. "theta4_at(theta2)", and
    ``given`` what it is called with (said when it raises).
    Each call may take PROCEDURE_SECONDS; one that takes longer is reported as an endless loop.

    >>> from course_lib.fourbar import FourBar
    >>> bar, read = FourBar(0.07, 0.20, 0.15, 0.25), number("θ4")
    >>> procedure(lambda theta2: 2 * theta2, [(1.0,), (2.0,)], solver_code(FourBar), "function", read)
    [2.0, 4.0]
    >>> asks = procedure(lambda theta2: bar.solve(theta2).theta4, [(1.0,)], solver_code(FourBar), "function",
    ...                  read)
    >>> asks.ok, asks.message[:47]
    (False, 'Not yet: your function calls FourBar.solve, fro')
    """
    from .worked import _limited, _TimeUp  # the time limit of worked answers

    results = []
    for arguments in calls:
        solver: list[str] = []

        def watch(frame, event, _, solver=solver):
            if event == "call" and not solver and solves(frame.f_code):
                solver.append(frame.f_code.co_qualname)

        shown = ", ".join(f"{float(value):.6g}" for value in arguments)
        previous = sys.getprofile()
        sys.setprofile(watch)
        try:
            with contextlib.redirect_stdout(io.StringIO()), warnings.catch_warnings(), \
                    np.errstate(all="ignore"):
                warnings.simplefilter("ignore")
                result = _limited(PROCEDURE_SECONDS, functools.partial(function, *arguments))
        except _TimeUp:
            sys.setprofile(previous)
            return wrong(f"your {called} did not return within {PROCEDURE_SECONDS:g} s when called with "
                         f"({shown}) (an endless loop?); one call should take a moment.")
        except Exception as error:
            sys.setprofile(previous)
            text = str(error).splitlines()[0][:160] if str(error) else ""
            said = f"{type(error).__name__}: {text}" if text else type(error).__name__
            return wrong(f"your {called} raised {said} when called with ({shown}); it is called with "
                         f"{given}.")
        finally:
            sys.setprofile(previous)
        if solver:
            return wrong(f"your {called} calls {solver[0]}, from course_lib: the task asks for the work that "
                         "function does, so the check calls yours with course_lib's solves watched. Compute "
                         "the answer from the task's formulas with numpy (compare with course_lib outside "
                         "your function, if you like).")
        value = parse(result)
        if isinstance(value, Feedback):
            return wrong(f"what your {called} returns at ({shown}): "
                         + value.message.removeprefix("Not yet: "))
        results.append(value)
    return results


def _finite_leaves(value: Any) -> bool:
    """Whether every number in ``value`` (numbers, arrays, and lists or tuples of them, nested) is finite."""
    if isinstance(value, list | tuple) and not isinstance(_reals(value), np.ndarray):
        return all(map(_finite_leaves, value))
    numbers = _reals(value)
    return numbers is None or bool(np.all(np.isfinite(numbers)))


def reads(parse: Callable[[Any], Any] | None = None, task: Mapping[str, Any] | None = None,
          possible: Callable[..., Any] | None = None):
    """Make a checker of ``check``: its task arguments first — with ``task``, each one checked by
    :func:`task_argument` against its kind there (every argument after the answer must have one), then
    ``possible`` called with them all (it raises, by :func:`task_possible`, for a task that has no answer):
    a bad task raises :class:`InvalidArgumentError` whatever the answer.  Then the answer: "no answer yet"
    for None, the parser's feedback on an unreadable answer, else ``check`` on the answer as read; a
    failure while judging becomes feedback, wrong arguments raise."""

    def decorate(check):
        signature = inspect.signature(check)
        _, *arguments = signature.parameters
        if task is not None and set(arguments) != set(task):
            raise TypeError(f"{check.__name__}: give the kind of every task argument and only those: it "
                            f"takes {arguments}, task= names {list(task)}")

        @functools.wraps(check)
        def checker(answer, *args, **kwargs):
            bound = signature.bind(answer, *args, **kwargs)
            bound.apply_defaults()
            given = {name: bound.arguments[name] if task is None
                     else task_argument(name, bound.arguments[name], task[name]) for name in arguments}
            if possible is not None:
                possible(**given)
            blanks = isinstance(answer, tuple | list) and len(answer) > 0 and all(a is None for a in answer)
            if answer is None or answer is Ellipsis or blanks:
                return Feedback(False, "No answer yet: build your answer in the cell above, then run this "
                                       "check.")
            oversized = _oversized(answer)
            if oversized:  # judged by size before any work, so a check answers within moments
                return wrong(oversized)
            try:
                with np.errstate(all="ignore"):
                    value = parse(answer) if parse else answer
                    return value if isinstance(value, Feedback) else check(value, **given)
            except Exception as error:  # the last resort: a student sees feedback, not a traceback
                return wrong(f"this answer could not be checked ({type(error).__name__}); give it in the "
                             "form the task asks for.")

        return checker

    return decorate


_NOT_NUMBERS = (  # what a student is told an entry is instead of a number
    (type(None) | type(Ellipsis), "None (fill in every entry)"),
    (bool | np.bool_, "True/False (a bool is not a number)"),
    (str | bytes, "a string (drop the quotes)"),
    (complex | np.complexfloating, "a complex number"),
    (Mapping, "a dict"),
    (set | frozenset, "a set (a set has no order: use a tuple)"),
    (Iterator, "an iterator (make a list or tuple of it)"),
)


def _not_a_number(item: Any) -> str:
    """What ``item`` (or something inside it) is when it cannot be a real number; "" otherwise."""
    if phrase := next((phrase for kind, phrase in _NOT_NUMBERS if isinstance(item, kind)), ""):
        return phrase
    if isinstance(item, np.ndarray) and item.dtype.kind in "bcUSO":
        item = item.ravel().tolist()
    if isinstance(item, list | tuple):
        return next(filter(None, map(_not_a_number, item)), "")
    if getattr(item, "is_extended_real", None) is False:  # sympy's I, zoo
        return "a complex number"
    if getattr(item, "free_symbols", None):
        return "a sympy expression with symbols (substitute numbers, then take float(...))"
    return "a function (call it to get its value)" if callable(item) else ""


def _floats(answer: Any) -> tuple[np.ndarray | None, str]:
    """``answer`` as a flat float array, or None and what it is instead."""
    if problem := _not_a_number(answer):
        return None, problem
    try:
        array = np.asarray(answer)
        if array.dtype.kind not in "iuf":
            array = np.array([float(item) for item in array.ravel().tolist()])
    except OverflowError:
        return None, "a number too large for a float"
    except Exception:
        nested = isinstance(answer, list | tuple)
        return None, "a ragged nested list" if nested else f"an object of type {type(answer).__name__}"
    return array.astype(float).ravel(), ""


def _whole_result(answer: Any) -> str:
    """What a solve's whole result is, in words ("a Motion, a solve's whole result (r1, theta1, …)"), when
    ``answer`` is one (a Motion, a Newton run); "" otherwise."""
    from ..motion import Motion
    from ..newton import NewtonResult

    if isinstance(answer, Motion):
        names = list(getattr(type(answer), "_values", ()) or answer.position)
        listed = ", ".join(names[:4]) + (", …" if len(names) > 4 else "")
        return f"a {type(answer).__name__}, a solve's whole result ({listed})"
    if isinstance(answer, NewtonResult):
        return "a NewtonResult, a Newton run's whole result (x, iterations, history, …)"
    return ""


def vector(size: int | tuple[int, ...], what: str):
    """A parser: ``size`` (or any size of a tuple) finite real numbers as a float array; one as a float."""
    sizes = (size,) if isinstance(size, int) else size
    count = max(sizes)
    expected = "a number (a plain float)" if count == 1 else f"{count} plain numbers (floats)"

    def parse(answer):
        values, problem = _floats(answer)
        if values is None:
            if problem == "a complex number" and not _container(answer):
                vector_z = " (for a vector z = x + iy, give (z.real, z.imag))" if count == 2 else ""
                return wrong(f"{what} should be {expected}, not a complex number{vector_z}.")
            if problem == "a complex number":  # complex entries in a pair or list: each is one real number
                return wrong(f"{what} should be {expected}; an entry is a complex number (with j or I): each "
                             "entry is one real number.")
            return wrong(f"{what} should be {expected}, not {problem}.")
        if values.size not in sizes:
            if whole := _whole_result(answer):
                return wrong(f"{what} should be {expected}; got {whole}: take from it the "
                             f"{'value' if count == 1 else 'values'} the task asks for.")
            counted = {0: "no numbers", 1: "a single number"}.get(values.size, f"{values.size} numbers")
            shape = np.shape(answer) if isinstance(answer, np.ndarray | list | tuple) else ()
            if len(shape) > 1 and values.size > 1:
                counted += " (rows of numbers, shape {})".format("×".join(map(str, shape)))
            return wrong(f"{what} should be {expected}; got {counted}.")
        if not np.all(np.isfinite(values)):
            return wrong(f"{what} contains NaN or infinity.")
        return float(values[0]) if count == 1 else values

    return parse


number = functools.partial(vector, 1)  # a parser: one finite real number, as a float


def integer(what: str):
    """A parser: one whole number (6 or 6.0), as an int."""

    def parse(answer):
        values, problem = _floats(answer)
        if values is None or values.size != 1 or not float(values[0]).is_integer():
            return wrong(f"{what} should be a whole number" + (f", not {problem}." if problem else "."))
        return int(values[0])

    return parse


def word(choices: Sequence[str], message: str, clean=lambda text: re.sub(r"[\s_\-,()]", "", text.lower())):
    """A parser: a string that reads, cleaned (lower case, no spaces or brackets), as one of ``choices``."""
    return lambda text: clean(text) if isinstance(text, str) and clean(text) in choices else wrong(message)


def fields(what: str, *parts, keys: Sequence[str] = ()):
    """A parser: a tuple or list of len(parts) entries (or a dict with ``keys``), each read by its part."""

    def parse(answer):
        if keys and isinstance(answer, Mapping):
            if set(keys) - set(answer):
                return wrong(f"the dict needs the keys {', '.join(keys)}.")
            answer = [answer[key] for key in keys]
        answer = answer.tolist() if isinstance(answer, np.ndarray) and answer.ndim == 1 else answer
        if not isinstance(answer, list | tuple) or len(answer) != len(parts):
            got = f"{len(answer)} entries" if isinstance(answer, list | tuple) else _not_a_number(answer)
            return wrong(f"give {what}; got {_whole_result(answer) or got or 'a single value'}.")
        values = [part(entry) for part, entry in zip(parts, answer, strict=True)]
        problem = next((v for v in values if isinstance(v, Feedback)), None)
        if problem is not None and len(parts) == 2 and not any(
                isinstance(part(entry), Feedback) for part, entry in zip(parts, answer[::-1], strict=True)):
            return wrong(f"the two entries are in the other order: give {what}.")
        return values if problem is None else problem

    return parse


def choice(answer: Any, correct: str, why_not: Mapping[str, str], message: str) -> Feedback:
    """A multiple-choice answer: one letter among the keys of ``why_not`` plus ``correct``."""
    letters = sorted({*why_not, correct})
    read = word(letters, f"answer with one letter among {', '.join(letters)} (a string).")
    return reads(read)(lambda letter: right(message) if letter == correct else wrong(why_not[letter]))(answer)


def _pairs(value, reference) -> tuple[np.ndarray, np.ndarray, Any]:
    """Float arrays to compare, and the index of the entries kept: None in a tuple ``reference`` stands for
    any value."""
    kept = ...
    if isinstance(reference, tuple) and any(r is None for r in reference):
        kept = [i for i, r in enumerate(reference) if r is not None]
        reference = [reference[i] for i in kept]
    return np.asarray(value, float)[kept], np.asarray(reference, float), kept


def close(value, reference, rtol: float = RELATIVE_TOL, atol: float = 1e-12) -> bool:
    value, reference, _ = _pairs(value, reference)
    difference = np.abs(value - reference)
    return value.shape == reference.shape and bool(np.all(difference <= atol + rtol * np.abs(reference)))


#: close, with an absolute floor of 1e-9 (for quantities that may be zero)
near = functools.partial(close, atol=1e-9)


def angles_close(value, reference, tol: float = ANGLE_TOL) -> bool:
    value, reference, _ = _pairs(value, reference)
    gaps = np.abs(wrap_angle(value - reference, nan_ok=True))
    return value.shape == reference.shape and bool(np.all(gaps <= tol))


def in_degrees(value, reference, precision: Precision | None = None) -> bool:
    """True when ``value`` is ``reference`` written in degrees (modulo 360°), to ``precision`` in degrees
    (to :data:`ANGLE_TOL` without one)."""
    if precision is None:
        return angles_close(np.radians(value), reference) and not angles_close(value, reference)
    return (precision.agrees(np.radians(value), reference, angles=True, digits=precision.digits - 2)
            and not precision.agrees(value, reference, angles=True))


def _holds(matches: Callable[[Any, Any], bool], answer: Any, candidate: Any) -> bool:
    """Whether a rule's candidate fits the answer; one that cannot be computed or compared does not."""
    try:
        if isinstance(candidate, list):
            return any(_holds(matches, answer, each) for each in candidate)
        function = isinstance(candidate, types.FunctionType)
        return bool(candidate(answer) if function else matches(answer, candidate))
    except Exception:
        return False


def diagnose(answer: Any, matches: "Callable[[Any, Any], bool] | Precision", rules, otherwise: str,
             angles=False) -> Feedback:
    """The verdict of the first (candidate, verdict) rule that fits: a candidate is a value (None in a tuple:
    any entry), a list of them or a function of the answer; ✔ for the first rule, else the hint ("Not yet:
    …", a Feedback verdict as it is); the hint ``otherwise`` when none fits.  ``matches`` a
    :class:`Precision`: values are compared to it (``angles`` marks the entries compared modulo 2π), and
    an answer that is the first rule's value to fewer digits is told to give more, before any other rule.
    """
    precision = matches if isinstance(matches, Precision) else None
    if precision is not None:
        def matches(value, candidate):
            return precision.agrees(value, candidate, angles)
    for index, (candidate, verdict) in enumerate(rules):
        if _holds(matches, answer, candidate):
            return verdict if isinstance(verdict, Feedback) else (wrong if index else right)(verdict)
        if index == 0 and precision is not None and not isinstance(candidate, types.FunctionType):
            references = candidate if isinstance(candidate, list) else [candidate]
            hints = (_try(lambda r=r: precision.more_digits(answer, r, angles)) for r in references)
            hint = next((hint for hint in hints if hint is not None), None)
            # the right numbers in other units or another order, unless a rule of the checker says so itself
            if hint is None and not any(_names_units(verdict) and _holds(matches, answer, c)
                                        for c, verdict in rules[1:]):
                hints = (_try(lambda r=r: _recognise(answer, r, precision, angles)) for r in references)
                hint = next((wrong(hint) for hint in hints if hint is not None), None)
            if hint is not None and not any(  # close to the answer, and not a known mistake's value
                    not isinstance(c, types.FunctionType) and not _partial(c) and _holds(matches, answer, c)
                    for c, _ in rules[1:]):
                return hint
    return wrong(otherwise)


#: The most nodes a sympy answer may hold: every task's formula is far smaller.
MOST_NODES = 5000


def _oversized(answer) -> str | None:
    """Why an answer is too large to be any task's (a sympy expression of more than MOST_NODES nodes, or more
    than MOST_TYPED numbers), said before any work on it; None for an answer of a reasonable size."""
    if (getattr(type(answer), "__module__", None) or "").startswith("sympy"):
        import sympy as sp

        nodes = 0
        for nodes, _ in enumerate(sp.preorder_traversal(answer), start=1):
            if nodes > MOST_NODES:
                return (f"this expression holds more than {MOST_NODES} terms and symbols; the task's answer "
                        "is a short formula of the symbols it names.")
        return None
    try:
        count = int(answer.size if isinstance(answer, np.ndarray) else np.size(answer))
    except Exception:  # an answer numpy cannot size is judged (and refused) by the checker's own reading
        return None
    if count > MOST_TYPED:
        return f"this answer holds {count:,} numbers; the task asks for a few: give just those."
    return None


def _names_units(verdict) -> bool:
    """Whether a rule's hint is itself about units or order (then it speaks, not the general reading)."""
    text = (verdict.message if isinstance(verdict, Feedback) else str(verdict)).lower()
    return any(word in text for word in ("mm", "millimet", "degree", "order", "swap", "rpm", "ms ", "milli"))


#: Units a student may have used instead of SI: (factor from SI, what it looks like).
_OTHER_UNITS = ((1e3, "in milli-units (mm, ms or mm/s: 1000 times the SI value)"),
                (180 / np.pi, "in degrees (or deg/s, deg/s²) where the task asks for radians"),
                (30 / np.pi, "in rpm where the task asks for rad/s"),
                (np.pi / 30, "in rad/s where the task asks for rpm"),
                (1e-3, "in kilo-units, or SI where milli-units (mm, ms) are asked: 1/1000 of the value"))


def _recognise(answer, reference, precision: Precision, angles=False) -> str | None:
    """What makes a wrong answer the right numbers after all: an entry (or all) in other units, or the
    entries in another order; None when neither does.  Entries are counted from 1."""
    if isinstance(reference, tuple) and any(r is None for r in reference):
        return None
    values, references = _reals(answer), _reals(reference)
    if values is None or references is None or values.shape != references.shape or values.ndim > 1:
        return None
    flat = np.atleast_1d(values).astype(float)
    size = flat.size
    sizes = np.abs(np.atleast_1d(references))
    zero = sizes <= 1e-9 * sizes.max()  # an entry that is zero: no unit shows on it
    for factor, looks in _OTHER_UNITS:
        if precision.agrees(flat / factor, np.atleast_1d(references), angles):
            return f"{'your answer is' if size == 1 else 'every entry is'} the right value {looks}."
        for i in (i for i in range(size if size > 1 else 0) if not zero[i]):
            scaled = flat.copy()
            scaled[i] /= factor
            if precision.agrees(scaled, references, angles):
                return f"entry {i + 1} is the right value {looks}."
    if 1 < size <= 6:
        for order in itertools.permutations(range(size)):
            if list(order) != list(range(size)) and precision.agrees(flat[list(order)], references, angles):
                return ("these are the right numbers in another order: give them in the order the task "
                        "lists them.")
    return None


def _partial(candidate) -> bool:
    """Whether a rule's candidate leaves some entries free (None in a tuple)."""
    return isinstance(candidate, tuple) and any(entry is None for entry in candidate)


def _try(compute: Callable[[], Any]) -> Any:
    """``compute()``, or None when it cannot be computed."""
    try:
        return compute()
    except Exception:
        return None


def first(rules, correct: str) -> Feedback:
    """The hint of the first (condition, hint) rule whose condition is True; ✔ ``correct`` when none is."""
    return next((wrong(hint) for condition, hint in rules if condition), right(correct))


def angle_verdict(value: float, reference: float, alternatives, otherwise: str,
                  precision: Precision = DECIMALS) -> Feedback:
    """An angle (rad) judged modulo 2π to ``precision``: right, another known angle (each with its hint), or
    in degrees."""
    return diagnose(value, precision, [
        (reference, f"Correct (to {precision}; angles are compared modulo 2π)."),
        *alternatives,
        (lambda v: in_degrees(v, reference, precision), "that is the right angle in degrees; the course (and "
                                                        "course_lib) works in radians."),
        *((lambda v, o=other: in_degrees(v, o, precision), "that is in degrees — and " + hint)
          for other, hint in alternatives),
    ], otherwise, angles=True)


def _evaluate(expr, names: Sequence[str], count: int = 6) -> tuple[np.ndarray, list]:
    """``expr`` at random points: lengths in [0.5, 2], everything else in [−1.4, 1.4] (fixed seed)."""
    import sympy as sp
    generator = np.random.default_rng(20240601)
    ranges = [(0.5, 2.0) if re.fullmatch(r"l\d|r\d|r1y", name) else (-1.4, 1.4) for name in names]
    points = [[generator.uniform(*limits) for limits in ranges] for _ in range(count)]
    function = sp.lambdify(sp.symbols(names, real=True), expr, modules="numpy")
    return np.array([complex(function(*point)) for point in points]), points


def same(expr, reference, names: Sequence[str]) -> bool:
    """Algebraically equal: equal at random points in double precision, then at three of them to 30
    digits (evaluated with 40).  Not ``sympy.simplify``: its run time depends on the hash seed."""
    import sympy as sp
    (a, points), (b, _) = _evaluate(expr, names), _evaluate(reference, names)
    if not np.allclose(a, b, rtol=1e-9, atol=1e-12):
        return False
    for point in points[:3]:
        values = {s: sp.Float(v, 40) for s, v in zip(sp.symbols(names, real=True), point, strict=True)}
        scale = abs(sp.N(reference.xreplace(values), 40)) + 1
        if not abs(sp.N((expr - reference).xreplace(values), 40)) < 1e-30 * scale:
            return False
    return True


def proportional(expr, reference, names: Sequence[str]) -> bool:
    """expr = k·reference for a nonzero constant k (the same equation expr = 0)."""
    import sympy as sp
    (a, _), (b, _) = _evaluate(expr, names), _evaluate(reference, names)
    ratio = a / b
    if (np.any(np.abs(b) < 1e-9) or not np.all(np.isfinite(a)) or not 1e-12 < abs(ratio[0])
            or abs(ratio[0].imag) >= 1e-12 or not np.allclose(ratio, ratio[0], rtol=1e-9, atol=0)):
        return False
    return same(expr, sp.nsimplify(ratio[0].real, rational=True) * reference, names)


def plain(answer: Any, names: Sequence[str]):
    """One sympy expression in the symbols ``names``: θ(t) → θ, every symbol real (its assumptions
    ignored), "a = b" read as a − b (as b for "ω4 = b"); the feedback instead when it is not one."""
    import sympy as sp

    from ..symbolic import static

    if isinstance(answer, str):
        return wrong("build a sympy expression (not a string), e.g. with sp.symbols.")
    if held := _container(answer):
        return wrong(f"that is {held}, not one sympy expression: give the expression itself.")
    try:
        problem = "" if hasattr(answer, "free_symbols") else _not_a_number(answer)
        expr = None if problem else sp.sympify(answer, strict=True)
    except Exception:
        problem = f"an object of type {type(answer).__name__}"
    if problem:
        return wrong(f"that is not a sympy expression but {problem}; build one from sp.symbols(...).")
    if isinstance(expr, sp.Equality):  # "new = formula", either way round: the formula; else lhs − rhs
        if expr.lhs.is_Symbol and expr.lhs.name not in names:
            expr = expr.rhs
        elif expr.rhs.is_Symbol and expr.rhs.name not in names:
            expr = expr.lhs
        else:
            expr = expr.lhs - expr.rhs
    if not isinstance(expr, sp.Expr) or getattr(expr, "is_Matrix", False):
        what = _container(expr) or f"a sympy {type(expr).__name__}"
        return wrong(f"that is {what}, not one sympy expression (a formula such as l2*sp.cos(theta2)).")
    if expr.atoms(sp.Derivative):
        return wrong("your expression still holds a Derivative(θ(t), t); write it with ω "
                     "(course_lib.symbolic.d_dt does that) or with plain symbols.")
    if expr.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        return wrong("your expression is infinite or undefined — a division by zero?")
    expr = static(expr)
    expr = expr.xreplace({s: sp.Symbol(s.name, real=True) for s in expr.free_symbols})
    if extra := sorted(s.name for s in expr.free_symbols if s.name not in names):
        return wrong(f"your expression uses symbols the task does not define: {', '.join(extra)} "
                     f"(allowed: {', '.join(names)}).")
    return expr if expr.free_symbols else wrong(f"that holds no symbol: the task asks for a formula in "
                                                f"{', '.join(names)}.")


def _is_array(answer: Any) -> bool:
    """Whether ``answer`` is a sympy Array (an N-dim array: it is neither a Matrix nor an expression)."""
    if not (getattr(type(answer), "__module__", None) or "").startswith("sympy"):
        return False
    from sympy import NDimArray  # sympy is imported already: the answer is one of its objects

    return isinstance(answer, NDimArray)


def _container(answer: Any) -> str:
    """What holds several entries, in words ("a list of 2", "a 2×1 Matrix", "a sympy Array of 2", "a numpy
    array of 3"); "" for anything else (an expression, a number, a string)."""
    if isinstance(answer, Mapping):
        return f"a dict of {len(answer)}"
    if getattr(answer, "is_Matrix", False):
        return "a {}×{} Matrix".format(*answer.shape)
    if _is_array(answer):
        return f"a sympy Array of {len(answer)}" if answer.rank() == 1 else \
            "a sympy Array of shape {}".format("×".join(map(str, answer.shape)))
    if isinstance(answer, np.ndarray):
        return f"a numpy array of {answer.size}" if answer.ndim <= 1 else \
            "a numpy array of shape {}".format("×".join(map(str, answer.shape)))
    if isinstance(answer, list | tuple):
        return f"a {type(answer).__name__ if type(answer) in (list, tuple) else 'sequence'} of {len(answer)}"
    return ""


def _items(answer: Any) -> list[tuple[Any, Any]]:
    """The entries (label, entry) of a container (:func:`_container`), flattened row by row."""
    if isinstance(answer, Mapping):
        return [(str(k), v) for k, v in answer.items()]
    if _is_array(answer):
        return list(enumerate(_flatten(answer.tolist())))
    if isinstance(answer, np.ndarray):
        return list(enumerate(np.ravel(np.array(answer, dtype=object))))
    return list(enumerate(answer))  # a Matrix iterates over its entries, row by row


def _flatten(nested: Any) -> list:
    return [leaf for item in nested for leaf in (_flatten(item) if isinstance(item, list) else [item])] \
        if isinstance(nested, list) else [nested]


def _entries(answer: Any) -> tuple[Any, str]:
    """A lone entry out of one-element containers; else the entries (label, entry) and what holds them."""
    while True:
        kind = _container(answer)
        if not kind:
            return answer, ""
        entries = _items(answer)
        if len(entries) != 1:
            return entries, kind if entries else "empty"
        answer = entries[0][1]


def _lone(entry: Any) -> Any:
    """An entry out of the one-element containers around it ([x], Matrix([x]), np.array([x]))."""
    inner, kind = _entries(entry)
    return entry if kind else inner


def as_expressions(answer: Any) -> list:
    """The equations of an answer as the checkers read them: one sympy expression per equation, each equal to
    zero.  ``sp.Eq(lhs, rhs)`` is ``lhs − rhs`` (a Matrix equation gives one per row); a list, tuple, Matrix,
    sympy Array or numpy array gives its entries (a one-entry container around an entry is taken off); an
    expression alone is one equation.  Later cells of an exercise use it to take any form its check accepts.

    >>> import sympy as sp
    >>> x, y = sp.symbols("x y")
    >>> as_expressions([sp.Eq(x, 2 * y), [y - 1]])
    [x - 2*y, y - 1]
    >>> as_expressions(sp.Eq(sp.Matrix([x, y]), sp.Matrix([1, 2])))
    [x - 1, y - 2]
    """
    import sympy as sp

    if isinstance(answer, sp.Equality):
        answer = answer.lhs - answer.rhs
    entries, kind = _entries(answer)
    rows = [_lone(entry) for _, entry in entries] if kind else [entries]
    return [row.lhs - row.rhs if isinstance(row, sp.Equality) else row for row in rows]


def same_equations(rows: Any, reference: Sequence) -> bool:
    """Whether ``rows`` (any form :func:`as_expressions` reads) are the equations ``reference`` (expressions
    equal to zero), each up to a non-zero constant factor, in any order: the rule the checkers apply.

    >>> import sympy as sp
    >>> x, y = sp.symbols("x y")
    >>> same_equations([2 * y - 2, sp.Eq(x, y)], [x - y, y - 1]), same_equations([x - y], [x - y, y - 1])
    (True, False)
    """
    import sympy as sp

    rows, reference = as_expressions(rows), [sp.sympify(expr) for expr in reference]
    names = sorted({symbol.name for expr in reference for symbol in expr.free_symbols})
    exprs = [plain(row, names) for row in rows]
    real = [plain(expr, names) for expr in reference]
    if len(exprs) != len(real) or any(isinstance(expr, Feedback) for expr in exprs + real):
        return False
    return any(all(_try(lambda a=a, b=b: proportional(a, b, names)) for a, b in zip(order, real, strict=True))
               for order in itertools.permutations(exprs))


def judge_expression(answer: Any, symbols: Sequence, rules, otherwise: str, system: str = "") -> Feedback:
    """A sympy answer in ``symbols`` (or their names) judged by :func:`diagnose`, the reference first:
    one expression compared by :func:`same` (a Matrix or list of them is told which element to pass), or
    with ``system`` (how to give it) equations "= 0", each up to a constant factor, in any order."""
    names = tuple(map(str, symbols))

    def matches(expr, candidate):
        return not isinstance(expr, Feedback) and same(expr, candidate, names)

    if system:
        return _judge_system(answer, names, rules, otherwise, system)
    entries, kind = _entries(answer)
    if kind:
        hits = [label for label, entry in entries if _holds(matches, plain(entry, names), rules[0][0])]
        where = f"pass its element [{hits[0]}] alone" if hits else "pick the one element the task asks for"
        return wrong(f"that is {kind}; the task asks for one expression: "
                     + ("build it from sp.symbols(...)." if kind == "empty" else where + "."))
    expr = plain(entries, names)
    return expr if isinstance(expr, Feedback) else diagnose(expr, matches, rules, otherwise)


def _judge_system(answer: Any, names: Sequence[str], rules, otherwise: str, system: str) -> Feedback:
    """Equations "= 0" judged as a set (:func:`judge_expression` with ``system``): the rows as
    :func:`as_expressions` reads them (an equation is lhs − rhs), each read by :func:`plain`."""
    import sympy as sp

    count = len(rules[0][0])
    relation = sp.core.relational.Relational
    if getattr(answer, "is_Matrix", False) and any(isinstance(entry, relation) for entry in answer):
        return wrong(f"that is a Matrix of equations (sp.Eq rows), which sympy warns against: a Matrix holds "
                     f"expressions. Give {system}, each an expression equal to zero (or a list of sp.Eq).")
    whole = answer.lhs - answer.rhs if isinstance(answer, sp.Equality) else answer
    kind = _entries(whole)[1]
    rows = as_expressions(answer)
    complex_loop = any(isinstance(row, sp.Basic) and row.has(sp.I) and _try(lambda row=row: sp.expand_complex(
        row.xreplace({s: sp.Symbol(s.name, real=True) for s in row.free_symbols})).has(sp.I)) for row in rows)
    if complex_loop and len(rows) < count:
        return wrong(f"that is the loop as one complex number z = x + i·y (each vector l·e^(iθ)); the task "
                     f"asks for its {count} real components: give {system} — sp.re(z) and sp.im(z) with "
                     "real symbols, or each component written with cos and sin.")
    if len(rows) != count:
        if kind:
            got = _container(whole)
        elif isinstance(whole, sp.Expr):
            got = "one equation" if isinstance(answer, sp.Equality) else "one expression"
        else:
            got = _not_a_number(whole) or f"an object of type {type(whole).__name__}"
        return wrong(f"give {system}; got {got}.")
    if complex_loop:
        return wrong("a component holds the imaginary unit I: each component is real — take sp.re(z) and "
                     "sp.im(z) of the complex loop (with real symbols), or write them with cos and sin.")
    exprs = [plain(row, names) for row in rows]
    problem = next((expr for expr in exprs if isinstance(expr, Feedback)), None)
    return problem if problem is not None else diagnose(exprs, lambda exprs, candidate: any(
        all(proportional(a, b, names) for a, b in zip(order, candidate, strict=True))
        for order in itertools.permutations(exprs)), rules, otherwise)
