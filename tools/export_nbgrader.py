"""Export the exercise sets as an nbgrader course source: ``nbgrader/source/exNN/exNN_name.ipynb``.

Usage: python tools/export_nbgrader.py [notebooks/solutions/exNN_name.ipynb ...]   (default: all)
       make nbgrader

The solution notebooks (``notebooks/solutions/``) stay the one source of every task; ``make exercises``
keeps making the self-study copies from them, and this tool gives an instructor the same tasks for
nbgrader (``nbgrader generate_assignment exNN``, then ``collect`` / ``autograde`` / ``generate_feedback``
as on any JupyterHub with nbgrader).  Each solution notebook is written, outputs cleared, with
nbgrader's cell metadata:

* a **solution cell** (``solution: true``) for each code cell holding a ``### BEGIN SOLUTION`` /
  ``### END SOLUTION`` block; the block's ``# HINT:`` line moves above the block, as ``# Hint: …``, so
  the released copy keeps it when nbgrader replaces the block by its stub;
* an **autograded test cell** (``grade: true``, locked, with points) for each check cell
  ``checks.check_…(…)``, rewritten as ``feedback = checks.check_…(…)`` and
  ``assert feedback.ok, feedback.message`` — a wrong answer fails the test with the checker's message
  (what looks wrong, never the expected value), which nbgrader's feedback shows;
* **read-only** (``locked: true``) for every other cell: statements, given data, set-up code.

Points go by task, from the kinds in the ``(…)`` at the end of its ``## Task N · …`` heading, which may
stand on any line of a markdown cell (below the end of the previous task's text, say): ``POINTS`` below
(``compute + interpret`` = 2 + 1; any other kind ``DEFAULT_POINTS``); a task with several check
cells shares its points between them.  The heading shows the student those points,
``(compute + interpret, 3 points)``: points written there that differ from its kinds' are refused
(``ExerciseFormatError``), so the heading and the grade cannot disagree; a heading without points is
graded by its kinds alone.
Edit ``nbgrader/source/`` afterwards to weigh tasks differently, or change ``POINTS`` (and the headings).
The course's ``nbgrader/nbgrader_config.py`` sets the course id, the stub, the execution time limit and
the feedback page (``nbgrader/templates/feedback_offline/``: MathJax in the page, long lines wrapped).
"""

from __future__ import annotations

import ast
import copy
import pathlib
import sys

import nbformat

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
from make_exercises import (  # noqa: E402
    BEGIN,
    END,
    HINT,
    SOLUTIONS,
    ExerciseFormatError,
    _answer_names,
    split_solution,
    task_headings,
)

COURSE = ROOT / "nbgrader"
SOURCE = COURSE / "source"
POINTS = {"compute": 2, "derive": 2, "declare": 2, "interpret": 1}
DEFAULT_POINTS = 2
SCHEMA_VERSION = 3


def assignment_name(solution_path: pathlib.Path) -> str:
    """``ex03`` for ``notebooks/solutions/ex03_fourbar.ipynb``."""
    return solution_path.stem.split("_", 1)[0]


def task_points(kinds: str | None) -> float:
    """Points of a task from its heading's kinds, e.g. ``"compute + interpret"`` → 3.

    A kind not in ``POINTS`` (or a heading without one) counts ``DEFAULT_POINTS``.
    """
    parts = [part.strip() for part in (kinds or "").split("+") if part.strip()] or [""]
    return sum(POINTS.get(kind, DEFAULT_POINTS) for kind in parts)


def points_text(points: float) -> str:
    """How a heading writes a task's points: ``"2 points"``, ``"1 point"``."""
    points = int(points) if float(points).is_integer() else points
    return f"{points:g} point" + ("" if points == 1 else "s")


def heading_kinds(markdown: str, where: str = "cell") -> list[tuple[int | None, str | None]]:
    """The ``(task, kinds)`` of each level-2 heading of a markdown cell (``(None, None)`` for a heading that
    is not a task's), with the points a task heading writes checked against its kinds' (:func:`task_points`):
    ``ExerciseFormatError`` when they differ."""
    found = []
    for task, kinds, written in task_headings(markdown):
        if written is not None and written != points_text(task_points(kinds)):
            worth = points_text(task_points(kinds))
            raise ExerciseFormatError(f"{where}: Task {task}'s heading says ({kinds}, {written}), but its "
                                      f"kinds are worth {worth} (POINTS in tools/export_nbgrader.py)")
        found.append((task, kinds))
    return found


def check_call(source: str, where: str = "cell") -> str | None:
    """The call of a check cell (``checks.check_…(…)``, the cell's only statement), else ``None``."""
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return None
    if len(tree.body) != 1 or not isinstance(tree.body[0], ast.Expr):
        return None
    call = tree.body[0].value
    if not (isinstance(call, ast.Call) and isinstance(call.func, ast.Attribute)
            and isinstance(call.func.value, ast.Name) and call.func.value.id == "checks"
            and call.func.attr.startswith("check_")):
        return None
    return source.strip()


def test_source(call: str) -> str:
    """An autograded test cell: the checker's verdict asserted, its message as the failure."""
    return f"feedback = {call}\nassert feedback.ok, feedback.message"


