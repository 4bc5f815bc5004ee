"""What a check accepts, the set accepts: every accepted form of a right answer runs the rest of the copy.

For every task of ex01–ex05, each variant below is a form of the right answer a student may give — rounded at
the stated precision, a tuple, list, numpy array or sympy Matrix, sympy numbers, another order or sign where
the check accepts it, ``sp.Eq`` rows, a solve's ``Motion`` or Newton run where a solve's answer is asked, the
student's own Newton iterates, and where a task asks for a procedure (ex03 Tasks 1, 3 and 4, ex05 Tasks 1 and
2) the student's function returning those forms, printing as it goes, or written with math and another rule.
The student copy (made from the solution by tools/make_exercises.py) gets the solution's answer in every
answer cell, with the variant replacing the task's answer; then the whole copy runs
top to bottom in a fresh namespace, as a kernel runs it (every displayed value formatted as IPython does,
sympy's LaTeX included), and must raise nothing, warn nothing, and show ✔ in every check cell — the variant's
own first.  One run per set puts every task's last variant in at once and executes it in a real kernel.
"""

from __future__ import annotations

import ast
import contextlib
import importlib.util
import io
import pathlib
import re
import warnings

import matplotlib.pyplot as plt
import nbformat
import pytest
from IPython.core.formatters import DisplayFormatter
from nbclient import NotebookClient

from course_lib.checks import Feedback

ROOT = pathlib.Path(__file__).resolve().parent.parent
spec = importlib.util.spec_from_file_location("make_exercises", ROOT / "tools" / "make_exercises.py")
make_exercises = importlib.util.module_from_spec(spec)
spec.loader.exec_module(make_exercises)

SOLUTIONS = {path.stem[:4]: path
             for path in sorted((ROOT / "notebooks" / "solutions").glob("ex0[1-5]*.ipynb"))}

