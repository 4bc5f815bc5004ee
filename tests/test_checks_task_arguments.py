"""A bad task is the instructor's mistake, never the student's: every checker of course_lib.checks checks its
task arguments (the linkage, the crank angles, the branch or mode an exercise notebook passes it) before it
reads the answer, and refuses a bad one with ``InvalidArgumentError`` naming the argument — whatever the
answer, even none.  A good task still gives ✔ for the right answer and ✘ for a wrong one, and feedback,
never an exception, for any answer at all.

The checkers are found by ``inspect`` in the modules ``course_lib/checks/__init__.py`` imports, and the
table below must hold every one of them.  Right answers come from independent routes (circles, the
Cartesian slider-crank, finite differences, sympy, a sweep), the helpers of the other checker tests.
"""

from __future__ import annotations

import ast
import functools
import importlib
import inspect
import math
import pathlib
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import pytest
import scipy.integrate
import scipy.optimize
import sympy as sp
from feedback import course_newton_count
from geometry import circle_intersections, course_inverse_angles
from test_checks import BENCH, MY_SAW, ROBOT, _fivebar_points, _rates_by_sympy, _saw_by_slider_crank
from test_checks import fourbar_by_circles as circles
from test_checks_ex06 import (
    DECLARED,
    GUESS,
    LEVER_LOOP,
    R2,
    RAM_LOOP,
    D,
    by_hand,
    ram_by_differences,
    sweep_ratio,
)

from course_lib import checks
from course_lib.checks import ShaperDrawing
from course_lib.checks.engine import task_argument
from course_lib.errors import InvalidArgumentError
from course_lib.fivebar import FiveBar
from course_lib.fourbar import FourBar
from course_lib.saw import Saw
from course_lib.slider_crank import OffsetSliderCrank

NAN, INF = float("nan"), float("inf")
TRIPLE = FourBar(crank=0.14, coupler=0.12, rocker=0.10, ground=0.20)  # non-Grashof: toggles at ±1.3336 rad
SHORT_ROD = Saw(r1y=0.03, r2=0.06, r3=0.08)  # the rod cannot reach the slider line near θ2 = −π/2
HIGH_RAM = ShaperDrawing(ram_height=0.44)  # BC cannot reach the ram's line near θ2 = 0


# ---------------------------------------------------------------- the checkers, found by inspect


def checker_modules():
    """The modules ``course_lib/checks/__init__.py`` imports (``from . import ex01, …``)."""
    source = pathlib.Path(inspect.getfile(checks)).read_text()
    names = [alias.name for node in ast.walk(ast.parse(source))
             if isinstance(node, ast.ImportFrom) and node.level == 1 and node.module is None
             for alias in node.names]
    assert names, "course_lib/checks/__init__.py imports no checker modules"
    return [importlib.import_module(f"course_lib.checks.{name}") for name in names]


def public_checkers() -> dict[str, Any]:
    found = {}
    for module in checker_modules():
        for name, function in inspect.getmembers(module, inspect.isfunction):
            if name.startswith("check_") and function.__module__ == module.__name__:
                found[name] = function
    return found


CHECKERS = public_checkers()


def task_parameters(name: str) -> list[str]:
    """The checker's task arguments: every parameter after the answer."""
    return list(inspect.signature(CHECKERS[name]).parameters)[1:]


# ---------------------------------------------------------------- right answers by independent routes


@functools.cache
def point_velocity():
    length, theta, speed, h = 0.080, np.radians(135.0), 12.0, 1e-7

    def tip(t):  # clockwise: the angle decreases in time
        return length * np.array([np.cos(theta - speed * t), np.sin(theta - speed * t)])

    return (tip(h) - tip(-h)) / (2 * h)


def tilted_loop(t1_zero=False):
    l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
    t1, t2, t3, t4 = sp.symbols("theta1:5", real=True)
    t1 = 0 if t1_zero else t1
    z = l2 * sp.exp(sp.I * t2) + l3 * sp.exp(sp.I * t3) - l4 * sp.exp(sp.I * t4) - l1 * sp.exp(sp.I * t1)
    return [sp.expand_complex(part) for part in (sp.re(z), sp.im(z))]


@functools.cache
def newton_count():
    root, _, count = course_newton_count()
    return root, count


def bench_loop(theta2, q):
    l1, l2, l3, l4 = 0.25, 0.07, 0.20, 0.15
    return np.array([l2 * np.cos(theta2) + l3 * np.cos(q[0]) - l4 * np.cos(q[1]) - l1,
                     l2 * np.sin(theta2) + l3 * np.sin(q[0]) - l4 * np.sin(q[1])])


