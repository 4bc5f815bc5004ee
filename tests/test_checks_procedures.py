"""ex03 and ex05 grade the method their Task 1 asks for: the student's procedure, not a number the library
gives.

ex03 Task 1 asks for θ4 of the crossed four-bar from Norton's half-angle quadratic, ex05 Task 1 for the
five-bar's end effector from X3 = g·Y3 + f and the quadratic in Y3.  ``bench.solve`` and ``robot.forward``
give those numbers with none of that work.  With ``method=`` (as the notebooks' check cells call them) the
checkers take the student's function, call it at the task's angles and at other crank angles, and watch that
it calls none of course_lib's solves; a right number alone, or a function that asks the library, is not ✔.
The references here are independent of the code under test: the four-bar and the five-bar by circle
intersections (tests/geometry.py), the student's procedures typed from the task's formulas.
"""

from __future__ import annotations

import math
import pathlib

import nbformat
import numpy as np
import pytest
from geometry import circle_intersections
from test_checks import BENCH, ROBOT, fourbar_by_circles, rejects

from course_lib import checks

ROOT = pathlib.Path(__file__).resolve().parent.parent
THETA2 = np.radians(120.0)
SOLVED = BENCH.solve(THETA2, branch="crossed")
THETA1, THETA4 = np.radians(70.0), np.radians(125.0)


# ---------------------------------------------------------------- ex03: θ4 by the half-angle quadratic


def norton(theta2, sign=+1, cos=np.cos, sin=np.sin):
    """θ4 from the task's formulas (K1, K2, K3, a, b, c, the root with ``sign``), the bench's lengths."""
    l1, l2, l3, l4 = 0.25, 0.07, 0.20, 0.15
    K1, K2, K3 = l1 / l2, l1 / l4, (l2**2 - l3**2 + l4**2 + l1**2) / (2 * l2 * l4)
    a = cos(theta2) - K1 - K2 * cos(theta2) + K3
    b = -2 * sin(theta2)
    c = K1 - (K2 + 1) * cos(theta2) + K3
    return 2 * np.arctan((-b + sign * np.sqrt(b**2 - 4 * a * c)) / (2 * a))


def theta4_task(answer, method="half-angle"):
    return checks.check_fourbar_theta4(answer, BENCH, THETA2, "crossed", method=method)


def test_the_quadratic_is_the_crossed_branch_wherever_the_check_calls_it():
    """The check's fresh crank angles, and the task's: Norton's + root is θ4 of the crossed assembly there (by
    circle intersections), so a right procedure can pass everywhere the check calls it."""
    for theta2 in [THETA2, *checks.ex03.FRESH_THETA2]:
        crossed = fourbar_by_circles(BENCH, theta2, "crossed")[1]
        assert abs(math.remainder(norton(theta2) - crossed, 2 * math.pi)) < 1e-9, np.degrees(theta2)


def test_the_notebook_asks_for_the_procedures():
    for name, call in (("ex03_fourbar", "checks.check_fourbar_theta4("),
                       ("ex05_fivebar", "checks.check_fivebar_forward(")):
        for folder in ("solutions", "exercises"):
            cells = nbformat.read(ROOT / "notebooks" / folder / f"{name}.ipynb", as_version=4).cells
            sources = [cell.source for cell in cells if cell.cell_type == "code"]
            assert any(s.startswith(call) and "method=" in s for s in sources), (name, folder)


def test_a_procedure_of_the_quadratic_passes_in_the_forms_a_student_writes():
    for answer in (norton, lambda t: round(float(norton(t)), 4), lambda t: norton(t) + 2 * np.pi,
                   lambda t: np.array([norton(t)]), lambda t: norton(t, cos=math.cos, sin=math.sin),
                   lambda t: fourbar_by_circles(BENCH, t, "crossed")[1]):  # geometry: no solve of course_lib
        feedback = theta4_task(answer)
        assert feedback.ok and "7 other crank angles" in feedback.message, feedback


def test_a_right_number_from_the_given_solve_is_not_a_tick():
    number = BENCH.solve(THETA2, branch="crossed").theta4
    assert checks.check_fourbar_theta4(number, BENCH, THETA2, "crossed").ok  # lesson 03's Try it: a number
    rejects(theta4_task(number), "number is right", "quadratic")
    rejects(theta4_task(float(norton(THETA2))), "number is right")  # the number alone, however found
    for by_the_solve in (lambda t: BENCH.solve(t, branch="crossed").theta4,
                         lambda t: BENCH.motion(t, branch="crossed").theta4,
                         lambda t: BENCH.mechanism.solve({"theta2": t}, guess={"theta3": 0.3, "theta4": -2.6})
                         .position["theta4"]):
        feedback = theta4_task(by_the_solve)
        rejects(feedback, "calls", "course_lib")
    rejects(theta4_task(lambda t: BENCH.solve(t, branch="crossed").theta4), "FourBar.solve")