#: set → task → the variants: code run after the solution's answer, rebinding the answer in another form
VARIANTS: dict[str, dict[int, list[str]]] = {
    "ex01": {
        1: ["mobility_counts = (6, 7, 0, 1)",
            "mobility_counts = [6, 7, 0, 1]",
            "mobility_counts = np.array([6, 7, 0, 1])",
            "mobility_counts = (6.0, 7.0, 0.0, 1.0)",
            "mobility_counts = tuple(sp.Integer(n) for n in (6, 7, 0, 1))",
            "mobility_counts = {key: np.int64(value) for key, value in mobility_counts.items()}"],
        2: ["loop_components = tuple(loop_components)",
            "loop_components = loop_vector",
            "loop_components = loop_vector.T",
            "loop_components = sp.ImmutableMatrix(loop_vector)",
            "loop_components = np.array(loop_components, dtype=object)",
            "loop_components = sp.Array(loop_components)",
            "loop_components = [[component] for component in loop_components]",
            "loop_components = [sp.Matrix([component]) for component in loop_components]",
            "loop_components = loop_components[::-1]",  # (y, x): the same two equations
            "loop_components = [-component for component in loop_components]",
            "loop_components = [2 * loop_components[0], -loop_components[1]]",
            "loop_components = [sp.Eq(component, 0) for component in loop_components]",
            "loop_components = [sp.Eq(l2 * sp.cos(theta2) + l3 * sp.cos(theta3),"
            " l4 * sp.cos(theta4) + l1 * sp.cos(theta1)),"
            " sp.Eq(l2 * sp.sin(theta2) + l3 * sp.sin(theta3), l4 * sp.sin(theta4) + l1 * sp.sin(theta1))]",
            "loop_components = sp.Eq(link_vector(l2, theta2) + link_vector(l3, theta3),"
            " link_vector(l4, theta4) + link_vector(l1, theta1))",
            "z = (l2 * sp.exp(sp.I * theta2) + l3 * sp.exp(sp.I * theta3) - l4 * sp.exp(sp.I * theta4)"
            " - l1 * sp.exp(sp.I * theta1))\nloop_components = [sp.re(z), sp.im(z)]",
            "z = (l2 * sp.exp(sp.I * theta2) + l3 * sp.exp(sp.I * theta3) - l4 * sp.exp(sp.I * theta4)"
            " - l1 * sp.exp(sp.I * theta1))\n"
            "loop_components = [(z + sp.conjugate(z)) / 2, (z - sp.conjugate(z)) / (2 * sp.I)]"],
        3: ["velocity_A = np.array([float(f'{v:.4g}') for v in velocity_A])",  # 4 significant figures
            "velocity_A = tuple(velocity_A)",
            "velocity_A = velocity_A.tolist()",
            "velocity_A = [round(float(v), 4) for v in velocity_A]",
            "velocity_A = sp.Matrix(velocity_A)",
            "velocity_A = sp.Matrix([[float(f'{v:.4g}') for v in velocity_A]])",
            "velocity_A = tuple(sp.Float(v) for v in velocity_A)",
            "velocity_A = velocity_A.reshape(2, 1)",
            "velocity_A = np.array([float(f'{v:.4g}') for v in velocity_A], dtype=np.float32)"],
        4: ["why_it_moves = 'B'", "why_it_moves = ' b '", "why_it_moves = '(b)'"],
    },
    "ex02": {
        1: ["newton_update = x - f_cubic / sp.diff(f_cubic, x)",
            "newton_update = (2 * x**3 + 5) / (3 * x**2 - 2)",
            "newton_update = sp.Matrix([newton_update])",
            "newton_update = [newton_update]",
            "newton_update = sp.Eq(sp.Symbol('x_next'), newton_update)"],
        2: ["root_and_count = (round(root_and_count[0], 6), root_and_count[1])",
            "root_and_count = list(root_and_count)",
            "root_and_count = np.array(root_and_count)",
            "root_and_count = (sp.Float(root_and_count[0]), sp.Integer(root_and_count[1]))",
            "root_and_count = (root_and_count[0], float(root_and_count[1]))",
            "root_and_count = cubic_result",  # the Newton run itself
            "x_n, count = 2.0, 0\nwhile True:\n    step = f_number(x_n) / df_number(x_n)\n"
            "    x_n, count = x_n - step, count + 1\n    if abs(step) < 1e-6:\n        break\n"
            "root_and_count = (x_n, count)"],
        3: ["failure_reason = 'A'", "failure_reason = ' (a) '"],
        4: ["first_step = np.array([float(f'{v:.4g}') for v in first_step])",
            "first_step = tuple(first_step)",
            "first_step = first_step.tolist()",
            "first_step = sp.Matrix(J0).LUsolve(sp.Matrix(-F0))",
            "first_step = first_step.reshape(2, 1)",
            "first_step = tuple(sp.Float(float(f'{v:.4g}')) for v in first_step)"],
        5: ["reached_branch = reached_branch.capitalize()", "reached_branch = f' {reached_branch} '",
            "reached_branch = reached_branch.upper()"],
    },
    "ex03": {
        1: ["solution = theta4_crossed_at\n"
            "theta4_crossed_at = lambda theta2: round(float(solution(theta2)), 4)",
            "solution = theta4_crossed_at\ntheta4_crossed_at = lambda theta2: solution(theta2) + 2 * np.pi",
            "solution = theta4_crossed_at\ntheta4_crossed_at = lambda theta2: solution(theta2) - 2 * np.pi",
            "solution = theta4_crossed_at\ntheta4_crossed_at = lambda theta2: sp.Float(solution(theta2))",
            "solution = theta4_crossed_at\ntheta4_crossed_at = lambda theta2: np.array([solution(theta2)])",
            "solution = theta4_crossed_at\n"
            "def theta4_crossed_at(theta2):\n    print('θ2 =', theta2)\n    return solution(theta2)",
            # math instead of numpy, and the root chosen by geometry: B right of A → O4 (the crossed side)
            "import math\ndef theta4_crossed_at(theta2):\n"
            "    K1, K2, K3 = l1 / l2, l1 / l4, (l2**2 - l3**2 + l4**2 + l1**2) / (2 * l2 * l4)\n"
            "    a = math.cos(theta2) - K1 - K2 * math.cos(theta2) + K3\n"
            "    b, c = -2 * math.sin(theta2), K1 - (K2 + 1) * math.cos(theta2) + K3\n"
            "    ax, ay = l2 * math.cos(theta2), l2 * math.sin(theta2)\n"
            "    for sign in (1, -1):\n"
            "        theta4 = 2 * math.atan((-b + sign * math.sqrt(b * b - 4 * a * c)) / (2 * a))\n"
            "        bx, by = l1 + l4 * math.cos(theta4), l4 * math.sin(theta4)\n"
            "        if (l1 - ax) * (by - ay) - (0 - ay) * (bx - ax) < 0:\n"
            "            return theta4"],
        2: ["omega4_formula = (sp.Symbol('omega2') * L2 * sp.sin(sp.Symbol('theta2') - sp.Symbol('theta3'))"
            " / (L4 * sp.sin(sp.Symbol('theta4') - sp.Symbol('theta3'))))",
            "omega4_formula = sp.Eq(w4, omega4_formula)",
            "omega4_formula = sp.Matrix([omega4_formula])",
            "omega4_formula = [omega4_formula]",
            "omega4_formula = matrix.LUsolve(rhs)[1]"],
        3: ["solution = rocker_rates_at\n"
            "rocker_rates_at = lambda *instant: tuple(float(f'{v:.4g}') for v in solution(*instant))",
            "solution = rocker_rates_at\nrocker_rates_at = lambda *instant: list(solution(*instant))",
            "solution = rocker_rates_at\nrocker_rates_at = lambda *instant: np.array(solution(*instant))",
            "solution = rocker_rates_at\n"
            "rocker_rates_at = lambda *instant: tuple(sp.Float(v) for v in solution(*instant))",
            "solution = rocker_rates_at\n"
            "rocker_rates_at = lambda *instant: np.array(solution(*instant)).reshape(2, 1)",
            "solution = rocker_rates_at\ndef rocker_rates_at(theta2, theta3, theta4, omega2, alpha2):\n"
            "    print('θ2 =', theta2)\n    return solution(theta2, theta3, theta4, omega2, alpha2)",
            # J typed by hand, −ω2·∂F/∂θ2 as the right-hand side, one inverse for both solves
            "def rocker_rates_at(theta2, theta3, theta4, omega2, alpha2):\n"
            "    J = np.array([[-l3 * np.sin(theta3), l4 * np.sin(theta4)],\n"
            "                  [l3 * np.cos(theta3), -l4 * np.cos(theta4)]])\n"
            "    dF_dtheta2 = np.array([-l2 * np.sin(theta2), l2 * np.cos(theta2)])\n"
            "    inverse = np.linalg.inv(J)\n"
            "    omega3, omega4 = inverse @ (-omega2 * dF_dtheta2)\n"
            "    squares = (omega2**2 * l2 * np.array([-np.cos(theta2), -np.sin(theta2)])\n"
            "               + omega3**2 * l3 * np.array([-np.cos(theta3), -np.sin(theta3)])\n"
            "               - omega4**2 * l4 * np.array([-np.cos(theta4), -np.sin(theta4)]))\n"
            "    alpha3, alpha4 = inverse @ (-alpha2 * dF_dtheta2 - squares)\n"
            "    return float(omega4), float(alpha4)"],
        4: ["solution = crank_limit\n"
            "crank_limit = lambda *lengths: (round(solution(*lengths)[0], 4), 'extended')",
            "solution = crank_limit\ncrank_limit = lambda *lengths: [solution(*lengths)[0], 'Extended']",
            "solution = crank_limit\n"
            "crank_limit = lambda *lengths: (np.float64(solution(*lengths)[0]), ' EXTENDED ')",
            "solution = crank_limit\n"
            "crank_limit = lambda *lengths: (solution(*lengths)[0] + 2 * np.pi, 'extended')",
            # math, and the bound chosen by the linkage: |AO4| reaches l3 + l4 before θ2 = π
            "import math\ndef crank_limit(l1, l2, l3, l4):\n"
            "    reach = l3 + l4\n"
            "    assert l1 + l2 > reach, 'this crank turns through π'\n"
            "    return math.acos((l1 * l1 + l2 * l2 - reach * reach) / (2 * l1 * l2)), 'extended'"],
    },
    "ex04": {
        1: ["omega3_formula = (-sp.Symbol('omega2') * r2 * sp.cos(sp.Symbol('theta2'))"
            " / (r3 * sp.cos(sp.Symbol('theta3'))))",
            "omega3_formula = sp.Eq(w3, omega3_formula)",
            "omega3_formula = sp.Matrix([omega3_formula])",
            "omega3_formula = [omega3_formula]"],
        2: ["r1_sign = 'A'", "r1_sign = ' (a) '",  # the sign question, in Task 2's second answer cell
            "from course_lib.saw import SEED_CODE\n"
            "position = solve_consecutive(np.radians(50.0), saw=my_saw, x0=SEED_CODE)",
            "position = solve_consecutive(np.radians(50.0), saw=my_saw, variant='substituted')",
            "position = position.stages['position']",  # its Newton run, a NewtonResult
            "from course_lib.newton import newton\n"
            "from course_lib.saw import position_jacobian, position_residual\n"
            "position = newton(lambda q: position_residual(q, np.radians(50.0), saw=my_saw),"
            " np.array([-0.1, -0.5, 3.0]), jac=lambda q: position_jacobian(q, saw=my_saw))",
            # the student's own Newton loop on their own equations (Fc first: Newton does not mind the order)
            "def F(q):\n    r1, t1, t3 = q\n    t2 = np.radians(50.0)\n"
            "    return np.array([r1 * np.sin(t1) - 0.030,\n"
            "                     -r1 * np.cos(t1) + 0.060 * np.cos(t2) + 0.150 * np.cos(t3),\n"
            "                     r1 * np.sin(t1) - 0.060 * np.sin(t2) - 0.150 * np.sin(t3)])\n"
            "def J(q):\n    r1, t1, t3 = q\n"
            "    return np.array([[np.sin(t1), r1 * np.cos(t1), 0.0],\n"
            "                     [-np.cos(t1), r1 * np.sin(t1), -0.150 * np.sin(t3)],\n"
            "                     [np.sin(t1), r1 * np.cos(t1), -0.150 * np.cos(t3)]])\n"
            "position = [np.array([-0.1, -0.5, 3.0])]\n"
            "while len(position) < 2 or np.linalg.norm(position[-1] - position[-2]) >= 1e-6:\n"
            "    position.append(position[-1] + np.linalg.solve(J(position[-1]), -F(position[-1])))",
            "position = np.array(position.stages['position'].history)",
            "position = [list(row) for row in position.stages['position'].history]"],
        3: ["from course_lib.saw import SEED_CODE\n"
            "at_speed = solve_simultaneous(np.radians(50.0), 6.0, 4.0, saw=my_saw, x0=SEED_CODE)",
            "at_speed = at_speed.newton",
            "from course_lib.newton import newton\nfrom course_lib.saw import SEED_PRINTED, system_jacobian,"
            " system_residual\n"
            "at_speed = newton(lambda q: system_residual(q, np.radians(50.0), 6.0, 4.0, saw=my_saw),"
            " SEED_PRINTED, jac=lambda q: system_jacobian(q, saw=my_saw))",
            "at_speed = at_speed.newton.history"],
        4: ["why_two = 'A'", "why_two = '(a)'"],
    },
    "ex05": {
        1: ["solution = arms_down\n"
            "arms_down = lambda t1, t4: tuple(round(float(v), 6) for v in solution(t1, t4))",
            "solution = arms_down\narms_down = lambda t1, t4: list(solution(t1, t4))",
            "solution = arms_down\narms_down = lambda t1, t4: np.array(solution(t1, t4))",
            "solution = arms_down\narms_down = lambda t1, t4: tuple(sp.Float(v) for v in solution(t1, t4))",
            "solution = arms_down\narms_down = lambda t1, t4: np.array(solution(t1, t4)).reshape(2, 1)",
            "solution = arms_down\n"
            "def arms_down(theta1, theta4):\n    print(theta1, theta4)\n    return solution(theta1, theta4)"],
        2: ["solution = cranks_at\ncranks_at = lambda x3, y3: tuple(round(v, 4) for v in solution(x3, y3))",
            "solution = cranks_at\n"
            "cranks_at = lambda x3, y3: (solution(x3, y3)[0] + 2 * np.pi, solution(x3, y3)[1])",
            "solution = cranks_at\ncranks_at = lambda x3, y3: np.array(solution(x3, y3))",
            "solution = cranks_at\ncranks_at = lambda x3, y3: list(solution(x3, y3))",
            "solution = cranks_at\ndef cranks_at(x3, y3):\n    print(x3, y3)\n    return solution(x3, y3)",
            # math, one root function for both legs
            "import math\ndef cranks_at(x3, y3):\n"
            "    k = robot.inverse_coefficients(x3, y3)\n"
            "    def root(a, b, c, sigma):\n"
            "        return 2 * math.atan((-b + sigma * math.sqrt(b * b - 4 * a * c)) / (2 * a))\n"
            "    return root(k['a1'], k['b1'], k['c1'], -1), root(k['a2'], k['b2'], k['c2'], +1)"],
        3: ["g_formula = ((-2 * L1 * sp.sin(th1) + 2 * L4 * sp.sin(th4))"
            " / (2 * (L5 + L1 * sp.cos(th1) - L4 * sp.cos(th4))))",
            "g_formula = sp.Eq(sp.Symbol('g'), g_formula)",
            "g_formula = sp.Matrix([g_formula])",
            "g_formula = sp.cancel(g_formula)"],
        4: ["singularity_4 = 'Serial1'", "singularity_4 = 'serial 1'", "singularity_4 = 'serial_leg1'",
            "singularity_4 = ' SERIAL1 '"],
        5: ["singularity_5 = 'Parallel'", "singularity_5 = ' parallel'"],
    },
}