@functools.cache
def newton_step():
    theta2, seed, h = np.radians(40.0), np.array([0.5, 1.5]), 1e-6
    J = np.column_stack([(bench_loop(theta2, seed + h * e) - bench_loop(theta2, seed - h * e)) / (2 * h)
                         for e in np.eye(2)])
    return np.linalg.solve(J, -bench_loop(theta2, seed))


@functools.cache
def seed_branch():
    """(reached, other) branch of plain Newton from (2.5, 0.3) at 40°, by the side of B from A → O4."""
    theta2, q = np.radians(40.0), np.array([2.5, 0.3])
    l1, l2, l3, l4 = 0.25, 0.07, 0.20, 0.15
    for _ in range(60):
        J = [[-l3 * np.sin(q[0]), l4 * np.sin(q[1])], [l3 * np.cos(q[0]), -l4 * np.cos(q[1])]]
        q = q + np.linalg.solve(J, -bench_loop(theta2, q))
    A = l2 * np.array([np.cos(theta2), np.sin(theta2)])
    B = A + l3 * np.array([np.cos(q[0]), np.sin(q[0])])
    side = (l1 - A[0]) * (B - A)[1] - (0.0 - A[1]) * (B - A)[0]
    return ("open", "crossed") if side > 0 else ("crossed", "open")


@functools.cache
def toggle_limit():
    return scipy.optimize.brentq(lambda t: np.hypot(0.20 - 0.14 * np.cos(t), 0.14 * np.sin(t)) - 0.22,
                                 0.1, 3.0, xtol=1e-15)


def omega4_formula(sign=1):
    l2, l4, t2, t3, t4, w2 = sp.symbols("l2 l4 theta2 theta3 theta4 omega2", real=True)
    return sign * w2 * l2 * sp.sin(t2 - t3) / (l4 * sp.sin(t4 - t3))  # Norton's form


def saw_omega3(sign=1):
    r1y, r2, r3, w2 = sp.symbols("r1y r2 r3 omega2", positive=True)
    t2, t3 = sp.symbols("theta2 theta3", real=True)
    height = r2 * sp.sin(t2) + r3 * sp.sin(t3) - r1y  # implicit differentiation of the rod's height
    return sign * -sp.diff(height, t2) / sp.diff(height, t3) * w2


@functools.cache
def fivebar_down():
    P2, P4 = _fivebar_points(np.radians(70.0), np.radians(125.0))
    first, second = circle_intersections(P2, 0.15, P4, 0.16)
    return min(first, second, key=lambda p: p[1]), max(first, second, key=lambda p: p[1])


@functools.cache
def fivebar_inverse():
    """(θ1, θ4) in working mode (−1, +1) at (0.02, 0.21), and (θ1, θ4) with the other σ2, from the course's
    half-angle coefficients typed out."""
    lengths = (0.11, 0.15, 0.16, 0.12, 0.09)
    return tuple(course_inverse_angles(0.02, 0.21, lengths, -1, sigma2) for sigma2 in (+1, -1))


def fivebar_g(sign=1):
    l1, l4, l5, t1, t4 = sp.symbols("l1 l4 l5 theta1 theta4", real=True)
    X3, Y3, l2, l3 = sp.symbols("X3 Y3 l2 l3", real=True)
    ecl2 = (X3 - l1 * sp.cos(t1) - l5 / 2) ** 2 + (Y3 - l1 * sp.sin(t1)) ** 2 - l2**2
    ecl3 = (X3 - l4 * sp.cos(t4) + l5 / 2) ** 2 + (Y3 - l4 * sp.sin(t4)) ** 2 - l3**2
    linear = sp.expand(ecl2 - ecl3)
    return sign * -linear.coeff(Y3) / linear.coeff(X3)


@functools.cache
def serial_pose():
    """θ1, θ4, x3, y3 of ROBOT with leg 1 stretched (a serial singularity), from circles."""
    theta1 = np.radians(100.0)
    P3 = np.array([0.045, 0.0]) + 0.26 * np.array([np.cos(theta1), np.sin(theta1)])
    P5 = np.array([-0.045, 0.0])
    P4 = circle_intersections(P5, 0.12, P3, 0.16)[1]
    return theta1, float(np.arctan2(*(P4 - P5)[::-1])), float(P3[0]), float(P3[1])


@functools.cache
def crank_roots():
    """(inside (0, π), outside) crank angles putting BENCH's rocker at 135°, from circles."""
    theta4 = np.radians(135.0)
    B = np.array([BENCH.l1 + BENCH.l4 * np.cos(theta4), BENCH.l4 * np.sin(theta4)])
    roots = [np.arctan2(A[1], A[0]) for A in circle_intersections([0.0, 0.0], BENCH.l2, B, BENCH.l3)]
    return next(r for r in roots if 0 < r < np.pi), next(r for r in roots if not 0 < r < np.pi)


