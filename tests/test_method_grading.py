"""ex04 grades the method its Tasks 2 and 3 ask for: Newton's iterations, not only the numbers they end at.

Task 2 asks for the position by the consecutive Newton–Raphson, Task 3 for a_r by the simultaneous 9×9 Newton;
the closed form (``my_saw.motion``) gives the same numbers with no Newton at all.  With ``method=`` (as the
notebook's check cells call them) the checkers read the solve the student stores: the solver's Motion (its
Newton run inside), a NewtonResult, or the student's own iterates, seed first — each step recomputed here as a
Newton step of the saw's equations at the student's own iterates, from the report's seed.  A right number from
the closed form, or right numbers alone, is not ✔.  The student's own Newton below is written independently:
the saw's equations typed out, a Jacobian by central differences, the nine equations by sympy.

ex03 Tasks 3 and 4 and ex05 Task 2 grade the method in the way ex03 and ex05 Task 1 do
(tests/test_checks_procedures.py): the student writes a function — ω4, α4 by the Jacobian solve from the
position, θ2_max by the law of cosines from the lengths, (θ1, θ4) by the half-angle roots from the end
effector — and the check calls it at fresh inputs the student has not seen, with course_lib's solves watched
(all but the call the task gives: ``loop_jacobian``, ``inverse_coefficients``).  The pair ``bench.solve``,
``input_range`` or ``robot.inverse`` gives is not ✔, nor a function that calls them; a wrong function is told
its cause; one that never returns is answered, not waited for.  The students' functions below are written
independently: the Jacobian and the quadratic velocity terms by central differences of the loop, the limits
checked by circle intersections, the five-bar's angles from the course's coefficients typed out
(tests/geometry.py).
"""

from __future__ import annotations

import functools
import math
import pathlib
import time

import nbformat
import numpy as np
import pytest
import sympy as sp
from geometry import course_inverse_angles
from test_checks import BENCH, ROBOT, rejects

from course_lib import checks
from course_lib.checks import engine
from course_lib.fourbar import FourBar
from course_lib.saw import Saw, solve_consecutive, solve_simultaneous

MY_SAW = Saw(r1y=0.030, r2=0.060, r3=0.150)
THETA2, OMEGA2, ALPHA2 = np.radians(50.0), 6.0, 4.0
SEED = np.array([-0.1, -0.5, 3.0, 0.5, 0.0, -0.5, 0.5, 0.0, -0.5])  # the report's printed seed
EX04 = pathlib.Path(__file__).resolve().parent.parent / "notebooks" / "solutions" / "ex04_power_saw.ipynb"


def position_equations(q, theta2=THETA2, r1y=0.030, r2=0.060, r3=0.150, sp=np):
    """The saw's loop and slider line (Fx, Fy, Fc), typed from the course material (numbers, or sympy with
    ``sp=sympy``)."""
    r1, t1, t3 = q
    return [-r1 * sp.cos(t1) + r2 * sp.cos(theta2) + r3 * sp.cos(t3),
            r1 * sp.sin(t1) - r2 * sp.sin(theta2) - r3 * sp.sin(t3),
            r1 * sp.sin(t1) - r1y]


def position_equations_of(r1y, r2, r3):
    """The position equations of a saw with these lengths, at the task's θ2."""
    return lambda q: position_equations(q, r1y=r1y, r2=r2, r3=r3)


@functools.cache
def _nine(omega2=OMEGA2, alpha2=ALPHA2, theta2=THETA2):
    """The nine equations and their Jacobian, lambdified: the position equations and their first and second
    time derivatives, by sympy, along θ2(t) with θ2' = ω2, θ2'' = α2."""
    t, theta2_value = sp.Symbol("t"), theta2
    r1, t1, t3, theta2 = (sp.Function(name)(t) for name in ("r1", "theta1", "theta3", "theta2"))
    F = sp.Matrix(position_equations((r1, t1, t3), theta2, sp=sp))
    rates = [F, F.diff(t), F.diff(t, 2)]
    x = sp.symbols("r1 theta1 theta3 v_r omega1 omega3 a_r alpha1 alpha3")
    plain = {}
    for q, name in enumerate((r1, t1, t3)):
        plain[name.diff(t, 2)], plain[name.diff(t)] = x[6 + q], x[3 + q]
    plain.update({theta2.diff(t, 2): alpha2, theta2.diff(t): omega2})
    rows = sp.Matrix.vstack(*rates).subs(plain).subs({r1: x[0], t1: x[1], t3: x[2], theta2: theta2_value})
    return sp.lambdify([x], rows, "numpy"), sp.lambdify([x], rows.jacobian(x), "numpy")


