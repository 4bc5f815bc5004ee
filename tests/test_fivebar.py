"""Tests for course_lib.fivebar: the course's closed forms re-derived in sympy, round trips in
every working mode, the meaning of σ, the degenerate cases, singularities and bad input.

Expected values come from independent routes: a sympy derivation of the constraint equations,
a direct circle–circle intersection written here, finite differences, and course_lib.newton.
"""

import math
import warnings

import geometry
import numpy as np
import pytest
import sympy as sp
from hypothesis import assume, given
from hypothesis import strategies as st

from course_lib.errors import InvalidGeometryError, SingularJacobianError, UnreachableError
from course_lib.fivebar import WORKING_MODES, FiveBar
from course_lib.newton import newton

ROBOT = FiveBar(l1=0.10, l2=0.15, l3=0.15, l4=0.10, l5=0.08)
ANGLE = st.floats(-math.pi, math.pi, allow_nan=False)
MODE = st.sampled_from([1, -1])

# ----------------------------------------------------------------------------- sympy derivation
l1, l2, l3, l4, l5 = sp.symbols("l1:6", positive=True)
th1, th4, X3, Y3, u = sp.symbols("theta1 theta4 X3 Y3 u", real=True)
P2 = sp.Matrix([l1 * sp.cos(th1) + l5 / 2, l1 * sp.sin(th1)])
P4 = sp.Matrix([l4 * sp.cos(th4) - l5 / 2, l4 * sp.sin(th4)])
P3 = sp.Matrix([X3, Y3])
ECL2 = (P3 - P2).dot(P3 - P2) - l2**2
ECL3 = (P3 - P4).dot(P3 - P4) - l3**2
LENGTHS = {l1: 0.10, l2: 0.15, l3: 0.15, l4: 0.10, l5: 0.08}


F_SYM, G_SYM = sp.symbols("f g", real=True)


PYTHAGORAS = {sp.sin(th1) ** 2: 1 - sp.cos(th1) ** 2, sp.sin(th4) ** 2: 1 - sp.cos(th4) ** 2}


def _identical_zero_form(expression):
    """Expanded, with sin² replaced by 1 − cos²: two equal expressions give the same form."""
    return sp.expand(sp.expand(expression).subs(PYTHAGORAS))


def _linear_relation():
    """EcL2 − EcL3 is linear in X3, Y3: solve it for X3 = g·Y3 + f (explicit f, g)."""
    difference = sp.expand(ECL2 - ECL3)
    coefficient_x, coefficient_y = difference.coeff(X3), difference.coeff(Y3)
    rest = _identical_zero_form(difference.subs({X3: 0, Y3: 0}))
    return -rest / coefficient_x, -coefficient_y / coefficient_x


def _quadratic(into):
    """Substitute X3 = g·Y3 + f (f, g kept as symbols, as the course does): [a, B, c] in Y3."""
    return sp.Poly(sp.expand(into.subs(X3, G_SYM * Y3 + F_SYM)), Y3).all_coeffs()


def _lambdified(expressions, variables):
    return sp.lambdify(variables, [sp.sympify(e).subs(LENGTHS) for e in expressions], "numpy")


F_EXPLICIT, G_EXPLICIT = _linear_relation()
FG_NUMERIC = _lambdified([F_EXPLICIT, G_EXPLICIT], [th1, th4])


def test_f_and_g_match_the_sympy_derivation():
    course_f = (l1**2 - l2**2 + l3**2 - l4**2 + l1 * l5 * sp.cos(th1) + l4 * l5 * sp.cos(th4)) / (
        2 * (l5 + l1 * sp.cos(th1) - l4 * sp.cos(th4))
    )
    denominator = 2 * (l5 + l1 * sp.cos(th1) - l4 * sp.cos(th4))
    course_g = (-2 * l1 * sp.sin(th1) + 2 * l4 * sp.sin(th4)) / denominator
    assert sp.cancel(F_EXPLICIT - course_f) == 0 and sp.cancel(G_EXPLICIT - course_g) == 0
    angles = np.array([[0.3, 2.9], [1.2, 1.9], [-0.7, 2.2], [2.5, 0.4]])
    k = ROBOT.forward_coefficients(angles[:, 0], angles[:, 1])
    f_sym, g_sym = FG_NUMERIC(angles[:, 0], angles[:, 1])
    assert np.allclose(k["f"], f_sym, rtol=1e-12, atol=1e-15)
    assert np.allclose(k["g"], g_sym, rtol=1e-12, atol=1e-15)


