"""Every lesson and exercise set runs wherever a student opens it, not only beside its own notebook file.

* Each lesson, each exercise set's solution and each student copy, as the percent script the website offers
  (``tools/build_site.percent_script``), runs with plain ``python`` in a folder that holds no notebook: exit
  code 0, no traceback, no warning.  That is the ``.py`` download, and Run All of a kernel started elsewhere
  (Colab, VS Code) with the cell tags stripped (no lesson cell is tagged; tests/test_notebook_outputs.py).
* Worked answers are checked there from the copy course_lib ships (``course_lib/checks/worked_answers.json``,
  package data, with the tested versions lesson 00 compares with); both equal what the lessons and
  environment.txt hold, and a wheel built from the repository carries them.
* Every lesson opens with the set-up cell of tools/repository.py: silent where course_lib is installed; where
  it is not, it says so and installs it with pip from the repository, or names the command that installs it.
"""

from __future__ import annotations

import concurrent.futures
import contextlib
import importlib.util
import io
import json
import os
import re
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import nbformat
import numpy as np
import pytest

from course_lib.checks import (
    WORKED_ANSWERS_FILE,
    WorkedAnswerError,
    packaged_answers,
    run_worked_answer,
    worked_answers,
)
from course_lib.errors import InvalidArgumentError

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import build_site  # noqa: E402
import package_data  # noqa: E402
import repository  # noqa: E402

LESSONS = sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))
SETS = sorted((ROOT / "notebooks" / "solutions").glob("ex*.ipynb")) + sorted(
    (ROOT / "notebooks" / "exercises").glob("ex*.ipynb"))
SCRIPT_SECONDS = 300  # the slowest lesson (07) takes about 16 s alone on a busy machine


def _name(path: Path) -> str:
    return path.relative_to(ROOT / "notebooks").as_posix()


# ------------------------------------------------------------------------------ every notebook, as a script

def _run_script(notebook: Path, folder: Path) -> subprocess.CompletedProcess:
    """The notebook's percent script, run with ``python`` in ``folder`` (which holds nothing else)."""
    folder.mkdir(parents=True)
    script = folder / notebook.with_suffix(".py").name
    script.write_text(build_site.percent_script(nbformat.read(notebook, as_version=4)), encoding="utf-8")
    environment = {**os.environ, "MPLBACKEND": "Agg",
                   "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")]))}
    return subprocess.run([sys.executable, script.name], cwd=folder, env=environment, capture_output=True,
                          text=True, timeout=SCRIPT_SECONDS)


@pytest.fixture(scope="module")
def script_runs(tmp_path_factory):
    """Every lesson's and set's script run, two at a time: notebook → (its folder, the finished process)."""
    base = tmp_path_factory.mktemp("run-anywhere")
    folders = {path: base / _name(path).replace("/", "-").removesuffix(".ipynb") for path in LESSONS + SETS}
    workers = max(1, min(2, os.cpu_count() or 1))
    with concurrent.futures.ThreadPoolExecutor(workers) as pool:
        running = {path: pool.submit(_run_script, path, folder) for path, folder in folders.items()}
        return {path: (folders[path], future.result()) for path, future in running.items()}


@pytest.mark.parametrize("notebook", LESSONS + SETS, ids=_name)
def test_the_notebook_runs_as_a_python_script_in_a_folder_without_notebooks(script_runs, notebook):
    folder, run = script_runs[notebook]
    assert not list(folder.glob("*.ipynb")) and not (folder.parent / notebook.name).exists()
    shown = (f"exit code {run.returncode}\n--- stdout (end)\n{run.stdout[-3000:]}\n"
             f"--- stderr\n{run.stderr[-3000:]}")
    assert run.returncode == 0, shown
    assert "Traceback (most recent call last)" not in run.stdout + run.stderr, shown
    assert not re.search(r"^\w*(?:Error|Warning)\b", run.stderr, re.M), shown


def test_lesson_00_compares_its_set_up_with_the_versions_installed_with_course_lib(script_runs):
    """Away from environment.txt (as on Colab), lesson 00 compares the versions with course_lib's copy."""
    _, run = script_runs[ROOT / "notebooks" / "00_start_here.ipynb"]
    assert "set-up OK (compared with the tested versions installed with course_lib)" in run.stdout


# ------------------------------------------------------------------------------ what course_lib ships

def test_the_packaged_worked_answers_and_versions_are_the_lessons_and_environment_txt():
    assert package_data.stale() == [], (
        "course_lib's package data is out of date: run `python tools/package_data.py` and commit it")
    shipped = json.loads(WORKED_ANSWERS_FILE.read_text(encoding="utf-8"))
    assert set(shipped) == {path.name for path in LESSONS if worked_answers(path)}
    for path in LESSONS:  # each answer, where the file says: in a markdown cell, inside <details>
        cells = nbformat.read(path, as_version=4).cells
        for answer in shipped.get(path.name, []):
            cell = cells[answer["cell"] - 1]
            assert cell.cell_type == "markdown" and "<details" in cell.source
            assert answer["code"] in cell.source and answer["printed"] in cell.source
    environment = (ROOT / "environment.txt").read_text().splitlines()
    pins = [line for line in environment if re.match(r"[\w-]+==", line)]
    tested = (ROOT / "course_lib" / "environment.txt").read_text().splitlines()
    assert [line for line in tested if not line.startswith("#")] == pins


