"""A lesson's worked answer runs in a box (``run_worked_answer``): a time limit, no ``exit()``, no
``input()``, deep copies of the lesson's variables, and a named error — never a raw traceback — for a bad
notebook file, a failing answer or a wrong argument."""

from __future__ import annotations

import inspect
import json
import re
import sys
import threading
import time
import types

import numpy as np
import pytest

from course_lib.checks import WorkedAnswerError, run_worked_answer, worked_answers
from course_lib.errors import InvalidArgumentError


def _answer_cell(code: str, printed: str = "1\n") -> dict:
    return {"cell_type": "markdown", "metadata": {},
            "source": f"<details><summary>Answer</summary>\n\n```python\n{code}```\n```text\n{printed}```\n"
                      "</details>"}


def lesson(tmp_path, *answers: str, printed: str = "1\n"):
    """A lesson file: one code cell, then one folded worked answer per code in ``answers`` (cells 2, 3, …)."""
    cells = [{"cell_type": "code", "metadata": {}, "source": "x = 1", "outputs": [], "execution_count": None}]
    cells += [_answer_cell(code, printed) for code in answers]
    path = tmp_path / "lesson.ipynb"
    path.write_text(json.dumps({"cells": cells, "metadata": {}, "nbformat": 4, "nbformat_minor": 5}))
    return path


def failure(path, namespace=None, **options) -> str:
    with pytest.raises(WorkedAnswerError) as caught:
        run_worked_answer(path, {} if namespace is None else namespace, **options)
    return str(caught.value)


# --- a time limit -------------------------------------------------------------------------------------------

def test_an_endless_loop_is_stopped_and_reported_with_its_cell(tmp_path):
    path = lesson(tmp_path, "total = 0\nwhile True:\n    total += 1\n")
    start = time.monotonic()
    message = failure(path, timeout=0.3)
    assert time.monotonic() - start < 5
    assert "did not finish within 0.3 s" in message and "cell 2" in message and "lesson.ipynb" in message
    assert re.search(r"line [23] of the answer", message)


def test_an_answer_that_swallows_the_stop_is_stopped_again(tmp_path):
    code = "try:\n    while True:\n        pass\nexcept BaseException:\n    pass\nwhile True:\n    pass\n"
    start = time.monotonic()
    message = failure(lesson(tmp_path, code), timeout=0.3)
    assert time.monotonic() - start < 5 and "did not finish" in message


def test_a_hang_inside_a_lesson_function_is_stopped(tmp_path):
    def spin():
        while True:
            pass

    message = failure(lesson(tmp_path, "spin()\n"), {"spin": spin}, timeout=0.3)
    assert "did not finish within 0.3 s" in message and "line 1 of the answer" in message


def test_the_time_limit_works_off_the_main_thread_and_leaves_no_stop_behind(tmp_path):
    """A Jupyter kernel or a pytest-xdist worker may run code off the main thread: the limit still holds
    there, and an answer that finished leaves no stop to be raised later into the caller."""
    hang = lesson(tmp_path, "while True:\n    pass\n")
    quick = tmp_path / "quick.ipynb"
    quick.write_text(json.dumps({"cells": [_answer_cell("print(1)\n")]}))
    results = []

    def call():
        try:
            run_worked_answer(hang, {}, timeout=0.3)
        except WorkedAnswerError as error:
            results.append(str(error))
        results.append(run_worked_answer(quick, {}, timeout=0.3).printed)
        total = 0
        for step in range(3_000_000):  # Python code running past the limit: no stop may arrive here
            total += step
        time.sleep(0.5)
        events = []  # and trace functions (debuggers, coverage) still see every line run here

        def trace(frame, event, arg):
            events.append(event)
            return trace

        sys.settrace(trace)
        exec(compile("a = 1\nb = 2\nc = 3\n", "<three lines>", "exec"), {})
        sys.settrace(None)
        results.append(f"done, {events.count('line')} lines traced")

    worker = threading.Thread(target=call)
    worker.start()
    worker.join(20)
    assert not worker.is_alive()
    assert len(results) == 3 and "did not finish" in results[0]
    assert results[1:] == ["1", "done, 3 lines traced"]


def test_without_cpythons_async_exceptions_a_trace_function_keeps_the_limit(tmp_path, monkeypatch):
    from course_lib.checks import worked

    monkeypatch.setattr(worked, "_async_raiser", lambda: None)
    message = failure(lesson(tmp_path, "while True:\n    pass\n"), timeout=0.3)
    assert "did not finish within 0.3 s" in message
    assert run_worked_answer(lesson(tmp_path, "print(1)\n"), {}, timeout=2).printed == "1"

def test_the_time_limit_has_a_default_of_a_few_seconds_and_is_a_keyword(tmp_path):
    timeout = inspect.signature(run_worked_answer).parameters["timeout"]
    assert timeout.kind is inspect.Parameter.KEYWORD_ONLY and 1 <= timeout.default <= 10
    assert run_worked_answer(lesson(tmp_path, "print(1)\n"), {}, timeout=2.5).printed == "1"


# --- exit(), input(), exceptions ----------------------------------------------------------------------------

@pytest.mark.parametrize("code", ["raise SystemExit(3)\n", "import sys\nsys.exit()\n", "exit()\n",
                                  "quit(0)\n"])
def test_an_exit_is_a_named_failure(tmp_path, code):
    message = failure(lesson(tmp_path, code))
    assert "calls exit()" in message and "SystemExit" in message and "cell 2" in message


@pytest.mark.parametrize("code", [
    "value = float(input('length? '))\n",
    "try:\n    value = input()\nexcept Exception:\n    value = 1\nprint(value)\n",  # not swallowed
])
def test_a_request_for_input_is_a_named_failure(tmp_path, code):
    message = failure(lesson(tmp_path, code))
    assert "asks for input (calls input())" in message and "cell 2" in message