@functools.cache
def rocker_pin_speed():
    theta2, omega2, h = np.radians(120.0), 10.0, 1e-6
    pins = [BENCH.l4 * np.array([np.cos(t4), np.sin(t4)])
            for t4 in (circles(BENCH, angle, "open")[1] for angle in (theta2 - h, theta2 + h))]
    return np.linalg.norm(pins[1] - pins[0]) / (2 * h) * omega2


@functools.cache
def motor_start():
    A = 8.0

    def alpha(t, T):  # rise, hold, fall over thirds of T
        return A * np.clip(np.minimum(3 * t / T, 3 - 3 * t / T), 0.0, 1.0) if t < T else 0.0

    def turn(T):
        return scipy.integrate.quad(lambda t: (T - t) * alpha(t, T), 0, T, points=[T / 3, 2 * T / 3])[0]

    T = scipy.optimize.brentq(lambda T: turn(T) - 2 * np.pi, 0.5, 5.0, xtol=1e-13)
    omega = scipy.integrate.quad(lambda t: alpha(t, T), 0, T, points=[T / 3, 2 * T / 3])[0]
    return T, omega * 60 / (2 * np.pi), omega


@functools.cache
def saw_rates():
    """(v_r, ω1, ω3) at θ2 = π/2, ω2 = 6.472 by central differences of the Cartesian slider-crank."""
    theta2, omega2, h = np.pi / 2, 6.472, 1e-6
    ahead, behind = (np.array(_saw_by_slider_crank(theta2 + s * h)[:3]) for s in (1, -1))
    return (ahead - behind) / (2 * h) * omega2


@functools.cache
def blade_peak():
    textbook = OffsetSliderCrank(MY_SAW.r2, MY_SAW.r3, MY_SAW.r1y)
    grid = np.linspace(0, 2 * np.pi, 3601)
    start = grid[np.argmax(np.abs(textbook.solve(grid, 6.472, branch="left").v_xC))]
    best = scipy.optimize.minimize_scalar(lambda t: -abs(float(textbook.solve(t, 6.472, branch="left").v_xC)),
                                          bracket=(start - 0.01, start + 0.01))
    return -best.fun


@functools.cache
def fivebar_theta4():
    P5 = np.array([-ROBOT.l5 / 2, 0.0])
    left, right = circle_intersections(P5, ROBOT.l4, [-0.03, 0.2], ROBOT.l3)  # σ2 = +1 left, −1 right
    return float(np.arctan2(*(right - P5)[::-1])), float(np.arctan2(*(left - P5)[::-1]))


@functools.cache
def reach_height():
    """The height where the pen going up X = −0.03 first stretches a leg: bisection on reachability."""
    low, high = 0.1, 0.4
    for _ in range(60):
        middle = (low + high) / 2
        reached = bool(ROBOT.inverse(-0.03, middle, on_failure="nan").reachable)
        low, high = (middle, high) if reached else (low, middle)
    return low, float(np.sqrt((ROBOT.l3 + ROBOT.l4) ** 2 - (-0.03 + ROBOT.l5 / 2) ** 2))


@functools.cache
def stroke_and_ratio():
    return float(np.ptp(by_hand(np.radians(np.arange(0, 360, 0.5)))[3])), sweep_ratio(R2, D, 720)


# ---------------------------------------------------------------- the table


@dataclass(frozen=True)
class Bad:
    """A bad task: ``changes`` to the good task's arguments; the error must name ``name`` (and show the
    value given for it, unless ``shows`` is False: an impossible task is said in words)."""

    label: str
    changes: dict
    name: str
    shows: bool = True


def bad(name: str, value: Any, label: str = "") -> Bad:
    """One argument replaced by a value that is not what it must be."""
    return Bad(label or f"{name}={value!r}"[:40], {name: value}, name)


def impossible(label: str, name: str, **changes: Any) -> Bad:
    """Arguments each fine alone that make a task with no answer."""
    return Bad(f"impossible: {label}", changes, name, shows=False)


@dataclass(frozen=True)
class Task:
    """A good task (keyword arguments), its right and a wrong answer (zero-argument functions of
    independent routes), and the bad tasks that must be refused."""

    task: dict
    right: Any
    wrong: Any
    bad: list = field(default_factory=list)


def choice(right: str, wrong: str) -> Task:
    return Task({}, lambda: right, lambda: wrong)