def test_quadratic_in_y3_matches_the_course_file_000():
    """a·Y3² + b·Y3 + c from substituting into EcL3 equals the course's printed a, b, c."""
    a_s, b_s, c_s = _quadratic(ECL3)
    fs, gs = F_SYM, G_SYM
    printed_b = 2 * fs * gs + gs * l5 - 2 * gs * l4 * sp.cos(th4) - 2 * l4 * sp.sin(th4)
    printed_c = fs**2 - l3**2 + l4**2 + fs * l5 + l5**2 / 4 - l4 * (2 * fs + l5) * sp.cos(th4)
    for derived, course in zip((a_s, b_s, c_s), [1 + gs**2, printed_b, printed_c], strict=True):
        assert _identical_zero_form(derived - course) == 0
    f_n, g_n = FG_NUMERIC(1.2, 1.9)
    numeric = _lambdified([a_s, b_s, c_s], [th1, th4, fs, gs])(1.2, 1.9, f_n, g_n)
    k = ROBOT.forward_coefficients(1.2, 1.9)
    assert np.allclose([k["a"], k["b"], k["c"]], numeric, rtol=1e-12)


def test_file_002_route_gives_the_same_roots_with_b_of_opposite_sign_convention():
    """002 substitutes into EcL2 and writes Y3 = (b + σ√…)/2a with its own b = −B."""
    a_s, b_s, c_s = _quadratic(ECL2)
    fs, gs = F_SYM, G_SYM
    b_002 = -2 * fs * gs + gs * l5 + 2 * gs * l1 * sp.cos(th1) + 2 * l1 * sp.sin(th1)
    c_002 = fs**2 + l1**2 - l2**2 - fs * l5 + l5**2 / 4 + l1 * (l5 - 2 * fs) * sp.cos(th1)
    assert _identical_zero_form(b_s + b_002) == 0  # B = −b
    assert _identical_zero_form(c_s - c_002) == 0 and sp.expand(a_s - 1 - gs**2) == 0
    f_n, g_n = FG_NUMERIC(1.2, 1.9)
    a_n, b_n, c_n = (float(v) for v in _lambdified([a_s, b_002, c_s], [th1, th4, fs, gs])(1.2, 1.9, f_n, g_n))
    for sigma in (1, -1):
        y3_002 = (b_n + sigma * math.sqrt(b_n**2 - 4 * a_n * c_n)) / (2 * a_n)
        assert abs(ROBOT.forward(1.2, 1.9, sigma).y3 - y3_002) < 1e-14


def test_half_angle_coefficients_match_the_sympy_derivation():
    for equation, angle, names in ((ECL2, th1, ("a1", "b1", "c1")), (ECL3, th4, ("a2", "b2", "c2"))):
        expanded = sp.expand(sp.expand_trig(sp.expand(equation)))
        expanded = expanded.subs({sp.sin(angle) ** 2: 1 - sp.cos(angle) ** 2})
        tangent = expanded.subs(
            {sp.cos(angle): (1 - u**2) / (1 + u**2), sp.sin(angle): 2 * u / (1 + u**2)}
        )
        polynomial = sp.Poly(sp.expand(sp.cancel(tangent * (1 + u**2))), u)
        a_s, b_s, c_s = polynomial.all_coeffs()
        numeric = _lambdified([a_s, b_s, c_s], [X3, Y3])
        points = np.array([[0.0, 0.2], [0.05, 0.12], [-0.11, 0.18], [0.02, -0.15]])
        k = ROBOT.inverse_coefficients(points[:, 0], points[:, 1])
        for name, expected in zip(names, numeric(points[:, 0], points[:, 1]), strict=True):
            assert np.allclose(k[name], expected, rtol=1e-12, atol=1e-15)


# ------------------------------------------------------------------------------ helpers (independent)
def residuals(robot, theta1, theta4, x3, y3):
    """|P3 − P2| − l2 and |P3 − P4| − l3, written out here."""
    p2 = (robot.l1 * math.cos(theta1) + robot.l5 / 2, robot.l1 * math.sin(theta1))
    p4 = (robot.l4 * math.cos(theta4) - robot.l5 / 2, robot.l4 * math.sin(theta4))
    return (math.hypot(x3 - p2[0], y3 - p2[1]) - robot.l2, math.hypot(x3 - p4[0], y3 - p4[1]) - robot.l3)


def circle_intersections(robot, theta1, theta4):
    """Both points at distance l2 from P2 and l3 from P4 (textbook circle–circle formula)."""
    p2 = np.array([robot.l1 * math.cos(theta1) + robot.l5 / 2, robot.l1 * math.sin(theta1)])
    p4 = np.array([robot.l4 * math.cos(theta4) - robot.l5 / 2, robot.l4 * math.sin(theta4)])
    return geometry.circle_intersections(p4, robot.l3, p2, robot.l2)


def angle_gap(a, b):
    return abs((a - b + math.pi) % (2 * math.pi) - math.pi)


def well_conditioned(robot, theta1, theta4, x3, y3, margin=1e-3):
    m = robot.singularity_measures(theta1, theta4, x3, y3)
    return min(abs(m.serial_leg1), abs(m.serial_leg4), abs(m.parallel)) > margin


