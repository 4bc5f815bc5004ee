"""The worked answer of a lesson's "Try it", kept hidden in every viewer and still proved right.

A lesson writes its worked answer in a markdown cell, inside ``<details>``: GitHub, nbviewer, nbconvert's
HTML, JupyterLab and the course website all keep it folded until the reader opens it.  The answer holds a
```python block and, right after it, a ```text block with what that code prints.  :func:`run_worked_answer`
reads the lesson file, runs that code on the lesson's variables and checks that it prints exactly the text
shown, so the cell after the answer can assert that the printed answer passes the Try-it's own checker —
without showing the answer in its source.

Where the lesson file is not in the working folder (Colab, a kernel started elsewhere, the lesson run as a
``.py`` script), the answers come from the copy course_lib ships, :data:`WORKED_ANSWERS_FILE`, written by
``python tools/package_data.py`` from the lessons (``tests/test_run_anywhere.py`` keeps it equal to them);
the notebook file, when it is there, wins.

The answer runs in a box: on deep copies of the lesson's variables (the lesson's own are never changed),
with a time limit, and with ``input()`` refused; a hang, an ``exit()``, a request for input or an
exception in the answer is a :class:`WorkedAnswerError` naming the notebook and the cell.
"""

from __future__ import annotations

import builtins
import contextlib
import copy
import ctypes
import io
import json
import math
import numbers
import os
import re
import sys
import threading
import time
import traceback
import types
from collections.abc import Callable, Iterable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import CourseLibError, InvalidArgumentError

__all__ = ["WorkedAnswer", "WorkedAnswerError", "worked_answers", "run_worked_answer", "WORKED_TIMEOUT",
           "WORKED_ANSWERS_FILE", "packaged_answers"]

_FENCE = re.compile(r"```python\n(?P<code>.*?)```\s*```text\n(?P<printed>.*?)```", re.S)

#: Seconds a worked answer may run by default: the slowest lesson answer (lesson 12, sympy) takes about 1 s
#: on a fresh kernel, and a shared machine (Binder, CI on two busy cores) may be several times slower.
WORKED_TIMEOUT = 10.0

#: The lessons' worked answers as course_lib ships them (package data): lesson file name → its answers,
#: each ``{"cell": n, "code": …, "printed": …}``; read where the lesson file is not at hand.
WORKED_ANSWERS_FILE = Path(__file__).with_name("worked_answers.json")

#: Names through which code reaches every variable by its name as text: with one of them, the answer works
#: on a copy of every variable, not only of those it names.
_EVERY_NAME = frozenset({"globals", "vars", "locals", "eval", "exec"})

#: IPython's own entries of a lesson's ``globals()`` (its input and output history, its shell), never copied.
_SHELL_NAMES = frozenset({"__builtins__", "In", "Out", "_ih", "_oh", "_dh", "get_ipython", "exit", "quit"})

#: Objects shared with the lesson, never copied: modules, functions, classes (``copy`` shares most already).
_SHARED = (types.ModuleType, types.FunctionType, types.BuiltinFunctionType, types.MethodType, type)


class WorkedAnswerError(CourseLibError):
    """A lesson's worked answer cannot be found, fails (an exception, a hang, an ``exit()``, a request for
    input) or does not print what it shows."""


class _Stopped(BaseException):
    """Raised into a worked answer to stop it (a BaseException, so ``except Exception`` in it cannot keep
    it running)."""


class _TimeUp(_Stopped):
    """The answer ran past its time limit."""


class _InputAsked(_Stopped):
    """The answer called ``input()`` (or ``breakpoint()``): nobody is there to type."""


@dataclass(frozen=True)
class WorkedAnswer:
    """A worked answer: its ``code``, the text it ``printed`` and the ``names`` it defined."""

    code: str
    printed: str
    names: Mapping[str, Any]

    def __float__(self) -> float:
        return float(self.printed)

    @property
    def numbers(self) -> tuple[float, ...]:
        """The numbers in the printed text, in order (not the digits of names such as theta2 or X3).

        >>> WorkedAnswer("", "theta2 = 1.4192 rad (81.32 deg), X3 = -2e-3 m", {}).numbers
        (1.4192, 81.32, -0.002)
        """
        pattern = r"(?<![\w.])[-+]?\d+(?:\.\d*)?(?:[eE][-+]?\d+)?"
        return tuple(float(text) for text in re.findall(pattern, self.printed))