TABLE = {
    # ---- ex01
    "check_mobility": Task({}, lambda: (6, 7, 0, 1), lambda: (5, 7, 0, -2)),
    "check_tilted_loop": Task({}, tilted_loop, lambda: tilted_loop(t1_zero=True)),
    "check_link_vector": Task(
        {"length": 0.06, "angle_degrees": 30.0}, lambda: (0.06 * math.sqrt(3) / 2, 0.03),
        lambda: (0.03, 0.06 * math.sqrt(3) / 2),
        [bad("length", None), bad("length", -0.06), bad("length", 0.0), bad("length", "0.06"),
         bad("angle_degrees", NAN), bad("angle_degrees", INF), bad("angle_degrees", "30"),
         bad("angle_degrees", [30.0, 60.0])]),
    "check_point_velocity": Task(
        {"length": 0.080, "angle_degrees": 135.0, "speed": 12.0, "clockwise": True}, point_velocity,
        lambda: -point_velocity(),
        [bad("length", None), bad("angle_degrees", "135"), bad("speed", -12.0), bad("speed", NAN),
         bad("speed", 0.0), bad("clockwise", "yes"), bad("clockwise", 1), bad("clockwise", None)]),
    "check_redundant_parallelogram": choice("b", "a"),
    # ---- ex02
    "check_newton_update": Task({}, lambda: (2 * sp.Symbol("x") ** 3 + 5) / (3 * sp.Symbol("x") ** 2 - 2),
                                lambda: sp.Symbol("x") + (sp.Symbol("x") ** 3 - 2 * sp.Symbol("x") - 5)
                                / (3 * sp.Symbol("x") ** 2 - 2)),
    "check_newton_iterations": Task({}, newton_count, lambda: (newton_count()[0], newton_count()[1] + 1)),
    "check_newton_cycle": choice("a", "c"),
    "check_fourbar_newton_step": Task(
        {"linkage": BENCH, "theta2": np.radians(40.0), "seed": (0.5, 1.5)}, newton_step,
        lambda: -newton_step(),
        [bad("linkage", None), bad("linkage", (0.07, 0.20, 0.15, 0.25)), bad("theta2", "40"),
         bad("theta2", NAN), bad("seed", None), bad("seed", (0.5,)), bad("seed", (NAN, 1.5)),
         bad("seed", "0.5, 1.5"), impossible("singular Jacobian at the seed", "seed", seed=(0.5, 0.5))]),
    "check_seed_branch": Task(
        {"linkage": BENCH, "theta2": np.radians(40.0), "seed": (2.5, 0.3)}, lambda: seed_branch()[0],
        lambda: seed_branch()[1],
        [bad("linkage", None), bad("linkage", MY_SAW), bad("theta2", INF), bad("theta2", None),
         bad("seed", [2.5, 0.3, 0.0]), bad("seed", (2.5, "0.3")),
         impossible("no assembly at θ2", "theta2", linkage=TRIPLE, theta2=np.pi),
         impossible("Newton cannot start from the seed", "seed", seed=(0.3, 0.3))]),
    # ---- ex03
    "check_fourbar_theta4": Task(
        {"linkage": BENCH, "theta2": np.radians(120.0), "branch": "crossed"},
        lambda: circles(BENCH, np.radians(120.0), "crossed")[1],
        lambda: circles(BENCH, np.radians(120.0), "open")[1],
        [bad("linkage", None), bad("linkage", MY_SAW), bad("theta2", "abc"), bad("theta2", NAN),
         bad("theta2", [1.0, 2.0]), bad("branch", "up"), bad("branch", None), bad("branch", 1),
         bad("branch", "Open"), bad("method", "quadratic"), bad("method", True),
         impossible("no assembly at θ2", "theta2", linkage=TRIPLE, theta2=np.pi)]),
    "check_omega4_expression": Task({}, omega4_formula, lambda: omega4_formula(-1)),
    "check_fourbar_rates": Task(
        {"linkage": BENCH, "theta2": np.radians(200.0), "omega2": 15.0, "alpha2": -40.0, "branch": "open"},
        lambda: _rates_by_sympy(BENCH, np.radians(200.0), 15.0, -40.0, "open")[:2],
        lambda: _rates_by_sympy(BENCH, np.radians(200.0), 15.0, -40.0, "open")[1::-1],
        [bad("linkage", None), bad("theta2", None), bad("omega2", "15"), bad("omega2", INF),
         bad("alpha2", NAN), bad("alpha2", 1j), bad("branch", "up"), bad("branch", True),
         bad("method", "half-angle"), bad("method", "jacobian"),
         impossible("no assembly at θ2", "theta2", linkage=TRIPLE, theta2=np.pi),
         impossible("a toggle while moving", "theta2", linkage=TRIPLE,
                    theta2=max(TRIPLE.input_range().toggle_angles))]),
    "check_toggle_angle": Task(
        {"linkage": TRIPLE}, lambda: (toggle_limit(), "extended"), lambda: (toggle_limit(), "folded"),
        [bad("linkage", None), bad("linkage", (0.14, 0.12, 0.10, 0.20)), bad("linkage", "triple"),
         bad("method", "triangle"), bad("method", True),
         impossible("a crank that turns fully", "linkage", linkage=BENCH)]),
    # ---- ex04
    "check_saw_omega3_expression": Task({}, saw_omega3, lambda: saw_omega3(-1)),
    "check_saw_position": Task(
        {"saw": MY_SAW, "theta2": np.radians(50.0)}, lambda: _saw_by_slider_crank(np.radians(50.0))[:3],
        lambda: (lambda r1, t1, t3: (r1, t1, np.pi - t3))(*_saw_by_slider_crank(np.radians(50.0))[:3]),
        [bad("saw", None), bad("saw", BENCH), bad("theta2", "50"), bad("theta2", NAN), bad("theta2", None),
         bad("method", "Newton"), bad("method", "simultaneous"),
         impossible("the rod cannot reach", "theta2", saw=SHORT_ROD, theta2=-np.pi / 2)]),
    "check_saw_slider_acceleration": Task(
        {"saw": MY_SAW, "theta2": np.radians(50.0), "omega2": 6.0, "alpha2": 4.0},
        lambda: _saw_by_slider_crank(np.radians(50.0), 6.0, 4.0)[3],
        lambda: -_saw_by_slider_crank(np.radians(50.0), 6.0, 4.0)[3],
        [bad("saw", "my_saw"), bad("theta2", INF), bad("omega2", None), bad("omega2", NAN),
         bad("alpha2", "4"), bad("method", "consecutive"), bad("method", True),
         impossible("the rod cannot reach", "theta2", saw=SHORT_ROD, theta2=-np.pi / 2)]),
    "check_saw_r1_sign": choice("a", "d"),
    "check_saw_linear_stage": choice("a", "d"),
    # ---- ex05
    "check_fivebar_forward": Task(
        {"robot": ROBOT, "theta1": np.radians(70.0), "theta4": np.radians(125.0), "mode": -1},
        lambda: fivebar_down()[0], lambda: fivebar_down()[1],
        [bad("robot", None), bad("robot", BENCH), bad("theta1", "70"), bad("theta4", NAN), bad("mode", 0),
         bad("mode", "down"), bad("mode", True), bad("mode", None), bad("method", "half-angle"),
         bad("method", 1), impossible("the distal links cannot meet", "theta1", theta1=0.0, theta4=np.pi)]),
    "check_fivebar_inverse": Task(
        {"robot": ROBOT, "x3": 0.02, "y3": 0.21, "modes": (-1, +1)}, lambda: fivebar_inverse()[0],
        lambda: fivebar_inverse()[1],
        [bad("robot", None), bad("x3", None), bad("y3", INF), bad("x3", "0.02"), bad("modes", (1, 2)),
         bad("modes", "up"), bad("modes", (1,)), bad("modes", (True, 1)), bad("modes", None),
         bad("method", "quadratic"), bad("method", 1), impossible("out of reach", "y3", y3=1.0)]),
    "check_fivebar_g": Task({}, fivebar_g, lambda: fivebar_g(-1)),
    "check_fivebar_singularity": Task(
        dict(zip(("theta1", "theta4", "x3", "y3"), serial_pose(), strict=True), robot=ROBOT),
        lambda: "serial1", lambda: "parallel",
        [bad("robot", None), bad("theta1", "100"), bad("theta4", NAN), bad("x3", None), bad("y3", INF),
         impossible("a point that is not the robot's end effector there", "x3",
                    x3=serial_pose()[2] + 0.01)]),
    # ---- the lessons
    "check_crank_angle_for_rocker": Task(
        {"linkage": BENCH, "theta4": np.radians(135.0)}, lambda: crank_roots()[0], lambda: crank_roots()[1],
        [bad("linkage", None), bad("linkage", ROBOT), bad("theta4", "135"), bad("theta4", NAN),
         impossible("a rocker angle never reached", "theta4", theta4=-np.pi / 2)]),
    "check_rocker_pin_speed": Task(
        {"linkage": BENCH, "theta2": np.radians(120.0), "omega2": 10.0}, rocker_pin_speed,
        lambda: 1.5 * rocker_pin_speed(),
        [bad("linkage", None), bad("theta2", None), bad("omega2", "10"), bad("omega2", NAN),
         bad("branch", "up"), bad("branch", 0),
         impossible("no assembly at θ2", "theta2", linkage=TRIPLE, theta2=np.pi)]),
    "check_motor_start": Task(
        {"alpha_max": 8.0}, lambda: motor_start()[:2], lambda: (motor_start()[0], motor_start()[2]),
        [bad("alpha_max", None), bad("alpha_max", 0.0), bad("alpha_max", -8.0), bad("alpha_max", "8"),
         bad("alpha_max", NAN), bad("alpha_max", INF)]),
    "check_saw_rates": Task(
        {"saw": MY_SAW, "theta2": np.pi / 2, "omega2": 6.472}, saw_rates, lambda: -saw_rates(),
        [bad("saw", None), bad("saw", "MY_SAW"), bad("theta2", "x"), bad("omega2", NAN), bad("omega2", None),
         impossible("the rod cannot reach", "theta2", saw=SHORT_ROD, theta2=-np.pi / 2)]),
    "check_blade_peak_speed": Task(
        {"saw": MY_SAW, "omega2": 6.472}, blade_peak, lambda: MY_SAW.r2 * 6.472,
        [bad("saw", None), bad("saw", ROBOT), bad("omega2", 0.0), bad("omega2", None), bad("omega2", "6"),
         bad("omega2", -INF), impossible("a saw that cannot turn fully", "saw", saw=SHORT_ROD)]),
    "check_fivebar_theta4": Task(
        {"robot": ROBOT, "x3": -0.03, "y3": 0.2, "sigma2": -1}, lambda: fivebar_theta4()[0],
        lambda: fivebar_theta4()[1],
        [bad("robot", None), bad("x3", None), bad("y3", NAN), bad("sigma2", 0), bad("sigma2", "-1"),
         bad("sigma2", 2), bad("sigma2", None), impossible("out of reach", "y3", y3=1.0)]),
    "check_reach_height": Task(
        {"robot": ROBOT, "x3": -0.03}, lambda: reach_height()[0], lambda: reach_height()[1],
        [bad("robot", None), bad("robot", FiveBar), bad("x3", None), bad("x3", "a"), bad("x3", INF),
         impossible("a line beyond both legs", "x3", x3=5.0)]),
    # ---- ex06 and lesson 12
    "check_shaper_loops": Task(
        {"shaper": checks.SHAPER}, lambda: [LEVER_LOOP, RAM_LOOP], lambda: [LEVER_LOOP, LEVER_LOOP],
        [bad("shaper", None), bad("shaper", "SHAPER"), bad("shaper", BENCH),
         impossible("a drawing that cannot turn fully", "shaper", shaper=HIGH_RAM)]),
    "check_shaper_position": Task(
        {"theta2": np.radians(60.0)}, lambda: (DECLARED, GUESS, by_hand(np.radians(60.0))),
        lambda: (DECLARED, GUESS, by_hand(np.radians(60.0), right=False)),
        [bad("theta2", None), bad("theta2", "60"), bad("theta2", NAN), bad("shaper", None),
         bad("shaper", {"crank": 0.06}),
         impossible("no assembly at θ2", "theta2", theta2=0.0, shaper=HIGH_RAM)]),
    "check_ram_motion": Task(
        {"theta2": np.radians(60.0), "omega2": 8.0}, lambda: ram_by_differences(np.radians(60.0), 8.0),
        lambda: (ram_by_differences(np.radians(60.0), 8.0)[0], 0.0),
        [bad("theta2", INF), bad("omega2", None), bad("omega2", "8"), bad("alpha2", NAN), bad("alpha2", "0"),
         bad("shaper", 5), impossible("no assembly at θ2", "theta2", theta2=0.0, shaper=HIGH_RAM)]),
    "check_ram_stroke": Task(
        {}, lambda: (stroke_and_ratio(), "left"), lambda: ((stroke_and_ratio()[0] / 2, stroke_and_ratio()[1]),
                                                           "left"),
        [bad("shaper", None), bad("shaper", "x"), bad("shaper", (0.06, 0.15)),
         impossible("a drawing that cannot turn fully", "shaper", shaper=HIGH_RAM)]),
    "check_quick_return_time_ratio": Task(
        {"crank": 0.05, "pivot_distance": 0.08}, lambda: sweep_ratio(0.05, 0.08, 400_000),
        lambda: 1 / sweep_ratio(0.05, 0.08, 400_000),
        [bad("crank", None), bad("crank", -0.05), bad("crank", "0.05"), bad("pivot_distance", NAN),
         bad("pivot_distance", [0.08]), impossible("a crank longer than the pivot distance", "crank",
                                                   crank=0.1, pivot_distance=0.05)]),
}