# ------------------------------------------------------------------------------------ round trips
@given(ANGLE, ANGLE, MODE)
def test_forward_matches_circle_intersection_and_sigma_is_the_larger_y3(theta1, theta4, mode):
    result = ROBOT.forward(theta1, theta4, mode, on_failure="nan")
    assume(result.reachable)
    first, second = circle_intersections(ROBOT, theta1, theta4)
    upper, lower = (first, second) if first[1] >= second[1] else (second, first)
    expected = upper if mode == 1 else lower
    assume(abs(first[1] - second[1]) > 1e-9)  # ties (D = 0) are tested on their own below
    assert np.allclose([result.x3, result.y3], expected, atol=1e-12)
    assert max(abs(r) for r in residuals(ROBOT, theta1, theta4, result.x3, result.y3)) < 1e-13


@given(ANGLE, ANGLE, MODE)
def test_inverse_of_forward_recovers_the_cranks_in_one_working_mode(theta1, theta4, mode):
    x3, y3 = ROBOT.forward(theta1, theta4, mode, on_failure="nan")
    assume(np.isfinite(x3) and well_conditioned(ROBOT, theta1, theta4, x3, y3))
    gaps = []
    for modes in WORKING_MODES:
        back1, back4 = ROBOT.inverse(x3, y3, modes)
        gaps.append(max(angle_gap(back1, theta1), angle_gap(back4, theta4)))
    assert sorted(gaps)[0] < 1e-9
    assert sorted(gaps)[1] > 1e-6  # and only one mode does


@given(st.floats(-0.3, 0.3), st.floats(-0.3, 0.3), st.sampled_from(WORKING_MODES))
def test_forward_of_inverse_returns_the_point_in_every_mode(x3, y3, modes):
    theta1, theta4 = ROBOT.inverse(x3, y3, modes, on_failure="nan")
    assume(np.isfinite(theta1) and well_conditioned(ROBOT, theta1, theta4, x3, y3))
    assert max(abs(r) for r in residuals(ROBOT, theta1, theta4, x3, y3)) < 1e-12
    candidates = [ROBOT.forward(theta1, theta4, mode) for mode in (1, -1)]
    assert min(math.hypot(c.x3 - x3, c.y3 - y3) for c in candidates) < 1e-10


@given(st.floats(-0.3, 0.3), st.floats(-0.3, 0.3), MODE, MODE)
def test_sigma_takes_the_course_root_of_the_half_angle_formula(x3, y3, sigma1, sigma2):
    k = ROBOT.inverse_coefficients(x3, y3)
    assume(abs(k["a1"]) > 1e-4 and abs(k["a2"]) > 1e-4)
    d1, d2 = k["b1"] ** 2 - 4 * k["a1"] * k["c1"], k["b2"] ** 2 - 4 * k["a2"] * k["c2"]
    assume(d1 > 1e-8 and d2 > 1e-8)
    course1 = 2 * math.atan((-k["b1"] + sigma1 * math.sqrt(d1)) / (2 * k["a1"]))
    course4 = 2 * math.atan((-k["b2"] + sigma2 * math.sqrt(d2)) / (2 * k["a2"]))
    theta1, theta4 = ROBOT.inverse(x3, y3, (sigma1, sigma2))
    assert angle_gap(theta1, course1) < 1e-9 and angle_gap(theta4, course4) < 1e-9


def test_forward_agrees_with_newton_on_the_two_constraints():
    theta1, theta4 = 1.2, 1.9
    for mode, seed in ((1, [0.0, 0.25]), (-1, [0.0, -0.05])):
        result = newton(lambda p: np.array(residuals(ROBOT, theta1, theta4, *p)), np.array(seed), tol=1e-13)
        assert np.allclose(list(ROBOT.forward(theta1, theta4, mode)), result.x, atol=1e-12)


def test_arrays_broadcast_like_scalar_calls():
    theta1 = np.linspace(0.2, 2.0, 3)[:, None]
    theta4 = np.linspace(1.0, 2.9, 4)[None, :]
    result = ROBOT.forward(theta1, theta4, -1)
    assert result.x3.shape == (3, 4)
    assert result.y3[2, 1] == ROBOT.forward(2.0, theta4[0, 1], -1).y3
    back = ROBOT.inverse(result.x3, result.y3, (1, -1), on_failure="nan")
    assert back.theta1.shape == (3, 4)
    assert ROBOT.joints(theta1, theta4, result.x3, result.y3).shape == (3, 4, 5, 2)


# ----------------------------------------------------------------------------------- degenerate cases
def _d_zero_angles(theta1=2.0):
    """θ4 with D = l5 + l1 cos θ1 − l4 cos θ4 = 0 (P2 straight above/below P4)."""
    return theta1, math.acos((ROBOT.l5 + ROBOT.l1 * math.cos(theta1)) / ROBOT.l4)


def test_denominator_zero_is_solved_without_warnings():
    theta1, theta4 = _d_zero_angles()
    assert abs(ROBOT.forward_coefficients(theta1, theta4)["D"]) < 1e-15
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        up = ROBOT.forward(theta1, theta4, +1)
        down = ROBOT.forward(theta1, theta4, -1)
    expected = circle_intersections(ROBOT, theta1, theta4)
    for point in (up, down):
        assert max(abs(r) for r in residuals(ROBOT, theta1, theta4, *point)) < 1e-14
        assert min(math.hypot(point.x3 - e[0], point.y3 - e[1]) for e in expected) < 1e-13
    assert abs(up.y3 - down.y3) < 1e-13 and abs(up.x3 - down.x3) > 0.01  # a tie in Y3


