"""What a check of exercise set 06 accepts, the student copy accepts: each accepted form of a task's right
answer, put in the student copy's answer cell (the other tasks answered as the solution answers them), runs
the whole copy — every code cell, in order — with no traceback and no warning, and every check in it says ✔.

The forms are the ones the checks accept (tests/test_checks_ex06.py: the loops in every form, the position as
the Motion, its ``position``, a dict or the four numbers to 4 decimals, the ram's rates as the Motion, a dict
or rounded, the stroke and ratio rounded, the stops in either order, rounded or from the exact condition, the
cutting direction as a student writes it).
"""

from __future__ import annotations

import contextlib
import io
import pathlib
import warnings

import matplotlib
import nbformat
import pytest
from test_checks_ex06 import ACCEPTED_LOOPS, LOOPS_CELL

ROOT = pathlib.Path(__file__).resolve().parent.parent
COPY = ROOT / "notebooks" / "exercises" / "ex06_your_own_mechanism.ipynb"
SOLUTION = ROOT / "notebooks" / "solutions" / "ex06_your_own_mechanism.ipynb"
ANSWER = "# Your answer: replace None."

SOLVED = ('shaper = Mechanism(loops, unknowns=[th4, r4, th5, x], inputs=[th2],\n'
          '                   parameters={r2: R2, d: D, l4: L4, l5: L5, h: H},\n'
          '                   points={"O4": sp.zeros(2, 1), "O2": sp.Matrix([0, d]),\n'
          '                           "A": sp.Matrix([0, d]) + R(r2, th2), "B": R(l4, th4),\n'
          '                           "C": sp.Matrix([x, h])},\n'
          '                   links={"crank": ("O2", "A"), "lever": ("O4", "B"), "link BC": ("B", "C")},\n'
          '                   ground=["O4", "O2"], sliders=["A", "C"])\n'
          'guess = {th4: 1.2, r4: 0.2, th5: 0.1, x: 0.2}\n')
#: Task N → {form: the answer cell}, each a right answer in a form its check accepts.
VARIANTS = {
    1: {name: LOOPS_CELL + source for name, source in ACCEPTED_LOOPS.items()},
    2: {
        "the Motion": SOLVED + "position = shaper.solve({th2: theta2}, guess=guess)",
        "four numbers to 4 decimals": SOLVED + 'solved = shaper.solve({th2: theta2}, guess=guess).position\n'
                                               'position = tuple(round(float(solved[name]), 4) '
                                               'for name in ("theta4", "r4", "theta5", "x"))',
        "a dict by symbol": SOLVED + 'solved = shaper.solve({th2: theta2}, guess=guess).position\n'
                                     'position = {th4: solved["theta4"], r4: solved["r4"], '
                                     'th5: solved["theta5"], x: solved["x"]}',
        "no drawing, names, other order": (
            'shaper = Mechanism(loops, unknowns=[x, th5, r4, th4], inputs=[th2],\n'
            '                   parameters={"r2": R2, "d": D, "l4": L4, "l5": L5, "h": H})\n'
            'guess = {"theta4": 1.2, "r4": 0.2, "theta5": 0.1, "x": 0.2}\n'
            'position = shaper.solve({"theta2": theta2}, guess=guess).position'),
    },
    3: {
        "the Motion": "ram = shaper.solve({th2: theta2}, rates={th2: omega2}, accelerations={th2: 0.0}, "
                      "guess=guess)",
        "4 significant figures": 'motion = shaper.solve({th2: theta2}, rates={th2: omega2}, guess=guess)\n'
                                 "ram = [float(f\"{motion.velocity['x']:.4g}\"), "
                                 "float(f\"{motion.acceleration['x']:.4g}\")]",
        "a dict": 'motion = shaper.solve({th2: theta2}, rates={th2: omega2}, guess=guess)\n'
                  'ram = {"v_x": motion.velocity["x"], "a_x": motion.acceleration["x"]}',
    },
    4: {
        "3 significant figures, an array": "SOLUTION\n"
                                           'stroke_and_ratio = np.array([float(f"{value:.3g}") for value in '
                                           'stroke_and_ratio])',
        "cutting as -x, stops a list": 'SOLUTION\ncutting = {"left": "-x", "right": "+x"}[cutting]\n'
                                       'stops = [float(stop) for stop in stops]',
        "cutting as a sentence": 'SOLUTION\ncutting = f"to the {cutting}".upper()',
        "stops in the other order, in (−π, π], to 3 decimals":
            'SOLUTION\nstops = [round(float((stop + np.pi) % (2 * np.pi) - np.pi), 3)\n'
            '         for stop in stops[::-1]]',
        "stops from O4A ⟂ O2A, a tuple": 'SOLUTION\nbeta = np.arcsin(R2 / D)\nstops = (-beta, np.pi + beta)',
    },
}


def _solutions() -> list[str]:
    """The solution notebook's answer blocks, in order, without their hint lines."""
    blocks = []
    for cell in nbformat.read(SOLUTION, as_version=4).cells:
        if cell.cell_type == "code" and "### BEGIN SOLUTION" in cell.source:
            lines = cell.source.split("\n")
            start, stop = lines.index("### BEGIN SOLUTION"), lines.index("### END SOLUTION")
            blocks.append("\n".join(line for line in lines[start + 1:stop] if not line.startswith("# HINT:")))
    return blocks