@pytest.mark.parametrize(("code", "kind", "line"), [
    ("a = 1\nb = a / 0\n", "ZeroDivisionError", 2),
    ("print(undefined_name)\n", "NameError", 1),
    ("import json\njson.loads('{')\n", "JSONDecodeError", 2),
    ("class Stop(BaseException):\n    pass\nraise Stop('here')\n", "Stop", 3),
])
def test_an_exception_in_the_answer_is_a_named_failure(tmp_path, code, kind, line):
    message = failure(lesson(tmp_path, "print(1)\n", code), which=1)
    assert f"raises {kind}" in message and "cell 3" in message and f"line {line} of the answer" in message


def test_an_answer_that_is_not_python_is_a_named_failure(tmp_path):
    message = failure(lesson(tmp_path, "print((1, 2)\n"))
    assert "is not valid Python" in message and "SyntaxError" in message and "cell 2" in message


# --- the lesson's variables ---------------------------------------------------------------------------------

def test_the_answer_works_on_deep_copies_of_the_lessons_variables(tmp_path):
    code = ("x.append(2)\nrows['a'].append(3)\narray[0] = 99.0\nbar.length = 0.0\n"
            "print(y is x, rows['a'] is x, np.pi > 3)\n")
    x = [1]
    namespace = {"x": x, "y": x, "rows": {"a": x}, "array": np.zeros(3), "np": np,
                 "bar": types.SimpleNamespace(length=0.1)}
    kept = dict(namespace)
    worked = run_worked_answer(lesson(tmp_path, code, printed="True True True\n"), namespace)
    assert x == [1] and namespace["array"].tolist() == [0.0, 0.0, 0.0] and namespace["bar"].length == 0.1
    assert namespace == kept and all(namespace[name] is kept[name] for name in kept)  # no name added
    assert worked.names["x"] == [1, 2, 3] and worked.names["np"] is np  # modules are shared, not copied


def test_the_returned_names_hold_the_copies_what_the_answer_defined_and_the_usual_builtins(tmp_path):
    code = "def area(r):\n    return 3 * r * r\nsizes.append(area(1))\nprint(sizes[-1] - 2)\n"
    sizes = [0]
    worked = run_worked_answer(lesson(tmp_path, code), {"sizes": sizes, "exit": "the lesson's own exit"})
    assert worked.names["area"](2) == 12 and worked.names["sizes"] == [0, 3] and sizes == [0]
    assert worked.names["exit"] == "the lesson's own exit" and "quit" not in worked.names
    assert worked.names["__builtins__"]["input"] is input  # the box's refusals do not outlive it


def test_variables_reached_through_globals_are_copies_too(tmp_path):
    x = [1]
    run_worked_answer(lesson(tmp_path, "globals()['x'].append(2)\nvars()['x'].append(3)\nprint(1)\n"),
                      {"x": x})
    assert x == [1]


def test_what_cannot_be_deep_copied_is_shared_and_the_answer_still_runs(tmp_path):
    lock, x = threading.Lock(), [1]

    def helper():
        return 1

    namespace = {"lock": lock, "helper": helper, "x": x, "numbers": (n for n in range(3))}
    code = "with lock:\n    x.append(helper())\nprint(next(numbers), len(x))\n"
    worked = run_worked_answer(lesson(tmp_path, code, printed="0 2\n"), namespace)
    assert worked.names["lock"] is lock and worked.names["helper"] is helper and x == [1]


# --- a bad notebook file ------------------------------------------------------------------------------------

@pytest.mark.parametrize(("content", "says"), [
    (b"this is not JSON", "is not a notebook"),
    (b"{}", 'no list of "cells"'),
    (b"[1, 2]", 'no list of "cells"'),
    (json.dumps({"cells": [{"source": "x = 1"}]}).encode(), 'cell 1 of notebook'),
    (json.dumps({"cells": [{"cell_type": "markdown", "source": 7}]}).encode(), 'not text'),
    ("é".encode("latin-1"), "cannot be read as text"),
])
def test_a_file_that_is_not_a_notebook_is_a_named_failure(tmp_path, content, says):
    path = tmp_path / "broken.ipynb"
    path.write_bytes(content)
    for call in (lambda: worked_answers(path), lambda: run_worked_answer(path, {})):
        with pytest.raises(WorkedAnswerError, match="broken.ipynb") as caught:
            call()
        assert says in str(caught.value)


# --- wrong arguments ----------------------------------------------------------------------------------------

@pytest.mark.parametrize(("options", "shown"), [
    ({"which": "0"}, "which must be the index (an int) of the worked answer in the notebook, -1 for the "
                     "last; got '0'"),
    ({"which": True}, "which must be the index (an int) of the worked answer in the notebook, -1 for the "
                      "last; got True"),
    ({"which": 0.0}, "got 0.0"),
    ({"namespace": None}, "namespace must be the lesson's variables, a dict such as globals(); got None"),
    ({"namespace": [("x", 1)]}, "namespace must be the lesson's variables"),
    ({"timeout": 0}, "timeout must be a positive, finite number of seconds; got 0"),
    ({"timeout": "5"}, "timeout must be a positive, finite number of seconds; got '5'"),
    ({"timeout": float("nan")}, "got nan"),
    ({"notebook": None}, "notebook must be the lesson's file name"),
])
def test_a_wrong_argument_is_refused_by_name_with_its_value(tmp_path, options, shown):
    arguments = {"notebook": lesson(tmp_path, "print(1)\n", "print(1)\n"), "namespace": {}} | options
    with pytest.raises(InvalidArgumentError) as caught:
        run_worked_answer(**arguments)
    assert shown in str(caught.value)

