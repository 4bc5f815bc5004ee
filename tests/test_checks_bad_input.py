"""Every checker answers any input with feedback: silly answers (strings, bools, dicts, sets, ragged
or nested lists, None inside a tuple, complex numbers, NaN, inf, huge ints, arrays of the wrong shape
or dtype, sympy objects, functions, …) give a ✘ with a message and never a traceback, and the
message shows none of the reference values."""

from __future__ import annotations

import fractions
import itertools
import re
import subprocess
import sys

import numpy as np
import pytest
import sympy as sp
from feedback import hides

from course_lib import checks
from course_lib.checks.engine import Feedback, reads
from course_lib.fivebar import FiveBar
from course_lib.fourbar import FourBar
from course_lib.profile import first_turn_time
from course_lib.saw import Saw, analytic

BENCH = FourBar(crank=0.07, coupler=0.20, rocker=0.15, ground=0.25)
TRIPLE = FourBar(crank=0.14, coupler=0.12, rocker=0.10, ground=0.20)
LESSON_BAR = FourBar(crank=0.10, coupler=0.25, rocker=0.20, ground=0.30)
MY_SAW = Saw(r1y=0.03, r2=0.06, r3=0.15)
ROBOT = FiveBar(l1=0.11, l2=0.15, l3=0.16, l4=0.12, l5=0.09)
X3, Y3 = ROBOT.forward(1.2, 2.2, 1)


def _blade_peak():
    x = analytic(np.linspace(0.0, 2 * np.pi, 20001), 6.472, 0.0, saw=MY_SAW)
    return np.abs(x[:, 3] * np.cos(x[:, 1]) - x[:, 0] * x[:, 4] * np.sin(x[:, 1])).max()


def _rates(theta2, omega2, alpha2):
    solution = BENCH.solve(theta2, omega2, alpha2)
    return [solution.omega4, solution.alpha4, solution.omega3, solution.alpha3]


