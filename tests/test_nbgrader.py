"""The nbgrader route (`make nbgrader`): the exported source grades as an instructor would grade it.

In a temporary course directory (a copy of nbgrader/nbgrader_config.py and the source exported by
tools/export_nbgrader.py), ``nbgrader generate_assignment ex03`` makes the student version; two students
then hand it in: one with every answer right, one with Task 1 answered on the wrong branch and Task 4 left
unanswered.  ``nbgrader autograde`` must give full marks to the first, the points of Tasks 2 and 3 only to
the second, and ``nbgrader generate_feedback`` must show the second the checker's own message.
"""

import html
import os
import pathlib
import shutil
import subprocess
import sys

import nbformat
import numpy as np

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import export_nbgrader  # noqa: E402

from course_lib import checks  # noqa: E402
from course_lib.fourbar import FourBar  # noqa: E402

ASSIGNMENT = "ex03"
SOLUTION = ROOT / "notebooks" / "solutions" / "ex03_fourbar.ipynb"
RIGHT_BRANCH, WRONG_BRANCH = "(-B + np.sqrt(", "(-B - np.sqrt("  # Task 1: crossed vs open root


def _nbgrader(course: pathlib.Path, *args: str) -> str:
    """Run an nbgrader command in the course directory (this Python's bin folder first on PATH:
    nbgrader runs ``alembic`` from there)."""
    env = dict(os.environ, PATH=f"{pathlib.Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    result = subprocess.run([sys.executable, "-m", "nbgrader", *args], cwd=course, env=env,
                            capture_output=True, text=True, timeout=300)
    log = result.stdout + result.stderr
    assert result.returncode == 0, f"nbgrader {' '.join(args)} failed:\n{log[-4000:]}"
    return log


def _cells_by_id(notebook) -> dict:
    return {cell.metadata["nbgrader"]["grade_id"]: cell
            for cell in notebook.cells if "nbgrader" in cell.metadata}


def _hand_in(course: pathlib.Path, student: str, released, answers: dict[str, str]) -> None:
    notebook = nbformat.from_dict(released)
    for grade_id, cell in _cells_by_id(notebook).items():
        if grade_id in answers:
            cell.source = answers[grade_id]
    target = course / "submitted" / student / ASSIGNMENT / SOLUTION.name
    target.parent.mkdir(parents=True)
    nbformat.write(notebook, target)


def test_export_marks_solutions_checks_and_read_only_statements():
    notebook = export_nbgrader.nbgrader_source(nbformat.read(SOLUTION, as_version=4), SOLUTION.name)
    roles = [cell.metadata["nbgrader"] for cell in notebook.cells]
    answers = [cell for cell in notebook.cells if cell.metadata["nbgrader"]["solution"]]
    tests = [cell for cell in notebook.cells if cell.metadata["nbgrader"]["grade"]]
    assert len(answers) == len(tests) == 4
    assert all(cell.source.startswith("# Hint: ") and "### BEGIN SOLUTION" in cell.source for cell in answers)
    assert all(cell.source.startswith("feedback = checks.check_")
               and cell.source.endswith("assert feedback.ok, feedback.message") for cell in tests)
    assert [cell.metadata["nbgrader"]["points"] for cell in tests] == [2, 2, 2, 3]
    assert all(role["locked"] for role in roles if not role["solution"])
    assert all(cell.cell_type != "code" or not cell.outputs for cell in notebook.cells)
    assert len({role["grade_id"] for role in roles}) == len(roles)


def test_task_points_come_from_the_kinds_in_the_heading():
    assert export_nbgrader.task_points("compute + interpret") == 3
    assert export_nbgrader.task_points("interpret") == 1
    assert export_nbgrader.task_points("sketch") == export_nbgrader.task_points(None) == 2


def test_generate_autograde_and_feedback_full_and_partial_marks(tmp_path):
    course = tmp_path / "course"
    source = course / "source" / ASSIGNMENT / SOLUTION.name
    source.parent.mkdir(parents=True)
    shutil.copyfile(ROOT / "nbgrader" / "nbgrader_config.py", course / "nbgrader_config.py")
    exported = export_nbgrader.nbgrader_source(nbformat.read(SOLUTION, as_version=4), SOLUTION.name)
    nbformat.write(exported, source)

    _nbgrader(course, "generate_assignment", ASSIGNMENT)
    released = nbformat.read(course / "release" / ASSIGNMENT / SOLUTION.name, as_version=4)
    student_view = "\n".join(cell.source for cell in released.cells)
    assert "BEGIN SOLUTION" not in student_view and RIGHT_BRANCH not in student_view
    assert "# Hint: " in student_view and "raise NotImplementedError()" in student_view

    full = {grade_id: cell.source for grade_id, cell in _cells_by_id(exported).items()
            if cell.metadata["nbgrader"]["solution"]}
    assert RIGHT_BRANCH in full["task1-answer"], "Task 1's worked answer changed: update this test"
    partial = dict(full, **{"task1-answer": full["task1-answer"].replace(RIGHT_BRANCH, WRONG_BRANCH)})
    del partial["task4-answer"]  # left as released: the stub raises NotImplementedError
    _hand_in(course, "alice", released, full)
    _hand_in(course, "bob", released, partial)

    _nbgrader(course, "autograde", ASSIGNMENT)
    from nbgrader.api import Gradebook

    with Gradebook(f"sqlite:///{course / 'gradebook.db'}") as gradebook:
        scores = {student: (gradebook.find_submission(ASSIGNMENT, student).score,
                            gradebook.find_submission(ASSIGNMENT, student).max_score)
                  for student in ("alice", "bob")}
    print(f"nbgrader scores for {ASSIGNMENT}: {scores}")
    assert scores["alice"] == (9, 9)
    assert scores["bob"] == (4, 9)  # Tasks 2 and 3 (2 + 2); not Task 1 (2, wrong branch) nor Task 4 (3)

    _nbgrader(course, "generate_feedback", ASSIGNMENT)
    feedback = (course / "feedback" / "bob" / ASSIGNMENT / SOLUTION.with_suffix(".html").name).read_text()
    bench = FourBar(crank=0.07, coupler=0.20, rocker=0.15, ground=0.25)
    theta2 = np.radians(120.0)
    message = checks.check_fourbar_theta4(bench.solve(theta2).theta4, bench, theta2, "crossed").message
    assert "open branch" in message
    assert html.escape(message, quote=False) in feedback or message in feedback
    assert "NotImplementedError" in feedback
    assert "Not yet" not in (course / "feedback" / "alice" / ASSIGNMENT
                             / SOLUTION.with_suffix(".html").name).read_text()