ROWS = [(name, task, variant) for name, tasks in VARIANTS.items() for task, variants in tasks.items()
        for variant in variants]
SHOW = DisplayFormatter()
AGG = "FigureCanvasAgg is non-interactive"  # plt.show() on this test's backend, not the student's


def _copy_with_answers(solution: pathlib.Path, variants: dict[int, str]) -> list[tuple[int | None, str, str]]:
    """The student copy's code cells as (task, role, source): each answer cell holds the solution's answer,
    followed by the task's variant (if any) where the variant rebinds an answer of that cell (a task may have
    two answer cells); role is "answer", "check" or "code"."""
    original = nbformat.read(solution, as_version=4)
    copy = make_exercises.student_copy(nbformat.read(solution, as_version=4), solution.name)
    cells, task = [], None
    for cell, source_cell in zip(copy.cells[1:], original.cells, strict=True):
        if source_cell.cell_type == "markdown":
            for heading, _ in make_exercises.headings(source_cell.source):
                task = heading
            continue
        if cell.cell_type != "code":
            continue
        if make_exercises.BEGIN in source_cell.source:
            assert re.search(r"^\w+ = None$", cell.source, re.M), cell.source  # the student's stub
            stubs = set(re.findall(r"^(\w+) = None$", cell.source, re.M))
            rebinds = task in variants and stubs & make_exercises._bound_names(ast.parse(variants[task]))
            source = source_cell.source + ("\n" + variants[task] if rebinds else "")
            cells.append((task, "answer", source))
        else:
            cells.append((task, "check" if cell.source.startswith("checks.check_") else "code", cell.source))
    return cells


