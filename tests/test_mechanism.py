"""course_lib.mechanism: each result against an independent route.

Routes: circle–circle intersections (tests/geometry.py) and the four-bar's hand-written half-angle
closed form (FourBar.solve's positions), Norton's sine formulas for ω3, ω4 and the loop differentiated
twice by hand for α3, α4 (written out below, in numpy), the offset slider-crank's x(θ2) differentiated
by sympy's chain rule, the five-bar's closed form (FiveBar.forward), central finite differences along
time paths with nonzero accelerations, the time derivatives rebuilt by the chain rule with sympy
Jacobians, Newton on the stacked 3n system, sequential one-instant solves (continuation by hand), and
finite-difference Jacobians.  No reference is the core's own work: the machines' rates come from the
core, so they are never used as a check of it.
"""

import numpy as np
import pytest
import sympy as sp
from geometry import circle_intersections, fourbar_pins

from course_lib.errors import (
    ConvergenceError,
    InvalidGeometryError,
    SingularJacobianError,
    UnreachableError,
)
from course_lib.fivebar import FiveBar
from course_lib.fourbar import FourBar
from course_lib.mechanism import Mechanism, Motion
from course_lib.newton import NewtonResult, finite_difference_jacobian, newton

th2, th3, th4, th5, th6 = sp.symbols("theta2 theta3 theta4 theta5 theta6")
l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
LOOP = sp.Matrix([l2 * sp.cos(th2) + l3 * sp.cos(th3) - l4 * sp.cos(th4) - l1,
                  l2 * sp.sin(th2) + l3 * sp.sin(th3) - l4 * sp.sin(th4)])
WIPER_LENGTHS = {l1: 0.20, l2: 0.06, l3: 0.18, l4: 0.12}
WIPER_POINTS = {"O2": sp.Matrix([0, 0]), "A": sp.Matrix([l2 * sp.cos(th2), l2 * sp.sin(th2)]),
                "B": sp.Matrix([l1 + l4 * sp.cos(th4), l4 * sp.sin(th4)]), "O4": sp.Matrix([l1, 0])}
WIPER = Mechanism(loops=[LOOP], unknowns=[th3, th4], inputs=[th2], parameters=WIPER_LENGTHS,
                  points=WIPER_POINTS, links=[("O2", "A"), ("A", "B"), ("B", "O4")])
DESK = FourBar(crank=0.06, coupler=0.18, rocker=0.12, ground=0.20)
GUESS = {th3: 0.4, th4: 1.6}


def fourbar(lengths):
    """The four-bar loop with other lengths (ground, crank, coupler, rocker)."""
    return Mechanism([LOOP], [th3, th4], [th2], dict(zip((l1, l2, l3, l4), lengths, strict=True)))


def norton_rates(theta2, theta3, theta4, omega2, alpha2, lengths=(0.20, 0.06, 0.18, 0.12)):
    """ω3, ω4 by Norton's sine formulas and α3, α4 from the loop differentiated twice by hand (Cramer's
    rule), for the four-bar of ``lengths`` (ground, crank, coupler, rocker): a route free of the core."""
    _, a, b, c = lengths
    s2, c2, s3, c3, s4, c4 = (f(v) for v in (theta2, theta3, theta4) for f in (np.sin, np.cos))
    omega3 = a * omega2 * np.sin(theta4 - theta2) / (b * np.sin(theta3 - theta4))
    omega4 = a * omega2 * np.sin(theta3 - theta2) / (c * np.sin(theta3 - theta4))
    # x: −a α2 s2 − a ω2² c2 − b α3 s3 − b ω3² c3 + c α4 s4 + c ω4² c4 = 0, and y likewise
    rx = a * alpha2 * s2 + a * omega2**2 * c2 + b * omega3**2 * c3 - c * omega4**2 * c4
    ry = -a * alpha2 * c2 + a * omega2**2 * s2 + b * omega3**2 * s3 - c * omega4**2 * s4
    m11, m12, m21, m22 = -b * s3, c * s4, b * c3, -c * c4
    det = m11 * m22 - m12 * m21
    return omega3, omega4, (rx * m22 - m12 * ry) / det, (m11 * ry - m21 * rx) / det


def angle_gap(a, b):
    return float(np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b))))).max())


def stacked(mapping, names):
    return np.stack([np.asarray(mapping[name]) for name in names], axis=-1)


# ------------------------------------------------------------------ the contract


def test_contract_sweep_is_the_open_branch_of_the_circle_construction():
    theta2 = np.radians(np.arange(0, 360, 2))
    motion = WIPER.solve({th2: theta2}, rates={th2: 10.0}, accelerations={th2: 3.0}, guess=GUESS)
    assert isinstance(motion, Motion)
    for mapping in (motion.position, motion.velocity, motion.acceleration):
        assert set(mapping) == {"theta3", "theta4"}
        assert all(np.shape(value) == theta2.shape for value in mapping.values())
    assert motion.converged.all() and not motion.singular.any()
    A, B = fourbar_pins(0.20, 0.06, 0.18, 0.12, theta2, "open")
    _, B_crossed = fourbar_pins(0.20, 0.06, 0.18, 0.12, theta2, "crossed")
    assert angle_gap(motion.position["theta3"], np.arctan2(B[:, 1] - A[:, 1], B[:, 0] - A[:, 0])) < 1e-12
    assert angle_gap(motion.position["theta4"], np.arctan2(B[:, 1], B[:, 0] - 0.20)) < 1e-12
    # the guess reaches the open assembly, and stays on it: never the crossed one
    crossed_theta4 = np.arctan2(B_crossed[:, 1], B_crossed[:, 0] - 0.20)
    assert np.all(np.abs(np.angle(np.exp(1j * (motion.position["theta4"] - crossed_theta4)))) > 0.1)


