"""Generate the student copies of the exercise notebooks from their solutions.

Usage: python tools/make_exercises.py [notebooks/solutions/exNN_name.ipynb ...]   (default: all)

Every code cell of ``notebooks/solutions/*.ipynb`` may hold one solution block, under a heading
``## Task N · … (kind, P points)`` that may stand anywhere in a markdown cell above it (the points are
nbgrader's, ``tools/export_nbgrader.py``: interpret 1, any other kind 2, a sum such as
``compute + interpret`` added up)::

    ### BEGIN SOLUTION
    # HINT: what to try, written once by the author
    answer = ...
    ### END SOLUTION

In the student copy (``notebooks/exercises/``, same file name) the block becomes the hint, as a
comment, and ``name = None`` for each name the block defines that a later cell uses: the check
cell right after it then prints "No answer yet" instead of failing.  Any other later code cell
that uses such a name (directly, or through another such cell) is wrapped in a guard::

    if answer is None:
        print("Answer Task N first (this cell uses answer).")
    else:
        <the cell's own code, indented>

so it prints which task to answer first, and runs unchanged once that task is answered (a last
expression the solution displays is displayed with ``display(...)``).  An untouched copy thus runs
top to bottom without a traceback; only a cell its solution tags ``raises-exception`` (an error
shown on purpose) shows one.

Each solution notebook is then re-executed in place, and the student copy written and
executed in a fresh kernel (``tools/execute_notebooks.execute``), so both are committed
with exactly the outputs a fresh run produces.
"""

from __future__ import annotations

import ast
import copy
import io
import pathlib
import re
import sys
import tokenize

import nbformat

ROOT = pathlib.Path(__file__).resolve().parent.parent
SOLUTIONS = ROOT / "notebooks" / "solutions"
EXERCISES = ROOT / "notebooks" / "exercises"

BEGIN = "### BEGIN SOLUTION"
END = "### END SOLUTION"
HINT = "# HINT:"
RAISES = "raises-exception"
#: ``## Task N · what it asks (kinds, P points)``: a task's heading, on any line of a markdown cell; the last
#: parentheses hold its kinds (``compute``, ``compute + interpret``, …) and the points they are worth
#: (``2 points``, ``1 point``; an older heading may leave the points out)
TASK_HEADING = re.compile(r"^##\s+Task\s+(\d+)\b(?:.*\(([^()]*)\)\s*$)?")
#: the inside of those parentheses: the kinds, then optionally ", P point(s)"
KINDS_AND_POINTS = re.compile(r"^(?P<kinds>.*?)(?:\s*,\s*(?P<points>\d+)\s+(?P<word>points?))?\s*$")

NOTE = (
    "*Your copy of this exercise set.* Each task's answer cell gives a hint and sets the answer to `None`: "
    "replace `None` with your answer, run the cell, then run the check cell below it. The check says ✔, or "
    "what looks wrong (never the expected value). A cell further down that uses an answer prints "
    "\"Answer Task N first\" until that task is answered, so **Run All** runs through the notebook with "
    "tasks still unanswered."
)
GUARD = "Answer Task {task} first (this cell uses {names})."


class ExerciseFormatError(ValueError):
    """A solution notebook breaks the block conventions (message names the cell)."""


def task_headings(markdown: str) -> list[tuple[int | None, str | None, str | None]]:
    """The level-2 headings of a markdown cell, in order: ``(N, kinds, points)`` for
    ``## Task N · … (kinds, P points)`` — ``points`` as written ("2 points", "1 point"; ``None`` when the
    heading gives none, ``kinds`` ``None`` without the parentheses) — and ``(None, None, None)`` for any
    other ``## `` heading."""
    found = []
    for line in markdown.split("\n"):
        if line.startswith("## "):
            task = TASK_HEADING.match(line.rstrip())
            if not task:
                found.append((None, None, None))
            elif task.group(2) is None:
                found.append((int(task.group(1)), None, None))
            else:
                parts = KINDS_AND_POINTS.match(task.group(2))
                points = f"{parts['points']} {parts['word']}" if parts["points"] else None
                found.append((int(task.group(1)), parts["kinds"].strip(), points))
    return found


def headings(markdown: str) -> list[tuple[int | None, str | None]]:
    """The level-2 headings of a markdown cell, in order: ``(N, kinds)`` for ``## Task N · … (kinds)`` or
    ``(kinds, P points)`` (``kinds`` ``None`` without the parentheses), ``(None, None)`` for any other
    ``## `` heading."""
    return [(task, kinds) for task, kinds, _ in task_headings(markdown)]