def test_the_table_holds_every_public_checker_and_every_task_argument():
    assert set(TABLE) == set(CHECKERS), ("checkers missing from the table: "
                                         f"{sorted(set(CHECKERS) - set(TABLE))}; not checkers: "
                                         f"{sorted(set(TABLE) - set(CHECKERS))}")
    for name, entry in TABLE.items():
        parameters = task_parameters(name)
        assert set(entry.task) <= set(parameters), name
        if parameters:  # every task argument is refused at least once, in three bad tasks or more
            assert len(entry.bad) >= 3, name
            assert {case.name for case in entry.bad} >= set(parameters), (name, parameters)
            assert all(set(case.changes) <= set(parameters) for case in entry.bad), name
        else:  # no task argument: there is nothing a task could get wrong
            assert not entry.bad, name


def test_a_checker_without_task_arguments_takes_the_answer_alone():
    for name in TABLE:
        if not task_parameters(name):
            with pytest.raises(TypeError):
                CHECKERS[name](TABLE[name].right(), "an extra task argument")


# ---------------------------------------------------------------- bad tasks raise, whatever the answer

ANSWERS = {"the right answer": "right", "no answer": None, "a silly answer": "silly"}
BAD_ROWS = [(name, case, answer) for name, entry in TABLE.items() for case in entry.bad for answer in ANSWERS]