def test_contract_rates_match_norton_and_the_loop_differentiated_by_hand():
    theta2 = np.radians(np.arange(0, 360, 2))
    motion = WIPER.solve({th2: theta2}, rates={th2: 10.0}, accelerations={th2: 3.0}, guess=GUESS)
    omega3, omega4, alpha3, alpha4 = norton_rates(theta2, motion.position["theta3"],
                                                  motion.position["theta4"], 10.0, 3.0)
    np.testing.assert_allclose(motion.velocity["theta3"], omega3, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(motion.velocity["theta4"], omega4, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(motion.acceleration["theta3"], alpha3, rtol=1e-11, atol=1e-10)
    np.testing.assert_allclose(motion.acceleration["theta4"], alpha4, rtol=1e-11, atol=1e-10)


def test_one_instant_gives_numbers_and_newton_history():
    motion = WIPER.solve({th2: 0.7}, rates={th2: 10.0}, accelerations={th2: 0.0}, guess=GUESS)
    closed = DESK.solve(0.7, 10.0, 0.0)
    assert isinstance(motion.position["theta4"], float) and isinstance(motion.converged, bool)
    assert isinstance(motion.iterations, int) and motion.singular is False
    assert angle_gap(motion.position["theta3"], closed.theta3) < 1e-12
    _, omega4, alpha3, _ = norton_rates(0.7, closed.theta3, closed.theta4, 10.0, 0.0)
    assert abs(motion.velocity["theta4"] - omega4) < 1e-12
    assert abs(motion.acceleration["theta3"] - alpha3) < 1e-10
    assert isinstance(motion.newton, NewtonResult) and motion.newton.converged
    assert motion.newton.history[0].tolist() == [0.4, 1.6]
    assert motion.newton.iterations == motion.iterations == len(motion.newton.history) - 1
    assert motion.inputs == {"theta2": 0.7}


def test_without_rates_velocity_and_acceleration_are_none():
    motion = WIPER.solve({"theta2": [0.1, 0.2]}, guess={"theta3": 0.4, "theta4": 1.6})
    assert motion.velocity is None and motion.acceleration is None and motion.newton is None
    only_acceleration = WIPER.solve({th2: 0.1}, accelerations={th2: 2.0}, guess=GUESS)
    closed = DESK.solve(0.1)
    alpha4 = norton_rates(0.1, closed.theta3, closed.theta4, 0.0, 2.0)[3]
    assert only_acceleration.velocity["theta4"] == 0.0
    assert abs(only_acceleration.acceleration["theta4"] - alpha4) < 1e-12


def test_inputs_and_rates_broadcast():
    theta2 = np.linspace(0.0, 1.0, 3)
    omega2 = np.array([[1.0], [-2.0]])
    motion = WIPER.solve({th2: theta2}, rates={th2: omega2}, guess=GUESS)
    assert motion.velocity["theta4"].shape == (2, 3) and motion.position["theta3"].shape == (2, 3)
    closed = DESK.solve(theta2)
    omega4 = norton_rates(theta2, closed.theta3, closed.theta4, omega2, 0.0)[1]
    np.testing.assert_allclose(motion.velocity["theta4"], omega4, rtol=1e-12, atol=1e-12)
    assert motion.inputs["theta2"].shape == (2, 3)


def test_joints_from_declared_points():
    theta2 = np.linspace(0, 2 * np.pi, 9)
    joints = WIPER.joints(WIPER.solve({th2: theta2}, guess=GUESS))
    A, B = fourbar_pins(0.20, 0.06, 0.18, 0.12, theta2, "open")
    np.testing.assert_allclose(joints["A"], A, atol=1e-12)
    np.testing.assert_allclose(joints["B"], B, atol=1e-12)
    np.testing.assert_allclose(joints["O4"], np.tile([0.20, 0.0], (9, 1)))
    assert WIPER.links == (("O2", "A"), ("A", "B"), ("B", "O4"))


# ------------------------------------------------------------------ rates by finite differences


def test_rates_match_central_differences_along_a_time_path():
    # θ2(t) = 0.3 + 2t + 1.5t²: ω2 = 2 + 3t, α2 = 3
    h = 1e-4
    t = np.linspace(0.2, 1.2, 11)
    path = lambda s: 0.3 + 2 * s + 1.5 * s**2  # noqa: E731
    here = WIPER.solve({th2: path(t)}, {th2: 2 + 3 * t}, {th2: 3.0}, guess=GUESS)
    names = ["theta3", "theta4"]
    q, q_rate, q_acc = (stacked(m, names) for m in (here.position, here.velocity, here.acceleration))
    after, before = (stacked(WIPER.solve({th2: path(t + s)}, guess=GUESS).position, ["theta3", "theta4"])
                     for s in (h, -h))
    np.testing.assert_allclose(q_rate, (after - before) / (2 * h), atol=1e-6)
    np.testing.assert_allclose(q_acc, (after - 2 * q + before) / h**2, atol=2e-4)


# ------------------------------------------------------------------ a length unknown: offset slider-crank


x, a_, b_, c_ = sp.symbols("x a b c")
SLIDER = Mechanism([sp.Matrix([a_ * sp.cos(th2) + b_ * sp.cos(th3) - x,
                               a_ * sp.sin(th2) + b_ * sp.sin(th3) - c_])],
                   unknowns=[th3, x], inputs=[th2], parameters={a_: 0.075, b_: 0.170, c_: 0.045})


def chain_rule_slider(sign):
    """x(θ2) and θ3(θ2) of the offset slider-crank in closed form, their rates by sympy's chain rule:
    v = x'·ω2, a = x''·ω2² + x'·α2 (θ3 likewise); a route free of the core."""
    t, w, al = sp.symbols("t w al")
    height = 0.045 - 0.075 * sp.sin(t)
    run = sign * sp.sqrt(0.170**2 - height**2)
    x_of, theta3_of = 0.075 * sp.cos(t) + run, sp.atan2(height, run)
    values = [f for g in (x_of, theta3_of) for f in (g, g.diff(t) * w, g.diff(t, 2) * w**2 + g.diff(t) * al)]
    return sp.lambdify([t, w, al], values, "numpy")


@pytest.mark.parametrize(("branch", "guess"), [("right", {th3: -0.2, x: 0.2}), ("left", {th3: 2.9, x: -0.1})])
def test_slider_travel_as_unknown_matches_the_chain_rule(branch, guess):
    theta2 = np.linspace(0, 4 * np.pi, 200)
    omega2, alpha2 = 6.0 + theta2, 1.0
    motion = SLIDER.solve({th2: theta2}, {th2: omega2}, {th2: alpha2}, guess=guess)
    book = chain_rule_slider(1 if branch == "right" else -1)
    x_, v, a, theta3, omega3, alpha3 = book(theta2, omega2, alpha2)
    np.testing.assert_allclose(motion.position["x"], x_, atol=1e-12)
    assert angle_gap(motion.position["theta3"], theta3) < 1e-12
    np.testing.assert_allclose(motion.velocity["x"], v, atol=1e-11)
    np.testing.assert_allclose(motion.velocity["theta3"], omega3, atol=1e-10)
    np.testing.assert_allclose(motion.acceleration["x"], a, atol=1e-9)
    np.testing.assert_allclose(motion.acceleration["theta3"], alpha3, atol=1e-8)
    assert SLIDER.rate_symbols[x][0].name == "v_x"


# ------------------------------------------------------------------ two loops sharing θ4: a Watt II six-bar

l5, l6, l7, delta = sp.symbols("l5 l6 l7 delta", positive=True)
WATT_LENGTHS = {l1: 0.20, l2: 0.06, l3: 0.18, l4: 0.12, l5: 0.10, l6: 0.16, l7: 0.14, delta: 0.5}
# loop 2 hangs on the rocker (a ternary link): C = O4 + l5·(θ4 + δ), D = C + l6·θ5 = O6 + l7·θ6,
# with O6 = O4 + (0.05, 0.25)
WATT = Mechanism(
    loops=[LOOP, sp.Matrix([l5 * sp.cos(th4 + delta) + l6 * sp.cos(th5) - l7 * sp.cos(th6) - 0.05,
                            l5 * sp.sin(th4 + delta) + l6 * sp.sin(th5) - l7 * sp.sin(th6) - 0.25])],
    unknowns=[th3, th4, th5, th6], inputs=[th2], parameters=WATT_LENGTHS)
WATT_GUESS = {th3: 0.4, th4: 1.6, th5: 0.3, th6: 1.2}


def test_six_bar_loops_close_and_match_circle_constructions():
    theta2 = np.linspace(0, 2 * np.pi, 90)
    motion = WATT.solve({th2: theta2}, guess=WATT_GUESS)
    t3, t4, t5, t6 = (motion.position[name] for name in ("theta3", "theta4", "theta5", "theta6"))
    # both loops close, written out with numpy
    loop1 = (0.06 * np.exp(1j * theta2) + 0.18 * np.exp(1j * t3) - 0.12 * np.exp(1j * t4) - 0.20)
    loop2 = 0.10 * np.exp(1j * (t4 + 0.5)) + 0.16 * np.exp(1j * t5) - 0.14 * np.exp(1j * t6) - (0.05 + 0.25j)
    assert np.abs(loop1).max() < 1e-12 and np.abs(loop2).max() < 1e-12
    # the first loop is the wiper four-bar; D is where the two circles about C and O6 meet
    assert angle_gap(t4, DESK.solve(theta2).theta4) < 1e-12
    O4 = np.array([0.20, 0.0])
    C = O4 + 0.10 * np.stack([np.cos(t4 + 0.5), np.sin(t4 + 0.5)], axis=-1)
    left, right = circle_intersections(C, 0.16, O4 + [0.05, 0.25], 0.14)
    D = C + 0.16 * np.stack([np.cos(t5), np.sin(t5)], axis=-1)
    on_left, on_right = np.abs(D - left).max(axis=1), np.abs(D - right).max(axis=1)
    assert np.all(on_left < 1e-12) or np.all(on_right < 1e-12)  # one assembly all the way round


def test_six_bar_rates_by_finite_differences():
    h, names = 1e-5, ["theta3", "theta4", "theta5", "theta6"]
    theta2 = np.linspace(0.1, 6.0, 12)
    here = WATT.solve({th2: theta2}, {th2: 7.0}, {th2: 0.0}, guess=WATT_GUESS)
    after, before = (stacked(WATT.solve({th2: theta2 + s}, guess=WATT_GUESS).position, names)
                     for s in (h, -h))
    velocity, acceleration = stacked(here.velocity, names), stacked(here.acceleration, names)
    np.testing.assert_allclose(velocity, 7.0 * (after - before) / (2 * h), atol=1e-6)
    q = stacked(here.position, names)
    np.testing.assert_allclose(acceleration, 49.0 * (after - 2 * q + before) / h**2, atol=5e-3)


# ------------------------------------------------------------------ two inputs: the five-bar robot


def test_two_inputs_five_bar_forward_kinematics():
    x3, y3, t1, t4 = sp.symbols("x3 y3 theta1 theta4")
    k1, k2, k3, k4, k5 = 0.10, 0.15, 0.15, 0.10, 0.08
    robot = Mechanism([(x3 - k1 * sp.cos(t1) - k5 / 2) ** 2 + (y3 - k1 * sp.sin(t1)) ** 2 - k2**2,
                       (x3 - k4 * sp.cos(t4) + k5 / 2) ** 2 + (y3 - k4 * sp.sin(t4)) ** 2 - k3**2],
                      unknowns=[x3, y3], inputs=[t1, t4])
    s = np.linspace(0.0, 0.5, 6)
    theta1, theta4 = 1.0 + s, 2.0 - s**2
    motion = robot.solve({t1: theta1, t4: theta4}, rates={t1: 1.0, t4: -2 * s}, guess={x3: 0.0, y3: 0.2})
    closed = FiveBar(k1, k2, k3, k4, k5).forward(theta1, theta4, mode=+1)
    np.testing.assert_allclose(motion.position["x3"], closed.x3, atol=1e-12)
    np.testing.assert_allclose(motion.position["y3"], closed.y3, atol=1e-12)
    h = 1e-6
    ahead = FiveBar(k1, k2, k3, k4, k5).forward(theta1 + h, 2.0 - (s + h) ** 2, mode=+1)
    behind = FiveBar(k1, k2, k3, k4, k5).forward(theta1 - h, 2.0 - (s - h) ** 2, mode=+1)
    np.testing.assert_allclose(motion.velocity["y3"], (ahead.y3 - behind.y3) / (2 * h), atol=1e-7)


# ------------------------------------------------------------------ the derivation, by another route


def test_time_derivatives_equal_the_chain_rule():
    q, u = sp.Matrix([th3, th4]), sp.Matrix([th2])
    z = sp.Matrix([*q, *u])
    rates = WIPER.rate_symbols
    z_rate = sp.Matrix([rates[s][0] for s in z])
    z_acc = sp.Matrix([rates[s][1] for s in z])
    first = LOOP.jacobian(z) * z_rate                              # dF/dt = ∂F/∂z · ż
    second = first.jacobian(z) * z_rate + first.jacobian(z_rate) * z_acc
    assert sp.simplify(WIPER.velocity_equations - first) == sp.zeros(2, 1)
    assert sp.simplify(WIPER.acceleration_equations - second) == sp.zeros(2, 1)
    # and the velocity system is J·q̇ = −F_u·u̇ with J = ∂F/∂q
    q_rate = sp.Matrix([rates[s][0] for s in q])
    by_jacobians = LOOP.jacobian(q) * q_rate + LOOP.jacobian(u) * rates[th2][0]
    assert sp.simplify(WIPER.velocity_equations - by_jacobians) == sp.zeros(2, 1)


def test_numeric_jacobians_match_finite_differences():
    rng = np.random.default_rng(3)
    q, u = rng.uniform(-3, 3, (5, 2)), rng.uniform(-3, 3, (5, 1))
    np.testing.assert_allclose(WIPER.jacobian(q, u),
                               finite_difference_jacobian(lambda v: WIPER.residual(v, u), q), atol=1e-9)
    np.testing.assert_allclose(WIPER.input_jacobian(q, u),
                               finite_difference_jacobian(lambda v: WIPER.residual(q, v), u), atol=1e-9)
    x6, rates = rng.uniform(-3, 3, 6), (u[0], [1.5], [-0.5])
    G, JG = WIPER.system(x6, *rates)
    np.testing.assert_allclose(JG, finite_difference_jacobian(lambda v: WIPER.system(v, *rates)[0], x6),
                               atol=1e-8)
    assert G.shape == (6,) and JG.shape == (6, 6)


def test_one_instant_and_a_long_sweep_give_the_rows_of_a_short_batch():
    # a long sweep is evaluated in pieces: it must give a short batch's rows to the bit; one instant must
    # agree with them to a few ulps, so a lesson prints the same digits whichever way it asks (the public
    # functions only)
    rng = np.random.default_rng(3)
    count = 2 * 65_536 + 17
    q, u = rng.uniform(-3, 3, (count, 2)), rng.uniform(-3, 3, (count, 1))
    rows = np.concatenate([rng.choice(count, 30), [0, 65_535, 65_536, count - 1]])
    np.testing.assert_array_equal(WIPER.residual(q, u)[rows], WIPER.residual(q[rows], u[rows]))
    np.testing.assert_array_equal(WIPER.jacobian(q, u)[rows], WIPER.jacobian(q[rows], u[rows]))
    for row in rows[:8]:
        np.testing.assert_allclose(WIPER.residual(q[row], u[row]), WIPER.residual(q[rows], u[rows])[
            list(rows).index(row)], rtol=1e-14, atol=1e-16)
        np.testing.assert_allclose(WIPER.jacobian(q[row], u[row]), WIPER.jacobian(q[rows], u[rows])[
            list(rows).index(row)], rtol=1e-14, atol=1e-16)
    # the acceleration terms hold squares of rates: 3000 instants one by one against one batch
    q_acc, q_rate, u_rate, u_acc = (rng.uniform(-30, 30, (3000, k)) for k in (2, 2, 1, 1))
    batch = WIPER.acceleration_residual(q_acc, q_rate, q[:3000], u[:3000], u_rate, u_acc)
    ones = np.array([WIPER.acceleration_residual(q_acc[k], q_rate[k], q[k], u[k], u_rate[k], u_acc[k])
                     for k in range(3000)])
    np.testing.assert_allclose(ones, batch, rtol=1e-14, atol=1e-12)


def test_one_instant_outside_the_domain_of_math_is_nan_as_in_an_array():
    # math.sqrt(-1) raises where numpy gives NaN: one instant must answer as a one-row batch does
    x, s = sp.symbols("x s")
    root = Mechanism([x - sp.sqrt(s)], [x], [s])
    with np.errstate(invalid="ignore"):
        one, batch = root.residual([1.0], [-4.0]), root.residual([[1.0]], [[-4.0]])
        assert np.isnan(one[0]) and np.isnan(batch[0, 0])
        assert root.residual([1.0], [4.0]).tolist() == [-1.0]
    huge = Mechanism([x**2 - s], [x], [s])  # 1e200**2 overflows: OverflowError in math, inf in numpy
    with np.errstate(over="ignore"):
        assert huge.residual([1e200], [0.0]).tolist() == [np.inf]


def test_newton_function_solves_the_loop_as_the_closed_form_does():
    from course_lib.newton import newton_batch

    theta2 = np.linspace(0.0, 2 * np.pi, 50, endpoint=False)[:, None]
    function = WIPER.newton_function(theta2)
    q = np.column_stack([np.full(50, 0.5), np.full(50, 1.5)])
    F, J = function(q)
    np.testing.assert_array_equal(F, WIPER.residual(q, theta2))
    np.testing.assert_allclose(J, WIPER.jacobian(q, theta2), rtol=1e-14, atol=1e-15)
    result = newton_batch(function, np.tile([0.6, 2.0], (50, 1)), jac=True, tol=1e-12)
    closed = DESK.solve(theta2[:, 0])
    assert result.converged.all()
    assert angle_gap(result.x, np.column_stack([closed.theta3, closed.theta4])) < 1e-12


def test_simultaneous_3n_system_gives_the_staged_answer():
    u, u_rate, u_acc = [0.7], [10.0], [3.0]
    staged = WIPER.solve({th2: 0.7}, {th2: 10.0}, {th2: 3.0}, guess=GUESS)
    result = newton(lambda v: WIPER.system(v, u, u_rate, u_acc)[0], np.array([0.4, 1.6, 0, 0, 0, 0]),
                    jac=lambda v: WIPER.system(v, u, u_rate, u_acc)[1], tol=1e-12)
    expected = [staged.position["theta3"], staged.position["theta4"], staged.velocity["theta3"],
                staged.velocity["theta4"], staged.acceleration["theta3"], staged.acceleration["theta4"]]
    np.testing.assert_allclose(result.x, expected, atol=1e-9)


# ------------------------------------------------------------------ continuation


def sequential(mechanism, values, guess):
    """Continuation by hand: one-instant solves, each seeded with the previous solution."""
    out, seed = [], guess
    for value in values:
        position = mechanism.solve({th2: value}, guess=seed).position
        seed = dict(position)
        out.append([position[s.name] for s in mechanism.unknowns])
    return np.array(out)


@pytest.mark.parametrize("count", [7, 180])
def test_sweep_lands_where_sequential_continuation_does(count):
    theta2 = np.linspace(0, 2 * np.pi, count)
    motion = WIPER.solve({th2: theta2}, guess=GUESS)
    np.testing.assert_allclose(stacked(motion.position, ["theta3", "theta4"]),
                               sequential(WIPER, theta2, GUESS), atol=1e-12)


def test_continuation_follows_a_double_crank_through_full_turns():
    # ground shortest: coupler and rocker turn fully; continuation keeps the angles continuous
    double_crank = fourbar((0.05, 0.12, 0.15, 0.13))
    theta2 = np.linspace(0, 4 * np.pi, 300)
    motion = double_crank.solve({th2: theta2}, guess={th3: 0.3, th4: 1.0})
    q = stacked(motion.position, ["theta3", "theta4"])
    np.testing.assert_allclose(q, sequential(double_crank, theta2, {th3: 0.3, th4: 1.0}), atol=1e-12)
    assert np.abs(np.diff(q, axis=0)).max() < 0.2          # no 2π jumps
    assert q[-1, 1] - q[0, 1] == pytest.approx(4 * np.pi)  # two full turns of the rocker


# ------------------------------------------------------------------ failures


TRIPLE_ROCKER = fourbar((0.20, 0.15, 0.10, 0.12))  # θ2 only within ±1.333578 rad


def test_input_beyond_reach_raises_unreachable_or_gives_nan():
    theta2 = np.linspace(0, 1.6, 50)
    with pytest.raises(UnreachableError, match=r"theta2=1\.33\d+ .*first at index 41") as info:
        TRIPLE_ROCKER.solve({th2: theta2}, guess={th3: 1.0, th4: 2.0})
    reference = FourBar(0.15, 0.10, 0.12, 0.20).solve(theta2, on_failure="nan")
    np.testing.assert_array_equal(info.value.mask, reference.mask)
    motion = TRIPLE_ROCKER.solve({th2: theta2}, {th2: 1.0}, guess={th3: 1.0, th4: 2.0}, on_failure="nan")
    np.testing.assert_array_equal(motion.converged, ~reference.mask)
    assert np.isnan(motion.position["theta4"][reference.mask]).all()
    assert np.isnan(motion.velocity["theta4"][reference.mask]).all()
    assert angle_gap(motion.position["theta4"][~reference.mask], reference.theta4[~reference.mask]) < 1e-12


def test_unreachable_one_instant_names_the_missing_root_and_keeps_newton_history():
    # the four-bar reduces to its half-angle quadratic: at θ2 = 2 it has no real root (the true cause)
    with pytest.raises(UnreachableError, match=r"theta2=2\.0\b.*no real root"):
        TRIPLE_ROCKER.solve({th2: 2.0}, guess={th3: 1.0, th4: 2.0})
    with pytest.raises(UnreachableError, match="theta2=2"):
        TRIPLE_ROCKER.solve({th2: [2.0, 0.0]}, guess={th3: 1.0, th4: 2.0})
    motion = TRIPLE_ROCKER.solve({th2: 2.0}, guess={th3: 1.0, th4: 2.0}, on_failure="nan")
    assert motion.converged is False and np.isnan(motion.position["theta3"])
    assert motion.newton.iterations == 50 and np.isfinite(motion.newton.x).all()  # its record is untouched


def test_newton_route_without_a_root_from_the_guess_is_a_convergence_error_with_history():
    # x⁴ + s = 0 does not reduce to a quadratic, and has no real root for s > 0
    x_, s_ = sp.symbols("x s")
    quartic = Mechanism([x_**4 + x_**2 + s_], [x_], [s_])
    assert quartic.closed_forms == [None]
    with pytest.raises(ConvergenceError, match=r"s=1\.0, from the guess") as info:
        quartic.solve({s_: 1.0}, guess={x_: 1.0})
    assert isinstance(info.value.result, NewtonResult) and not info.value.result.converged


def test_dependent_rows_are_refused_when_declared_and_a_singular_seed_is_named_as_the_seed():
    # x + y = u and 2x + 2y = 2u: J = [[1, 1], [2, 2]] is singular everywhere: refused at once
    p, r, s = sp.symbols("p r s")
    with pytest.raises(InvalidGeometryError, match=r"loops\[0\], loops\[1\] depend on each other"):
        Mechanism([p + r - s, 2 * p + 2 * r - 2 * s], unknowns=[p, r], inputs=[s])
    # x³ = s from the seed x = 0, where J = 3x² = 0: the seed is blamed, not the mechanism
    cubic = Mechanism([p**3 - s], [p], [s])
    with pytest.raises(SingularJacobianError, match=r"s=1\.0.*try another seed"):
        cubic.solve({s: 1.0}, guess={p: 0.0})
    with pytest.raises(SingularJacobianError, match=r"s=1\.0, the first instant.*try another seed"):
        cubic.solve({s: [1.0, 2.0]}, guess={p: 0.0})
    assert cubic.solve({s: [1.0, 8.0]}, guess={p: 0.5}).position["p"].tolist() == pytest.approx([1.0, 2.0])


# ------------------------------------------------------------------ bad declarations and inputs


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (dict(unknowns=[th3, th5]), r"unknowns: theta5 appears in no loop"),
        (dict(inputs=[th5]), r"inputs: theta5 appears in no loop"),
        (dict(unknowns=[th3]), r"loops give 2 equations for the 1 unknowns \[theta3\]"),
        (dict(unknowns=[th3, "theta4"]), r"unknowns must be sympy Symbols; got 'theta4'"),
        (dict(inputs=[th3]), r"unknowns and inputs must not share a symbol"),
        (dict(parameters={l1: 0.2, l2: 0.06, l3: 0.18}), r"parameters: l4 has no value.*'l1': 0\.2"),
        (dict(parameters={**WIPER_LENGTHS, l5: 1.0}), r"parameters: l5 appears in no loop"),
        (dict(parameters={**WIPER_LENGTHS, l4: float("nan")}), r"parameters\[l4\] must be finite; got nan"),
        (dict(parameters={**WIPER_LENGTHS, th3: 1.0}), r"parameters: theta3 is an unknown or input"),
        (dict(loops=[LOOP, "not an equation ("]), r"loops\[1\] must be a sympy expression \(= 0\) or Eq"),
        (dict(points={"A": sp.Matrix([l2, l2, l2])}), r"points\['A'\] must be a 2x1 Matrix"),
        (dict(points={"A": sp.Matrix([l2, 0])}, links=[("A", "Z")]), r"links: \('A', 'Z'\) names a point"),
    ],
)
def test_bad_declarations_name_the_argument(arguments, message):
    declaration = dict(loops=[LOOP], unknowns=[th3, th4], inputs=[th2], parameters=WIPER_LENGTHS) | arguments
    with pytest.raises(InvalidGeometryError, match=message):
        Mechanism(**declaration)