def _path(notebook: Any) -> Path:
    """``notebook`` as a Path, or :class:`InvalidArgumentError` for what is not a file name."""
    if not isinstance(notebook, str | os.PathLike) or isinstance(notebook, bytes):
        raise InvalidArgumentError(f"notebook must be the lesson's file name (a str or Path, such as "
                                   f"'00_start_here.ipynb'); got {notebook!r}")
    return Path(notebook)


def _answers(notebook: str | Path) -> list[tuple[int, str, str]]:
    """(cell number counted from 1, code, printed text) of each worked answer folded in ``notebook``: read
    from the file when it is there, else from course_lib's copy of the lesson's answers."""
    path = _path(notebook)
    if not path.is_file():
        shipped = _shipped().get(path.name)
        if shipped is None:
            raise WorkedAnswerError(f"notebook {str(notebook)!r} is not a file here, and course_lib holds no "
                                    "copy of its worked answers: run the lesson from its own folder")
        return [(answer["cell"], answer["code"], answer["printed"]) for answer in shipped]
    try:
        content = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError) as error:
        raise WorkedAnswerError(f"notebook {str(notebook)!r} cannot be read as text: {error}") from None
    except json.JSONDecodeError as error:
        raise WorkedAnswerError(f"notebook {str(notebook)!r} is not a notebook (a .ipynb file is JSON): "
                                f"{error}") from None
    cells = content.get("cells") if isinstance(content, dict) else None
    if not isinstance(cells, list):
        raise WorkedAnswerError(f"notebook {str(notebook)!r} is not a notebook: it has no list of \"cells\"; "
                                f"got {_short(content)}")
    found = []
    for number, cell in enumerate(cells, start=1):
        if not isinstance(cell, dict) or "cell_type" not in cell:
            raise WorkedAnswerError(f"cell {number} of notebook {str(notebook)!r} is not a notebook cell "
                                    f"(it has no \"cell_type\"); got {_short(cell)}")
        source = cell.get("source", "")
        if isinstance(source, list) and all(isinstance(line, str) for line in source):
            source = "".join(source)
        if not isinstance(source, str):
            raise WorkedAnswerError(f"cell {number} of notebook {str(notebook)!r} has a \"source\" that is "
                                    f"not text; got {_short(source)}")
        if cell["cell_type"] == "markdown" and "<details" in source:
            found += [(number, match["code"], match["printed"]) for match in _FENCE.finditer(source)]
    return found


def _shipped() -> dict[str, list[dict[str, Any]]]:
    """The content of :data:`WORKED_ANSWERS_FILE` (empty when it is missing: a checkout before its first
    ``tools/package_data.py``)."""
    try:
        return json.loads(WORKED_ANSWERS_FILE.read_text(encoding="utf-8"))
    except FileNotFoundError:
        return {}


def packaged_answers(notebooks: Iterable[str | Path]) -> dict[str, list[dict[str, Any]]]:
    """The worked answers of ``notebooks`` as :data:`WORKED_ANSWERS_FILE` holds them: each lesson's file name
    → its answers in order, ``{"cell": n, "code": …, "printed": …}`` (cells counted from 1).

    >>> import tempfile
    >>> cell = {"cell_type": "markdown", "metadata": {},
    ...         "source": "<details>\\n\\n```python\\nprint(2)\\n```\\n```text\\n2\\n```\\n</details>"}
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder, "lesson.ipynb")
    ...     _ = path.write_text(json.dumps({"cells": [{"cell_type": "code", "source": ""}, cell]}))
    ...     packaged_answers([path])
    {'lesson.ipynb': [{'cell': 2, 'code': 'print(2)\\n', 'printed': '2\\n'}]}
    """
    if isinstance(notebooks, str | bytes | os.PathLike) or not isinstance(notebooks, Iterable):
        raise InvalidArgumentError(f"notebooks must be a list of lesson file names (str or Path); "
                                   f"got {_short(notebooks)}")
    found = {}
    for notebook in notebooks:
        answers = _answers(notebook)  # the name checked first
        found[Path(notebook).name] = [{"cell": cell, "code": code, "printed": printed}
                                      for cell, code, printed in answers]
    return found