def solution_source(source: str, where: str = "cell", later: list[str] = ()) -> str:
    """The solution cell with its hint, and the names the answer must define, above the block.

    Both stay in the released copy, where nbgrader replaces the block by its stub. ``later``: the
    sources of the code cells after this one (the names they use are the answer's names).
    """
    split = split_solution(source, where)
    if split is None:
        raise ExerciseFormatError(f"{where}: no solution block")
    _, body, hint = split
    lines = source.split("\n")
    start = next(i for i, line in enumerate(lines) if line.strip() == BEGIN)
    stop = next(i for i, line in enumerate(lines) if line.strip() == END)
    answer = [line for line in body if not line.strip().startswith(HINT)]
    names = _answer_names(body, list(later))
    above = [f"# Hint: {hint}"] + ([f"# Your answer defines: {', '.join(names)}"] if names else [])
    return "\n".join(lines[:start] + above + [BEGIN] + answer + [END] + lines[stop + 1 :])


def _nbgrader(grade_id: str, *, solution=False, grade=False, locked=False, points=None) -> dict:
    metadata = {"grade": grade, "grade_id": grade_id, "locked": locked, "schema_version": SCHEMA_VERSION,
                "solution": solution, "task": False}
    if points is not None:
        metadata["points"] = points
    return metadata


def nbgrader_source(solution: nbformat.NotebookNode, name: str = "") -> nbformat.NotebookNode:
    """The nbgrader source version of a solution notebook (outputs cleared, cell metadata set)."""
    notebook = copy.deepcopy(solution)
    task, kinds, checks_in_task = None, None, {}
    roles = []  # (cell, role, task)
    for index, cell in enumerate(notebook.cells):
        where = f"{name} cell {index}"
        if cell.cell_type == "markdown":
            found = heading_kinds(cell.source, where)  # on any line: a task may start below other text
            if found:
                task, kinds = found[-1]
            roles.append((cell, "statement", task, kinds))
            continue
        if cell.cell_type != "code":
            roles.append((cell, "statement", task, kinds))
            continue
        cell.outputs, cell.execution_count = [], None
        if BEGIN in cell.source or END in cell.source:
            if task is None:
                raise ExerciseFormatError(f"{where}: a solution block outside a '## Task N · … (kind)' part")
            later = [other.source for other in notebook.cells[index + 1 :]
                     if other.cell_type == "code" and BEGIN not in other.source]  # a later task: its own
            cell.source = solution_source(cell.source, where, later)
            roles.append((cell, "solution", task, kinds))
        elif check_call(cell.source) is not None and task is not None:
            cell.source = test_source(check_call(cell.source))
            checks_in_task[task] = checks_in_task.get(task, 0) + 1
            roles.append((cell, "test", task, kinds))
        else:
            roles.append((cell, "given", task, kinds))
    counts: dict[tuple[int | None, str], int] = {}
    for index, (cell, role, task, kinds) in enumerate(roles):
        metadata = dict(cell.metadata)
        if role == "solution":
            key = (task, "answer")
            counts[key] = counts.get(key, 0) + 1
            suffix = "" if counts[key] == 1 else f"-{counts[key]}"
            metadata["nbgrader"] = _nbgrader(f"task{task}-answer{suffix}", solution=True)
        elif role == "test":
            key = (task, "check")
            counts[key] = counts.get(key, 0) + 1
            suffix = "" if counts[key] == 1 else f"-{counts[key]}"
            points = task_points(kinds) / checks_in_task[task]
            points = int(points) if float(points).is_integer() else round(points, 2)
            metadata["nbgrader"] = _nbgrader(f"task{task}-check{suffix}", grade=True, locked=True,
                                             points=points)
        else:
            metadata["nbgrader"] = _nbgrader(f"cell-{index:03d}", locked=True)
        cell.metadata = metadata
        cell["id"] = metadata["nbgrader"]["grade_id"]
    if not checks_in_task:
        raise ExerciseFormatError(f"{name}: no check cell (checks.check_…) inside a task")
    missing = sorted({task for _, role, task, _ in roles if role == "solution"} - set(checks_in_task))
    if missing:
        raise ExerciseFormatError(f"{name}: tasks {missing} have an answer but no check cell")
    notebook.nbformat, notebook.nbformat_minor = 4, 5
    return notebook


def total_points(notebook: nbformat.NotebookNode) -> float:
    return sum(cell.metadata.get("nbgrader", {}).get("points", 0) for cell in notebook.cells)


def source_path(solution_path: pathlib.Path) -> pathlib.Path:
    return SOURCE / assignment_name(solution_path) / solution_path.name


def main(argv: list[str]) -> int:
    paths = [pathlib.Path(a).resolve() for a in argv] or sorted(SOLUTIONS.glob("ex*.ipynb"))
    for path in paths:
        notebook = nbgrader_source(nbformat.read(path, as_version=4), path.name)
        target = source_path(path)
        target.parent.mkdir(parents=True, exist_ok=True)
        nbformat.write(notebook, target)
        tests = sum(cell.metadata["nbgrader"]["grade"] for cell in notebook.cells)
        print(f"wrote {target.relative_to(ROOT)}  ({tests} graded checks, {total_points(notebook):g} points)")
    print(f"next: cd {COURSE.relative_to(ROOT)}; nbgrader generate_assignment exNN (README: For instructors)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