def copy_cells(answers: dict[int, str]) -> list[str]:
    """The student copy's code cells, Task N's answer cell replaced by ``answers[N]`` (``SOLUTION`` in it:
    the solution's block); the answer cells of the other tasks as handed out (``None``)."""
    blocks = _solutions()
    cells = [cell.source for cell in nbformat.read(COPY, as_version=4).cells if cell.cell_type == "code"]
    where = [k for k, source in enumerate(cells) if ANSWER in source]
    assert len(where) == len(blocks) == 4
    for task, answer in answers.items():
        cells[where[task - 1]] = answer.replace("SOLUTION", blocks[task - 1])
    return cells


def run(cells: list[str]) -> tuple[list, str]:
    """Run the cells in order in one namespace, every warning an error; the checks' verdicts and what the
    cells printed."""
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    namespace, verdicts, printed = {}, [], io.StringIO()
    show = plt.show
    plt.show = lambda *args, **kwargs: plt.close("all")
    try:
        with warnings.catch_warnings(), contextlib.redirect_stdout(printed):
            warnings.simplefilter("error")
            for source in cells:
                if source.startswith("checks.check_"):
                    verdicts.append(eval(compile(source, "check cell", "eval"), namespace))
                else:
                    exec(compile(source, "cell", "exec"), namespace)
    finally:
        plt.show = show
        plt.close("all")
    return verdicts, printed.getvalue()


CASES = [(task, name) for task, forms in VARIANTS.items() for name in forms]


@pytest.mark.parametrize(("task", "name"), CASES, ids=[f"task {task}: {name}" for task, name in CASES])
def test_every_accepted_form_runs_the_whole_student_copy(task, name):
    answers = {number: "SOLUTION" for number in VARIANTS} | {task: VARIANTS[task][name]}
    verdicts, printed = run(copy_cells(answers))
    assert len(verdicts) == 4 and all(verdict.ok for verdict in verdicts), verdicts
    assert "Answer Task" not in printed, printed


def test_numbers_from_the_drawing_without_a_declaration_are_not_a_tick():
    """Task 2 answered from the given drawing cell (its pin, end, ram_pin), no shaper: not ✔, and the cells
    after it say which task to answer first (no traceback)."""
    from_drawing = ("shaper = guess = None\n"
                    "position = (float(np.arctan2(pin[1], pin[0])), float(np.hypot(*pin)), "
                    "float(np.arctan2(H - end[1], ram_pin[0] - end[0])), float(ram_pin[0]))")
    verdicts, printed = run(copy_cells({1: "SOLUTION", 2: from_drawing}))
    assert [verdict.ok for verdict in verdicts] == [True, False, False, False], verdicts
    assert "declare the shaper" in verdicts[1].message and "Answer Task 2 first" in printed


#: a task's numbers given as a student may, the check saying ✘ on them
STOPS_GIVEN = 'stops = (-0.41, 3.55)\nstroke_and_ratio = (0.3, 1.5)\ncutting = "left"'
#: wrong-but-plausible answers → (the answers, the task whose check says ✘, what the cells after it print)
WRONG = {
    "one loop only": ({1: "SOLUTION\nloops = [lever_loop]"}, 1, "not the shaper's two vector loops yet"),
    "two vectors that are not loops": ({1: "SOLUTION\nloops = [R(r2, th2), R(l4, th4)]"}, 1,
                                       "not the shaper's two vector loops yet"),
    "the guess a list": ({1: "SOLUTION", 2: "SOLUTION\nguess = [1.2, 0.2, 0.1, 0.2]", 4: STOPS_GIVEN}, 2,
                         "shaper and guess do not solve the shaper"),
    "the guess with θ4 + π and r4 < 0": (
        {1: "SOLUTION", 2: "SOLUTION\nguess = {th4: 1.2 + np.pi, r4: -0.2, th5: 0.1, x: 0.2}",
         4: STOPS_GIVEN}, 2, "shaper and guess do not solve the shaper"),
    "shaper not a Mechanism": ({1: "SOLUTION", 2: "SOLUTION\nshaper = 'the shaper'", 4: STOPS_GIVEN}, 2,
                               "shaper is not a Mechanism yet"),
    "the stops as text": ({1: "SOLUTION", 2: "SOLUTION", 3: "SOLUTION", 4: 'SOLUTION\nstops = "3.5, 5.9"'}, 4,
                          "give two crank angles in radians"),
}


@pytest.mark.parametrize("name", list(WRONG))
def test_a_wrong_answer_runs_the_rest_of_the_copy_and_says_the_cell_needs_a_right_answer(name):
    answers, task, says = WRONG[name]
    verdicts, printed = run(copy_cells(answers))
    assert not verdicts[task - 1].ok, verdicts
    assert all(verdict.ok for verdict, number in zip(verdicts, range(1, 5), strict=True)
               if number in answers and number != task and answers[number] == "SOLUTION"), verdicts
    assert says in printed, printed
    if task == 2:  # both cells that use shaper and guess say so: the drawing and the stops' plot
        assert printed.count(says) == 2, printed