def _short(value: Any, most: int = 80) -> str:
    """``repr(value)``, cut to ``most`` characters."""
    text = repr(value)
    return text if len(text) <= most else text[:most - 1] + "…"


def worked_answers(notebook: str | Path) -> list[tuple[str, str]]:
    """The (code, printed text) pairs of the worked answers folded in ``<details>`` in ``notebook``.

    >>> import tempfile
    >>> cell = {"cell_type": "markdown", "metadata": {}, "source": "<details><summary>Answer</summary>\\n\\n"
    ...         "```python\\nprint(6 * 7)\\n```\\n```text\\n42\\n```\\n</details>"}
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder, "lesson.ipynb")
    ...     _ = path.write_text(json.dumps({"cells": [cell]}))
    ...     worked_answers(path)
    [('print(6 * 7)\\n', '42\\n')]
    """
    return [(code, printed) for _, code, printed in _answers(notebook)]


def _global_names(code: types.CodeType) -> set[str]:
    """Every name ``code`` (and the functions, classes and comprehensions in it) looks up or sets."""
    names = set(code.co_names)
    for constant in code.co_consts:
        if isinstance(constant, types.CodeType):
            names |= _global_names(constant)
    return names


def _copied(namespace: Mapping[str, Any], wanted: set[str] | None) -> dict[str, Any]:
    """A dict of ``namespace`` where the values of the names in ``wanted`` (all of them when None, but
    IPython's own) are deep copies, sharing one memo so that two names for one object stay one object; a
    value that cannot be deep-copied (a module, a function, an open file) is the object itself."""
    names, memo = dict(namespace), {}
    for name, value in names.items():
        if (name in _SHELL_NAMES or (wanted is not None and name not in wanted)
                or isinstance(value, _SHARED)):
            continue
        trial = dict(memo)  # a failed copy leaves half-made objects in its memo: keep them out
        try:
            names[name] = copy.deepcopy(value, trial)
        except Exception:  # noqa: S112 — not copyable: the answer gets the object itself
            continue
        memo = trial
    return names


def _refuse(name: str) -> Callable[..., None]:
    """A stand-in for the builtin ``name`` (``input``, ``breakpoint``) that raises :class:`_InputAsked`."""
    def refuse(*args: Any, **kwargs: Any) -> None:
        raise _InputAsked(name)
    refuse.__name__ = refuse.__qualname__ = name
    return refuse


def _exit(code: Any = None) -> None:
    raise SystemExit(code)


def _boxed_builtins(namespace: Mapping[str, Any]) -> dict[str, Any]:
    """The lesson's builtins, with ``input`` and ``breakpoint`` refused and ``exit``/``quit`` raising
    SystemExit (IPython's would end the kernel; the interpreter's close ``sys.stdin``)."""
    base = namespace.get("__builtins__", builtins)
    base = vars(base) if isinstance(base, types.ModuleType) else base
    boxed = dict(base) if isinstance(base, Mapping) else dict(vars(builtins))
    boxed.update(input=_refuse("input"), breakpoint=_refuse("breakpoint"), exit=_exit, quit=_exit)
    return boxed


def _async_raiser() -> Callable[[int], int] | None:
    """A function raising :class:`_TimeUp` in the thread of that id at its next bytecode (CPython's
    ``PyThreadState_SetAsyncExc``), or None where there is no such C API (PyPy).  It is never called to
    clear a pending one: CPython would then keep its eval breaker set for good, which slows every later
    loop and stops trace functions (debuggers, coverage) from seeing lines."""
    function = getattr(getattr(ctypes, "pythonapi", None), "PyThreadState_SetAsyncExc", None)
    if function is None:
        return None
    return lambda thread: function(ctypes.c_ulong(thread), ctypes.py_object(_TimeUp))