#: checker name → (the call with the task's parameters, the reference values it must never show)
CHECKERS = {
    "mobility": (checks.check_mobility, [6, 7, 0, 1]),
    "tilted_loop": (checks.check_tilted_loop, []),
    "link_vector": (lambda a: checks.check_link_vector(a, 0.06, 30.0), [0.06 * np.sqrt(3) / 2, 0.03]),
    "point_velocity": (
        lambda a: checks.check_point_velocity(a, 0.080, 135.0, 12.0, clockwise=True),
        -12.0 * 0.080 * np.array([-np.sin(np.radians(135.0)), np.cos(np.radians(135.0))]),
    ),
    "redundant_parallelogram": (checks.check_redundant_parallelogram, []),
    "newton_update": (checks.check_newton_update, []),
    "newton_iterations": (checks.check_newton_iterations, [2.0945514815423265]),
    "newton_cycle": (checks.check_newton_cycle, []),
    "fourbar_newton_step": (
        lambda a: checks.check_fourbar_newton_step(a, BENCH, np.radians(40.0), (0.5, 1.5)),
        np.linalg.solve(BENCH.loop_jacobian(0.5, 1.5), -BENCH.loop_residual(np.radians(40.0), 0.5, 1.5)),
    ),
    "seed_branch": (lambda a: checks.check_seed_branch(a, BENCH, np.radians(40.0), (2.5, 0.3)), []),
    "fourbar_theta4": (
        lambda a: checks.check_fourbar_theta4(a, BENCH, np.radians(120.0), "crossed"),
        [BENCH.solve(np.radians(120.0), branch="crossed").theta4],
    ),
    "omega4_expression": (checks.check_omega4_expression, []),
    "fourbar_rates": (
        lambda a: checks.check_fourbar_rates(a, BENCH, np.radians(200.0), 15.0, -40.0, "open"),
        _rates(np.radians(200.0), 15.0, -40.0),
    ),
    "toggle_angle": (lambda a: checks.check_toggle_angle(a, TRIPLE), TRIPLE.input_range().toggle_angles),
    "saw_omega3_expression": (checks.check_saw_omega3_expression, []),
    "saw_position": (
        lambda a: checks.check_saw_position(a, MY_SAW, np.radians(50.0)),
        analytic(np.radians(50.0), saw=MY_SAW)[:3],
    ),
    "saw_slider_acceleration": (
        lambda a: checks.check_saw_slider_acceleration(a, MY_SAW, np.radians(50.0), 6.0, 4.0),
        [analytic(np.radians(50.0), 6.0, 4.0, saw=MY_SAW)[6]],
    ),
    "saw_linear_stage": (checks.check_saw_linear_stage, []),
    "fivebar_forward": (
        lambda a: checks.check_fivebar_forward(a, ROBOT, np.radians(70.0), np.radians(125.0), mode=-1),
        list(ROBOT.forward(np.radians(70.0), np.radians(125.0), -1)),
    ),
    "fivebar_inverse": (
        lambda a: checks.check_fivebar_inverse(a, ROBOT, 0.02, 0.21, modes=(-1, +1)),
        list(ROBOT.inverse(0.02, 0.21, modes=(-1, 1))),
    ),
    "fivebar_g": (checks.check_fivebar_g, []),
    "fivebar_singularity": (lambda a: checks.check_fivebar_singularity(a, ROBOT, 1.2, 2.2, X3, Y3), []),
    "crank_angle_for_rocker": (
        lambda a: checks.check_crank_angle_for_rocker(a, LESSON_BAR, LESSON_BAR.solve(1.0).theta4),
        [1.0],
    ),
    "rocker_pin_speed": (
        lambda a: checks.check_rocker_pin_speed(a, BENCH, np.radians(120.0), 10.0),
        [abs(BENCH.solve(np.radians(120.0), 10.0).omega4) * BENCH.l4],
    ),
    "motor_start": (
        lambda a: checks.check_motor_start(a, 8.0),
        [first_turn_time(8.0), 2 * 8.0 * first_turn_time(8.0) / 3 * 60 / (2 * np.pi)],
    ),
    "saw_rates": (
        lambda a: checks.check_saw_rates(a, MY_SAW, np.pi / 2, 6.472),
        analytic(np.pi / 2, 6.472, 0.0, saw=MY_SAW)[3:6],
    ),
    "blade_peak_speed": (lambda a: checks.check_blade_peak_speed(a, MY_SAW, 6.472), [_blade_peak()]),
    "fivebar_theta4": (
        lambda a: checks.check_fivebar_theta4(a, ROBOT, -0.03, 0.2, -1),
        [ROBOT.inverse(-0.03, 0.2, modes=(1, -1)).theta4],
    ),
    "reach_height": (
        lambda a: checks.check_reach_height(a, ROBOT, -0.03),
        [np.sqrt((ROBOT.l1 + ROBOT.l2) ** 2 - (-0.03 - ROBOT.l5 / 2) ** 2)],
    ),
}

x, y, t = sp.symbols("x y t")
theta = sp.Function("theta2")(t)


class ArrayRefuses:
    """An object that breaks numpy's conversion."""

    def __array__(self, *args, **kwargs):
        raise RuntimeError("no array")


class FloatRefuses:
    def __float__(self):
        raise ZeroDivisionError("no float")


def _nested(depth):
    value = [0.777]
    for _ in range(depth):
        value = [value]
    return value


