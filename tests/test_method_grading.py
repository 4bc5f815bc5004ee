"""ex04 grades the method its Tasks 2 and 3 ask for: Newton's iterations, not only the numbers they end at.

Task 2 asks for the position by the consecutive Newton–Raphson, Task 3 for a_r by the simultaneous 9×9 Newton;
the closed form (``my_saw.motion``) gives the same numbers with no Newton at all.  With ``method=`` (as the
notebook's check cells call them) the checkers read the solve the student stores: the solver's Motion (its
Newton run inside), a NewtonResult, or the student's own iterates, seed first — each step recomputed here as a
Newton step of the saw's equations at the student's own iterates, from the report's seed.  A right number from
the closed form, or right numbers alone, is not ✔.  The student's own Newton below is written independently:
the saw's equations typed out, a Jacobian by central differences, the nine equations by sympy.
"""

from __future__ import annotations

import functools
import pathlib

import nbformat
import numpy as np
import pytest
import sympy as sp

from course_lib import checks
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


@functools.cache
def _nine():
    """The nine equations and their Jacobian, lambdified: the position equations and their first and second
    time derivatives, by sympy, along θ2(t) with θ2' = ω2, θ2'' = α2."""
    t = sp.Symbol("t")
    r1, t1, t3, theta2 = (sp.Function(name)(t) for name in ("r1", "theta1", "theta3", "theta2"))
    F = sp.Matrix(position_equations((r1, t1, t3), theta2, sp=sp))
    rates = [F, F.diff(t), F.diff(t, 2)]
    x = sp.symbols("r1 theta1 theta3 v_r omega1 omega3 a_r alpha1 alpha3")
    plain = {}
    for q, name in enumerate((r1, t1, t3)):
        plain[name.diff(t, 2)], plain[name.diff(t)] = x[6 + q], x[3 + q]
    plain.update({theta2.diff(t, 2): ALPHA2, theta2.diff(t): OMEGA2})
    rows = sp.Matrix.vstack(*rates).subs(plain).subs({r1: x[0], t1: x[1], t3: x[2], theta2: THETA2})
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