def nine_equations(x):
    return np.ravel(_nine()[0](x))


def newton_by_hand(F, seed, steps, jacobian=None):
    """Newton's iterates, seed first, with J by central differences (or ``jacobian``)."""
    def F_(x):
        return np.asarray(F(x), float)

    rows = [np.array(seed, float)]
    for _ in range(steps):
        x = rows[-1]
        J = jacobian(x) if jacobian else np.column_stack([(F_(x + 1e-7 * e) - F_(x - 1e-7 * e)) / 2e-7
                                                          for e in np.eye(len(x))])
        rows.append(x + np.linalg.solve(J, -F_(x)))
    return rows


def position(answer, method="consecutive"):
    return checks.check_saw_position(answer, MY_SAW, THETA2, method=method)


def acceleration(answer, method="simultaneous"):
    return checks.check_saw_slider_acceleration(answer, MY_SAW, THETA2, OMEGA2, ALPHA2, method=method)


def test_the_notebook_grades_the_method_of_tasks_2_and_3():
    sources = [cell.source for cell in nbformat.read(EX04, as_version=4).cells if cell.cell_type == "code"]
    assert any(s.startswith("checks.check_saw_position(") and 'method="consecutive"' in s for s in sources)
    assert any(s.startswith("checks.check_saw_slider_acceleration(") and 'method="simultaneous"' in s
               for s in sources)


def test_newtons_work_passes_as_a_solve_a_newton_run_or_the_students_own_iterates():
    by_hand = newton_by_hand(position_equations, SEED[:3], 6)
    assert np.max(np.abs(by_hand[-1] - by_hand[-2])) < 1e-9  # converged: the numbers are the position
    consecutive = solve_consecutive(THETA2, saw=MY_SAW)
    for answer in (consecutive, consecutive.stages["position"], by_hand, np.array(by_hand),
                   solve_consecutive(THETA2, saw=MY_SAW, variant="substituted")):
        feedback = position(answer)
        assert feedback.ok and "consecutive Newton" in feedback.message, feedback
    nine = newton_by_hand(nine_equations, SEED, 7, jacobian=lambda x: np.asarray(_nine()[1](x), float))
    simultaneous = solve_simultaneous(THETA2, OMEGA2, ALPHA2, saw=MY_SAW)
    for answer in (simultaneous, simultaneous.newton, nine):
        feedback = acceleration(answer)
        assert feedback.ok and "simultaneous Newton" in feedback.message, feedback


def test_a_right_number_from_the_closed_form_is_not_a_tick():
    closed = MY_SAW.motion(THETA2, OMEGA2, ALPHA2)
    assert checks.check_saw_position(closed, MY_SAW, THETA2).ok  # the numbers are right …
    for feedback in (position(closed), acceleration(closed)):  # … but not the method
        assert not feedback.ok and "closed form" in feedback.message, feedback
        assert "Newton" in feedback.message, feedback
    for feedback in (position((closed.r1, closed.theta1, closed.theta3)), acceleration(closed.a_r)):
        assert not feedback.ok and "numbers alone" in feedback.message, feedback


@pytest.mark.parametrize(("answer", "says"), [
    (lambda: [SEED[:3], np.array(tuple(MY_SAW.motion(THETA2))[:3])], "step 1"),  # seed, then the answer
    (lambda: newton_by_hand(position_equations, SEED[:3], 2) + [np.array(tuple(MY_SAW.motion(THETA2))[:3])],
     "step 3"),
    (lambda: newton_by_hand(position_equations, [-0.12, -0.3, 3.2], 6), "report's seed"),
    (lambda: solve_simultaneous(THETA2, saw=MY_SAW), "simultaneous Newton"),
    (lambda: [list(np.round(row, 4)) for row in newton_by_hand(position_equations, SEED[:3], 6)], "step"),
])
def test_iterates_that_are_not_the_asked_newton_run_are_named(answer, says):
    feedback = position(answer())
    assert not feedback.ok and says in feedback.message, feedback


