"""Cross-references in what a reader reads: every "lesson NN", "section N", "Task N" and "exercises NN"
named in a lesson's or an exercise set's markdown, in README.md or in docs/ points to something that
exists — the lesson's notebook, a numbered section heading of the lesson meant, a task of the set."""

import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
LESSONS = {p.name[:2]: p for p in sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))}
SETS = {p.name[2:4]: p for p in sorted((ROOT / "notebooks" / "solutions").glob("ex[0-9][0-9]_*.ipynb"))}
NOTEBOOKS = [*LESSONS.values(), *SETS.values()]
TEXTS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]

LESSON = re.compile(r"\b[Ll]essons?\s+((?:\d\d(?:\s*(?:[–-]|,|and|or|to)\s*)?)+)")
SECTION = re.compile(r"\b[Ss]ections?\s+(\d+(?:\s*(?:[–-]|,|and|or)\s*\d+)*)")
OF_LESSON = re.compile(r"\b[Ll]esson\s+(\d\d)(?:'s|’s)\s+sections?\s+(\d+)"
                       r"|\b[Ss]ection\s+(\d+)\s+of\s+lesson\s+(\d\d)")
TASK = re.compile(r"\bTasks?\s+(\d(?:\s*(?:[–-]|,|and|or)\s*\d)*)")


def markdown(path: Path) -> list[str]:
    if path.suffix == ".md":
        return [path.read_text()]
    cells = json.loads(path.read_text())["cells"]
    return ["".join(c["source"]) for c in cells if c["cell_type"] == "markdown"]


def numbers(text: str) -> list[int]:
    """The numbers of "03–05", "03, 04 and 06": a range stands for every number in it."""
    found, values = re.findall(r"\d+|[–-]", text), []
    for k, token in enumerate(found):
        if token in "–-" and values and k + 1 < len(found) and found[k + 1].isdigit():
            values.extend(range(values[-1] + 1, int(found[k + 1])))
        elif token.isdigit():
            values.append(int(token))
    return values


def sections(path: Path) -> set[int]:
    """The numbered sections of a notebook: its headings "## N. title"."""
    return {int(m.group(1)) for text in markdown(path) for m in re.finditer(r"^##\s+(\d+)\.\s", text, re.M)}


def tasks(path: Path) -> set[int]:
    heading = re.compile(r"^##\s+Task\s+(\d+)\b", re.M)
    return {int(m.group(1)) for text in markdown(path) for m in heading.finditer(text)}


@pytest.mark.parametrize("path", NOTEBOOKS + TEXTS, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_lesson_named_exists(path):
    wrong = [f"lesson {n:02d}: {m.group(0)!r}" for text in markdown(path) for m in LESSON.finditer(text)
             for n in numbers(m.group(1)) if f"{n:02d}" not in LESSONS]
    assert not wrong, wrong


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_section_named_is_a_numbered_heading_of_the_lesson_meant(path):
    wrong = []
    for text in markdown(path):
        elsewhere = set()
        for m in OF_LESSON.finditer(text):  # "lesson 03's section 4", "section 4 of lesson 03"
            lesson, number = (m.group(1), m.group(2)) if m.group(1) else (m.group(4), m.group(3))
            elsewhere.add(m.start())
            if lesson not in LESSONS or int(number) not in sections(LESSONS[lesson]):
                wrong.append(f"lesson {lesson} section {number}")
        for m in SECTION.finditer(text):
            before = text[max(0, m.start() - 40):m.start()]
            named = re.search(r"[Ll]esson\s+\d\d", before)
            if any(abs(m.start() - start) < 40 for start in elsewhere) or named:
                continue  # another lesson's section: checked above, or named just before it
            own = sections(path)
            wrong += [f"section {n} ({m.group(0)!r})" for n in numbers(m.group(1)) if n not in own]
    assert not wrong, wrong


@pytest.mark.parametrize("path", list(SETS.values()), ids=lambda p: p.name)
def test_every_task_named_is_a_task_of_the_set(path):
    own = tasks(path)
    wrong = [f"Task {n}" for text in markdown(path) for m in TASK.finditer(text) for n in numbers(m.group(1))
             if n not in own]
    assert own and not wrong, wrong


@pytest.mark.parametrize("path", NOTEBOOKS + TEXTS, ids=lambda p: p.relative_to(ROOT).as_posix())
def test_every_exercise_set_named_exists(path):
    named = re.compile(r"\b[Ee]xercises?\s+(?:set\s+)?(\d\d)\b")
    wrong = [m.group(0) for text in markdown(path) for m in named.finditer(text) if m.group(1) not in SETS]
    assert not wrong, wrong


def test_the_patterns_read_what_a_sentence_says():
    assert numbers("03–05") == [3, 4, 5] and numbers("03, 04 and 06") == [3, 4, 6]
    assert [m.group(1) for m in LESSON.finditer("see lessons 02–03 and lesson 12")] == ["02–03 and ", "12"]
    assert 4 in sections(LESSONS["03"]) and 9 not in sections(LESSONS["03"])
