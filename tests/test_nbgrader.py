"""The nbgrader route (`make nbgrader`): the exported source grades as an instructor would grade it.

Points: every set's graded checks are worth what the kinds in its task headings say (interpret 1, any other
kind 2, a sum added), read here from the solution notebooks independently of the exporter.

Grading: in one temporary course directory (a copy of the shipped nbgrader/ configuration and the source
exported by tools/export_nbgrader.py), ``nbgrader generate_assignment`` makes the student versions of every
set (ex01–ex06), and ``release_assignment`` puts ex03 into a temporary exchange under the configured course
id.
For each set two students hand in: one with every answer right, one with one task answered wrongly and
another left unanswered.  ``nbgrader autograde`` must give full marks to the first, and to the second all
the points but those two tasks'; ``nbgrader generate_feedback`` must show the second the checker's own
message, typeset its formulas with a local MathJax (no CDN), and wrap long messages.
"""

import html
import os
import pathlib
import re
import shutil
import subprocess
import sys

import nbformat
import numpy as np
import pytest
from traitlets.config.loader import PyFileConfigLoader

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import export_nbgrader  # noqa: E402

from course_lib import checks  # noqa: E402
from course_lib.fourbar import FourBar  # noqa: E402

SOLUTIONS = sorted((ROOT / "notebooks" / "solutions").glob("ex*.ipynb"))
SHIPPED = ROOT / "nbgrader"
HEADING = re.compile(r"^## Task (\d+) · .*\(([^(),]+)(?:, (\d+) points?)?\)\s*$")

EX03 = ROOT / "notebooks" / "solutions" / "ex03_fourbar.ipynb"
EX06 = ROOT / "notebooks" / "solutions" / "ex06_your_own_mechanism.ipynb"
RIGHT_BRANCH, WRONG_BRANCH = "(-b + np.sqrt(", "(-b - np.sqrt("  # ex03 Task 1: crossed vs open root
RAM_IN_M = 'ram = (motion.velocity["x"], motion.acceleration["x"])'  # ex06 Task 3, and the same in mm
RAM_IN_MM = 'ram = (1000 * motion.velocity["x"], 1000 * motion.acceleration["x"])'
#: per set: the solution, the task answered wrongly (grade id, text replaced, replacement), the task left
#: unanswered (as released: nbgrader's stub raises NotImplementedError)
SOLUTIONS_DIR = ROOT / "notebooks" / "solutions"
SETS = {
    "ex01": (SOLUTIONS_DIR / "ex01_vector_loops_and_mobility.ipynb",
             (4, 'why_it_moves = "b"', 'why_it_moves = "a"'), 2),
    "ex02": (SOLUTIONS_DIR / "ex02_newton_raphson.ipynb",
             (3, 'failure_reason = "a"', 'failure_reason = "b"'), 1),
    "ex03": (EX03, (1, RIGHT_BRANCH, WRONG_BRANCH), 4),
    "ex04": (SOLUTIONS_DIR / "ex04_power_saw.ipynb", (4, 'why_two = "a"', 'why_two = "b"'), 1),
    # ex05 Task 2: θ1 on the other root, the working mode (+1, +1) instead of (−1, +1)
    "ex05": (SOLUTIONS_DIR / "ex05_fivebar.ipynb", (2, 'theta1 = 2 * np.arctan((-k["b1"] - np.sqrt(',
                                                     'theta1 = 2 * np.arctan((-k["b1"] + np.sqrt('), 4),
    "ex06": (EX06, (3, RAM_IN_M, RAM_IN_MM), 4),
}


def heading_points(solution: pathlib.Path) -> dict[int, int]:
    """Task number → points, from the kinds of the ``## Task N · … (kinds)`` or ``(kinds, P points)``
    headings on any line of a markdown cell; the points a heading writes must be those of its kinds."""
    points = {}
    for cell in nbformat.read(solution, as_version=4).cells:
        if cell.cell_type == "markdown":
            for line in cell.source.split("\n"):
                found = HEADING.match(line)
                if found:
                    kinds = [kind.strip() for kind in found[2].split("+")]
                    points[int(found[1])] = sum(1 if kind == "interpret" else 2 for kind in kinds)
                    assert found[3] is None or int(found[3]) == points[int(found[1])], line
    return points


def _exported(solution: pathlib.Path):
    return export_nbgrader.nbgrader_source(nbformat.read(solution, as_version=4), solution.name)


