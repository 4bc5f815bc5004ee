"""The exercise notebooks: the student copies are up to date, hold no solution text, and run clean.

The copies in notebooks/exercises/ are regenerated in memory from notebooks/solutions/ by
tools/make_exercises.py and compared cell by cell (type, source, tags — not outputs, which
nbval checks).  Then every line of every solution body must be absent from the copy, and no copy
may point at the solutions.  The committed outputs of each untouched copy (a fresh run, executed
by the tool) must hold no error but the ones its solution shows on purpose, and each cell that
needs an answer must say which task to answer first; with the answers filled in, those cells must
show what the solution shows.  The generator itself is tested on small hand-made notebooks.
"""

from __future__ import annotations

import ast
import importlib.util
import pathlib
import re

import nbformat
import pytest
from nbclient import NotebookClient

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
def test_student_copy_speaks_to_the_student_and_matches_its_stubs(solution):
    copy = nbformat.read(ROOT / "notebooks" / "exercises" / solution.name, as_version=4)
    text = _text(copy)
    assert "solutions/" not in text  # no way to the worked answers
    assert "NotImplementedError" not in text  # the stubs are `name = None`, as the banner says
    banner = copy.cells[0].source
    assert "solution" not in banner.lower() and "make exercises" not in banner
    assert "replace `None`" in banner and "check cell" in banner
    code = [cell.source for cell in copy.cells if cell.cell_type == "code"]
    assert any(re.search(r"^\w+ = None$", source, re.M) for source in code)


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


# ---------------------------------------------------------------- an untouched copy, run top to bottom

TASK = re.compile(r"^##\s+Task\s+(\d+)\b")
ANSWER_FIRST = re.compile(r"^Answer Task (\d+) first \(this cell uses (.+)\)\.$")


def _answer_tasks(solution_cells, copy_cells) -> dict[str, int]:
    """Each name a stub sets to None → the number of the task whose heading stands above it."""
    tasks, task = {}, None
    for source_cell, cell in zip(solution_cells, copy_cells, strict=True):
        if source_cell.cell_type == "markdown":
            for line in source_cell.source.split("\n"):
                if line.startswith("## "):
                    task = int(TASK.match(line)[1]) if TASK.match(line) else None
        elif make_exercises.BEGIN in source_cell.source:
            tasks.update((name, task) for name in re.findall(r"^(\w+) = None$", cell.source, re.M))
    return tasks


def _loaded_names(source: str) -> set[str]:
    return {node.id for node in ast.walk(ast.parse(source))
            if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load)}


def _printed(cell) -> str:
    return "".join(output.get("text", "") for output in cell.outputs if output.output_type == "stream")


@pytest.mark.parametrize("solution", SOLUTIONS, ids=lambda path: path.stem)
def test_an_untouched_copy_runs_without_a_traceback_and_says_which_task_to_answer_first(solution):
    original = nbformat.read(solution, as_version=4).cells
    copy = nbformat.read(ROOT / "notebooks" / "exercises" / solution.name, as_version=4).cells[1:]
    assert len(copy) == len(original)
    answers = _answer_tasks(original, copy)
    assert len(set(answers.values())) >= 3 and None not in answers.values()
    for cell, source_cell in zip(copy, original, strict=True):
        if cell.cell_type != "code":
            continue
        assert cell.metadata.get("tags", []) == source_cell.metadata.get("tags", []), cell.source
        errors = [output for output in cell.outputs if output.output_type == "error"]
        # the only error an untouched copy may show is one its solution shows on purpose, by its tag
        assert not errors or "raises-exception" in source_cell.metadata.get("tags", []), (cell.source, errors)
        if make_exercises.BEGIN in source_cell.source:
            assert "# Hint: " in cell.source and re.search(r"^\w+ = None$", cell.source, re.M), cell.source
            continue
        if cell.source.startswith("checks.check_"):
            text = "".join(str(output.get("data", {}).get("text/plain", "")) for output in cell.outputs)
            assert text.startswith("✘ No answer yet"), cell.source
            continue
        needed = _loaded_names(source_cell.source) & set(answers)
        printed = [line for line in _printed(cell).split("\n") if line.startswith("Answer Task")]
        if not needed:
            assert printed == [], cell.source
            continue
        # one line, naming the earliest task among the answers the cell uses, and that task's names
        assert len(printed) == 1 and ANSWER_FIRST.match(printed[0]), (cell.source, cell.outputs)
        task, names = ANSWER_FIRST.match(printed[0]).groups()
        first = min(answers[name] for name in needed)
        assert int(task) == first, printed[0]
        assert set(re.split(r", | and ", names)) == {name for name in needed if answers[name] == first}
        assert not any(output.output_type in {"display_data", "execute_result"} for output in cell.outputs)
        assert source_cell.source.split("\n")[0].strip() in cell.source  # the cell's own code is still there