def test_the_nine_unknowns_by_another_method_are_named():
    consecutive = solve_consecutive(THETA2, OMEGA2, ALPHA2, saw=MY_SAW)
    feedback = acceleration(consecutive)
    assert not feedback.ok and "consecutive Newton" in feedback.message and "solve_simultaneous" in \
        feedback.message, feedback
    feedback = acceleration(newton_by_hand(position_equations, SEED[:3], 6))  # the position stage alone
    assert not feedback.ok and "only r1, θ1, θ3" in feedback.message, feedback


def test_newtons_steps_at_another_motor_state_or_unfinished_are_told_which():
    """The student's own 9×9 Newton (sympy's equations) at a motor state off the task's: with ω2 of the
    wrong sign a_r is right (ω2 enters squared) but the steps are not the task's; α2 or both flipped, θ2
    in degrees, a run stopped after two steps — each named from the iterates."""
    for motor, steps, says in (((-OMEGA2, ALPHA2, THETA2), 7, "sign of ω2 is flipped"),
                               ((OMEGA2, -ALPHA2, THETA2), 7, "at α2 = -4 rad/s², not the task's."),
                               ((-OMEGA2, -ALPHA2, THETA2), 7, "at ω2 = -6 rad/s; α2 = -4 rad/s², not the"),
                               ((OMEGA2, ALPHA2, 50.0), 7, "the crank angle in degrees"),
                               ((-OMEGA2, ALPHA2, THETA2), 2, "-6 rad/s, not the task's; the run stopped"),
                               ((OMEGA2, ALPHA2, THETA2), 2, "stopped before converging"),
                               ((OMEGA2, ALPHA2, THETA2), 3, "precision, but your iterates stopped before")):
        equations, jacobian = _nine(*motor)
        rows = newton_by_hand(lambda x, F=equations: np.ravel(F(x)), SEED, steps,
                              jacobian=lambda x, J=jacobian: np.asarray(J(x), float))
        feedback = acceleration(rows)
        assert not feedback.ok and says in feedback.message, (motor, steps, feedback)
    right = newton_by_hand(nine_equations, SEED, 7, jacobian=lambda x: np.asarray(_nine()[1](x), float))
    assert acceleration(right).ok
    for table in ([sp.Matrix(row) for row in right], [row.reshape(9, 1) for row in right],  # columns,
                  [sp.Matrix([list(row)]) for row in right], sp.Matrix(np.array(right).tolist())):  # rows
        assert acceleration(table).ok, table
    rounded = acceleration(np.round(np.array(right), 8))
    assert not rounded.ok and "rounded to 8 decimals" in rounded.message, rounded
    single = acceleration(np.array(right, dtype=np.float32))
    assert not single.ok and "only to about 7 digits" in single.message, single
    other = newton_by_hand(position_equations_of(0.045, 0.075, 0.170), SEED[:3], 2)  # the course's saw
    feedback = position(other)
    assert not feedback.ok and "the course's saw" in feedback.message and "stopped before" in feedback.message
    four = acceleration(right[:5])  # stopped where one more step moves nothing by more than the tolerance
    assert four.ok and "4 iterations" in four.message, four
    steps = newton_by_hand(position_equations, SEED[:3], 6)
    for decimals in (2, 4, 10):  # rounded iterates, wherever the unknowns' sizes put their last digit
        for check, rows in ((position, steps), (acceleration, right)):
            told = check([row if k == 0 else np.round(row, decimals) for k, row in enumerate(rows)])
            assert not told.ok and f"rounded to {decimals} decimals" in told.message, (decimals, told)
    both = position([row if k == 0 else np.round(row, 4) for k, row in enumerate(steps[:3])])
    assert "stopped before converging" in both.message and "rounded to 4" in both.message, both
    single = position([row if k == 0 else row.astype(np.float32).astype(float)
                       for k, row in enumerate(steps)])
    assert not single.ok and "float32" in single.message, single