@pytest.mark.parametrize(("name", "case", "answer"), BAD_ROWS,
                         ids=[f"{name[6:]}-{case.label}-{answer}" for name, case, answer in BAD_ROWS])
def test_a_bad_task_argument_raises_naming_it_before_the_answer_is_read(name, case, answer):
    entry = TABLE[name]
    given = entry.right() if ANSWERS[answer] == "right" else ([[1.0], "x", None] if ANSWERS[answer] else None)
    with pytest.raises(InvalidArgumentError) as caught:
        CHECKERS[name](given, **{**entry.task, **case.changes})
    message = str(caught.value)
    assert case.name in message, message
    if case.shows:
        assert repr(case.changes[case.name])[:60] in message, message
    if not case.shows:
        assert "no reference answer exists for this task" in message, message


# ---------------------------------------------------------------- good tasks judge the answer

GOOD_ROWS = [(name, verdict) for name in TABLE for verdict in ("right", "wrong")]


@pytest.mark.parametrize(("name", "verdict"), GOOD_ROWS, ids=[f"{n[6:]}-{v}" for n, v in GOOD_ROWS])
def test_a_good_task_gives_a_tick_for_the_right_answer_and_a_cross_for_a_wrong_one(name, verdict):
    entry = TABLE[name]
    answer = entry.right() if verdict == "right" else entry.wrong()
    feedback = CHECKERS[name](answer, **entry.task)
    assert isinstance(feedback, checks.Feedback)
    assert feedback.ok is (verdict == "right"), feedback
    assert str(feedback)[0] == ("✔" if verdict == "right" else "✘"), feedback


