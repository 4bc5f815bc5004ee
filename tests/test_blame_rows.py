"""Blame by the physics, and messages true of what the student gave (ex01–ex05 and the lessons' five-bar).

Each row is one answer a student gives and the cause the checker must name: a sign slip or a wrong
coordinate of the five-bar's end effector on the coordinate that is wrong (the notes' X3 slip included), θ1 of
leg 1 given for θ4 whichever σ1, a vector loop given as one complex number, expressions held in numpy arrays,
sympy Arrays or nested lists, a Matrix of equations, a whole solve where numbers are asked, the entries of a
pair in the other order.  References come from independent routes: circles for the five-bar, the course's
formulas typed out, sympy's own complex numbers.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest
import sympy as sp
from feedback import hides
from geometry import circle_intersections, course_inverse_angles

from course_lib import checks
from course_lib.fivebar import FiveBar
from course_lib.fourbar import FourBar
from course_lib.newton import newton

ROBOT = FiveBar(l1=0.11, l2=0.15, l3=0.16, l4=0.12, l5=0.09)
BENCH = FourBar(crank=0.07, coupler=0.20, rocker=0.15, ground=0.25)
THETA1, THETA4 = np.radians(70.0), np.radians(125.0)


def rejects(feedback, *words, hidden=()):
    assert not feedback.ok, feedback
    assert all(word in feedback.message for word in words), feedback
    assert hides(feedback, *hidden), feedback


# ---------------------------------------------------------------- the five-bar's end effector (ex05 Task 1)


def arms_down():
    """(X3, Y3) arms down from the two circles about the elbows; and the course's slipped X3: the line of
    the notes that takes X3 = g·(b − √(b² − 4ac))/2a + f (the sign of b flipped), coefficients typed out."""
    l1, l2, l3, l4, l5 = 0.11, 0.15, 0.16, 0.12, 0.09
    P2 = np.array([l1 * np.cos(THETA1) + l5 / 2, l1 * np.sin(THETA1)])
    P4 = np.array([l4 * np.cos(THETA4) - l5 / 2, l4 * np.sin(THETA4)])
    down = min(circle_intersections(P2, l2, P4, l3), key=lambda p: p[1])
    D = l5 + l1 * np.cos(THETA1) - l4 * np.cos(THETA4)
    f = (l1**2 - l2**2 + l3**2 - l4**2 + l1 * l5 * np.cos(THETA1) + l4 * l5 * np.cos(THETA4)) / (2 * D)
    g = (-2 * l1 * np.sin(THETA1) + 2 * l4 * np.sin(THETA4)) / (2 * D)
    a, b = 1 + g**2, 2 * f * g + g * l5 - 2 * g * l4 * np.cos(THETA4) - 2 * l4 * np.sin(THETA4)
    c = f**2 - l3**2 + l4**2 + f * l5 + l5**2 / 4 - l4 * (2 * f + l5) * np.cos(THETA4)
    assert abs((-b - np.sqrt(b * b - 4 * a * c)) / (2 * a) - down[1]) < 1e-12  # the course's Y3, arms down
    return down, g * (b - np.sqrt(b * b - 4 * a * c)) / (2 * a) + f


@pytest.mark.parametrize(("answer", "says", "not_says"), [
    (lambda d, slip: (-d[0], d[1]), ("y3 is right", "x3 has the wrong sign", "f and g"), "Y3 = (−b"),
    (lambda d, slip: (slip, d[1]), ("y3 is right", "x3 is not", "lesson 08"), "wrong sign"),
    (lambda d, slip: (d[0] + 0.004, d[1]), ("y3 is right", "x3 is off", "X3 = g·Y3 + f"), "Y3 = (−b"),
    (lambda d, slip: (d[0], -d[1]), ("x3 is right", "y3 has the wrong sign"), "x3 has"),
    (lambda d, slip: (d[0], d[1] + 0.004), ("x3 is right", "y3 is off"), "x3 is off"),
])
def test_a_five_bar_slip_is_named_on_the_coordinate_that_is_wrong(answer, says, not_says):
    down, slip = arms_down()
    assert abs(slip - down[0]) > 1e-4  # the slip moves X3 here
    feedback = checks.check_fivebar_forward(answer(down, slip), ROBOT, THETA1, THETA4, -1)
    rejects(feedback, *says, hidden=down)
    assert not_says not in feedback.message, feedback


# ---------------------------------------------------------------- lesson 09: θ1 given for θ4, either σ1


@pytest.mark.parametrize("sigma1", [1, -1])
@pytest.mark.parametrize("sigma2", [1, -1])
def test_theta1_given_for_theta4_is_named_for_either_sigma1(sigma1, sigma2):
    lengths, x3, y3 = (0.10, 0.15, 0.15, 0.10, 0.08), -0.06, 0.13
    robot = FiveBar(*lengths)
    theta1, theta4 = course_inverse_angles(x3, y3, lengths, sigma1, sigma2)
    assert checks.check_fivebar_theta4(theta4, robot, x3, y3, sigma2).ok
    rejects(checks.check_fivebar_theta4(theta1, robot, x3, y3, sigma2), "θ1 of leg 1", hidden=[theta4])


# ---------------------------------------------------------------- ex01 Task 2: the forms of a loop

l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
t1, t2, t3, t4 = sp.symbols("theta1:5", real=True)
Z = l2 * sp.exp(sp.I * t2) + l3 * sp.exp(sp.I * t3) - l4 * sp.exp(sp.I * t4) - l1 * sp.exp(sp.I * t1)
X = l2 * sp.cos(t2) + l3 * sp.cos(t3) - l4 * sp.cos(t4) - l1 * sp.cos(t1)
Y = l2 * sp.sin(t2) + l3 * sp.sin(t3) - l4 * sp.sin(t4) - l1 * sp.sin(t1)


@pytest.mark.parametrize("answer", [Z, [Z], sp.Matrix([Z]), (Z,)], ids=["z", "[z]", "Matrix", "tuple"])
def test_a_loop_as_one_complex_number_is_refused_saying_which_form_is_asked(answer):
    rejects(checks.check_tilted_loop(answer), "one complex number", "2 real components", "sp.re(z)")


def test_complex_components_are_refused_and_their_real_and_imaginary_parts_pass():
    rejects(checks.check_tilted_loop([Z, sp.conjugate(Z)]), "imaginary unit")
    assert checks.check_tilted_loop([sp.re(Z), sp.im(Z)]).ok  # real symbols: sympy's own re and im
    assert checks.check_tilted_loop([sp.expand_complex(sp.re(Z)), sp.expand_complex(sp.im(Z))]).ok
    assert checks.check_tilted_loop([(Z + sp.conjugate(Z)) / 2, (Z - sp.conjugate(Z)) / (2 * sp.I)]).ok


@pytest.mark.parametrize("answer", [
    [np.array([X]), np.array([Y])], [[X], [Y]], sp.Array([X, Y]), sp.Array([[X], [Y]]), np.array([[X], [Y]]),
    [sp.Matrix([X]), sp.Matrix([Y])], sp.Eq(sp.Matrix([X + l1 * sp.cos(t1), Y + l1 * sp.sin(t1)]),
                                              sp.Matrix([l1 * sp.cos(t1), l1 * sp.sin(t1)])),
    [sp.Eq(X, 0), sp.Eq(Y, 0)], {"x": X, "y": Y},
], ids=["arrays of one", "lists of one", "sympy Array", "sympy Array 2×1", "numpy 2×1", "1×1 Matrices",
        "Matrix equation", "Eq rows", "dict"])
def test_every_container_of_the_two_components_is_read(answer):
    assert checks.check_tilted_loop(answer).ok
    assert checks.same_equations(answer, [X, Y])
    assert len(checks.as_expressions(answer)) == 2


def test_a_matrix_of_equations_is_refused_naming_what_sympy_warns_about():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # sympy's own deprecation warning, shown in the student's cell
        rows = sp.Matrix([sp.Eq(X, 0), sp.Eq(Y, 0)])
    rejects(checks.check_tilted_loop(rows), "Matrix of equations", "list")


@pytest.mark.parametrize(("answer", "says"), [
    ([X, Y, 0], "got a list of 3"), (sp.Eq(X, 0), "got one equation"), (X, "got one expression"),
    ("X", "a string"), ([], "got a list of 0"),
])
def test_the_wrong_count_of_components_names_what_was_given(answer, says):
    rejects(checks.check_tilted_loop(answer), "give the two components", says)


W2 = sp.Symbol("omega2")
OMEGA4 = W2 * l2 * sp.sin(t2 - t3) / (l4 * sp.sin(t4 - t3))


@pytest.mark.parametrize(("answer", "says"), [
    (np.array([OMEGA4, 2 * OMEGA4]), "a numpy array of 2"),
    (sp.Array([OMEGA4, OMEGA4]), "a sympy Array of 2"),
    ([OMEGA4, 0], "a list of 2"), (sp.Matrix([[OMEGA4, 0]]), "a 1×2 Matrix"),
])
def test_one_formula_held_with_others_is_named_by_its_container(answer, says):
    feedback = checks.check_omega4_expression(answer)
    rejects(feedback, says, "element [0]")
    assert "with symbols" not in feedback.message  # not "a sympy expression with symbols"


@pytest.mark.parametrize("answer", [np.array([OMEGA4]), sp.Array([OMEGA4]), [np.array([OMEGA4])],
                                    sp.Matrix([OMEGA4]), [[OMEGA4]]])
def test_one_formula_in_a_one_entry_container_passes(answer):
    assert checks.check_omega4_expression(answer).ok


# ---------------------------------------------------------------- whole solves and pairs in the other order


def test_a_whole_solve_where_numbers_are_asked_is_named_as_what_it_is():
    theta2 = np.radians(120.0)
    rejects(checks.check_fourbar_theta4(BENCH.solve(theta2, branch="crossed"), BENCH, theta2, "crossed"),
            "FourBarSolution", "a solve's whole result", "theta4")
    rejects(checks.check_fourbar_rates(BENCH.solve(theta2, 15.0, -40.0), BENCH, theta2, 15.0, -40.0, "open"),
            "FourBarSolution", "values the task asks for")
    # where a solve's answer is asked, the solve passes
    assert checks.check_fivebar_forward(ROBOT.forward(THETA1, THETA4, mode=-1), ROBOT, THETA1, THETA4, -1).ok
    cranks = ROBOT.inverse(0.02, 0.21, modes=(-1, 1))
    assert checks.check_fivebar_inverse(cranks, ROBOT, 0.02, 0.21, (-1, 1)).ok


def test_newtons_run_passes_for_root_and_count_and_a_tighter_run_is_named():
    course = newton(lambda v: v**3 - 2 * v - 5, 2.0, jac=lambda v: 3 * v**2 - 2)
    assert checks.check_newton_iterations(course).ok
    tight = newton(lambda v: v**3 - 2 * v - 5, 2.0, jac=lambda v: 3 * v**2 - 2, tol=1e-12)
    rejects(checks.check_newton_iterations(tight), "stopped after", "tol=1e-6")
    swapped = (course.iterations, course.x)
    rejects(checks.check_newton_iterations(swapped), "other order", "(root, iterations)")


def test_a_toggle_answer_in_the_other_order_is_named():
    triple = FourBar(crank=0.14, coupler=0.12, rocker=0.10, ground=0.20)
    limit = float(np.arccos((0.20**2 + 0.14**2 - 0.22**2) / (2 * 0.20 * 0.14)))  # |AO4| = l3 + l4
    assert checks.check_toggle_angle((limit, "extended"), triple).ok
    rejects(checks.check_toggle_angle(("extended", round(limit, 4)), triple), "other order", hidden=[limit])


# ---------------------------------------------------------------- lessons 02 and 06: the Try its' readings


def test_a_rate_from_a_crank_angle_rounded_as_asked_passes_where_the_reference_entry_is_zero():
    """Lesson 06's rates at θ2 = π/2 typed as 1.5708: ω3 = −ω2 r2 cos θ2 / (r3 cos θ3) is about −1e-5 where
    the reference is 0; the zero entry is judged on the vector's size (4 significant figures of it)."""
    from course_lib.saw import Saw

    saw, omega2 = Saw(), 6.472

    def rates(theta2):
        """(v_r, ω1, ω3) from the slider's x = r2 cos θ2 + r3 cos θ3: r1 = −√(x² + r1y²), θ1 = atan(r1y/x)."""
        theta3 = np.pi - np.arcsin((saw.r1y - saw.r2 * np.sin(theta2)) / saw.r3)
        omega3 = -omega2 * saw.r2 * np.cos(theta2) / (saw.r3 * np.cos(theta3))
        x = saw.r2 * np.cos(theta2) + saw.r3 * np.cos(theta3)
        vx = -omega2 * saw.r2 * np.sin(theta2) - omega3 * saw.r3 * np.sin(theta3)
        r1 = -np.hypot(x, saw.r1y)
        return np.array([x * vx / r1, -saw.r1y * vx / (x * x + saw.r1y**2), omega3])

    typed = rates(1.5708)
    assert abs(typed[2]) > 1e-6 and np.allclose(typed[:2], rates(np.pi / 2)[:2], rtol=1e-4)
    assert checks.check_saw_rates(typed, saw, np.pi / 2, omega2).ok
    off = typed + [0.0, 0.0, 1e-3]  # ω3 really off: not a unit slip
    feedback = checks.check_saw_rates(off, saw, np.pi / 2, omega2)
    assert not feedback.ok and "milli" not in feedback.message, feedback