def test_a_wrong_solve_still_gets_its_diagnosis():
    at_rest = solve_simultaneous(THETA2, saw=MY_SAW)  # ω2 = α2 = 0 left out
    assert "at rest" in acceleration(at_rest).message
    in_degrees = solve_consecutive(50.0, saw=MY_SAW)
    assert "degrees" in position(in_degrees).message
    closed_mm = 1000 * np.array(tuple(MY_SAW.motion(THETA2))[:3])
    assert "millimetres" in position(closed_mm).message


def test_without_a_method_a_solve_or_the_numbers_pass():
    closed = MY_SAW.motion(THETA2, OMEGA2, ALPHA2)
    for answer in (closed, solve_consecutive(THETA2, saw=MY_SAW), (closed.r1, closed.theta1, closed.theta3)):
        assert checks.check_saw_position(answer, MY_SAW, THETA2).ok
    for answer in (closed, closed.a_r, solve_simultaneous(THETA2, OMEGA2, ALPHA2, saw=MY_SAW)):
        assert checks.check_saw_slider_acceleration(answer, MY_SAW, THETA2, OMEGA2, ALPHA2).ok


# ---------------------------------------------------------------- ex03 Task 3: ω4, α4 by the Jacobian solve

EX03 = EX04.parent / "ex03_fourbar.ipynb"
EX05 = EX04.parent / "ex05_fivebar.ipynb"
THETA2_T3, OMEGA2_T3, ALPHA2_T3 = np.radians(200.0), 15.0, -40.0
TASK_POSITION = tuple(float(angle) for angle in tuple(BENCH.solve(THETA2_T3))[:2])  # the task's θ3, θ4


def bench_loop(theta2, q):
    """The bench's loop (l1 = 0.25, l2 = 0.07, l3 = 0.20, l4 = 0.15 m), typed from the course material."""
    l1, l2, l3, l4 = 0.25, 0.07, 0.20, 0.15
    return np.array([l2 * np.cos(theta2) + l3 * np.cos(q[0]) - l4 * np.cos(q[1]) - l1,
                     l2 * np.sin(theta2) + l3 * np.sin(q[0]) - l4 * np.sin(q[1])])


def rates_by_jacobian(theta2, theta3, theta4, omega2, alpha2, keep_squares=True, jacobian=None):
    """(ω4, α4) by J·q̇ = −ω2·∂F/∂θ2 and J·q̈ = −α2·∂F/∂θ2 − γ: J and ∂F/∂θ2 by central differences of the
    loop (or J by ``jacobian``, as the task gives it), γ (the ω² terms) as the second difference of F along
    (θ2 + ω2·s, q + q̇·s)."""
    q, h, s = np.array([theta3, theta4]), 1e-6, 1e-4
    J = jacobian(theta3, theta4) if jacobian else np.column_stack(
        [(bench_loop(theta2, q + h * e) - bench_loop(theta2, q - h * e)) / (2 * h) for e in np.eye(2)])
    dF = (bench_loop(theta2 + h, q) - bench_loop(theta2 - h, q)) / (2 * h)
    q_dot = np.linalg.solve(J, -omega2 * dF)

    def along(step):
        return bench_loop(theta2 + omega2 * step, q + q_dot * step)

    gamma = (along(s) - 2 * along(0.0) + along(-s)) / s**2 if keep_squares else 0.0
    q_ddot = np.linalg.solve(J, -alpha2 * dF - gamma)
    return float(q_dot[1]), float(q_ddot[1])


def rates_task(answer, method="Jacobian"):
    return checks.check_fourbar_rates(answer, BENCH, THETA2_T3, OMEGA2_T3, ALPHA2_T3, "open", method=method)


def test_the_notebooks_grade_the_method_of_ex03_tasks_3_and_4_and_ex05_task_2():
    for path, call, method in ((EX03, "checks.check_fourbar_rates(", 'method="Jacobian"'),
                               (EX03, "checks.check_toggle_angle(", 'method="law of cosines"'),
                               (EX05, "checks.check_fivebar_inverse(", 'method="half-angle"')):
        for folder in ("solutions", "exercises"):
            cells = nbformat.read(path.parent.parent / folder / path.name, as_version=4).cells
            assert any(cell.source.startswith(call) and method in cell.source
                       for cell in cells if cell.cell_type == "code"), (path.name, folder, call)