def test_a_symbol_left_over_in_the_loops_is_named():
    k = sp.Symbol("k")
    with pytest.raises(InvalidGeometryError, match=r"parameters: k has no value"):
        Mechanism([LOOP + sp.Matrix([k, 0])], [th3, th4], [th2], WIPER_LENGTHS)


@pytest.mark.parametrize(
    ("arguments", "message"),
    [
        (dict(inputs={th3: 0.1}), r"inputs has the key theta3, which is not one of \['theta2'\]"),
        (dict(inputs={}), r"inputs must give a value for theta2"),
        (dict(inputs=[0.1]), r"inputs must be a dict keyed by theta2; got \[0\.1\]"),
        (dict(inputs={th2: [0.0, np.inf]}), r"inputs\[theta2\] must be finite.*got inf"),
        (dict(rates={th2: np.nan}), r"rates\[theta2\] must be finite.*got nan"),
        (dict(rates={"omega2": 1.0}), r"rates has the key 'omega2'"),
        (dict(guess={th3: np.nan, th4: 1.6}), r"guess\[theta3\] must be finite.*got nan"),
        (dict(guess={th3: 0.4}), r"guess must give a value for theta4"),
        (dict(guess={th3: [0.4, 0.5], th4: 1.6}), r"guess must give one number per unknown"),
        (dict(inputs={th2: [0.1, 0.2, 0.3]}, rates={th2: [1.0, 2.0]}),
         r"must broadcast to one shape; got shapes .*'inputs\[theta2\]': \(3,\).*'rates\[theta2\]': \(2,\)"),
        (dict(on_failure="ignore"), r"on_failure must be one of 'raise', 'nan'; got 'ignore'"),
        (dict(tol=-1.0), r"tol must be a positive number; got -1\.0"),
    ],
)
def test_bad_inputs_name_the_argument_and_value(arguments, message):
    call = dict(inputs={th2: 0.3}, guess=GUESS) | arguments
    with pytest.raises(InvalidGeometryError, match=message):
        WIPER.solve(**call)