def _run(cells) -> dict[int, list[Feedback]]:
    """Run the cells as a kernel does, in one fresh namespace; every check cell's feedback, by task.
    Raises what a cell raises; every warning a kernel would show is an error."""
    shown_checks: dict[int, list[Feedback]] = {}

    def display(value):
        SHOW.format(value)  # every representation a front end asks for (text, LaTeX, PNG)

    namespace = {"__name__": "__main__", "display": display}
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # any warning a student would see
        warnings.filterwarnings("ignore", category=DeprecationWarning)  # a kernel shows these only from
        warnings.filterwarnings("ignore", category=PendingDeprecationWarning)  # the student's own code
        warnings.filterwarnings("error", category=DeprecationWarning, module="__main__")
        warnings.filterwarnings("ignore", message=AGG)
        try:
            for task, role, source in cells:
                tree = ast.parse(source)
                last = tree.body.pop() if tree.body and isinstance(tree.body[-1], ast.Expr) else None
                exec(compile(tree, f"<cell of task {task}>", "exec"), namespace)
                if last is not None:
                    code = compile(ast.Expression(last.value), f"<cell of task {task}>", "eval")
                    value = eval(code, namespace)
                    if value is not None:
                        display(value)
                    if role == "check":
                        shown_checks.setdefault(task, []).append(value)
        finally:
            plt.close("all")
    return shown_checks