def test_the_rates_by_the_jacobian_pass_at_the_task_and_at_every_fresh_instant():
    task = BENCH.solve(THETA2_T3)
    ours = rates_by_jacobian(THETA2_T3, task.theta3, task.theta4, OMEGA2_T3, ALPHA2_T3)
    assert checks.check_fourbar_rates(ours, BENCH, THETA2_T3, OMEGA2_T3, ALPHA2_T3, "open").ok  # the numbers
    for answer in (rates_by_jacobian, lambda *args: rates_by_jacobian(*args, jacobian=BENCH.loop_jacobian),
                   lambda *args: [float(f"{v:.4g}") for v in rates_by_jacobian(*args)],
                   lambda *args: np.array(rates_by_jacobian(*args)).reshape(2, 1)):
        feedback = rates_task(answer)
        assert feedback.ok and "5 other instants" in feedback.message, feedback


def test_the_pair_the_solve_gives_is_not_a_tick_for_the_jacobian_task():
    solved = BENCH.solve(THETA2_T3, OMEGA2_T3, ALPHA2_T3)
    pair = (solved.omega4, solved.alpha4)
    assert checks.check_fourbar_rates(pair, BENCH, THETA2_T3, OMEGA2_T3, ALPHA2_T3, "open").ok  # no method
    rejects(rates_task(pair), "numbers are right", "Jacobian solve")
    rejects(rates_task(solved), "whole result")  # the Motion itself
    def by_the_solve(theta2, theta3, theta4, omega2, alpha2):
        solved = BENCH.solve(theta2, omega2, alpha2)
        return solved.omega4, solved.alpha4

    rejects(rates_task(by_the_solve), "FourBar.solve", "course_lib", "arguments theta3, theta4")
    rejects(rates_task(lambda t2, t3, t4, w2, a2: tuple(BENCH.motion(t2, w2, a2))[3::2]), "calls",
            "course_lib")
    rejects(rates_task(lambda t2, t3, t4, w2, a2: (
        (motion := BENCH.mechanism.solve({"theta2": t2}, {"theta2": w2}, {"theta2": a2},
                                         guess={"theta3": t3, "theta4": t4})).velocity["theta4"],
        motion.acceleration["theta4"])), "calls", "course_lib")


@pytest.mark.parametrize(("answer", "says"), [
    (lambda t2, t3, t4, w2, a2: rates_by_jacobian(t2, t3, t4, w2, a2, keep_squares=False),
     "ω² (centripetal)"),
    (lambda t2, t3, t4, w2, a2: rates_by_jacobian(t2, t3, t4, w2, 0.0), "constant speed"),
    (lambda t2, t3, t4, w2, a2: rates_by_jacobian(t2, t3, t4, OMEGA2_T3, ALPHA2_T3), "task's ω2"),
    (lambda t2, t3, t4, w2, a2: rates_by_jacobian(t2, *TASK_POSITION, w2, a2), "task's position"),
    (lambda *args: rates_by_jacobian(THETA2_T3, *TASK_POSITION, OMEGA2_T3, ALPHA2_T3),
     "same (ω4, α4) at every instant"),
    (lambda *args: rates_by_jacobian(*args)[::-1], "swapped"),
    (lambda t2, w2, a2: (0.0, 0.0), "TypeError"),
    (lambda *args: None, "None"), (lambda *args: rates_by_jacobian(*args)[0], "a single number"),
])
def test_a_wrong_rates_procedure_is_told_its_cause(answer, says):
    task = BENCH.solve(THETA2_T3)
    rejects(rates_task(answer), says,
            hidden=rates_by_jacobian(THETA2_T3, task.theta3, task.theta4, OMEGA2_T3, ALPHA2_T3))


# ---------------------------------------------------------------- ex03 Task 4: the limit, law of cosines

TRIPLE = FourBar(crank=0.14, coupler=0.12, rocker=0.10, ground=0.20)