def test_sigma_keeps_larger_y3_on_both_sides_of_d_zero():
    """The course's σ switches between the two assemblies where D changes sign (their Y3 tie)."""
    theta1, theta4 = _d_zero_angles()
    for offset in (-1e-3, -1e-9, 0.0, 1e-9, 1e-3):
        up, down = ROBOT.forward(theta1 + offset, theta4, 1), ROBOT.forward(theta1 + offset, theta4, -1)
        assert up.y3 >= down.y3 - 1e-15 and abs(up.x3 - down.x3) > 0.01
    before, after = ROBOT.forward(theta1 - 1e-9, theta4, 1), ROBOT.forward(theta1 + 1e-9, theta4, 1)
    assert abs(before.x3 - after.x3) > 0.2  # the jump: σ = +1 changes assembly across D = 0


def test_exact_d_zero_takes_the_limit_from_positive_d():
    robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.0)  # P2 = (ε, 0.1), P4 = (ε, −0.1): D = 0 exactly
    assert robot.forward_coefficients(math.pi / 2, -math.pi / 2)["D"] == 0.0
    at_zero = robot.forward(math.pi / 2, -math.pi / 2, 1)
    half_chord = math.sqrt(0.15**2 - 0.10**2)
    assert abs(at_zero.x3 + half_chord) < 1e-15 and abs(at_zero.y3) < 1e-15  # left of P4 → P2
    assert robot.forward_coefficients(math.pi / 2, -math.pi / 2 - 1e-7)["D"] > 0
    nearby = robot.forward(math.pi / 2, -math.pi / 2 - 1e-7, 1)
    assert math.hypot(at_zero.x3 - nearby.x3, at_zero.y3 - nearby.y3) < 1e-6
    assert abs(robot.forward(math.pi / 2, -math.pi / 2, -1).x3 - half_chord) < 1e-15


def test_a1_zero_gives_theta_pi_where_the_course_formula_divides_by_zero():
    # P3 on the circle of radius l2 about P2 = P1 + l1(cos π, sin π)
    x3, y3 = ROBOT.l5 / 2 - ROBOT.l1 + ROBOT.l2 * math.cos(1.3), ROBOT.l2 * math.sin(1.3)
    k = ROBOT.inverse_coefficients(x3, y3)
    assert abs(k["a1"]) < 1e-15
    roots = [ROBOT.inverse(x3, y3, (sigma, 1)).theta1 for sigma in (1, -1)]
    assert min(angle_gap(root, math.pi) for root in roots) < 1e-12
    for theta1 in roots:
        assert abs(residuals(ROBOT, theta1, 0.0, x3, y3)[0]) < 1e-14
    # σ keeps its meaning: the finite root is the course's with the same σ, the other is π
    sigma_finite = 1 if k["b1"] > 0 else -1
    finite = ROBOT.inverse(x3, y3, (sigma_finite, 1)).theta1
    assert angle_gap(finite, 2 * math.atan(-k["c1"] / k["b1"])) < 1e-12


def test_tiny_a1_keeps_both_roots_accurate():
    x3, y3 = ROBOT.l5 / 2 - ROBOT.l1 + ROBOT.l2 * math.cos(1.3) + 1e-12, ROBOT.l2 * math.sin(1.3)
    assert 0 < abs(ROBOT.inverse_coefficients(x3, y3)["a1"]) < 1e-11
    for sigma in (1, -1):
        theta1 = ROBOT.inverse(x3, y3, (sigma, 1)).theta1
        assert abs(residuals(ROBOT, theta1, 0.0, x3, y3)[0]) < 1e-14


@given(ANGLE, ANGLE, MODE)
def test_coincident_pivots_l5_zero(theta1, theta4, mode):
    robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.0)
    x3, y3 = robot.forward(theta1, theta4, mode, on_failure="nan")
    assume(np.isfinite(x3) and well_conditioned(robot, theta1, theta4, x3, y3))
    assert max(abs(r) for r in residuals(robot, theta1, theta4, x3, y3)) < 1e-13
    assert np.allclose(robot.joints(theta1, theta4, x3, y3)[[0, 4]], 0.0)
    solutions = [robot.inverse(x3, y3, modes) for modes in WORKING_MODES]
    assert min(max(angle_gap(a, theta1), angle_gap(b, theta4)) for a, b in solutions) < 1e-9


def test_p2_on_p4_is_reported():
    robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.0)  # θ1 = θ4 puts P2 exactly on P4
    with pytest.raises(UnreachableError, match="P2 and P4 coincide"):
        robot.forward(0.7, 0.7)
    assert not robot.forward(0.7, 0.7, on_failure="nan").reachable