def _checkpoint() -> None:
    """Nothing: calling a Python function makes the interpreter raise a pending asynchronous exception."""


def _limited(seconds: float, run: Callable[[], Any]) -> Any:
    """``run()``, with :class:`_TimeUp` raised in it once ``seconds`` have passed, and again every 0.1 s
    while it still runs (an ``except BaseException`` that swallows one stop meets the next; only code that
    swallows every one, in a loop, could outrun them).

    A watcher thread raises it in this thread (CPython's ``PyThreadState_SetAsyncExc``): no cost while
    the code runs, any thread (a Jupyter kernel, a pytest-xdist worker), no signal handler and no trace
    function taken from a debugger.  Without that C API, a trace function checks the clock at every line
    instead.  Code blocked inside one C call (``time.sleep``) stops only when that call returns.
    """
    raiser = _async_raiser()
    if raiser is None:
        return _traced(seconds, run)
    target, gate, finished = threading.get_ident(), threading.Lock(), threading.Event()

    def watch() -> None:
        wait = seconds
        while not finished.wait(wait):
            if not gate.acquire(blocking=False):  # run() has ended: the gate is closed for good
                return
            try:
                raiser(target)
            finally:
                gate.release()
            wait = 0.1

    threading.Thread(target=watch, name="worked-answer time limit", daemon=True).start()
    try:
        return run()
    finally:
        # The first call after run() closes the gate (no Python code runs between): no stop is raised
        # after it.  One raised just before is raised here, at the latest when _checkpoint() is called,
        # and reported as the hang it nearly was; none is left pending for the lesson's own code.
        gate.acquire()
        try:
            _checkpoint()
        finally:
            finished.set()


def _traced(seconds: float, run: Callable[[], Any]) -> Any:
    """:func:`_limited` by a trace function (where there is no ``PyThreadState_SetAsyncExc``): each line
    run checks the clock, and the first past the deadline raises :class:`_TimeUp`."""
    deadline, previous = time.monotonic() + seconds, sys.gettrace()

    def trace(frame: types.FrameType, event: str, arg: Any) -> Callable | None:
        if time.monotonic() > deadline:
            raise _TimeUp
        return trace

    sys.settrace(trace)
    try:
        return run()
    finally:
        sys.settrace(previous)


def _line_of(error: BaseException, filename: str) -> str:
    """" (line n of the answer)" for the last line of the answer in ``error``'s traceback, else ""."""
    frames = traceback.extract_tb(error.__traceback__)
    lines = [frame.lineno for frame in frames if frame.filename == filename]
    if isinstance(error, SyntaxError) and error.filename == filename and error.lineno:
        lines.append(error.lineno)
    return f" (line {lines[-1]} of the answer)" if lines else ""


def _require_arguments(namespace: Any, which: Any, timeout: Any) -> None:
    """:class:`InvalidArgumentError` for a ``namespace`` that is not a mapping, a ``which`` that is not an
    int, a ``timeout`` that is not a positive number of seconds."""
    if not isinstance(namespace, Mapping):
        raise InvalidArgumentError(f"namespace must be the lesson's variables, a dict such as globals(); "
                                   f"got {_short(namespace)}")
    if isinstance(which, bool) or not isinstance(which, numbers.Integral):
        raise InvalidArgumentError(f"which must be the index (an int) of the worked answer in the notebook, "
                                   f"-1 for the last; got {which!r}")
    if (isinstance(timeout, bool) or not isinstance(timeout, numbers.Real) or not math.isfinite(timeout)
            or timeout <= 0):
        raise InvalidArgumentError(f"timeout must be a positive, finite number of seconds; got {timeout!r}")