@pytest.mark.parametrize(("answer", "says"), [
    (lambda t: norton(t, -1), "open assembly"),
    (lambda t: norton(THETA2), "same θ4 at every crank angle"),  # the task's angle typed in
    (lambda t: SOLVED.theta4, "same θ4 at every crank angle"),  # a solve made outside, read inside
    (lambda t: norton(t, +1 if t < 3.0 else -1), "200°"),  # right at 120°, the other root further round
    (lambda t: norton(np.degrees(t)), "degrees"),  # θ2 in degrees inside a, b, c
    (lambda t: norton(np.radians(t)), "np.radians"),  # the function converts what is radians already
    (lambda t: np.degrees(norton(t)), "degrees"),
    (lambda t: fourbar_by_circles(BENCH, t, "crossed")[0], "coupler angle θ3"),
    (lambda t: (norton(t), norton(t, -1)), "2 numbers"),
    (lambda t: None, "None"), (lambda t: "2.1", "string"), (lambda t: float("nan"), "NaN"),
    (lambda t: 1 / 0, "ZeroDivisionError"), (lambda t, u: 0.0, "TypeError"),
])
def test_a_wrong_procedure_is_told_what_is_wrong_without_a_traceback(answer, says):
    rejects(theta4_task(answer), says, hidden=(norton(THETA2),))


def test_theta2_in_degrees_inside_a_b_c_is_named_for_a_number_too():
    """Lesson 03's Try it and ex03: a θ4 computed with cos 120, sin 120 in a, b, c (either root), or with
    degrees in only one of cos θ2 and sin θ2, is told so, not sent back to recheck the coefficients in
    general."""
    def degrees_in_sin(t, sign):
        return norton(t, sign, sin=lambda angle: np.sin(np.degrees(angle)))

    def degrees_in_cos(t, sign):
        return norton(t, sign, cos=lambda angle: np.cos(np.degrees(angle)))

    for sign in (+1, -1):
        for number, says in ((norton(120.0, sign), "cos θ2 and sin θ2"),
                             (degrees_in_sin(THETA2, sign), "sin θ2 of b"),
                             (degrees_in_cos(THETA2, sign), "cos θ2 of a and c")):
            for method in (None, "half-angle"):
                rejects(checks.check_fourbar_theta4(float(number), BENCH, THETA2, "crossed", method=method),
                        "degrees", says, "np.radians")
        rejects(theta4_task(lambda t, sign=sign: degrees_in_sin(t, sign)), "your function", "sin θ2 of b")


# ---------------------------------------------------------------- ex05: the end effector by X3 = g·Y3 + f


def course_forward(theta1, theta4, sign=-1, slip=False):
    """(X3, Y3) from the task's formulas, the exercise robot's lengths; ``slip``: +b in X3 (lesson 08 §7)."""
    l1, l2, l3, l4, l5 = 0.11, 0.15, 0.16, 0.12, 0.09
    D = l5 + l1 * np.cos(theta1) - l4 * np.cos(theta4)
    f = (l1**2 - l2**2 + l3**2 - l4**2 + l1 * l5 * np.cos(theta1) + l4 * l5 * np.cos(theta4)) / (2 * D)
    g = (-2 * l1 * np.sin(theta1) + 2 * l4 * np.sin(theta4)) / (2 * D)
    a, b = 1 + g**2, 2 * f * g + g * l5 - 2 * g * l4 * np.cos(theta4) - 2 * l4 * np.sin(theta4)
    c = f**2 - l3**2 + l4**2 + f * l5 + l5**2 / 4 - l4 * (2 * f + l5) * np.cos(theta4)
    y3 = (-b + sign * np.sqrt(b**2 - 4 * a * c)) / (2 * a)
    return (g * ((b + sign * np.sqrt(b**2 - 4 * a * c)) / (2 * a) if slip else y3) + f, y3)


def by_circles(theta1, theta4, lower=True):
    """The end effector where the circles of l2 about P2 and l3 about P4 meet: the lower or upper point."""
    P2 = np.array([0.11 * np.cos(theta1) + 0.045, 0.11 * np.sin(theta1)])
    P4 = np.array([0.12 * np.cos(theta4) - 0.045, 0.12 * np.sin(theta4)])
    points = circle_intersections(P2, 0.15, P4, 0.16)
    return tuple((min if lower else max)(points, key=lambda p: p[1]))