# ------------------------------------------------------------------------------------ singularities
def test_serial_singularity_stretched_leg_is_detected():
    phi = 1.9
    x3, y3 = ROBOT.l5 / 2 + 0.25 * math.cos(phi), 0.25 * math.sin(phi)  # |P3 − P1| = l1 + l2
    theta1, theta4 = ROBOT.inverse(x3, y3, (1, -1))
    assert angle_gap(theta1, phi) < 1e-7
    assert abs(ROBOT.singularity_measures(theta1, theta4, x3, y3).serial_leg1) < 1e-7
    with pytest.raises(SingularJacobianError, match="leg 1"):
        ROBOT.crank_rates(theta1, theta4, x3, y3, 0.01, 0.0)
    assert np.isnan(ROBOT.crank_rates(theta1, theta4, x3, y3, 0.01, 0.0, on_failure="nan")).all()


def test_serial_singularity_folded_leg4_is_detected():
    short = FiveBar(0.10, 0.15, 0.06, 0.10, 0.08)  # leg 4 folds: |P3 − P5| = l4 − l3
    x3, y3 = -0.04 + 0.04 * math.cos(2.0), 0.04 * math.sin(2.0)
    theta1, theta4 = short.inverse(x3, y3, (-1, 1))
    assert abs(short.singularity_measures(theta1, theta4, x3, y3).serial_leg4) < 1e-7
    with pytest.raises(SingularJacobianError, match="leg 4"):
        short.crank_rates(theta1, theta4, x3, y3, 0.0, 0.01)


def test_parallel_singularity_is_detected_where_the_forward_roots_merge():
    robot = FiveBar(0.10, 0.12, 0.12, 0.10, 0.08)  # l1 + l4 + l5 > l2 + l3: distal links can stretch
    theta4 = math.acos((0.0424 - 0.0576) / 0.036)  # |P2 − P4| = l2 + l3 = 0.24 with θ1 = 0
    p2, p4 = np.array([0.14, 0.0]), np.array([0.1 * math.cos(theta4) - 0.04, 0.1 * math.sin(theta4)])
    assert abs(np.linalg.norm(p2 - p4) - 0.24) < 1e-12
    up, down = robot.forward(0.0, theta4, 1), robot.forward(0.0, theta4, -1)
    assert math.hypot(up.x3 - down.x3, up.y3 - down.y3) < 1e-6
    assert abs(robot.singularity_measures(0.0, theta4, *up).parallel) < 1e-7
    with pytest.raises(SingularJacobianError, match="parallel"):
        robot.end_effector_velocity(0.0, theta4, *up, 1.0, 0.0)


def test_jacobians_match_finite_differences():
    theta1, theta4 = 1.2, 1.9
    x3, y3 = ROBOT.forward(theta1, theta4)
    h = 1e-6
    A = ROBOT.jacobian_end_effector(theta1, theta4, x3, y3)
    B = ROBOT.jacobian_cranks(theta1, theta4, x3, y3)
    c = ROBOT.constraints
    A_fd = np.stack([(c(theta1, theta4, x3 + h, y3) - c(theta1, theta4, x3 - h, y3)) / (2 * h),
                     (c(theta1, theta4, x3, y3 + h) - c(theta1, theta4, x3, y3 - h)) / (2 * h)], axis=1)
    B_fd = np.stack([(c(theta1 + h, theta4, x3, y3) - c(theta1 - h, theta4, x3, y3)) / (2 * h),
                     (c(theta1, theta4 + h, x3, y3) - c(theta1, theta4 - h, x3, y3)) / (2 * h)], axis=1)
    assert np.allclose(A, A_fd, atol=1e-9) and np.allclose(B, B_fd, atol=1e-9)


def test_velocities_match_finite_differences_of_the_position_solutions():
    theta1, theta4, omega1, omega4, dt = 1.2, 1.9, 0.7, -1.3, 1e-6
    x3, y3 = ROBOT.forward(theta1, theta4)
    ahead = np.array(list(ROBOT.forward(theta1 + omega1 * dt, theta4 + omega4 * dt)))
    behind = np.array(list(ROBOT.forward(theta1 - omega1 * dt, theta4 - omega4 * dt)))
    expected = (ahead - behind) / (2 * dt)
    velocity = ROBOT.end_effector_velocity(theta1, theta4, x3, y3, omega1, omega4)
    assert np.allclose(velocity, expected, atol=1e-7)
    modes = (-1, 1)  # the working mode that holds (1.2, 1.9) at this point
    assert angle_gap(ROBOT.inverse(x3, y3, modes).theta1, theta1) < 1e-9
    vx, vy = 0.03, -0.02
    ahead = np.array(list(ROBOT.inverse(x3 + vx * dt, y3 + vy * dt, modes)))
    behind = np.array(list(ROBOT.inverse(x3 - vx * dt, y3 - vy * dt, modes)))
    rates = ROBOT.crank_rates(theta1, theta4, x3, y3, vx, vy)
    assert np.allclose(rates, (ahead - behind) / (2 * dt), atol=1e-7)