@pytest.mark.parametrize(("name", "task", "variant"), ROWS,
                         ids=[f"{name}-task{task}-{index}" for index, (name, task, _) in enumerate(ROWS)])
def test_an_accepted_variant_runs_the_whole_copy_without_a_traceback_or_a_warning(name, task, variant):
    checked = _run(_copy_with_answers(SOLUTIONS[name], {task: variant}))
    assert task in checked, f"task {task} has no check cell"
    for each, feedbacks in checked.items():
        for feedback in feedbacks:
            assert isinstance(feedback, Feedback) and feedback.ok, (each, feedback)


def test_every_task_of_ex01_to_ex05_has_variants():
    for name, solution in SOLUTIONS.items():
        tasks = {task for task, role, _ in _copy_with_answers(solution, {}) if role == "answer"}
        assert tasks == set(VARIANTS[name]), name


@pytest.mark.parametrize("name", list(VARIANTS))
def test_the_last_variant_of_every_task_runs_in_a_kernel(name):
    """The same in a real kernel, all tasks of a set at once: no error output, nothing on stderr, ✔ shown."""
    solution = SOLUTIONS[name]
    last = {task: variants[-1] for task, variants in VARIANTS[name].items()}
    cells = _copy_with_answers(solution, last)
    notebook = nbformat.v4.new_notebook()
    notebook.cells = [nbformat.v4.new_code_cell(source) for _, _, source in cells]
    NotebookClient(notebook, timeout=600, kernel_name="python3",
                   resources={"metadata": {"path": str(solution.parent)}}).execute()
    for (task, role, source), cell in zip(cells, notebook.cells, strict=True):
        for output in cell.outputs:
            assert output.output_type != "error", (task, source, output.get("evalue"))
            stderr = output.output_type == "stream" and output.name == "stderr"
            assert not stderr, (task, source, output.text)
        if role == "check":
            text = "".join(str(output.get("data", {}).get("text/plain", "")) for output in cell.outputs)
            assert text.startswith("✔"), (task, source, text)