def _nbgrader(course: pathlib.Path, *args: str) -> str:
    """Run an nbgrader command in the course directory (this Python's bin folder first on PATH:
    nbgrader runs ``alembic`` from there)."""
    env = dict(os.environ, PATH=f"{pathlib.Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}")
    result = subprocess.run([sys.executable, "-m", "nbgrader", *args], cwd=course, env=env,
                            capture_output=True, text=True, timeout=600)
    log = result.stdout + result.stderr
    assert result.returncode == 0, f"nbgrader {' '.join(args)} failed:\n{log[-4000:]}"
    return log


def _cells_by_id(notebook) -> dict:
    return {cell.metadata["nbgrader"]["grade_id"]: cell
            for cell in notebook.cells if "nbgrader" in cell.metadata}


def _hand_in(course: pathlib.Path, student: str, assignment: str, name: str, released,
             answers: dict[str, str]) -> None:
    notebook = nbformat.from_dict(released)
    for grade_id, cell in _cells_by_id(notebook).items():
        if grade_id in answers:
            cell.source = answers[grade_id]
    target = course / "submitted" / student / assignment / name
    target.parent.mkdir(parents=True)
    nbformat.write(notebook, target)


# ---------------------------------------------------------------- the export, without nbgrader


@pytest.mark.parametrize("solution", SOLUTIONS, ids=lambda path: path.stem)
def test_every_set_is_worth_the_points_of_its_headings(solution):
    expected = heading_points(solution)
    assert len(expected) >= 3
    exported = {}
    for cell in _exported(solution).cells:
        grading = cell.metadata["nbgrader"]
        if grading["grade"]:
            task = int(re.match(r"task(\d+)-check", grading["grade_id"])[1])
            exported[task] = exported.get(task, 0) + grading["points"]
    assert exported == expected
    print(f"{solution.stem}: {sum(expected.values())} points {expected}")


def test_the_readme_lists_each_sets_points():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    instructors = readme[readme.index("## For instructors"):]
    instructors = instructors[: instructors.index("\n## ", 1)]
    listed = dict(re.findall(r"\b(ex\d\d) (\d+)\b", instructors))
    assert listed == {path.stem[:4]: str(sum(heading_points(path).values())) for path in SOLUTIONS}


def test_export_marks_solutions_checks_and_read_only_statements():
    notebook = _exported(EX03)
    roles = [cell.metadata["nbgrader"] for cell in notebook.cells]
    answers = [cell for cell in notebook.cells if cell.metadata["nbgrader"]["solution"]]
    tests = [cell for cell in notebook.cells if cell.metadata["nbgrader"]["grade"]]
    assert len(answers) == len(tests) == 4
    assert all(cell.source.startswith("# Hint: ") and "### BEGIN SOLUTION" in cell.source for cell in answers)
    assert all(cell.source.startswith("feedback = checks.check_")
               and cell.source.endswith("assert feedback.ok, feedback.message") for cell in tests)
    assert all(role["locked"] for role in roles if not role["solution"])
    assert all(cell.cell_type != "code" or not cell.outputs for cell in notebook.cells)
    assert len({role["grade_id"] for role in roles}) == len(roles)


def test_a_task_heading_below_other_text_starts_its_task():
    notebook = nbformat.v4.new_notebook(cells=[
        nbformat.v4.new_markdown_cell("## Task 1 · First (compute)"),
        nbformat.v4.new_code_cell("### BEGIN SOLUTION\n# HINT: h\nfirst = 1\n### END SOLUTION"),
        nbformat.v4.new_code_cell("checks.check_first(first)"),
        nbformat.v4.new_markdown_cell("Task 1 ends.\n\n## Task 2 · Second (compute + interpret)\n\nDo it."),
        nbformat.v4.new_code_cell("### BEGIN SOLUTION\n# HINT: h\nsecond = 2\n### END SOLUTION"),
        nbformat.v4.new_code_cell("checks.check_second(second)"),
    ])
    exported = export_nbgrader.nbgrader_source(notebook, "ex99.ipynb")
    graded = {cell.metadata["nbgrader"]["grade_id"]: cell.metadata["nbgrader"]["points"]
              for cell in exported.cells if cell.metadata["nbgrader"]["grade"]}
    assert graded == {"task1-check": 2, "task2-check": 3}


def test_task_points_come_from_the_kinds_in_the_heading():
    assert export_nbgrader.task_points("compute + interpret") == 3
    assert export_nbgrader.task_points("interpret") == 1
    assert export_nbgrader.task_points("sketch") == export_nbgrader.task_points(None) == 2


def test_the_shipped_configuration_names_the_course():
    config = PyFileConfigLoader("nbgrader_config.py", path=str(SHIPPED)).load_config()
    assert re.fullmatch(r"[A-Za-z0-9_-]+", config.CourseDirectory.course_id)
    assert config.HTMLExporter.template_name == "feedback_offline"
    assert all(pathlib.Path(folder).is_dir() for folder in config.HTMLExporter.extra_template_basedirs)