def law_of_cosines(l1, l2, l3, l4, reach=None):
    """The crank angle where |AO4|² = l1² + l2² − 2·l1·l2·cos θ2 reaches l3 + l4 (or ``reach``)."""
    reach = l3 + l4 if reach is None else reach
    return math.acos((l1 * l1 + l2 * l2 - reach * reach) / (2 * l1 * l2)), "extended"


def closes(l1, l2, l3, l4, theta2):
    """Whether the circles of l3 about the crank pin A and l4 about O4 meet at crank angle θ2 (A and O4 by
    their coordinates: |l3 − l4| ≤ |AO4| ≤ l3 + l4)."""
    gap = float(np.hypot(l2 * np.cos(theta2) - l1, l2 * np.sin(theta2)))
    return abs(l3 - l4) <= gap <= l3 + l4


def limit_task(answer, method="law of cosines"):
    return checks.check_toggle_angle(answer, TRIPLE, method=method)


def test_the_law_of_cosines_is_the_largest_angle_of_every_linkage_the_check_calls_it_for():
    for lengths in [(0.20, 0.14, 0.12, 0.10), *checks.ex03.FRESH_LINKAGES]:
        limit = law_of_cosines(*lengths)[0]
        assert 0 < limit < np.pi
        assert closes(*lengths, limit - 1e-6), lengths
        assert not any(closes(*lengths, theta2) for theta2 in np.linspace(limit + 1e-6, np.pi, 200)), lengths


def test_the_limit_by_the_law_of_cosines_passes():
    for answer in (law_of_cosines, lambda *lengths: (round(law_of_cosines(*lengths)[0], 4), " Extended"),
                   lambda *lengths: [law_of_cosines(*lengths)[0] - 2 * np.pi, "extended"]):
        feedback = limit_task(answer)
        assert feedback.ok and "5 other linkages" in feedback.message, feedback


def test_the_limit_the_library_gives_is_not_a_tick():
    limit = max(TRIPLE.input_range().toggle_angles)
    assert checks.check_toggle_angle((limit, "extended"), TRIPLE).ok  # no method: the pair is right
    rejects(limit_task((limit, "extended")), "angle and the word are right", "law of cosines")
    rejects(limit_task(lambda l1, l2, l3, l4: (max(FourBar(crank=l2, coupler=l3, rocker=l4, ground=l1)
                                                    .input_range().toggle_angles), "extended")),
            "FourBar.input_range", "course_lib")


@pytest.mark.parametrize(("answer", "says"), [
    (lambda *lengths: (law_of_cosines(*lengths)[0], "folded"), "how the links lie"),
    (lambda *lengths: law_of_cosines(0.20, 0.14, 0.12, 0.10), "same θ2_max for every linkage"),
    (lambda l1, l2, l3, l4: (law_of_cosines(l1, l2, l3, l4, abs(l3 - l4))[0]
                             if l1 * l1 + l2 * l2 - (l3 - l4) ** 2 < 2 * l1 * l2
                             else law_of_cosines(l1, l2, l3, l4)[0], "extended"), "|l3 − l4|"),
    (lambda *lengths: (math.degrees(law_of_cosines(*lengths)[0]), "extended"), "degrees"),
    (lambda *lengths: (-law_of_cosines(*lengths)[0], "extended"), "mirror"),
    (lambda l1, l2, l3: (1.0, "extended"), "TypeError"),
    (lambda *lengths: law_of_cosines(*lengths)[0], "a single value"),
])
def test_a_wrong_limit_procedure_is_told_its_cause(answer, says):
    rejects(limit_task(answer), says, hidden=[law_of_cosines(0.20, 0.14, 0.12, 0.10)[0]])


def test_crank_and_ground_read_in_fourbars_order_are_named():
    """A function that reads (l1, l2, l3, l4) as FourBar's (crank, coupler, rocker, ground): for the task's
    lengths that order is a linkage that stops too (at 2.026 rad), and the check names the order."""
    def swapped_order(crank, coupler, rocker, ground):  # the cosine clipped: finite for every linkage
        cosine = (ground**2 + crank**2 - (coupler + rocker) ** 2) / (2 * ground * crank)
        return float(np.arccos(np.clip(cosine, -1.0, 1.0))), "extended"

    rejects(limit_task(swapped_order), "task's linkage", "FourBar's order",
            hidden=[law_of_cosines(0.20, 0.14, 0.12, 0.10)[0]])