def _answered(solution: pathlib.Path, change: dict[str, str] | None = None) -> nbformat.NotebookNode:
    """The student copy with every stub replaced by the solution's answer cell, executed."""
    original = nbformat.read(solution, as_version=4).cells
    copy = make_exercises.student_copy(nbformat.read(solution, as_version=4), solution.name)
    for cell, source_cell in zip(copy.cells[1:], original, strict=True):
        if cell.cell_type == "code" and make_exercises.BEGIN in source_cell.source:
            cell.source = source_cell.source
            for name, value in (change or {}).items():
                if re.search(rf"^{name} = ", cell.source, re.M):
                    cell.source += f"\n{name} = {value}"
    NotebookClient(copy, timeout=600, kernel_name="python3",
                   resources={"metadata": {"path": str(solution.parent)}}).execute()
    return copy


def _shown(cell) -> list:
    """What a cell shows: printed text, and each displayed value as its kinds (its text if no picture)."""
    shown = []
    for output in cell.outputs:
        if output.output_type == "stream":
            shown.append(("text", output.text))
        elif output.output_type in {"display_data", "execute_result"}:
            data = output.get("data", {})
            shown.append(("picture",) if "image/png" in data else ("value", data.get("text/plain")))
        else:
            shown.append(("error", output.get("ename")))
    return shown


def _is_guarded(cell) -> bool:
    return cell.cell_type == "code" and cell.source.startswith("if ") and 'print("Answer Task' in cell.source


GUARDED = [path for path in SOLUTIONS if any(map(_is_guarded, nbformat.read(
    ROOT / "notebooks" / "exercises" / path.name, as_version=4).cells))]


@pytest.mark.parametrize("solution", GUARDED, ids=lambda path: path.stem)
def test_a_guarded_cell_runs_its_own_code_unchanged_once_the_task_is_answered(solution):
    original = nbformat.read(solution, as_version=4).cells
    answered = _answered(solution).cells[1:]
    guarded = 0
    for cell, source_cell in zip(answered, original, strict=True):
        if _is_guarded(cell):
            guarded += 1
            assert "Answer Task" not in _printed(cell)
            assert _shown(cell) == _shown(source_cell), cell.source
    assert guarded >= 1


def test_ex06_plot_refuses_stops_in_degrees():
    solution = ROOT / "notebooks" / "solutions" / "ex06_your_own_mechanism.ipynb"
    cells = _answered(solution, {"stops": "np.degrees(stops)"}).cells
    plot = next(cell for cell in cells if cell.cell_type == "code" and "stops" in _loaded_names(cell.source)
                and "axvline" in cell.source)
    assert "radians" in _printed(plot) and ("picture",) not in _shown(plot)
    assert not any(output.output_type == "error" for cell in cells if cell.cell_type == "code"
                   for output in cell.outputs)


# ---------------------------------------------------------------- the generator on small notebooks


def _notebook(*sources):
    notebook = nbformat.v4.new_notebook()
    notebook.cells = [nbformat.v4.new_markdown_cell(source[3:]) if source.startswith("md:")
                      else nbformat.v4.new_code_cell(source) for source in sources]
    return notebook


def _run(source: str, **names) -> str:
    """Run a generated cell as plain Python; what it prints (and displays) is returned."""
    shown = []
    namespace = {"print": lambda *args: shown.append(" ".join(map(str, args))),
                 "display": lambda value: shown.append(f"display {value!r}"), **names}
    exec(compile(source, "cell", "exec"), namespace)
    return "\n".join(shown)


def test_generator_replaces_the_block_by_the_hint_and_guards_dependent_cells():
    solution = _notebook(
        "import math",
        "md:## Task 1 · Square it (compute)",
        "given = 2\n### BEGIN SOLUTION\n# HINT: square it\nanswer = given**2\nhelper = 1\n### END SOLUTION",
        "checks.check_square(answer)",
        "unrelated = given + 1",
        "derived = helper + 1",
        "uses_derived = derived * 2\nuses_derived",
        "derived = 5\nfresh = derived",
    )
    copy = make_exercises.student_copy(solution, "ex99.ipynb")
    code = [cell for cell in copy.cells if cell.cell_type == "code"]
    stub = "given = 2\n# Hint: square it\n# Your answer: replace None.\nanswer = None\nhelper = None"
    assert code[1].source == stub
    assert [cell.source for cell in code[2:4]] == ["checks.check_square(answer)", "unrelated = given + 1"]
    assert code[4].source == (
        'if helper is None:\n    print("Answer Task 1 first (this cell uses helper).")\n'
        "else:\n    derived = helper + 1"
    )
    assert code[5].source.startswith("if helper is None:")
    assert code[5].source.endswith("display(uses_derived)")
    assert code[6].source == "derived = 5\nfresh = derived"  # rebinds `derived` itself: no guard
    assert _run(code[5].source, helper=None) == "Answer Task 1 first (this cell uses helper)."
    assert _run(code[5].source, helper=1, derived=2) == "display 4"
    assert not any("raises-exception" in cell.metadata.get("tags", []) for cell in copy.cells)
    assert copy.cells[0].cell_type == "markdown" and "replace `None`" in copy.cells[0].source
    assert all(cell.outputs == [] and cell.execution_count is None for cell in code)