# ---------------------------------------------------------------- nbgrader itself, on every set


@pytest.fixture(scope="module")
def course(tmp_path_factory):
    """A course directory where every set was generated, released, handed in (a full submission, and one
    with a task wrong and one left unanswered), autograded and fed back."""
    course = tmp_path_factory.mktemp("nbgrader") / "course"
    course.mkdir()
    shutil.copyfile(SHIPPED / "nbgrader_config.py", course / "nbgrader_config.py")
    shutil.copytree(SHIPPED / "templates", course / "templates")
    for assignment, (solution, (wrong_task, right, wrong), unanswered) in SETS.items():
        exported = _exported(solution)
        source = course / "source" / assignment / solution.name
        source.parent.mkdir(parents=True)
        nbformat.write(exported, source)
        _nbgrader(course, "generate_assignment", assignment)
        released = nbformat.read(course / "release" / assignment / solution.name, as_version=4)
        full = {grade_id: cell.source for grade_id, cell in _cells_by_id(exported).items()
                if cell.metadata["nbgrader"]["solution"]}
        answer = f"task{wrong_task}-answer"
        assert right in full[answer], f"{assignment} Task {wrong_task}'s answer changed: update this test"
        partial = dict(full, **{answer: full[answer].replace(right, wrong)})
        del partial[f"task{unanswered}-answer"]  # left as released: the stub raises NotImplementedError
        _hand_in(course, "alice", assignment, solution.name, released, full)
        _hand_in(course, "bob", assignment, solution.name, released, partial)
        _nbgrader(course, "autograde", assignment)
        _nbgrader(course, "generate_feedback", assignment)
    return course


def _feedback(course: pathlib.Path, student: str, assignment: str) -> pathlib.Path:
    solution = SETS[assignment][0]
    return course / "feedback" / student / assignment / solution.with_suffix(".html").name


def test_the_student_version_shows_hints_and_stubs_not_answers(course):
    released = nbformat.read(course / "release" / "ex03" / EX03.name, as_version=4)
    student_view = "\n".join(cell.source for cell in released.cells)
    assert "BEGIN SOLUTION" not in student_view and RIGHT_BRANCH not in student_view
    assert "# Hint: " in student_view and "raise NotImplementedError()" in student_view


@pytest.mark.parametrize("assignment", SETS)
def test_autograde_gives_full_and_partial_marks(course, assignment):
    from nbgrader.api import Gradebook

    solution, (wrong_task, _, _), unanswered = SETS[assignment]
    points = heading_points(solution)
    with Gradebook(f"sqlite:///{course / 'gradebook.db'}") as gradebook:
        scores = {student: (gradebook.find_submission(assignment, student).score,
                            gradebook.find_submission(assignment, student).max_score)
                  for student in ("alice", "bob")}
    print(f"nbgrader scores for {assignment}: {scores}")
    total = sum(points.values())
    assert scores["alice"] == (total, total)
    assert scores["bob"] == (total - points[wrong_task] - points[unanswered], total)


def test_feedback_shows_the_checkers_message(course):
    feedback = _feedback(course, "bob", "ex03").read_text(encoding="utf-8")
    bench = FourBar(crank=0.07, coupler=0.20, rocker=0.15, ground=0.25)
    theta2 = np.radians(120.0)

    def theta4_crossed_at(theta2):  # bob's answer: the task's quadratic with the open branch's root
        l1, l2, l3, l4 = bench.l1, bench.l2, bench.l3, bench.l4
        K1, K2, K3 = l1 / l2, l1 / l4, (l2**2 - l3**2 + l4**2 + l1**2) / (2 * l2 * l4)
        a, b = np.cos(theta2) - K1 - K2 * np.cos(theta2) + K3, -2 * np.sin(theta2)
        c = K1 - (K2 + 1) * np.cos(theta2) + K3
        return 2 * np.arctan((-b - np.sqrt(b**2 - 4 * a * c)) / (2 * a))

    message = checks.check_fourbar_theta4(theta4_crossed_at, bench, theta2, "crossed",
                                          method="half-angle").message
    assert "open assembly" in message and "theta4_crossed_at" in message
    assert html.escape(message, quote=False) in feedback or message in feedback
    assert "NotImplementedError" in feedback
    # a checker's ✘ starts "Not yet:" (MathJax's help text in the page has "Not yet implemented")
    assert "Not yet:" not in _feedback(course, "alice", "ex03").read_text(encoding="utf-8")
    autograded = nbformat.read(course / "autograded" / "bob" / "ex06" / EX06.name, as_version=4)
    failed = [output for cell in autograded.cells if cell.metadata["nbgrader"]["grade_id"] == "task3-check"
              for output in cell.outputs if output.output_type == "error"]
    assert [output.ename for output in failed] == ["AssertionError"] and "mm/s" in failed[0].evalue
    assert html.escape(failed[0].evalue, quote=False) in _feedback(course, "bob", "ex06").read_text("utf-8")