def split_solution(
    source: str, where: str = "cell", answers: tuple[str, ...] = ()
) -> tuple[str, list[str], str] | None:
    """Split a cell's source at its solution block.

    Returns ``(student_source, body_lines, hint)`` — the source with the block replaced by a
    stub that sets each of ``answers`` to ``None``, the lines of the block's body (hint line
    included), and the hint text — or ``None`` when the cell has no block.
    """
    lines = source.split("\n")
    begins = [i for i, line in enumerate(lines) if line.strip() == BEGIN]
    ends = [i for i, line in enumerate(lines) if line.strip() == END]
    if not begins and not ends:
        return None
    if len(begins) != 1 or len(ends) != 1 or ends[0] < begins[0]:
        raise ExerciseFormatError(f"{where}: needs exactly one {BEGIN!r} line followed by one {END!r} line")
    start, stop = begins[0], ends[0]
    if lines[start] != lines[start].lstrip():
        raise ExerciseFormatError(f"{where}: the solution block must be at the top level (not indented)")
    body = lines[start + 1 : stop]
    hints = [line.strip()[len(HINT) :].strip() for line in body if line.strip().startswith(HINT)]
    if not hints:
        raise ExerciseFormatError(f"{where}: the solution block has no '{HINT} ...' line")
    hint = " ".join(hints)
    stub = [f"# Hint: {hint}", "# Your answer: replace None."] + [f"{name} = None" for name in answers]
    student = "\n".join(lines[:start] + stub + lines[stop + 1 :])
    return student, body, hint


def _bound_names(tree: ast.AST) -> set[str]:
    """Names a piece of code assigns, defines or imports."""
    names: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Store | ast.Del):
            names.add(node.id)
        elif isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef):
            names.add(node.name)
        elif isinstance(node, ast.Import | ast.ImportFrom):
            names.update((alias.asname or alias.name).split(".")[0] for alias in node.names)
    return names


def _used_names(tree: ast.AST) -> set[str]:
    return {
        node.id for node in ast.walk(tree) if isinstance(node, ast.Name) and isinstance(node.ctx, ast.Load)
    }


def _free_names(tree: ast.Module) -> set[str]:
    """Names a cell reads before it binds them itself (statement by statement)."""
    free: set[str] = set()
    bound: set[str] = set()
    for statement in tree.body:
        free |= _used_names(statement) - bound
        bound |= _bound_names(statement)
    return free


def _answer_names(body: list[str], later: list[str]) -> tuple[str, ...]:
    """The names a solution body defines that later cells use, in order of definition."""
    used = set().union(*(_used_names(ast.parse(source)) for source in later))
    defines = ast.Name | ast.FunctionDef | ast.AsyncFunctionDef | ast.ClassDef  # a def binds its name too
    order = [node.id if isinstance(node, ast.Name) else node.name
             for node in ast.walk(ast.parse("\n".join(body))) if isinstance(node, defines)]
    bound = _bound_names(ast.parse("\n".join(body)))
    return tuple(dict.fromkeys(name for name in order if name in bound and name in used))


def _is_check(cell) -> bool:
    return cell.cell_type == "code" and cell.source.startswith("checks.check_")


def _displays_result(cell) -> bool:
    """Whether the cell's last expression shows a value: the solution's run says so, else any
    expression but a call (a call such as ``plt.show()`` usually returns None)."""
    tree = ast.parse(cell.source)
    if not tree.body or not isinstance(tree.body[-1], ast.Expr):
        return False
    if cell.get("outputs"):
        return any(output.output_type == "execute_result" for output in cell.outputs)
    return not isinstance(tree.body[-1].value, ast.Call)


def _indented(source: str) -> list[str]:
    """The source's lines indented by four spaces, except lines inside a multi-line string."""
    inside: set[int] = set()  # 0-based numbers of lines that continue a string token
    for token in tokenize.generate_tokens(io.StringIO(source).readline):
        if token.type == tokenize.STRING and token.end[0] > token.start[0]:
            inside.update(range(token.start[0], token.end[0]))
    return [line if not line.strip() or number in inside else "    " + line
            for number, line in enumerate(source.split("\n"))]