def test_a_function_the_answer_defines_is_its_stub_too():
    """An answer that is a procedure (ex03 and ex05 Task 1: the check calls the student's function): the
    block's def is the name the check cell uses, so the copy sets it to None as it does a value."""
    solution = _notebook(
        "md:## Task 1 · A procedure (compute)",
        "### BEGIN SOLUTION\n# HINT: def it\ndef theta4_at(theta2):\n    return 2 * theta2\n### END SOLUTION",
        "checks.check_procedure(theta4_at)",
    )
    copy = make_exercises.student_copy(solution, "ex99.ipynb")
    code = [cell for cell in copy.cells if cell.cell_type == "code"]
    assert code[0].source == "# Hint: def it\n# Your answer: replace None.\ntheta4_at = None"


def test_a_guard_names_each_task_in_turn_and_keeps_multiline_strings():
    solution = _notebook(
        "md:Some text first.\n\n## Task 1 · One (derive)",
        "### BEGIN SOLUTION\n# HINT: h\nfirst = 1\nsecond = 2\n### END SOLUTION",
        "md:A paragraph that follows Task 1.\n\n## Task 3 · Three (interpret)",
        "### BEGIN SOLUTION\n# HINT: h\nthird = 3\n### END SOLUTION",
        'note = """two\nlines"""\nprint(first + second + third, note)',
    )
    cell = make_exercises.student_copy(solution).cells[-1]
    assert cell.source == (
        "if first is None or second is None:\n"
        '    print("Answer Task 1 first (this cell uses first and second).")\n'
        'elif third is None:\n    print("Answer Task 3 first (this cell uses third).")\n'
        'else:\n    note = """two\nlines"""\n    print(first + second + third, note)'
    )
    assert _run(cell.source, first=None, second=2, third=None) == \
        "Answer Task 1 first (this cell uses first and second)."
    assert _run(cell.source, first=1, second=2, third=None) == "Answer Task 3 first (this cell uses third)."
    assert _run(cell.source, first=1, second=2, third=3) == "6 two\nlines"


def test_generator_requires_a_hint_balanced_markers_and_a_task():
    with pytest.raises(make_exercises.ExerciseFormatError, match="HINT"):
        make_exercises.student_copy(_notebook("### BEGIN SOLUTION\nx = 1\n### END SOLUTION"))
    with pytest.raises(make_exercises.ExerciseFormatError, match="exactly one"):
        make_exercises.student_copy(_notebook("### BEGIN SOLUTION\n# HINT: h\nx = 1"))
    with pytest.raises(make_exercises.ExerciseFormatError, match="top level"):
        make_exercises.student_copy(
            _notebook("if True:\n    ### BEGIN SOLUTION\n    # HINT: h\n    ### END SOLUTION")
        )
    with pytest.raises(make_exercises.ExerciseFormatError, match="Task N"):
        make_exercises.student_copy(_notebook("### BEGIN SOLUTION\n# HINT: h\nx = 1\n### END SOLUTION"))


def test_headings_are_read_on_any_line_of_a_markdown_cell():
    text = "Closing words on Task 3.\n\n## Task 4 · Stroke and time ratio (compute + interpret)\n\nSweep…"
    assert make_exercises.headings(text) == [(4, "compute + interpret")]
    assert make_exercises.headings("## Task 2 · No kind\n## What to take away") == [(2, None), (None, None)]
    assert make_exercises.headings("### Task 5 · a level-3 heading (interpret)") == []


def test_solution_lines_lists_the_block_bodies():
    solution = _notebook("a = 1\n### BEGIN SOLUTION\n# HINT: h\nb = a + 1\n\n### END SOLUTION", "c = 3")
    assert make_exercises.solution_lines(solution) == ["# HINT: h", "b = a + 1"]