SILLY = {"None": None, "text": "abc", "NaN": NAN, "ragged": [[1.0], [2.0, 3.0]], "nested None": [[None]],
         "dict": {"theta2": 1.0}}
SILLY_ROWS = [(name, silly) for name in TABLE for silly in SILLY]


@pytest.mark.parametrize(("name", "silly"), SILLY_ROWS, ids=[f"{n[6:]}-{s}" for n, s in SILLY_ROWS])
def test_a_good_task_answers_any_answer_with_feedback(name, silly):
    feedback = CHECKERS[name](SILLY[silly], **TABLE[name].task)
    assert isinstance(feedback, checks.Feedback) and not feedback.ok, feedback


# ---------------------------------------------------------------- the helper itself


@pytest.mark.parametrize(("kind", "value", "expected"), [
    ("rad", np.float64(0.5), 0.5), ("rad", 2, 2.0), ("rad", np.array(1.5), 1.5), ("m", sp.Float(0.25), 0.25),
    ("positive m", 0.06, 0.06), ("nonzero rad/s", -3.0, -3.0), ((1, -1), np.int64(-1), -1), ((1, -1), 1.0, 1),
    (("open", "crossed"), "open", "open"), (((1, 1), (-1, 1)), [-1, 1], (-1, 1)),
    (((1, 1), (-1, 1)), np.array([1, 1]), (1, 1)), (bool, np.True_, True), (FourBar, BENCH, BENCH),
])
def test_a_good_task_argument_is_kept_as_the_checker_uses_it(kind, value, expected):
    kept = task_argument("argument", value, kind)
    assert kept == expected and type(kept) is type(expected)


def test_a_pair_is_kept_as_a_float_array():
    assert task_argument("seed", (1, 2), "pair rad").tolist() == [1.0, 2.0]