def run_worked_answer(notebook: str | Path, namespace: Mapping[str, Any], which: int = -1, *,
                      timeout: float = WORKED_TIMEOUT) -> WorkedAnswer:
    """Run the worked answer ``which`` (default: the last) of ``notebook`` on a copy of ``namespace`` (the
    lesson's ``globals()``); raises :class:`WorkedAnswerError` unless it prints exactly the text it shows.
    The answer is read from ``notebook`` when that file is here, else from course_lib's copy of the lesson's
    answers (:data:`WORKED_ANSWERS_FILE`, found by the file's name): a lesson on Colab or run as a script.

    The answer runs in a box: every variable it names is a deep copy (modules, functions and what cannot
    be copied are shared), so the lesson's variables never change; it may run ``timeout`` seconds
    (:data:`WORKED_TIMEOUT` unless given); it cannot ask for ``input()`` nor end the kernel.  A hang, an
    ``exit()``, an input request or an exception is a :class:`WorkedAnswerError` naming the notebook and
    the cell (counted from 1).

    >>> import tempfile
    >>> cell = {"cell_type": "markdown", "metadata": {}, "source": "<details>\\n\\n```python\\n"
    ...         "print(f'{x ** 0.5:.4f}')\\n```\\n```text\\n1.4142\\n```\\n</details>"}
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder, "lesson.ipynb")
    ...     _ = path.write_text(json.dumps({"cells": [cell]}))
    ...     float(run_worked_answer(path, {"x": 2.0}))
    1.4142

    An answer that never ends is stopped:

    >>> cell["source"] = ("<details>\\n\\n```python\\nwhile True:\\n    pass\\n```\\n"
    ...                   "```text\\n\\n```\\n</details>")
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder, "lesson.ipynb")
    ...     _ = path.write_text(json.dumps({"cells": [cell]}))
    ...     run_worked_answer(path, {}, timeout=0.2)  # doctest: +ELLIPSIS
    Traceback (most recent call last):
    ...
    course_lib.checks.worked.WorkedAnswerError: the worked answer in cell 1 ... did not finish within 0.2 s...
    """
    _require_arguments(namespace, which, timeout)
    answers = _answers(notebook)
    if not answers or not -len(answers) <= which < len(answers):
        raise WorkedAnswerError(f"notebook {str(notebook)!r} has {len(answers)} worked answers (a ```python "
                                f"block and a ```text block inside <details>); asked for which={which!r}")
    cell, code, shown = answers[which]
    where = f"the worked answer in cell {cell} of {str(notebook)!r}"
    filename = f"<worked answer in {Path(notebook).name}, cell {cell}>"
    try:
        compiled = compile(code, filename, "exec")
    except (SyntaxError, ValueError) as error:  # ValueError: a NUL character in the code
        raise WorkedAnswerError(f"{where} is not valid Python: {type(error).__name__}: {error}") from None
    wanted = _global_names(compiled)
    output, problem = io.StringIO(), None

    def run() -> dict[str, Any]:
        names = _copied(namespace, None if wanted & _EVERY_NAME else wanted)
        names.update(__builtins__=_boxed_builtins(namespace), exit=_exit, quit=_exit)
        exec(compiled, names)  # noqa: S102 — the lesson's own answer, in its box
        return names

    try:
        with contextlib.redirect_stdout(output):
            names = _limited(float(timeout), run)
    except _TimeUp as error:
        problem = f"did not finish within {timeout} s (an endless loop?){_line_of(error, filename)}"
    except _InputAsked as error:
        problem = (f"asks for input (calls {error.args[0]}()){_line_of(error, filename)}: nobody types while "
                   "a lesson checks its answer; give the value in the code")
    except SystemExit as error:
        problem = f"calls exit() (SystemExit {error.code!r}){_line_of(error, filename)}: a lesson cannot stop"
    except KeyboardInterrupt:  # the reader stopped the lesson: so be it
        raise
    except BaseException as error:
        problem = f"raises {type(error).__name__}: {error}{_line_of(error, filename)}"
    if problem is not None:
        raise WorkedAnswerError(f"{where} {problem}") from None
    names["__builtins__"] = namespace.get("__builtins__", vars(builtins))  # the lesson's own again
    for name in ("exit", "quit"):
        if names.get(name) is _exit:
            names.pop(name)
            if name in namespace:
                names[name] = namespace[name]
    if output.getvalue().strip() != shown.strip():
        raise WorkedAnswerError(f"{where} prints {output.getvalue()!r}, but "
                                f"the lesson shows {shown!r}")
    return WorkedAnswer(code, output.getvalue().strip(), names)
