"""The committed notebooks as a reader meets them, before anything runs.

- Every explorer cell and every animation cell carries a still picture (``image/png``) beside the
  live widget or the JavaScript player, so GitHub, ``nbconvert`` and an unopened notebook show it.
- No student copy (notebooks/exercises) shows a ``NameError``: an unanswered task says so in words.
- Every notebook is stored exactly as JupyterLab 4 saves it (``tools/execute_notebooks.normalize``),
  so opening a lesson does not mark it modified.
"""

import base64
import pathlib
import re
import sys

import nbformat
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
from execute_notebooks import KERNELSPEC, normalize, read  # noqa: E402

NOTEBOOKS = sorted((ROOT / "notebooks").rglob("*.ipynb"))
STUDENT_COPIES = sorted((ROOT / "notebooks" / "exercises").glob("*.ipynb"))
EXPLORER_CALL = re.compile(r"\b(?:\w+_explorer|explore)\(")
ANIMATION_CALL = re.compile(r"\b(?:animation_html|animate_linkage|animate)\(")
PNG = b"\x89PNG\r\n\x1a\n"


def _name(path: pathlib.Path) -> str:
    return str(path.relative_to(ROOT / "notebooks"))


def _calls(cell, pattern) -> bool:
    """The cell's code calls the function (a line that only imports it does not count)."""
    code = [line for line in cell.source.splitlines()
            if not line.lstrip().startswith(("import ", "from ", "#"))]
    return cell.cell_type == "code" and any(pattern.search(line) for line in code)


def _deliberate_error(cell) -> bool:
    return "raises-exception" in cell.metadata.get("tags", []) and any(
        output.output_type == "error" for output in cell.outputs)


def _picture_cells(pattern):
    cells = []
    for path in NOTEBOOKS:
        notebook = nbformat.read(path, as_version=4)
        for index, cell in enumerate(notebook.cells):
            if _calls(cell, pattern) and not _deliberate_error(cell):
                cells.append(pytest.param(cell, id=f"{_name(path)}#{index}"))
    return cells


def _pngs(cell) -> list[bytes]:
    shown = [output for output in cell.outputs if output.output_type in ("display_data", "execute_result")]
    return [base64.b64decode(output["data"]["image/png"]) for output in shown
            if "image/png" in output["data"]]


@pytest.mark.parametrize("cell", _picture_cells(EXPLORER_CALL))
def test_explorer_cell_shows_a_picture_and_the_widget(cell):
    pngs = _pngs(cell)
    assert pngs and all(png.startswith(PNG) for png in pngs), "no image/png output: re-run the notebook"
    widget = [output for output in cell.outputs
              if "application/vnd.jupyter.widget-view+json" in output.get("data", {})]
    assert widget, "no widget view: the explorer is not the cell's displayed value"
    texts = [output.get("data", {}).get("text/plain", "") for output in cell.outputs]
    assert not any("HBox(children=" in text for text in texts), "the widget's repr instead of the readout"


@pytest.mark.parametrize("cell", _picture_cells(ANIMATION_CALL))
def test_animation_cell_shows_a_still_and_the_player(cell):
    pngs = _pngs(cell)
    assert pngs and all(png.startswith(PNG) for png in pngs), (
        "no image/png output: display animation_html(...) itself as the cell's value (not HTML(...))"
    )
    assert any("<script" in output.get("data", {}).get("text/html", "") for output in cell.outputs)


def test_the_committed_notebooks_have_explorer_and_animation_cells():
    assert len(_picture_cells(EXPLORER_CALL)) >= 11 and len(_picture_cells(ANIMATION_CALL)) >= 3


@pytest.mark.parametrize("path", STUDENT_COPIES, ids=_name)
def test_student_copy_shows_no_name_error(path):
    notebook = nbformat.read(path, as_version=4)
    for index, cell in enumerate(notebook.cells):
        for output in cell.get("outputs", []):
            assert output.get("ename") != "NameError", f"cell {index}: {output.get('evalue')}"
            assert "NameError" not in output.get("text", ""), f"cell {index}"


@pytest.mark.parametrize("path", NOTEBOOKS, ids=_name)
def test_notebook_is_stored_as_jupyterlab_saves_it(path):
    text = path.read_text(encoding="utf-8")
    notebook = read(path)
    assert (notebook.nbformat, notebook.nbformat_minor) == (4, 5)
    ids = [cell.get("id") for cell in notebook.cells]
    assert None not in ids and len(set(ids)) == len(ids), "every cell has its own id"
    assert notebook.metadata.get("kernelspec") == KERNELSPEC
    assert "widgets" not in notebook.metadata
    expected = nbformat.writes(normalize(notebook, path.name))
    assert text == expected + ("" if expected.endswith("\n") else "\n"), (
        "not as JupyterLab writes it: run `python tools/execute_notebooks.py --normalize-only` on it"
    )


@pytest.mark.parametrize("path", sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb")), ids=_name)
def test_no_lesson_cell_raises_on_purpose(path):
    """Run All goes top to bottom anywhere (Colab, VS Code, a plain kernel): a cell that shows a refusal
    catches it and prints its message, so no lesson cell is tagged to fail or keeps an error output."""
    notebook = nbformat.read(path, as_version=4)
    for index, cell in enumerate(notebook.cells):
        assert "raises-exception" not in cell.metadata.get("tags", []), f"cell {index} is tagged to fail"
        assert not any(output.output_type == "error" for output in cell.get("outputs", [])), \
            f"cell {index} keeps an error output"


@pytest.mark.parametrize("path", sorted((ROOT / "notebooks").glob("**/*.ipynb")), ids=_name)
def test_display_maths_stands_as_its_own_paragraph(path):
    """A $$…$$ block between lines of text breaks the website's and the PDF's formulas (stray $, text set as
    maths): every display-maths block has a blank line (or the cell's edge) before and after it."""
    notebook = nbformat.read(path, as_version=4)
    for index, cell in enumerate(notebook.cells):
        if cell.cell_type != "markdown":
            continue
        lines, inside = cell.source.split("\n"), False
        for k, line in enumerate(lines):
            text = line.strip()
            opens = not inside and text.startswith("$$")
            closes = (opens and len(text) > 2 and text.endswith("$$")) or (inside and text.endswith("$$"))
            if opens:
                assert k == 0 or not lines[k - 1].strip(), f"cell {index}: text right before {text[:40]!r}"
                inside = not closes
            elif closes:
                inside = False
            if closes:
                after = lines[k + 1].strip() if k + 1 < len(lines) else ""
                assert not after, f"cell {index}: text right after {text[-40:]!r}"