# ---------------------------------------------------------------- ex05 Task 2: θ1, θ4 by the half-angle roots

LENGTHS = (0.11, 0.15, 0.16, 0.12, 0.09)


def half_angle(x3, y3, sigma1=-1, sigma2=+1):
    return course_inverse_angles(x3, y3, LENGTHS, sigma1, sigma2)


def inverse_task(answer, method="half-angle"):
    return checks.check_fivebar_inverse(answer, ROBOT, 0.02, 0.21, (-1, +1), method=method)


def test_every_fresh_point_has_four_working_modes_apart():
    for x3, y3 in checks.ex05.FRESH_POINTS:
        for leg in (0, 1):
            roots = [half_angle(x3, y3, *modes)[leg] for modes in ((1, 1), (-1, -1))]
            assert np.all(np.isfinite(roots)) and abs(math.remainder(roots[0] - roots[1], 2 * math.pi)) > 0.1


def test_the_angles_by_the_half_angle_roots_pass():
    def from_the_given_coefficients(x3, y3):  # the coefficients the task gives, the roots by hand
        k = ROBOT.inverse_coefficients(x3, y3)
        return tuple(2 * math.atan((-b - s * math.sqrt(b * b - 4 * a * c)) / (2 * a)) for a, b, c, s in (
            (k["a1"], k["b1"], k["c1"], +1), (k["a2"], k["b2"], k["c2"], -1)))

    for answer in (half_angle, from_the_given_coefficients, lambda x3, y3: np.round(half_angle(x3, y3), 4)):
        feedback = inverse_task(answer)
        assert feedback.ok and "6 other points" in feedback.message, feedback


def test_the_angles_the_library_solves_are_not_a_tick():
    solved = ROBOT.inverse(0.02, 0.21, modes=(-1, +1))
    assert checks.check_fivebar_inverse(solved, ROBOT, 0.02, 0.21, (-1, +1)).ok  # no method
    rejects(inverse_task(solved), "angles are right", "half-angle")
    rejects(inverse_task(tuple(solved)), "angles are right")
    rejects(inverse_task(lambda x3, y3: tuple(ROBOT.inverse(x3, y3, modes=(-1, 1)))), "FiveBar.inverse",
            "course_lib")
    rejects(inverse_task(lambda x3, y3: tuple(ROBOT.inverse(x3, y3, assembly={"theta1": 1, "theta4": -1}))),
            "FiveBar.inverse")


@pytest.mark.parametrize(("answer", "says"), [
    (lambda x3, y3: half_angle(x3, y3, +1, +1), "working mode (+1, +1)"),
    (lambda x3, y3: half_angle(x3, y3, -1, -1), "working mode (-1, -1)"),
    (lambda x3, y3: half_angle(0.02, 0.21), "same angles at every point"),
    (lambda x3, y3: half_angle(x3, y3) if (x3, y3) == (0.02, 0.21) else half_angle(x3, y3, 1, -1),
     "not at (x3, y3) = (0, 0.18) m"),
    (lambda x3, y3: half_angle(x3, y3)[::-1], "swapped"),
    (lambda x3, y3: tuple(np.degrees(half_angle(x3, y3))), "degrees"),
    (lambda x3: (0.0, 0.0), "TypeError"), (lambda x3, y3: (np.nan, 0.0), "NaN"),
])
def test_a_wrong_inverse_procedure_is_told_its_cause(answer, says):
    rejects(inverse_task(answer), says, hidden=half_angle(0.02, 0.21))


# ---------------------------------------------------------------- no check waits for a function that hangs


def forever(*arguments):
    while True:
        pass


@pytest.mark.parametrize("check", [rates_task, limit_task, inverse_task], ids=["rates", "limit", "inverse"])
def test_a_function_that_never_returns_is_reported_not_waited_for(check, monkeypatch):
    monkeypatch.setattr(engine, "PROCEDURE_SECONDS", 0.3)
    start = time.perf_counter()
    feedback = check(forever)
    assert time.perf_counter() - start < 3.0
    rejects(feedback, "did not return within 0.3 s", "endless loop")