#: silly answers a student can produce, each with a label for the test id
SILLY = {
    "None": None,
    "Ellipsis": ...,
    "all None": (None, None),
    "None inside": (2.09, None),
    "None first": [None, 4],
    "empty string": "",
    "word": "abc",
    "numeric string": "1.2",
    "string pair": "0, 0.06",
    "bytes": b"1.5",
    "True": True,
    "False": False,
    "numpy bool": np.True_,
    "empty dict": {},
    "dict": {"a": 1.0, "b": 2.0},
    "set": {1.0, 2.0},
    "frozenset": frozenset({3}),
    "empty list": [],
    "empty tuple": (),
    "list of empty": [[]],
    "ragged": [[1.0], [2.0, 3.0]],
    "deeply nested": _nested(40),
    "nested strings": [["a", "b"]],
    "bool list": [True, False],
    "number and bool": [1.0, True],
    "number and string": [1.0, "2"],
    "dict inside": [{"a": 1}, 2.0],
    "complex": 1j,
    "complex zero imaginary": complex(0.5, 0.0),
    "numpy complex": np.complex128(1 + 2j),
    "complex in list": [1j, 2.0],
    "huge int": 10**400,
    "huge negative int": -(10**400),
    "huge int in tuple": (6, 7, 0, 10**400),
    "nan": float("nan"),
    "inf": float("inf"),
    "-inf": float("-inf"),
    "nan pair": [float("nan"), 1.0],
    "inf in four": (6, 7, 0, float("inf")),
    "too many": [1.0, 2.0, 3.0, 4.0, 5.0],
    "matrix of zeros": np.zeros((3, 3)),
    "empty array": np.array([]),
    "empty 2-d array": np.empty((0, 2)),
    "string array": np.array(["a", "b"]),
    "bool array": np.array([True, False]),
    "complex array": np.array([1 + 1j, 2.0]),
    "object array with None": np.array([1.0, None], dtype=object),
    "datetime": np.datetime64("2020-01-01"),
    "symbol": x,
    "expression": x**2 + 1,
    "sympy number Matrix": sp.Matrix([1.5, 2.5, 3.5]),
    "sympy symbol Matrix": sp.Matrix([[x, y], [y, x]]),
    "sympy I": sp.I,
    "sympy zoo": sp.zoo,
    "sympy nan": sp.nan,
    "sympy oo": sp.oo,
    "sympy Eq": sp.Eq(x, 1),
    "sympy true": sp.true,
    "sympy relation": x < 1,
    "sympy FiniteSet": sp.FiniteSet(1, 2),
    "sympy Tuple": sp.Tuple(1, x),
    "sympy function class": sp.sin,
    "sympy Lambda": sp.Lambda(x, x**2),
    "undefined function": sp.Function("f")(x),
    "derivative": sp.Derivative(theta, t),
    "integral": sp.Integral(x, x),
    "function": lambda value: value,
    "builtin": print,
    "ufunc": np.sin,
    "class": float,
    "object": object(),
    "range": range(3),
    "iterator": iter([1.0, 2.0]),
    "generator": (value for value in [1.0]),
    "array refuses": ArrayRefuses(),
    "float refuses": FloatRefuses(),
    "fraction": fractions.Fraction(1, 3),
    "negative": -1,
    "zero": 0,
    "tiny": 1e-308,
    "large": 1e308,
    "large pair": [1e308, -1e308],
    "float": 3.0,
}

CASES = list(itertools.product(CHECKERS, SILLY))


@pytest.mark.parametrize(("checker", "answer"), CASES, ids=[f"{c}-{a}" for c, a in CASES])
def test_a_silly_answer_gets_feedback_never_a_traceback(checker, answer):
    check, references = CHECKERS[checker]
    feedback = check(SILLY[answer])
    assert isinstance(feedback, Feedback)
    assert not feedback.ok and feedback.message.strip(), feedback
    assert "could not be checked" not in feedback.message, feedback  # read and judged, not caught
    assert hides(feedback, *references), feedback


def test_the_table_is_large():
    assert len(CASES) >= 300


# ---------------------------------------------------------------- sympy's LUsolve and solve results


def _four_bar_rates():
    l2, l3, l4, w2, w3, w4 = sp.symbols("l2 l3 l4 omega2 omega3 omega4")
    t2, t3, t4 = sp.symbols("theta2 theta3 theta4")
    velocity = [
        -w2 * l2 * sp.sin(t2) - w3 * l3 * sp.sin(t3) + w4 * l4 * sp.sin(t4),
        w2 * l2 * sp.cos(t2) + w3 * l3 * sp.cos(t3) - w4 * l4 * sp.cos(t4),
    ]
    matrix, rhs = sp.linear_eq_to_matrix(velocity, [w3, w4])
    return matrix.LUsolve(rhs), sp.solve(velocity, [w3, w4], dict=True), w4


def test_an_unpacked_lusolve_matrix_says_which_element_to_pass():
    matrix, _, _ = _four_bar_rates()
    feedback = checks.check_omega4_expression(matrix)
    assert not feedback.ok and "2×1 Matrix" in feedback.message and "[1]" in feedback.message, feedback
    assert checks.check_omega4_expression(matrix[1]).ok
    assert checks.check_omega4_expression(sp.Matrix([matrix[1]])).ok  # 1×1: the one expression