def test_workspace_mask_is_the_intersection_of_two_annuli():
    x = np.linspace(-0.3, 0.3, 121)
    y = np.linspace(-0.3, 0.3, 101)
    X, Y = np.meshgrid(x, y)
    r1, r5 = np.hypot(X - 0.04, Y), np.hypot(X + 0.04, Y)
    expected = (r1 >= 0.05) & (r1 <= 0.25) & (r5 >= 0.05) & (r5 <= 0.25)
    clear = (np.abs(r1 - 0.05) > 1e-9) & (np.abs(r1 - 0.25) > 1e-9) & (np.abs(r5 - 0.05) > 1e-9)
    clear &= np.abs(r5 - 0.25) > 1e-9
    for modes in WORKING_MODES:
        w = ROBOT.workspace(x, y, modes)
        assert np.array_equal(w.reachable[clear], expected[clear])
        assert np.isnan(w.theta1[~w.reachable]).all() and np.isfinite(w.parallel[w.reachable]).all()
    assert 0.3 < expected.mean() < 0.5


def test_draw_names_the_links_and_labels_the_joints_where_they_are():
    theta1, theta4 = 1.2, 1.9
    end = ROBOT.forward(theta1, theta4)
    ax = ROBOT.draw(theta1, theta4, *end, title="arms up")
    lines = {line.get_gid(): line.get_xydata() for line in ax.lines if line.get_gid()}
    assert list(lines) == ["l1", "l2", "l3", "l4", "l5"]
    P2 = (0.04 + 0.10 * np.cos(theta1), 0.10 * np.sin(theta1))  # l5 / 2 + l1 (cos θ1, sin θ1)
    assert np.allclose(lines["l2"], [P2, (end.x3, end.y3)], atol=1e-15)
    assert [t.get_text() for t in ax.texts] == ["1", "2", "3", "4", "5"]
    assert ax.get_title() == "arms up"
    with pytest.raises(InvalidGeometryError, match="one configuration"):
        ROBOT.draw(np.array([1.0, 1.1]), theta4, 0.0, 0.2)


# ------------------------------------------------------------------------------------- bad input
@pytest.mark.parametrize(
    "lengths, name",
    [((0.0, 0.15, 0.15, 0.10, 0.08), "l1"), ((0.10, -0.15, 0.15, 0.10, 0.08), "l2"),
     ((0.10, 0.15, float("nan"), 0.10, 0.08), "l3"), ((0.10, 0.15, 0.15, float("inf"), 0.08), "l4"),
     ((0.10, 0.15, 0.15, 0.10, -0.01), "l5"), ((0.10, 0.15, 0.15, "long", 0.08), "l4")],
)
def test_bad_lengths_are_named(lengths, name):
    with pytest.raises(InvalidGeometryError, match=name):
        FiveBar(*lengths)


@pytest.mark.parametrize("mode", [0, 2, True, "up", 0.5])
def test_bad_forward_mode(mode):
    with pytest.raises(InvalidGeometryError, match="mode"):
        ROBOT.forward(1.0, 2.0, mode)


@pytest.mark.parametrize(
    "modes, name", [((1, 0), "sigma2"), ((2, 1), "sigma1"), (1, "modes"), ((1, 1, 1), "modes")]
)
def test_bad_inverse_modes(modes, name):
    with pytest.raises(InvalidGeometryError, match=name):
        ROBOT.inverse(0.0, 0.2, modes)


def test_bad_values_and_options_are_named():
    with pytest.raises(InvalidGeometryError, match="theta1"):
        ROBOT.forward(float("nan"), 1.0)
    with pytest.raises(InvalidGeometryError, match="y3"):
        ROBOT.inverse(0.0, float("inf"))
    with pytest.raises(InvalidGeometryError, match="on_failure"):
        ROBOT.inverse(0.0, 0.2, on_failure="ignore")
    with pytest.raises(InvalidGeometryError, match="on_failure"):
        ROBOT.crank_rates(1.2, 1.9, *ROBOT.forward(1.2, 1.9), 0.0, 0.0, on_failure="skip")
    with pytest.raises(InvalidGeometryError, match="not assembled"):
        ROBOT.end_effector_velocity(1.2, 1.9, 0.0, 0.0, 1.0, 1.0)
    with pytest.raises(InvalidGeometryError, match="1-D"):
        ROBOT.workspace(np.zeros((2, 2)), np.zeros(3))


def test_unreachable_inputs_are_named():
    with pytest.raises(UnreachableError, match=r"leg 1 .* x3=0.3, y3=0.2"):
        ROBOT.inverse(0.3, 0.2)
    with pytest.raises(UnreachableError, match=r"leg 4 .*\(1 of 2 inputs"):
        ROBOT.inverse([0.0, -0.03], [0.2, 0.0])  # (−0.03, 0) is 0.01 from P5, inside l3 − l4
    short = FiveBar(0.10, 0.10, 0.10, 0.10, 0.08)
    with pytest.raises(UnreachableError, match="theta1=0, theta4=3.14159"):
        short.forward(0.0, math.pi)
    result = short.inverse([0.0, 0.5], [0.15, 0.0], on_failure="nan")
    assert result.reachable.tolist() == [True, False] and np.isnan(result.theta4[1])