def forward_task(answer, method="quadratic"):
    return checks.check_fivebar_forward(answer, ROBOT, THETA1, THETA4, -1, method=method)


def test_the_derivation_is_arms_down_wherever_the_check_calls_it():
    for theta1, theta4 in [(THETA1, THETA4), *checks.ex05.FRESH_CRANKS]:
        assert np.allclose(course_forward(theta1, theta4), by_circles(theta1, theta4), atol=1e-12)


def test_a_procedure_of_the_derivation_passes_in_the_forms_a_student_writes():
    for answer in (course_forward, lambda t1, t4: [round(float(v), 6) for v in course_forward(t1, t4)],
                   lambda t1, t4: np.array(course_forward(t1, t4)).reshape(2, 1), by_circles):
        feedback = forward_task(answer)
        assert feedback.ok and "6 other pairs" in feedback.message, feedback


def test_a_right_point_from_the_given_forward_is_not_a_tick():
    point = ROBOT.forward(THETA1, THETA4, mode=-1)
    assert checks.check_fivebar_forward(point, ROBOT, THETA1, THETA4, -1).ok  # lesson 08's Try it
    rejects(forward_task(point), "numbers are right", "robot.forward")
    rejects(forward_task(by_circles(THETA1, THETA4)), "numbers are right")
    rejects(forward_task(lambda t1, t4: ROBOT.forward(t1, t4, mode=-1)), "FiveBar.forward", "course_lib")

    def from_the_library_coefficients(theta1, theta4):  # D, f, g, a, b, c not evaluated: the library's
        k = ROBOT.forward_coefficients(theta1, theta4)
        y3 = (-k["b"] - np.sqrt(k["b"] ** 2 - 4 * k["a"] * k["c"])) / (2 * k["a"])
        return k["g"] * y3 + k["f"], y3

    rejects(forward_task(from_the_library_coefficients), "FiveBar.forward_coefficients")


@pytest.mark.parametrize(("answer", "says"), [
    (lambda t1, t4: course_forward(t1, t4, +1), "arms up"),
    (lambda t1, t4: by_circles(t1, t4, lower=False), "arms up"),
    (lambda t1, t4: course_forward(THETA1, THETA4), "same point at every crank angle"),
    (lambda t1, t4: course_forward(np.degrees(t1), np.degrees(t4)), "degrees"),
    (lambda t1, t4: course_forward(np.radians(t1), np.radians(t4)), "np.radians"),
    (lambda t1, t4: course_forward(t1, t4, slip=True), "+b"),
    (lambda t1, t4: tuple(1000 * v for v in course_forward(t1, t4)), "millimetres"),
    (lambda t1, t4: course_forward(t1, t4)[::-1], "swapped"),
    (lambda t1, t4: course_forward(t1, t4)[1], "a single number"),
    (lambda t1, t4: None, "None"), (lambda t1, t4: ("x", "y"), "string"),
    (lambda t1, t4: (np.nan, 0.0), "NaN"),
    (lambda t1: (0.0, 0.0), "TypeError"),
])
def test_a_wrong_forward_procedure_is_told_what_is_wrong_without_a_traceback(answer, says):
    rejects(forward_task(answer), says, hidden=course_forward(THETA1, THETA4))


def test_the_watch_is_left_as_it_was():
    """The check's watch on the student's calls is removed after each call, even when the function raises."""
    import sys

    before = sys.getprofile()
    forward_task(lambda t1, t4: 1 / 0)
    theta4_task(norton)
    assert sys.getprofile() is before


def test_a_function_that_never_returns_is_answered_not_waited_for(monkeypatch):
    import time

    from course_lib.checks import engine
    from course_lib.fourbar import FourBar

    monkeypatch.setattr(engine, "PROCEDURE_SECONDS", 0.3)

    def forever(theta2):
        while True:
            pass

    start = time.perf_counter()
    feedback = engine.procedure(forever, [(1.0,), (2.0,)], engine.solver_code(FourBar), "function",
                                engine.number("θ4"))
    assert time.perf_counter() - start < 3.0
    assert not feedback.ok and "did not return within 0.3 s" in feedback.message
    assert engine.procedure(lambda theta2: 2 * theta2, [(1.0,)], engine.solver_code(FourBar), "function",
                            engine.number("θ4")) == [2.0]