@pytest.mark.parametrize(("kind", "value", "says"), [
    (FourBar, None, "theta2 must be a FourBar(crank, coupler, rocker, ground); got None"),
    ("rad", "abc", "theta2 must be a finite number in rad; got 'abc'"),
    ("rad", True, "theta2 must be a finite number in rad; got True"),
    ("positive m", 0.0, "theta2 must be a positive, finite number in m; got 0.0"),
    ("pair rad", 1.0, "theta2 must be a pair of finite numbers in rad; got 1.0"),
    (("open", "crossed"), "up", "theta2 must be one of 'open', 'crossed'; got 'up'"),
    ((1, -1), np.True_, "theta2 must be one of 1, -1; got"),
    (bool, 0, "theta2 must be True or False; got 0"),
    ("rad", np.zeros(10_000), "theta2 must be a finite number in rad; got array("),
])
def test_a_bad_task_argument_is_named_with_its_value(kind, value, says):
    with pytest.raises(InvalidArgumentError) as caught:
        task_argument("theta2", value, kind)
    assert str(caught.value).startswith(says) and len(str(caught.value)) < 200, str(caught.value)


def test_equivalent_spellings_of_a_good_task_still_judge_the_answer():
    right = fivebar_inverse()[0]
    for modes in ([-1, 1], np.array([-1, 1]), (np.int64(-1), 1.0)):
        assert checks.check_fivebar_inverse(right, ROBOT, 0.02, 0.21, modes).ok
    down = fivebar_down()[0]
    assert checks.check_fivebar_forward(down, ROBOT, np.radians(70.0), np.radians(125.0), -1.0).ok
    assert checks.check_point_velocity(point_velocity(), 0.080, 135.0, 12.0, np.True_).ok


# ---------------------------------------------------------------- the shaper's loops: no false ✔

th2, th4 = sp.Symbol("theta2", real=True), sp.Symbol("theta4", real=True)
r4 = sp.Symbol("r4", real=True)
LEVER, RAM = list(LEVER_LOOP), list(RAM_LOOP)
FALSE_PASSES = {  # each holds for the drawn shaper, but stops fixing the unknowns at some crank angle
    "lever x times cos θ2": [LEVER[0] * sp.cos(th2), LEVER[1], *RAM],
    "lever x times (θ2 − 1)": [LEVER[0] * (th2 - 1), LEVER[1], *RAM],
    "lever x times (θ2 − 1)²": [LEVER[0] * (th2 - 1) ** 2, LEVER[1], *RAM],
    "lever y times cos θ4": [LEVER[0], LEVER[1] * sp.cos(th4), *RAM],
    "lever x times (r4 − 1/10)": [LEVER[0] * (r4 - sp.Rational(1, 10)), LEVER[1], *RAM],
    "every row times (θ2 − 2)": [row * (th2 - 2) for row in (*LEVER, *RAM)],
    "ram x times sin θ2, reordered": [RAM[1], LEVER[0], RAM[0] * sp.sin(th2), LEVER[1]],
    "Max of the lever x": [sp.Max(LEVER[0], 0), LEVER[1], *RAM],
    "a term zero at the probes only": [LEVER[0] + sp.sin(8 * th2 - 4 * sp.pi / 9), LEVER[1], *RAM],
}


@pytest.mark.parametrize("rows", FALSE_PASSES.values(), ids=FALSE_PASSES)
def test_loops_that_fail_at_some_crank_angle_are_refused(rows):
    feedback = checks.check_shaper_loops(rows)
    assert isinstance(feedback, checks.Feedback) and not feedback.ok, feedback
    assert str(feedback).startswith("✘ Not yet"), feedback


def test_the_two_known_false_passes_name_the_equation_and_the_crank_angle():
    for rows, angle in (([LEVER[0] * sp.cos(th2), LEVER[1], *RAM], ("1.571", "4.712")),
                        ([LEVER[0] * (th2 - 1), LEVER[1], *RAM], ("1.000",))):
        feedback = checks.check_shaper_loops(rows)
        assert not feedback.ok and "equation 1" in feedback.message, feedback
        assert any(f"θ2 ≈ {a} rad" in feedback.message for a in angle), feedback


EQUIVALENT = {  # a factor that never vanishes, or one that vanishes only far from the drawn motion
    "lever x times (2 + cos θ2)": [LEVER[0] * (2 + sp.cos(th2)), LEVER[1], *RAM],
    "lever y times (r4 + 1)": [LEVER[0], LEVER[1] * (r4 + 1), *RAM],
    "every row times 3": [3 * row for row in (*LEVER, *RAM)],
    "rows combined": [LEVER[0] + RAM[0], LEVER[1], RAM[0], RAM[1] - 3 * LEVER[0]],
}


@pytest.mark.parametrize("rows", EQUIVALENT.values(), ids=EQUIVALENT)
def test_equivalent_loops_still_pass(rows):
    assert checks.check_shaper_loops(rows).ok


def test_the_table_is_large():
    rows = len(BAD_ROWS) + len(GOOD_ROWS) + len(SILLY_ROWS) + len(FALSE_PASSES) + len(EQUIVALENT)
    assert rows >= 150, rows
