"""Every task heading shows the student the points nbgrader gives the task.

A heading reads ``## Task 1 · Count a six-bar (compute, 2 points)``: the kinds first (``compute + interpret``
for two), then the points, ``1 point`` in the singular.  The points written must be ``task_points(kinds)`` of
``tools/export_nbgrader.py`` (what the exported set grades), and each set stays worth what the README lists:
ex01 7, ex02 8, ex03 9, ex04 7, ex05 8, ex06 9.  Every heading that writes points is checked, in all six
solution notebooks; ex01–ex05 must write them on every task, and their student copies show the same headings.
"""

from __future__ import annotations

import pathlib
import re
import sys

import nbformat
import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import export_nbgrader  # noqa: E402
import make_exercises  # noqa: E402

SOLUTIONS = sorted((ROOT / "notebooks" / "solutions").glob("ex*.ipynb"))
#: each set's points, as the README's "For instructors" lists them (interpret 1, any other kind 2, summed)
TOTALS = {"ex01": 7, "ex02": 8, "ex03": 9, "ex04": 7, "ex05": 8, "ex06": 9}
SHOWN = ("ex01", "ex02", "ex03", "ex04", "ex05")  # the sets of this change: points on every heading
WRITTEN = re.compile(r"^(?P<count>\d+) (?P<word>points?)$")


def task_headings(path: pathlib.Path) -> list[tuple[int, str | None, str | None]]:
    """(task, kinds, points as written) of every task heading of a notebook, in order."""
    return [heading for cell in nbformat.read(path, as_version=4).cells if cell.cell_type == "markdown"
            for heading in make_exercises.task_headings(cell.source) if heading[0] is not None]


def _with_points(path: pathlib.Path) -> bool:
    return any(points is not None for _, _, points in task_headings(path))


def test_every_set_is_here():
    assert [path.stem[:4] for path in SOLUTIONS] == list(TOTALS)


@pytest.mark.parametrize("solution", [path for path in SOLUTIONS if _with_points(path)],
                         ids=lambda path: path.stem)
def test_the_points_a_heading_shows_are_the_points_nbgrader_gives(solution):
    headings = task_headings(solution)
    for task, kinds, written in headings:
        assert written is not None, f"Task {task}: every heading of a set that shows points shows them"
        form = WRITTEN.match(written)
        assert form and (form["word"] == "point") == (form["count"] == "1"), written  # 1 point, 2 points
        assert int(form["count"]) == export_nbgrader.task_points(kinds), (task, kinds, written)
    exported = export_nbgrader.nbgrader_source(nbformat.read(solution, as_version=4), solution.name)
    shown = sum(int(WRITTEN.match(written)["count"]) for _, _, written in headings)
    assert export_nbgrader.total_points(exported) == shown == TOTALS[solution.stem[:4]]


@pytest.mark.parametrize("solution", SOLUTIONS, ids=lambda path: path.stem)
def test_each_set_is_worth_what_the_readme_lists(solution):
    kinds = [kinds for _, kinds, _ in task_headings(solution)]
    assert sum(map(export_nbgrader.task_points, kinds)) == TOTALS[solution.stem[:4]]
    exported = export_nbgrader.nbgrader_source(nbformat.read(solution, as_version=4), solution.name)
    assert export_nbgrader.total_points(exported) == TOTALS[solution.stem[:4]]


@pytest.mark.parametrize("name", SHOWN)
def test_ex01_to_ex05_show_the_points_of_every_task(name):
    solution = next(path for path in SOLUTIONS if path.stem.startswith(name))
    headings = task_headings(solution)
    assert len(headings) >= 4 and all(written for _, _, written in headings), headings
    copy = ROOT / "notebooks" / "exercises" / solution.name  # the student reads them there
    assert task_headings(copy) == headings


@pytest.mark.parametrize(("line", "expected"), [
    ("## Task 1 · Count a six-bar (compute, 2 points)", (1, "compute", "2 points")),
    ("## Task 4 · How far can this crank turn? (compute + interpret, 3 points)",
     (4, "compute + interpret", "3 points")),
    ("## Task 5 · And this one? (interpret, 1 point)", (5, "interpret", "1 point")),
    ("## Task 2 · Inverse kinematics in working mode (−1, +1) (compute, 2 points)",
     (2, "compute", "2 points")),
    ("## Task 3 · An older heading (derive)", (3, "derive", None)),
    ("## Task 6 · No kind at all", (6, None, None)),
    ("## What to take away", (None, None, None)),
])
def test_a_heading_is_read_as_its_task_kinds_and_points(line, expected):
    assert make_exercises.task_headings(line) == [expected]
    assert make_exercises.headings(line) == [expected[:2]]


def test_the_points_of_a_heading_are_written_as_nbgrader_counts_them():
    assert [export_nbgrader.points_text(export_nbgrader.task_points(kinds))
            for kinds in ("compute", "derive", "declare", "interpret", "compute + interpret")] == \
        ["2 points", "2 points", "2 points", "1 point", "3 points"]


@pytest.mark.parametrize("heading", ["## Task 1 · Wrong sum (interpret, 2 points)",
                                     "## Task 1 · Wrong sum (compute + interpret, 4 points)"])
def test_a_heading_whose_points_are_not_its_kinds_is_refused(heading):
    notebook = nbformat.v4.new_notebook()
    answer = "### BEGIN SOLUTION\n# HINT: h\nanswer = 1\n### END SOLUTION"
    notebook.cells = [nbformat.v4.new_markdown_cell(heading), nbformat.v4.new_code_cell(answer),
                      nbformat.v4.new_code_cell("checks.check_mobility(answer)")]
    with pytest.raises(make_exercises.ExerciseFormatError, match="heading says"):
        export_nbgrader.nbgrader_source(notebook, "ex99.ipynb")
    notebook.cells[0].source = heading.rsplit(",", 1)[0] + ")"  # the kinds alone: graded by them
    assert export_nbgrader.total_points(export_nbgrader.nbgrader_source(notebook, "ex99.ipynb")) == \
        export_nbgrader.task_points(heading.split("(")[1].split(",")[0])
