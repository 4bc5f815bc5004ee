"""Generate the student copies of the exercise notebooks from their solutions.

Usage: python tools/make_exercises.py [notebooks/solutions/exNN_name.ipynb ...]   (default: all)

Every code cell of ``notebooks/solutions/*.ipynb`` may hold one solution block::

    ### BEGIN SOLUTION
    # HINT: what to try, written once by the author
    answer = ...
    ### END SOLUTION

In the student copy (``notebooks/exercises/``, same file name) the block becomes the hint, as a
comment, and ``name = None`` for each name the block defines that a later cell uses: the check
cell right after it then prints "No answer yet" instead of failing, so Run All runs every cell of
an untouched copy without a traceback.  Any other later code cell that uses such a name (directly,
or through another such cell) is tagged ``raises-exception``: it cannot run until the student has
answered.

Each solution notebook is then re-executed in place, and the student copy written and
executed in a fresh kernel (``tools/execute_notebooks.execute``), so both are committed
with exactly the outputs a fresh run produces.
"""

from __future__ import annotations

import ast
import copy
import pathlib
import sys

import nbformat

ROOT = pathlib.Path(__file__).resolve().parent.parent
SOLUTIONS = ROOT / "notebooks" / "solutions"
EXERCISES = ROOT / "notebooks" / "exercises"

BEGIN = "### BEGIN SOLUTION"
END = "### END SOLUTION"
HINT = "# HINT:"
RAISES = "raises-exception"

NOTE = (
    "*Student copy* — generated from `notebooks/solutions/{name}` by `make exercises`; edit the solution, "
    "not this file. Replace each `raise NotImplementedError(...)` with your answer, run the cell, then run "
    "the check cell below it."
)


class ExerciseFormatError(ValueError):
    """A solution notebook breaks the block conventions (message names the cell)."""


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


def _tags(cell) -> list[str]:
    return list(cell.get("metadata", {}).get("tags", []))


def _set_tag(cell, tag: str) -> None:
    tags = _tags(cell)
    if tag not in tags:
        cell.setdefault("metadata", {})["tags"] = tags + [tag]


def _answer_names(body: list[str], later: list[str]) -> tuple[str, ...]:
    """The names a solution body defines that later cells use, in order of definition."""
    used = set().union(*(_used_names(ast.parse(source)) for source in later))
    order = [node.id for node in ast.walk(ast.parse("\n".join(body))) if isinstance(node, ast.Name)]
    bound = _bound_names(ast.parse("\n".join(body)))
    return tuple(dict.fromkeys(name for name in order if name in bound and name in used))


def _is_check(cell) -> bool:
    return cell.cell_type == "code" and cell.source.startswith("checks.check_")


def student_copy(solution: nbformat.NotebookNode, name: str = "") -> nbformat.NotebookNode:
    """The student copy of a solution notebook (not executed: no outputs)."""
    notebook = copy.deepcopy(solution)
    undefined: set[str] = set()  # names that are unbound or None once the solutions are removed
    for index, cell in enumerate(notebook.cells):
        if cell.cell_type == "code":
            cell.outputs, cell.execution_count = [], None
        else:
            continue
        where = f"{name} cell {index}"
        split = split_solution(cell.source, where)
        if split is not None:
            body = split[1]
            later = [
                other.source
                for other in notebook.cells[index + 1 :]
                if other.cell_type == "code" and BEGIN not in other.source  # a later task defines its own
            ]
            cell.source = split_solution(cell.source, where, _answer_names(body, later))[0]
            undefined |= _bound_names(ast.parse("\n".join(body)))
            continue
        tree = ast.parse(cell.source)
        if _used_names(tree) & undefined and not _is_check(cell):
            _set_tag(cell, RAISES)
            undefined |= _bound_names(tree)
    note = nbformat.v4.new_markdown_cell(NOTE.format(name=name or "…"))
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