def test_rates_reject_non_finite_inputs():
    x3, y3 = ROBOT.forward(1.2, 1.9)
    with pytest.raises(InvalidGeometryError, match="omega4"):
        ROBOT.end_effector_velocity(1.2, 1.9, x3, y3, 1.0, float("nan"))
    with pytest.raises(InvalidGeometryError, match="vx"):
        ROBOT.crank_rates(1.2, 1.9, x3, y3, float("inf"), 0.0)


def test_parallel_singularities_lie_where_the_elbows_meet():
    """With l2 = l3 and l1 + l4 + l5 < l2 + l3 the distal links align only when P2 = P4, i.e. with
    the pen on a circle of radius l2 about Q± = (0, ±√(l1² − (l5/2)²))."""
    q = math.sqrt(ROBOT.l1**2 - (ROBOT.l5 / 2) ** 2)
    checked = 0
    for sign in (1, -1):
        for phi in np.linspace(0.2, 2 * math.pi - 0.2, 7):
            x3, y3 = 0.15 * math.cos(phi), sign * q + 0.15 * math.sin(phi)
            if not ROBOT.inverse(x3, y3, on_failure="nan").reachable:
                continue
            measures = [abs(ROBOT.singularity_measures(*ROBOT.inverse(x3, y3, m), x3, y3).parallel)
                        for m in WORKING_MODES]
            assert min(measures) < 1e-9 and sorted(measures)[1] > 1e-3
            checked += 1
    assert checked >= 8


def test_results_unpack_index_and_convert_with_numpy():
    x3, y3 = ROBOT.forward(1.2, 1.9)
    assert np.array(ROBOT.forward(1.2, 1.9)).tolist() == [x3, y3]
    many = ROBOT.forward([1.2, 1.0], [1.9, 2.0])
    assert np.array(many).shape == (2, 2) and np.array_equal(np.array(many)[1], many.y3)
    inverse = ROBOT.inverse(x3, y3, modes=(-1, 1))
    assert np.allclose(np.array(inverse), [1.2, 1.9]) and inverse[0] == inverse.theta1 and len(inverse) == 2
    measures = ROBOT.singularity_measures(1.2, 1.9, x3, y3)
    assert np.array(measures).tolist() == [measures.serial_leg1, measures.serial_leg4, measures.parallel]


# ------------------------------------------------------------------------------- large arrays
def test_large_arrays_give_what_single_points_give():
    """More points than one block of the closed form (65,536), with a scalar y3 or a (n, 1) × (1, m)
    broadcast: each entry is what the point alone gives, bit for bit, including the unreachable ones."""
    rng = np.random.default_rng(5)
    x = rng.uniform(-0.3, 0.3, 70_001)
    for y in (0.17, rng.uniform(-0.3, 0.3, 70_001)):
        result = ROBOT.inverse(x, y, (-1, 1), on_failure="nan")
        assert 0 < result.reachable.mean() < 1
        for i in [*range(0, x.size, 701), 65_535, 65_536, x.size - 1]:
            y_i = np.broadcast_to(y, x.shape)[i]
            alone = ROBOT.inverse(float(x[i]), float(y_i), (-1, 1), on_failure="nan")
            assert alone.reachable == result.reachable[i]
            assert np.array_equal([alone.theta1, alone.theta4], [result.theta1[i], result.theta4[i]],
                                  equal_nan=True)
    grid = ROBOT.inverse(x[:400, None], x[None, 400:700], (1, 1), on_failure="nan")
    assert grid.theta1.shape == (400, 300)
    assert np.array_equal(grid.theta4[123, 45], ROBOT.inverse(x[123], x[445], on_failure="nan").theta4,
                          equal_nan=True)


def test_a_large_workspace_agrees_with_inverse_and_the_measures():
    x, y = np.linspace(-0.3, 0.3, 300), np.linspace(-0.28, 0.3, 250)   # 75,000 points
    w = ROBOT.workspace(x, y, (1, -1))
    X, Y = np.meshgrid(x, y)
    solution = ROBOT.inverse(X, Y, (1, -1), on_failure="nan")
    ok = solution.reachable
    assert np.array_equal(w.reachable, ok) and 0.3 < ok.mean() < 0.5
    assert np.array_equal(w.theta1, solution.theta1, equal_nan=True)
    assert np.array_equal(w.x3, X) and np.array_equal(w.y3, Y)          # the grid, X3 across, Y3 up
    assert w.x is w.x3 and w.y is w.y3                                    # the older names
    measures = ROBOT.singularity_measures(solution.theta1[ok], solution.theta4[ok], X[ok], Y[ok])
    for name in ("serial_leg1", "serial_leg4", "parallel"):
        assert np.array_equal(getattr(w, name)[ok], getattr(measures, name))
        assert np.isnan(getattr(w, name)[~ok]).all()


