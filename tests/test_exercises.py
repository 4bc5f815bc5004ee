"""The exercise notebooks: the student copies are up to date and hold no solution text.

The copies in notebooks/exercises/ are regenerated in memory from notebooks/solutions/ by
tools/make_exercises.py and compared cell by cell (type, source, tags — not outputs, which
nbval checks).  Then every line of every solution body must be absent from the copy, and the
generator itself is tested on small hand-made notebooks.
"""

from __future__ import annotations

import importlib.util
import pathlib
import re

import nbformat
import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
spec = importlib.util.spec_from_file_location("make_exercises", ROOT / "tools" / "make_exercises.py")
make_exercises = importlib.util.module_from_spec(spec)
spec.loader.exec_module(make_exercises)

SOLUTIONS = sorted((ROOT / "notebooks" / "solutions").glob("ex*.ipynb"))
EXPECTED = [
    "ex01_vector_loops_and_mobility",
    "ex02_newton_raphson",
    "ex03_fourbar",
    "ex04_power_saw",
    "ex05_fivebar",
    "ex06_your_own_mechanism",
]


def _cells(notebook):
    return [(cell.cell_type, cell.source, sorted(cell.metadata.get("tags", []))) for cell in notebook.cells]


def _text(notebook) -> str:
    """Every source and every output text of a notebook, one string."""
    parts = []
    for cell in notebook.cells:
        parts.append(cell.source)
        for output in cell.get("outputs", []):
            parts.append(output.get("text", ""))
            parts.append(output.get("evalue", ""))
            parts.extend(str(value) for value in output.get("data", {}).values())
    return "\n".join(parts)


def test_every_planned_exercise_set_exists():
    names = [path.stem for path in SOLUTIONS]
    assert [name for name in EXPECTED if name not in names] == [], "missing solution notebooks"


@pytest.mark.parametrize("solution", SOLUTIONS, ids=lambda path: path.stem)
def test_student_copy_is_up_to_date(solution):
    committed = ROOT / "notebooks" / "exercises" / solution.name
    assert committed.exists(), f"run `make exercises`: {committed.name} is missing"
    fresh = make_exercises.student_copy(nbformat.read(solution, as_version=4), solution.name)
    assert _cells(nbformat.read(committed, as_version=4)) == _cells(fresh), "run `make exercises`"


@pytest.mark.parametrize("solution", SOLUTIONS, ids=lambda path: path.stem)
def test_student_copy_holds_no_solution_text(solution):
    source = nbformat.read(solution, as_version=4)
    copy = nbformat.read(ROOT / "notebooks" / "exercises" / solution.name, as_version=4)
    text = _text(copy)
    assert "BEGIN SOLUTION" not in text and "END SOLUTION" not in text
    copy_lines = {line.strip() for line in text.split("\n")}
    body = make_exercises.solution_lines(source)
    assert body, "a solution notebook without solution blocks"
    leaked = [line for line in body if re.search(r"\w", line) and line in copy_lines]
    assert leaked == []


@pytest.mark.parametrize("solution", SOLUTIONS, ids=lambda path: path.stem)
def test_each_task_has_a_statement_an_answer_and_a_check(solution):
    notebook = nbformat.read(solution, as_version=4)
    cells = notebook.cells
    answers = [
        i for i, cell in enumerate(cells) if cell.cell_type == "code" and make_exercises.BEGIN in cell.source
    ]
    assert 3 <= len(answers) <= 6
    for i in answers:
        assert any(cell.cell_type == "markdown" and "Task" in cell.source for cell in cells[:i])
        following = cells[i + 1]
        assert following.cell_type == "code" and following.source.startswith("checks.check_")
        # the solution passes its own check (the outputs are those of a fresh run, nbval verifies)
        assert following.outputs and str(
            following.outputs[0].get("data", {}).get("text/plain", "")
        ).startswith("✔")


@pytest.mark.parametrize("solution", SOLUTIONS, ids=lambda path: path.stem)
def test_an_untouched_copy_shows_hints_and_no_answer_yet_never_a_traceback(solution):
    original = nbformat.read(solution, as_version=4).cells
    copy = nbformat.read(ROOT / "notebooks" / "exercises" / solution.name, as_version=4).cells[1:]
    assert len(copy) == len(original)
    stubs = 0
    for cell, source_cell in zip(copy, original, strict=True):
        if cell.cell_type != "code":
            continue
        errors = [output for output in cell.outputs if output.output_type == "error"]
        assert not any(error.ename == "NameError" for error in errors), cell.source
        if make_exercises.BEGIN in source_cell.source:
            stubs += 1
            assert "# Hint: " in cell.source and re.search(r"^\w+ = None$", cell.source, re.M), cell.source
        if cell.source.startswith("checks.check_"):
            text = "".join(str(output.get("data", {}).get("text/plain", "")) for output in cell.outputs)
            assert not errors and text.startswith("✘ No answer yet"), cell.source
        elif errors:  # any other failing cell is one that needs an answer, and says so by its tag
            assert "raises-exception" in cell.metadata.get("tags", []), cell.source
    assert stubs >= 3


# ---------------------------------------------------------------- the generator on small notebooks


def _notebook(*sources):
    notebook = nbformat.v4.new_notebook()
    notebook.cells = [nbformat.v4.new_code_cell(source) for source in sources]
    return notebook


def test_generator_replaces_the_block_by_the_hint_and_tags_dependent_cells():
    solution = _notebook(
        "import math",
        "given = 2\n### BEGIN SOLUTION\n# HINT: square it\nanswer = given**2\nhelper = 1\n### END SOLUTION",
        "checks.check_square(answer)",
        "unrelated = given + 1",
        "derived = helper + 1",
        "uses_derived = derived * 2",
    )
    copy = make_exercises.student_copy(solution, "ex99.ipynb")
    code = [cell for cell in copy.cells if cell.cell_type == "code"]
    stub = "given = 2\n# Hint: square it\n# Your answer: replace None.\nanswer = None\nhelper = None"
    assert code[1].source == stub
    tags = [("raises-exception" in cell.metadata.get("tags", [])) for cell in code]
    assert tags == [False, False, False, False, True, True]  # the check cell says "no answer yet" itself
    assert copy.cells[0].cell_type == "markdown" and "ex99.ipynb" in copy.cells[0].source
    assert all(cell.outputs == [] and cell.execution_count is None for cell in code)


def test_generator_requires_a_hint_and_balanced_markers():
    with pytest.raises(make_exercises.ExerciseFormatError, match="HINT"):
        make_exercises.student_copy(_notebook("### BEGIN SOLUTION\nx = 1\n### END SOLUTION"))
    with pytest.raises(make_exercises.ExerciseFormatError, match="exactly one"):
        make_exercises.student_copy(_notebook("### BEGIN SOLUTION\n# HINT: h\nx = 1"))
    with pytest.raises(make_exercises.ExerciseFormatError, match="top level"):
        make_exercises.student_copy(
            _notebook("if True:\n    ### BEGIN SOLUTION\n    # HINT: h\n    ### END SOLUTION")
        )


def test_solution_lines_lists_the_block_bodies():
    solution = _notebook("a = 1\n### BEGIN SOLUTION\n# HINT: h\nb = a + 1\n\n### END SOLUTION", "c = 3")
    assert make_exercises.solution_lines(solution) == ["# HINT: h", "b = a + 1"]