def test_joints_need_declared_points():
    with pytest.raises(InvalidGeometryError, match="joints needs points"):
        fourbar((0.2, 0.06, 0.18, 0.12)).joints(WIPER.solve({th2: 0.3}, guess=GUESS))


# ------------------------------------------------------------------ shared derivations, the course's routes


def test_with_parameters_shares_the_derivation_and_changes_the_numbers():
    other = WIPER.with_parameters({"l1": 0.20, "l2": 0.06, l3: 0.20, l4: 0.12})
    theta2 = np.linspace(0.0, 6.0, 7)
    motion = other.solve({th2: theta2}, {th2: 2.0}, guess=GUESS)
    closed = FourBar(0.06, 0.20, 0.12, 0.20).solve(theta2)
    assert angle_gap(motion.position["theta4"], closed.theta4) < 1e-12
    omega3 = norton_rates(theta2, closed.theta3, closed.theta4, 2.0, 0.0, (0.20, 0.06, 0.20, 0.12))[0]
    np.testing.assert_allclose(motion.velocity["theta3"], omega3, rtol=1e-12, atol=1e-12)
    assert other._derived is WIPER._derived and WIPER.parameters[l3] == 0.18
    partial = WIPER.with_parameters({l3: 0.20})  # the others keep their numbers
    assert dict(partial.parameters) == dict(other.parameters)
    with pytest.raises(InvalidGeometryError, match=r"some of \[l1, l2, l3, l4\] and nothing else"):
        WIPER.with_parameters({"l5": 0.2})
    with pytest.raises(InvalidGeometryError, match=r"parameters\[l2\] must be finite"):
        WIPER.with_parameters({l1: 0.2, l2: np.nan, l3: 0.18, l4: 0.12})