#: set → task → wrong answers a student may plausibly give: the check says ✘, and the cells after it say
#: in one sentence that they need a right answer above — no traceback, no warning.
WRONG: dict[str, dict[int, list[str]]] = {
    "ex01": {
        2: ["loop_components = 'l2*cos(theta2) + l3*cos(theta3) - l4*cos(theta4) - l1*cos(theta1)'",
            "loop_components = 0",
            "loop_components = [1, 2]",
            "loop_components = 'x, y'"],
        3: ["velocity_A = [0.6788j, 0.6788]",
            "velocity_A = np.array([0.6788j, 0.6788])",  # a complex array: float() of it would warn
            "velocity_A = -12.0j * 0.080 * np.exp(1j * np.radians(135.0))",  # v as one complex z
            "velocity_A = 0.6788 + 0.6788j",
            "velocity_A = [sp.I * 0.6788, 0.6788]",
            "velocity_A = '0.6788, 0.6788'"],
    },
}
WRONG_ROWS = [(name, task, answer) for name, tasks in WRONG.items() for task, answers in tasks.items()
              for answer in answers]


@pytest.mark.parametrize(("name", "task", "answer"), WRONG_ROWS,
                         ids=[f"{name}-task{task}-{index}"
                              for index, (name, task, _) in enumerate(WRONG_ROWS)])
def test_a_wrong_answer_runs_the_rest_of_the_copy_and_says_the_cell_needs_a_right_answer(name, task, answer):
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        checked = _run(_copy_with_answers(SOLUTIONS[name], {task: answer}))
    wrong = checked[task]
    assert all(isinstance(feedback, Feedback) and not feedback.ok for feedback in wrong), wrong
    assert all(feedback.ok for each, feedbacks in checked.items() if each != task for feedback in feedbacks)
    assert "the check above says what to fix" in printed.getvalue(), printed.getvalue()