MATHJAX_SCRIPT = re.compile(r"<script\b[^>]*\bsrc=\"([^\"]*)\"", re.I)


@pytest.mark.parametrize("assignment", SETS)
def test_feedback_carries_mathjax_in_the_page_and_wraps_long_messages(course, assignment):
    # MathJax's combined component in the page itself (a page fetched alone into a student's folder still
    # typesets), what it loads lazily from the local copy two folders up; nothing from a CDN
    page = _feedback(course, "bob", assignment)
    text = page.read_text(encoding="utf-8")
    inline = [script for script in re.findall(r"<script>(.*?)</script>", text, re.S) if len(script) > 1e6]
    assert len(inline) == 1 and "MathJax" in inline[0]
    text = text.replace(inline[0], "")  # (its licence names mathjax.org; the browser test blocks any request)
    sources = MATHJAX_SCRIPT.findall(text)
    assert not [src for src in sources if re.match(r"(https?:)?//", src)], sources
    assert not re.search(r"https?://[^\s\"']*mathjax", text, re.I)
    lazy = re.search(r'paths: \{mathjax: "([^"]+)"\}', text).group(1)
    assert (page.parent / lazy / "tex-svg.js").resolve().is_file(), lazy
    assert re.search(r"pre\s*\{[^}]*white-space:\s*pre-wrap;[^}]*overflow-wrap:\s*anywhere", text)


def test_release_assignment_to_an_exchange(course, tmp_path):
    exchange = tmp_path / "exchange"
    _nbgrader(course, "release_assignment", "ex03", f"--Exchange.root={exchange}")
    config = PyFileConfigLoader("nbgrader_config.py", path=str(SHIPPED)).load_config()
    course_id = config.CourseDirectory.course_id
    assert (exchange / course_id / "outbound" / "ex03" / EX03.name).is_file()


def _open(chromium, page_path: pathlib.Path) -> dict:
    """Open a feedback page from disk, every request but file: and data: blocked; what it shows."""
    context = chromium.new_context(viewport={"width": 1000, "height": 900})
    outside = []

    def route(request_route):
        if request_route.request.url.startswith(("file:", "data:")):
            request_route.continue_()
        else:
            outside.append(request_route.request.url)
            request_route.abort()

    context.route("**/*", route)
    page = context.new_page()
    try:
        page.goto(page_path.as_uri(), wait_until="load")
        page.wait_for_function("() => window.MathJax && MathJax.startup && MathJax.startup.promise")
        page.evaluate("() => MathJax.startup.promise")
        seen = {
            "outside": outside,
            "typeset": page.locator("mjx-container").count(),
            "raw": page.evaluate("() => document.body.innerText.includes('$r_2$')"),
            "too_wide": page.evaluate("""() => [...document.querySelectorAll(
                'div.output_subarea pre, div.input_area pre')]
                .filter(pre => pre.scrollWidth > pre.clientWidth + 1).map(pre => pre.innerText.slice(-80))
                """),
        }
        page.locator("div.output_error").first.scroll_into_view_if_needed()
        shot = page_path.with_suffix(".png")
        page.screenshot(path=str(shot))
        print(f"feedback {page_path.name}: {seen['typeset']} formulas typeset; screenshot {shot}")
    finally:
        context.close()
    return seen


def test_feedback_typesets_formulas_offline_and_wraps_long_hints(course, chromium, tmp_path):
    ex03, ex06 = (_open(chromium, _feedback(course, "bob", assignment)) for assignment in ("ex03", "ex06"))
    assert ex03["outside"] == ex06["outside"] == []
    assert ex06["typeset"] >= 20 and not ex06["raw"]  # the drawing's table and statements: $r_2$, …
    alone = tmp_path / "fetched" / "ex06.html"  # as the hub's fetch puts it: the page alone in a folder
    alone.parent.mkdir()
    shutil.copy2(_feedback(course, "bob", "ex06"), alone)
    fetched = _open(chromium, alone)
    assert fetched["outside"] == [] and fetched["typeset"] == ex06["typeset"] and not fetched["raw"]
    assert ex03["too_wide"] == ex06["too_wide"] == []  # ex03's branch hint is longer than the page is wide
