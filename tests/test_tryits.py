"""Every lesson's "Try it": its worked answer is hidden in every viewer, and the cell after it proves it.

* The answer (code and what it prints) sits in a markdown cell inside ``<details>``, so GitHub, nbviewer,
  nbconvert's HTML, JupyterLab and the course website fold it; no code cell shows it.
* In nbconvert's HTML (and the site's page, when the site is built) the printed answer appears only inside
  ``<details>``.
* The cell after it calls ``run_worked_answer`` (which re-runs the answer and compares what it prints) and
  asserts that the Try-it's own checker accepts the printed answer; strict nbval runs it with the lesson.
"""

from __future__ import annotations

import re
from html.parser import HTMLParser
from pathlib import Path

import nbformat
import pytest
from nbconvert import HTMLExporter

from course_lib.checks import worked_answers

ROOT = Path(__file__).resolve().parent.parent
LESSONS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))


def try_it(path: Path):
    """(notebook, index of the check cell, its checker's name) for a lesson with a Try-it, else None."""
    notebook = nbformat.read(path, as_version=4)
    for index, cell in enumerate(notebook.cells):
        if cell.cell_type == "code" and (found := re.search(r"^(check_\w+)\(\(?my_", cell.source, re.M)):
            return notebook, index, found[1]
    return None


WITH_TRY_IT = [path for path in LESSONS if try_it(path)]


def test_the_lessons_with_a_try_it_checker():
    names = {path.name[:2] for path in WITH_TRY_IT}
    assert names == {"00", "01", "02", "03", "04", "05", "06", "07", "08", "09", "10", "12"}, names


@pytest.mark.parametrize("path", WITH_TRY_IT, ids=lambda path: path.name[:2])
def test_the_worked_answer_is_folded_and_proved(path):
    notebook, check_index, checker = try_it(path)
    answers = worked_answers(path)
    assert len(answers) == 1, f"one worked answer (```python + ```text inside <details>) in {path.name}"
    code, printed = answers[0]
    assert code.strip() and printed.strip()
    later = [cell for cell in notebook.cells[check_index + 1:] if cell.cell_type == "code"]
    proof = next(cell for cell in later if "run_worked_answer" in cell.source)
    assert f'run_worked_answer("{path.name}", globals())' in proof.source
    assert re.search(rf"assert {checker}\(", proof.source) and "worked.numbers" in proof.source, proof.source
    assert not proof.metadata.get("jupyter", {}).get("source_hidden"), "the proof shows no answer"
    for cell in later:  # no code cell repeats the answer's code (it would show it on GitHub)
        assert not any(line.strip() and line.strip() in cell.source for line in code.splitlines()
                       if len(line.strip()) > 30), cell.source


class _Visible(HTMLParser):
    """The page's text outside ``<details>`` (and outside scripts and styles)."""

    def __init__(self):
        super().__init__()
        self.depth, self.skip, self.text = 0, 0, []

    def handle_starttag(self, tag, attrs):
        self.depth += tag == "details"
        self.skip += tag in ("script", "style")

    def handle_endtag(self, tag):
        self.depth -= tag == "details"
        self.skip -= tag in ("script", "style")

    def handle_data(self, data):
        if not self.depth and not self.skip:
            self.text.append(data)


def visible_text(html: str) -> str:
    parser = _Visible()
    parser.feed(html)
    return " ".join(" ".join(parser.text).split())


@pytest.mark.parametrize("path", WITH_TRY_IT, ids=lambda path: path.name[:2])
def test_the_printed_answer_shows_only_inside_details(path):
    (_, printed), = worked_answers(path)
    numbers = re.findall(r"(?<![\w.])-?\d+\.\d{3,}", printed)
    if path.name.startswith("01"):  # lesson 01's answer is four whole counts: the answer's line itself
        numbers = [line.strip() for line in printed.splitlines() if line.strip()]
    assert numbers, printed
    html, _ = HTMLExporter().from_filename(str(path))
    assert "<details" in html
    outside = visible_text(html)
    assert not [number for number in numbers if number in outside], path.name
    built = ROOT / "_build" / "html" / "notebooks" / path.with_suffix(".html").name
    if built.exists():  # the website, when it is built (CI builds it before the tests)
        assert not [number for number in numbers if number in visible_text(built.read_text())], built