def test_a_wheel_built_from_the_repository_carries_the_package_data(tmp_path):
    source = tmp_path / "source"
    source.mkdir()
    for name in ("pyproject.toml", "README.md", "LICENSE", "LICENSE-content"):
        shutil.copy(ROOT / name, source / name)
    shutil.copytree(ROOT / "course_lib", source / "course_lib", ignore=shutil.ignore_patterns("__pycache__"))
    subprocess.run([sys.executable, "-m", "pip", "wheel", "--quiet", "--no-deps", "--no-build-isolation",
                    "--disable-pip-version-check", "-w", str(tmp_path / "wheel"), str(source)],
                   check=True, capture_output=True, cwd=tmp_path)
    wheel, = (tmp_path / "wheel").glob("course_lib-*.whl")
    names = zipfile.ZipFile(wheel).namelist()
    assert {"course_lib/checks/worked_answers.json", "course_lib/environment.txt"} <= set(names)


def test_without_the_notebook_file_the_packaged_answer_is_run(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    worked = run_worked_answer("00_start_here.ipynb", {"np": np, "l2": 0.06})
    assert worked.numbers == pytest.approx((0.0, 0.06), abs=1e-12)  # l2 (cos 90°, sin 90°), by hand
    with pytest.raises(WorkedAnswerError, match=r"'99_no.ipynb' is not a file here, and course_lib holds no"):
        run_worked_answer("99_no.ipynb", {})


@pytest.mark.parametrize("notebooks", ["00_start_here.ipynb", Path("x.ipynb"), None, 3, [None]])
def test_packaged_answers_refuses_what_is_not_a_list_of_lessons_by_name(notebooks):
    with pytest.raises(InvalidArgumentError, match="notebook"):
        packaged_answers(notebooks)


def test_the_notebook_file_wins_over_the_packaged_answer(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    cell = nbformat.v4.new_markdown_cell(
        "<details>\n\n```python\nprint(l2 * 2)\n```\n```text\n0.12\n```\n</details>")
    nbformat.write(nbformat.v4.new_notebook(cells=[cell]), tmp_path / "00_start_here.ipynb")
    assert run_worked_answer("00_start_here.ipynb", {"l2": 0.06}).numbers == (0.12,)


# ------------------------------------------------------------------------------ the set-up cell

def _first_code_cell(path: Path):
    return next(cell for cell in nbformat.read(path, as_version=4).cells if cell.cell_type == "code")


@pytest.mark.parametrize("path", LESSONS + SETS, ids=_name)
def test_every_lesson_opens_with_the_set_up_cell_and_it_shows_nothing(path):
    cell = _first_code_cell(path)
    assert cell.source == repository.setup_cell(repository.repository_url(environ={}))
    assert cell.outputs == [], "where course_lib is installed, the set-up cell prints nothing"


def _run_setup_cell(source: str, monkeypatch, installed: bool):
    """Run the set-up cell here, with course_lib made missing (``installed=False``) and pip not called:
    (what it printed, the commands it would run)."""
    commands = []
    if not installed:
        real = importlib.util.find_spec
        monkeypatch.setattr(importlib.util, "find_spec",
                            lambda name, *rest: None if name == "course_lib" else real(name, *rest))
        monkeypatch.setattr(subprocess, "run", lambda command, **options: commands.append(command))
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(source, {"__name__": "__main__"})  # noqa: S102 — the lesson's cell
    return printed.getvalue(), commands


def test_the_set_up_cell_does_nothing_where_course_lib_is_installed(monkeypatch):
    url = "https://github.com/example-org/mechanism-kinematics"
    assert _run_setup_cell(repository.setup_cell(url), monkeypatch, installed=True) == ("", [])


def test_the_set_up_cell_installs_course_lib_from_the_repository_and_says_so(monkeypatch):
    url, branch = "https://github.com/example-org/mechanism-kinematics", "release/2027"
    monkeypatch.setenv(repository.BRANCH_ENV, branch)
    printed, commands = _run_setup_cell(repository.setup_cell(url), monkeypatch, installed=False)
    source = f"git+{url}@{branch}"
    assert commands == [[sys.executable, "-m", "pip", "install", "--quiet", source]]
    assert f"course_lib is not installed in this kernel: installing it from {source}" in printed
    assert printed.rstrip().endswith("course_lib is installed.")


def test_the_set_up_cell_without_an_address_names_the_command(monkeypatch):
    with pytest.raises(ModuleNotFoundError) as caught:
        _run_setup_cell(repository.setup_cell(None), monkeypatch, installed=False)
    assert f'"{sys.executable}" -m pip install -c environment.lock -r environment.txt' in str(caught.value)
    assert "course_lib is not installed in this kernel" in str(caught.value)


def test_the_repository_address_is_written_into_every_lesson_and_back():
    url = "https://gitlab.com/example-org/mechanism-kinematics"
    assert repository.WITH_SETUP == LESSONS + SETS
    for path in LESSONS + SETS:
        text = path.read_text(encoding="utf-8")
        written = repository.expected_lesson(text, url, path.name)
        cell = next(cell for cell in nbformat.reads(written, as_version=4).cells if cell.cell_type == "code")
        assert cell.source == repository.setup_cell(url)
        assert f'COURSE_LIB_SOURCE = "git+{url}@main"' in cell.source
        changed = [(old, new) for old, new in zip(text.splitlines(), written.splitlines(), strict=True)
                   if old != new]
        assert len(changed) == 1 and "COURSE_LIB_SOURCE" in changed[0][0], changed  # one line, as saved
        assert repository.expected_lesson(written, None, path.name) == text  # and back, byte for byte
    with pytest.raises(repository.RepositoryError, match="has 0 set-up lines"):
        repository.expected_lesson(json.dumps({"cells": []}), url, "lesson.ipynb")