def test_rates_with_known_trig_or_own_singular_mask_are_the_same_rates():
    theta2 = np.linspace(0, 2 * np.pi, 50)
    closed = DESK.solve(theta2)
    q, u = np.stack([closed.theta3, closed.theta4], -1), theta2[:, None]
    plain = WIPER.unknown_rates(q, u, [10.0], [3.0])
    trig = {name: (np.cos(a), np.sin(a)) for name, a in (("theta2", theta2), ("theta3", q[:, 0]))}
    known = WIPER.unknown_rates(q, u, [10.0], [3.0], trig=trig, singular=np.arange(50) == 7)
    older = WIPER.rates(q, u, [10.0], [3.0])                          # the older name, the same numbers
    assert all(np.array_equal(a, b, equal_nan=True) for a, b in zip(older, plain, strict=True))
    _, omega4, alpha3, _ = norton_rates(theta2, q[:, 0], q[:, 1], 10.0, 3.0)
    np.testing.assert_allclose(plain[0][:, 1], omega4, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(plain[1][:, 0], alpha3, rtol=1e-11, atol=1e-10)
    np.testing.assert_allclose(known[0][known[2] == 0], plain[0][known[2] == 0], rtol=1e-13)
    assert np.isnan(known[0][7]).all() and np.isnan(known[1][7]).all() and not plain[2].any()


def test_consecutive_and_simultaneous_routes_one_instant_and_batched():
    u, u_rate, u_acc, seed = [0.7], [10.0], [3.0], [0.4, 1.6, 0.0, 0.0, 0.0, 0.0]
    stages = WIPER.consecutive(u, u_rate, u_acc, seed, tol=1e-12)
    staged = WIPER.solve({th2: 0.7}, {th2: 10.0}, {th2: 3.0}, guess=GUESS)
    expected = [staged.position["theta3"], staged.position["theta4"], staged.velocity["theta3"],
                staged.velocity["theta4"], staged.acceleration["theta3"], staged.acceleration["theta4"]]
    np.testing.assert_allclose(np.concatenate([r.x for r in stages.values()]), expected, atol=1e-10)
    assert [r.iterations for r in stages.values()][1:] == [2, 2]  # linear stages: one step and a check
    assert len(stages["position"].history) == stages["position"].iterations + 1
    direct = WIPER.consecutive(u, u_rate, u_acc, seed, tol=1e-12, linear_stages="direct")
    assert direct["velocity"].iterations == direct["acceleration"].iterations == 1
    np.testing.assert_allclose(WIPER.simultaneous(u, u_rate, u_acc, seed, tol=1e-12).x, expected, atol=1e-10)
    # batched: every instant from the same seed, the same Newton steps as one at a time
    theta2 = np.linspace(0.2, 1.2, 5)[:, None]
    batch = WIPER.consecutive(theta2, np.full_like(theta2, 10.0), np.zeros_like(theta2), seed)
    for k in (0, 4):
        one = WIPER.consecutive(theta2[k], [10.0], [0.0], seed)
        for stage in one:
            assert batch[stage].iterations[k] == one[stage].iterations
            np.testing.assert_allclose(batch[stage].x[k], one[stage].x, rtol=1e-12, atol=1e-13)
    with pytest.raises(ConvergenceError, match=r"position stage at theta2=0\.7: Newton did not converge"):
        WIPER.consecutive(u, u_rate, u_acc, seed, max_iter=2)
    with pytest.raises(SingularJacobianError,
                       match="position stage at theta2=0.7: the Jacobian is ill-conditioned"):
        WIPER.consecutive(u, u_rate, u_acc, [1.0, 1.0, 0, 0, 0, 0])
    with pytest.raises(InvalidGeometryError, match="linear_stages must be one of"):
        WIPER.consecutive(u, u_rate, u_acc, seed, linear_stages="exact")


def test_an_equivalent_position_form_replaces_the_position_rows():
    # the loop with its rows swapped: the same roots, another position stage and the same rates
    swapped = Mechanism([sp.Matrix([LOOP[1], LOOP[0]])], [th3, th4], [th2], WIPER_LENGTHS)
    seed, motion = [0.4, 1.6, 0, 0, 0, 0], ([0.7], [10.0], [3.0])
    x = np.array([0.5, 1.5, 1.0, 2.0, 3.0, 4.0])
    G, JG = WIPER.system(x, *motion, position=swapped)
    G_loop, JG_loop = WIPER.system(x, *motion)
    np.testing.assert_array_equal(G[:2], G_loop[[1, 0]])
    np.testing.assert_array_equal(JG[:2], JG_loop[[1, 0]])
    np.testing.assert_array_equal(JG[2:], JG_loop[2:])
    a, b = WIPER.simultaneous(*motion, seed, position=swapped), WIPER.simultaneous(*motion, seed)
    np.testing.assert_allclose(a.x, b.x, atol=1e-9)
    stages = WIPER.consecutive(*motion, seed, position=swapped)
    np.testing.assert_allclose(stages["velocity"].x, b.x[2:4], atol=1e-9)


def test_the_compiled_code_does_not_depend_on_what_the_process_made_before():
    # a numbered Dummy among lambdify's arguments made it rename them all with Dummies numbered from a
    # process-wide counter, and those numbers ordered the printed sums: the bits of F could change from
    # one declaration to the next ("_Dummy_998" sorts after "_Dummy_1003")
    import inspect

    from course_lib import saw

    sources = []
    for made_before in (0, 1000):
        for _ in range(made_before):
            sp.Dummy()
        mechanism = saw._declaration.__wrapped__("substituted")
        sources.append(inspect.getsource(mechanism._newton_fn.function))
    assert sources[0] == sources[1]
    assert "r1y" in sources[0] and "Dummy" not in sources[0], sources[0]


def test_links_named_on_the_declaration_and_a_motion_of_values_found_elsewhere():
    named = Mechanism([LOOP], [th3, th4], [th2], WIPER_LENGTHS, points=WIPER_POINTS,
                      links={"crank": ("O2", "A"), "coupler": ("A", "B"), "rocker": ("B", "O4")})
    assert named.links == WIPER.links and named.links.names == ("crank", "coupler", "rocker")
    assert WIPER.links.names == ("link 1", "link 2", "link 3")  # a plain list keeps the old names
    with pytest.raises(InvalidGeometryError, match=r"links must be named by text; got the names \[3\]"):
        Mechanism([LOOP], [th3, th4], [th2], WIPER_LENGTHS, points=WIPER_POINTS, links={3: ("O2", "A")})
    # motion_of: the circle construction's positions (tests/geometry.py) as a Motion, singular by the rule
    theta2 = np.array([0.3, 1.1])
    A, B = fourbar_pins(0.20, 0.06, 0.18, 0.12, theta2, "open")
    position = {"theta3": np.arctan2(B[:, 1] - A[:, 1], B[:, 0] - A[:, 0]),
                "theta4": np.arctan2(B[:, 1], B[:, 0] - 0.20)}
    motion = WIPER.motion_of(position, {"theta2": theta2})
    assert motion.converged.tolist() == [True, True] and not motion.singular.any()
    np.testing.assert_allclose(WIPER.joints(motion)["B"], B, atol=1e-15)
    with pytest.raises(InvalidGeometryError, match=r"position must map each of \['theta3', 'theta4'\]"):
        WIPER.motion_of({"theta3": 0.1}, {"theta2": 0.3})
    with pytest.raises(InvalidGeometryError, match=r"position\[theta4\] must be .*got 'x'"):
        WIPER.motion_of({"theta3": 0.1, "theta4": "x"}, {"theta2": 0.3})
    assert bool(WIPER.is_singular([0.2, 0.2], [0.0])) and not WIPER.is_singular([0.4, 1.6], [0.0])