# ------------------------------------------------------------------ the machine is its declaration
def test_the_course_closed_form_against_the_core_derivation_from_the_declaration():
    # the forward closed form (the course's X3 = g·Y3 + f) against the core's solve of the declared loops
    theta1, theta4 = 1.0 + np.linspace(0, 0.4, 9), 2.0 - np.linspace(0, 0.3, 9)
    closed = ROBOT.forward(theta1, theta4, mode=+1)
    core = ROBOT.mechanism.solve({"theta1": theta1, "theta4": theta4},
                                 guess={"x3": float(closed.x3[0]), "y3": float(closed.y3[0])})
    np.testing.assert_allclose(core.position["x3"], closed.x3, atol=1e-12)
    np.testing.assert_allclose(core.position["y3"], closed.y3, atol=1e-12)
    # the joints are the declared points P1 … P5, here against the cranks written out by hand
    joints = ROBOT.joints(theta1, theta4, closed.x3, closed.y3)
    P2 = np.stack([0.10 * np.cos(theta1) + 0.04, 0.10 * np.sin(theta1)], -1)
    P4 = np.stack([0.10 * np.cos(theta4) - 0.04, 0.10 * np.sin(theta4)], -1)
    np.testing.assert_allclose(joints[:, 1], P2, atol=1e-15)
    np.testing.assert_allclose(joints[:, 3], P4, atol=1e-15)
    assert ROBOT.mechanism.links.names == ("l1", "l2", "l3", "l4", "l5")


def test_the_motion_rates_by_finite_differences_and_one_failure_keyword():
    h, s = 1e-6, np.linspace(0.0, 0.4, 5)
    motion = ROBOT.motion(1.0 + s, 2.0 - s, omega1=1.0, omega4=-1.0)
    ahead, behind = ROBOT.forward(1.0 + s + h, 2.0 - s - h), ROBOT.forward(1.0 + s - h, 2.0 - s + h)
    np.testing.assert_allclose(motion.velocity["x3"], (ahead.x3 - behind.x3) / (2 * h), atol=1e-8)
    np.testing.assert_allclose(motion.velocity["y3"], (ahead.y3 - behind.y3) / (2 * h), atol=1e-8)
    short = FiveBar(0.10, 0.05, 0.05, 0.10, 0.08)  # distal links reach 0.1 m: P2, P4 0.28 m apart at θ4 = π
    cranks = ([np.pi / 2, np.pi / 2], [np.pi / 2, np.pi])
    far = short.forward(*cranks, on_failure="nan")
    assert far.reachable.tolist() == short.forward(*cranks, on_failure="nan").reachable.tolist()
    assert far.reachable.tolist() == [True, False]
    assert short.motion(*cranks, on_failure="nan").converged.tolist() == [True, False]
    inverse = ROBOT.inverse([0.0, 1.0], [0.2, 1.0], on_failure="nan")
    assert inverse.reachable.tolist() == [True, False]


def test_both_singularities_are_the_core_rule():
    # on a parallel singularity (P2, P3, P4 on one line: l2, l3 folded, |P2P4| = l2 − l3) the end-effector
    # Jacobian is singular by the core's rule: velocity_jacobian raises, or gives NaN (either spelling)
    robot = FiveBar(0.10, 0.15, 0.12, 0.10, 0.08)
    theta1, P2 = np.pi / 2, np.array([0.04, 0.10])
    low, high = 0.0, np.arctan2(0.10, 0.08)  # |P2 P4| falls from 0.1 m + to its least, below 0.03 m
    for _ in range(60):  # bisection for |P2 P4| = 0.03
        middle = (low + high) / 2
        P4 = np.array([0.10 * np.cos(middle) - 0.04, 0.10 * np.sin(middle)])
        low, high = (middle, high) if np.linalg.norm(P2 - P4) > 0.03 else (low, middle)
    theta4 = (low + high) / 2
    P4 = np.array([0.10 * np.cos(theta4) - 0.04, 0.10 * np.sin(theta4)])
    x3, y3 = P2 + 0.15 * (P4 - P2) / np.linalg.norm(P4 - P2)
    assert bool(robot.mechanism.is_singular([x3, y3], [theta1, theta4]))
    assert abs(robot.singularity_measures(theta1, theta4, x3, y3).parallel) < 1e-9
    with pytest.raises(SingularJacobianError, match="parallel"):
        robot.velocity_jacobian(theta1, theta4, x3, y3)
    assert np.isnan(robot.velocity_jacobian(theta1, theta4, x3, y3, on_failure="nan")).all()
    # a serial one: leg 1 stretched (P1, P2, P3 on one line), the crank rates singular
    x3, y3 = np.array([0.04, 0.0]) + 0.25 * np.array([np.cos(2.3), np.sin(2.3)])
    theta4 = robot.inverse(x3, y3).theta4
    assert bool(robot._cores["inverse"].is_singular([2.3, theta4], [x3, y3]))
    with pytest.raises(SingularJacobianError, match="leg 1"):
        robot.crank_rates(2.3, theta4, x3, y3, 0.0, 0.1)