def test_the_other_crank_angle_in_degrees_is_named_as_both():
    bar = FourBar(crank=0.10, coupler=0.25, rocker=0.20, ground=0.30)
    theta4 = np.radians(105.0)  # one crank angle in (0, π) and one below 0 put the rocker there
    B = np.array([0.30 + 0.20 * np.cos(theta4), 0.20 * np.sin(theta4)])
    roots = [np.arctan2(A[1], A[0]) for A in circle_intersections([0.0, 0.0], 0.10, B, 0.25)]
    outside = next(root for root in roots if not 0 < root < np.pi)
    feedback = checks.check_crank_angle_for_rocker(np.degrees(outside), bar, theta4)
    rejects(feedback, "degrees", "outside (0, π)", hidden=[outside])


@pytest.mark.parametrize(("omega2", "alpha2", "cause"), [
    (6.0, 0.0, "α2 = 0"),          # the motor's angular acceleration left out
    (4.0, 6.0, "swapped"),        # ω2 and α2 given in each other's place
])
def test_the_saw_acceleration_names_the_motor_input_that_is_wrong(omega2, alpha2, cause):
    # the task's state θ2 = 0.9 rad, ω2 = 6 rad/s, α2 = 4 rad/s²; the answer a_r solved at another state, by
    # the course's closed form, rounded to the task's 4 significant figures
    from course_lib.saw import Saw, analytic

    a_r = float(f"{analytic(0.9, omega2, alpha2, saw=Saw())[6]:.4g}")
    feedback = checks.check_saw_slider_acceleration(a_r, Saw(), 0.9, 6.0, 4.0)
    assert not feedback.ok and cause in feedback.message