def test_a_solve_result_says_which_entry_to_pass():
    _, solutions, w4 = _four_bar_rates()
    feedback = checks.check_omega4_expression(solutions)  # [{ω3: …, ω4: …}]
    assert not feedback.ok and "omega4" in feedback.message, feedback
    assert checks.check_omega4_expression(solutions[0][w4]).ok


@pytest.mark.parametrize(
    "checker",
    [checks.check_newton_update, checks.check_saw_omega3_expression, checks.check_fivebar_g],
)
def test_a_matrix_of_expressions_is_explained(checker):
    a, b = sp.symbols("theta1 theta2")
    feedback = checker(sp.Matrix([a, b]))
    assert not feedback.ok and "Matrix" in feedback.message and "one expression" in feedback.message


def test_an_equation_is_read_as_its_right_hand_side():
    l2, l4, t2, t3, t4, w2, w4 = sp.symbols("l2 l4 theta2 theta3 theta4 omega2 omega4")
    omega4 = w2 * l2 * sp.sin(t2 - t3) / (l4 * sp.sin(t4 - t3))
    assert checks.check_omega4_expression(sp.Eq(w4, omega4)).ok


def test_a_number_where_a_formula_is_expected():
    feedback = checks.check_omega4_expression(2.5)
    assert not feedback.ok and "no symbol" in feedback.message


# ---------------------------------------------------------------- hints about the method


def test_crank_angle_hint_names_the_method_not_the_gap():
    theta4 = LESSON_BAR.solve(1.0).theta4
    feedback = checks.check_crank_angle_for_rocker(1.05, LESSON_BAR, theta4)
    assert not feedback.ok and "solve |B − A(θ2)| − l3 = 0" in feedback.message
    assert not re.search(r"\d\.\d|\de-?\d", feedback.message), feedback  # no number, only the method


def test_checkers_keep_the_documented_messages_for_known_mistakes():
    assert "whole number" in checks.check_newton_iterations((2.0945514815423265, 4.5)).message
    assert "None" in checks.check_newton_iterations((2.09, None)).message
    assert "whole number" in checks.check_mobility((6, 7, 0, float("inf"))).message
    assert "bool" in checks.check_fourbar_theta4(True, BENCH, 1.0, "open").message
    assert "string" in checks.check_fourbar_theta4("1.2", BENCH, 1.0, "open").message
    assert "complex" in checks.check_link_vector(0.06j, 0.06, 90.0).message
    assert "call it" in checks.check_reach_height(lambda: 0.24, ROBOT, -0.03).message


# ---------------------------------------------------------------- the engine


def test_a_failure_while_judging_is_feedback_and_a_wrong_call_still_raises():
    @reads()
    def check_fails(answer, parameter):
        raise KeyError(parameter)

    feedback = check_fails(1.0, "p")
    assert not feedback.ok and "could not be checked (KeyError)" in feedback.message
    with pytest.raises(TypeError):
        check_fails(1.0)  # the instructor's mistake: a missing argument


def test_numeric_checks_do_not_import_sympy():
    """The checks package imports sympy only inside the checkers of sympy answers (a library routine a
    checker calls may still need it, e.g. FourBar's rates from the mechanism core)."""
    script = (
        "import sys\n"
        "from course_lib import checks\n"
        "assert 'sympy' not in sys.modules, 'import course_lib.checks imports sympy'\n"
        "checks.check_mobility((6, 7, 0, 1)); checks.check_newton_iterations((2.09, 4))\n"
        "checks.check_link_vector((0.0, 0.06), 0.06, 90.0); checks.check_motor_start((1.9, 61.0), 5.0)\n"
        "checks.check_point_velocity([0.1, 0.2], 0.1, 90.0, 6.0, clockwise=False)\n"
        "checks.check_newton_cycle('b')\n"
        "for answer in ('x', None, [1, 2], {1}, 1j, 10**400, float('nan'), lambda: 1):\n"
        "    checks.check_mobility(answer); checks.check_motor_start(answer, 5.0)\n"
        "assert 'sympy' not in sys.modules, 'a numeric check imported sympy'\n"
    )
    subprocess.run([sys.executable, "-c", script], check=True)
