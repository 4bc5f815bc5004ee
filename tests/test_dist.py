"""`make dist` (tools/make_dist.py): the student and instructor bundles, and the student bundle at work.

The bundles hold the files of the commit checked out (HEAD).  The student bundle is unpacked into an
empty folder and installed there into a venv of its own, offline: the venv sees the packages of the
running environment through a path file (the pinned student set is in it) and gets ``course_lib``
from the bundle itself (``pip install --no-deps --no-build-isolation -e``).  Lesson 01 and exercise set
ex01 are then executed there, each in a fresh kernel of that venv, by nbconvert; a cell that fails
(other than those tagged ``raises-exception``, which stop until their task is answered) fails the test.
"""

import json
import pathlib
import re
import subprocess
import sys
import sysconfig
import tomllib
import zipfile

import nbformat
import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import make_dist  # noqa: E402

LESSON = "notebooks/01_vector_loops_and_mobility.ipynb"
EXERCISE = "notebooks/exercises/ex01_vector_loops_and_mobility.ipynb"


@pytest.fixture(scope="module")
def bundles(tmp_path_factory):
    output = tmp_path_factory.mktemp("dist")
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "make_dist.py"), "--output", str(output)],
                            cwd=ROOT, capture_output=True, text=True, timeout=300)
    assert result.returncode == 0, result.stdout + result.stderr
    print(result.stdout.strip())
    version = tomllib.loads(make_dist.committed()["pyproject.toml"][0].decode())["project"]["version"]
    top = f"mechanism-kinematics-{version}"
    return {"student": output / f"{top}-student.zip", "instructor": output / f"{top}-instructor.zip",
            "top": top}


def _names(archive: pathlib.Path, top: str) -> set[str]:
    with zipfile.ZipFile(archive) as opened:
        names = opened.namelist()
    assert all(name.startswith(f"{top}/") for name in names)
    return {name[len(top) + 1:] for name in names}


def test_the_student_bundle_has_lessons_exercises_and_course_lib_and_no_solutions(bundles):
    names = _names(bundles["student"], bundles["top"])
    files = make_dist.tracked()
    lessons = {path for path in files if re.fullmatch(r"notebooks/\d\d_[^/]+\.ipynb", path)}
    exercises = {path for path in files if re.fullmatch(r"notebooks/exercises/[^/]+\.ipynb", path)}
    assert lessons <= names and exercises <= names and len(lessons) >= 12 and len(exercises) >= 5
    assert {"course_lib/__init__.py", "course_lib/checks/__init__.py", "pyproject.toml", "environment.txt",
            "environment.lock", "README.md", "LICENSE", "LICENSE-content", "CITATION.cff",
            "course_lib/checks/worked_answers.json", "course_lib/environment.txt"} <= names  # + package data
    assert not any(name.startswith(("notebooks/solutions/", "nbgrader/", "tests/", "tools/", "binder/"))
                   for name in names)
    assert "environment-dev.txt" not in names
    with zipfile.ZipFile(bundles["student"]) as opened:
        readme = opened.read(f"{bundles['top']}/README.md").decode()
        for name in names:  # no solution text reaches a student
            if name.startswith("notebooks/"):
                assert "BEGIN SOLUTION" not in opened.read(f"{bundles['top']}/{name}").decode(), name
    assert "pip install -c environment.lock -r environment.txt" in readme and "00_start_here" in readme
    assert "python3 -m venv" in readme and "140 MB" in readme  # where only python3 exists; the download


def test_the_instructor_bundle_is_everything_tracked(bundles):
    assert _names(bundles["instructor"], bundles["top"]) == set(make_dist.tracked())


def test_the_bundles_are_reproducible(bundles, tmp_path):
    subprocess.run([sys.executable, str(ROOT / "tools" / "make_dist.py"), "--output", str(tmp_path)],
                   cwd=ROOT, check=True, capture_output=True)
    for kind in ("student", "instructor"):
        assert (tmp_path / bundles[kind].name).read_bytes() == bundles[kind].read_bytes()


def _failed_cells(notebook: nbformat.NotebookNode) -> list[str]:
    return [cell.source[:80] for cell in notebook.cells if cell.cell_type == "code"
            and "raises-exception" not in cell.metadata.get("tags", [])
            and any(output.output_type == "error" for output in cell.get("outputs", []))]


def test_the_student_bundle_installs_and_runs_a_lesson_and_an_exercise_set(bundles, tmp_path):
    folder = tmp_path / "student"
    folder.mkdir()
    with zipfile.ZipFile(bundles["student"]) as opened:
        opened.extractall(folder)
    bundle = folder / bundles["top"]
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True)
    python = venv / "bin" / "python"
    site = subprocess.run([str(python), "-c", "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                          capture_output=True, text=True, check=True).stdout.strip()
    # the tested packages, from the environment running this test (offline); course_lib is not among them
    pathlib.Path(site, "course-tested-set.pth").write_text(sysconfig.get_paths()["purelib"] + "\n")
    install = subprocess.run([sys.executable, "-m", "pip", "--python", str(python), "install", "--quiet",
                              "--disable-pip-version-check", "--no-index", "--no-deps",
                              "--no-build-isolation", "-e", str(bundle)],
                             capture_output=True, text=True, timeout=300)
    assert install.returncode == 0, install.stdout + install.stderr
    where = subprocess.run([str(python), "-c", "import course_lib, importlib.metadata as m; "
                            "print(course_lib.__file__); print(m.version('course_lib'))"],
                           cwd=tmp_path, capture_output=True, text=True, check=True).stdout.split()
    assert pathlib.Path(where[0]).is_relative_to(bundle), f"course_lib comes from {where[0]}, not the bundle"
    assert where[1] == tomllib.loads((bundle / "pyproject.toml").read_text())["project"]["version"]
    ran = {}
    for notebook in (LESSON, EXERCISE):
        out = tmp_path / "executed"
        result = subprocess.run([str(python), "-m", "nbconvert", "--to", "notebook", "--execute",
                                 "--ExecutePreprocessor.timeout=600", "--output-dir", str(out),
                                 str(bundle / notebook)], cwd=bundle, capture_output=True, text=True,
                                timeout=900)
        assert result.returncode == 0, result.stderr[-3000:]
        executed = nbformat.read(out / pathlib.Path(notebook).name, as_version=4)
        assert _failed_cells(executed) == [], f"{notebook}: cells that failed"
        ran[notebook] = sum(cell.cell_type == "code" for cell in executed.cells)
    checks = "".join(output.get("text", "") + output.get("data", {}).get("text/plain", "")
                     for cell in executed.cells if cell.cell_type == "code" for output in cell.outputs)
    assert "No answer yet" in checks  # the unanswered student copy gets its feedback
    print(json.dumps({"student_bundle_mb": round(bundles["student"].stat().st_size / 1e6, 1),
                      "code_cells_run": ran}))
