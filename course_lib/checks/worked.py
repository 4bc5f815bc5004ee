"""The worked answer of a lesson's "Try it", kept hidden in every viewer and still proved right.

A lesson writes its worked answer in a markdown cell, inside ``<details>``: GitHub, nbviewer, nbconvert's
HTML, JupyterLab and the course website all keep it folded until the reader opens it.  The answer holds a
```python block and, right after it, a ```text block with what that code prints.  :func:`run_worked_answer`
reads the lesson file, runs that code on the lesson's variables and checks that it prints exactly the text
shown, so the cell after the answer can assert that the printed answer passes the Try-it's own checker —
without showing the answer in its source.
"""

from __future__ import annotations

import contextlib
import io
import json
import re
from collections.abc import Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import CourseLibError

__all__ = ["WorkedAnswer", "WorkedAnswerError", "worked_answers", "run_worked_answer"]

_FENCE = re.compile(r"```python\n(?P<code>.*?)```\s*```text\n(?P<printed>.*?)```", re.S)


class WorkedAnswerError(CourseLibError):
    """A lesson's worked answer cannot be found, or does not print what it shows."""


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
    path = Path(notebook)
    if not path.is_file():
        raise WorkedAnswerError(f"notebook {str(notebook)!r} is not a file here: the worked answer is "
                                "re-checked when the lesson runs from its own folder")
    cells = json.loads(path.read_text(encoding="utf-8"))["cells"]
    return [(match["code"], match["printed"]) for cell in cells if cell["cell_type"] == "markdown"
            for source in ["".join(cell["source"])] if "<details" in source
            for match in _FENCE.finditer(source)]


def run_worked_answer(notebook: str | Path, namespace: Mapping[str, Any], which: int = -1) -> WorkedAnswer:
    """Run the worked answer ``which`` (default: the last) of ``notebook`` on a copy of ``namespace`` (the
    lesson's ``globals()``); raises :class:`WorkedAnswerError` unless it prints exactly the text it shows.

    >>> import tempfile
    >>> cell = {"cell_type": "markdown", "metadata": {}, "source": "<details>\\n\\n```python\\n"
    ...         "print(f'{x ** 0.5:.4f}')\\n```\\n```text\\n1.4142\\n```\\n</details>"}
    >>> with tempfile.TemporaryDirectory() as folder:
    ...     path = Path(folder, "lesson.ipynb")
    ...     _ = path.write_text(json.dumps({"cells": [cell]}))
    ...     float(run_worked_answer(path, {"x": 2.0}))
    1.4142
    """
    answers = worked_answers(notebook)
    if not answers or not -len(answers) <= which < len(answers):
        raise WorkedAnswerError(f"notebook {str(notebook)!r} has {len(answers)} worked answers (a ```python "
                                f"block and a ```text block inside <details>); asked for which={which!r}")
    code, shown = answers[which]
    names, output = dict(namespace), io.StringIO()
    with contextlib.redirect_stdout(output):
        exec(compile(code, f"<worked answer in {Path(notebook).name}>", "exec"), names)  # noqa: S102
    if output.getvalue().strip() != shown.strip():
        raise WorkedAnswerError(f"the worked answer in {str(notebook)!r} prints {output.getvalue()!r}, but "
                                f"the lesson shows {shown!r}")
    return WorkedAnswer(code, output.getvalue().strip(), names)