def guarded(source: str, needs: dict[int, list[str]], display_last: bool = False) -> str:
    """The cell's code behind a check of the answers it needs, task by task (``needs``: task → names).

    While an answer is still ``None`` the cell prints which task to answer first and does nothing else.
    """
    if display_last:  # inside ``else:`` a last expression is no longer shown by itself
        last = ast.parse(source).body[-1]
        lines = source.split("\n")
        expression = ast.get_source_segment(source, last)
        shown = (lines[last.lineno - 1][: last.col_offset] + f"display({expression})"
                 + lines[last.end_lineno - 1][last.end_col_offset :])
        source = "\n".join(lines[: last.lineno - 1] + shown.split("\n") + lines[last.end_lineno :])
    guard = []
    for task in sorted(needs):
        names = needs[task]
        condition = " or ".join(f"{name} is None" for name in names)
        listed = " and ".join([", ".join(names[:-1]), names[-1]] if len(names) > 1 else names)
        message = GUARD.format(task=task, names=listed)
        guard += [f"{'elif' if guard else 'if'} {condition}:", f'    print("{message}")']
    return "\n".join(guard + ["else:"] + _indented(source))


def student_copy(solution: nbformat.NotebookNode, name: str = "") -> nbformat.NotebookNode:
    """The student copy of a solution notebook (not executed: no outputs)."""
    notebook = copy.deepcopy(solution)
    task = None
    answer_task: dict[str, int] = {}  # each name set to None in a stub → its task
    roots: dict[str, set[str]] = {}  # a name that exists only once answers are given → those answers
    for index, cell in enumerate(notebook.cells):
        where = f"{name} cell {index}"
        if cell.cell_type == "markdown":
            for heading, _ in headings(cell.source):
                task = heading
            continue
        if cell.cell_type != "code":
            continue
        split = split_solution(cell.source, where)
        if split is not None:
            if task is None:
                raise ExerciseFormatError(f"{where}: a solution block outside a '## Task N · … (kind)' part")
            body = split[1]
            later = [
                other.source
                for other in notebook.cells[index + 1 :]
                if other.cell_type == "code" and BEGIN not in other.source  # a later task defines its own
            ]
            answers = _answer_names(body, later)
            student = split_solution(cell.source, where, answers)[0]
            if _free_names(ast.parse(student)) & set(roots):
                raise ExerciseFormatError(f"{where}: code outside the solution block uses an earlier answer")
            cell.source = student
            for answer in answers:
                answer_task[answer] = task
                roots[answer] = {answer}
        elif not _is_check(cell):
            tree = ast.parse(cell.source)
            needed = set().union(*(roots[used] for used in _free_names(tree) if used in roots))
            if needed:
                needs: dict[int, list[str]] = {}
                for answer in sorted(needed, key=list(answer_task).index):
                    needs.setdefault(answer_task[answer], []).append(answer)
                cell.source = guarded(cell.source, needs, _displays_result(cell))
            for bound in _bound_names(tree):
                if needed:
                    roots[bound] = set(needed)
                else:
                    roots.pop(bound, None)
        cell.outputs, cell.execution_count = [], None
    note = nbformat.v4.new_markdown_cell(NOTE)
    note.metadata["tags"] = ["student-copy-note"]
    notebook.cells.insert(0, note)
    notebook.nbformat_minor = max(notebook.get("nbformat_minor", 4), 5)
    for number, cell in enumerate(notebook.cells):  # deterministic ids: the file changes only with a cell
        cell["id"] = f"cell-{number:03d}"
    return notebook


def solution_lines(solution: nbformat.NotebookNode) -> list[str]:
    """Every line of every solution body (stripped), as they must never reach a student copy."""
    lines = []
    for index, cell in enumerate(solution.cells):
        if cell.cell_type == "code":
            split = split_solution(cell.source, f"cell {index}")
            if split is not None:
                lines += [line.strip() for line in split[1] if line.strip()]
    return lines


def exercise_path(solution_path: pathlib.Path) -> pathlib.Path:
    return EXERCISES / solution_path.name


def main(argv: list[str]) -> int:
    sys.path.insert(0, str(ROOT / "tools"))
    from execute_notebooks import execute

    paths = [pathlib.Path(a).resolve() for a in argv] or sorted(SOLUTIONS.glob("ex*.ipynb"))
    EXERCISES.mkdir(parents=True, exist_ok=True)
    for path in paths:
        seconds = execute(path)
        print(f"executed {path.relative_to(ROOT)}  ({seconds:.1f} s)")
        target = exercise_path(path)
        nbformat.write(student_copy(nbformat.read(path, as_version=4), path.name), target)
        seconds = execute(target)
        print(f"generated {target.relative_to(ROOT)}  ({seconds:.1f} s)")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
