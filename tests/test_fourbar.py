"""Four-bar linkage: every result checked against a second, independent route.

Routes used: circle–circle intersection (B is where the l3-circle about A meets the
l4-circle about O4), Newton on the loop equations, Norton's half-angle formula for θ3
written out separately, the textbook sine formulas for ω3 and ω4, central finite
differences of the position solution, the law of cosines, and hand-enumerated
Grashof cases.
"""

import dataclasses
import math
import tracemalloc

import numpy as np
import pytest
from geometry import fourbar_pins
from hypothesis import assume, given
from hypothesis import strategies as st

from course_lib.errors import InvalidGeometryError, SingularJacobianError, UnreachableError
from course_lib.fourbar import BRANCHES, FourBar
from course_lib.newton import newton

DESK = FourBar(crank=0.06, coupler=0.18, rocker=0.12, ground=0.20)
SWEEP = np.linspace(-np.pi, np.pi, 721)


def cross_sign(linkage, theta2, branch):
    joints = linkage.joints(theta2, branch=branch)
    A, B, O4 = joints[..., 1, :], joints[..., 2, :], joints[..., 3, :]
    u, v = O4 - A, B - A
    return np.sign(u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0])


def angle_difference(a, b):
    return np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b)))))


# ---------------------------------------------------------------- position
@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_closed_form_matches_circle_intersection(branch):
    A, B = fourbar_pins(DESK.l1, DESK.l2, DESK.l3, DESK.l4, SWEEP, branch)
    solution = DESK.solve(SWEEP, branch=branch)
    theta4 = np.arctan2(B[:, 1], B[:, 0] - DESK.l1)
    theta3 = np.arctan2(B[:, 1] - A[:, 1], B[:, 0] - A[:, 0])
    assert angle_difference(solution.theta4, theta4).max() < 1e-12
    assert angle_difference(solution.theta3, theta3).max() < 1e-12


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_closed_form_matches_newton(branch):
    crank_angles = np.linspace(0, 2 * np.pi, 13)
    closed = DESK.solve(crank_angles, branch=branch)
    for theta2, theta3, theta4 in zip(crank_angles, closed.theta3, closed.theta4, strict=True):
        result = newton(
            lambda x, t2=theta2: DESK.loop_residual(t2, x[0], x[1]),
            np.array([theta3 + 0.1, theta4 - 0.1]),
            jac=lambda x: DESK.loop_jacobian(x[0], x[1]),
            tol=1e-13,
        )
        assert result.converged
        assert angle_difference(result.x, [theta3, theta4]).max() < 1e-12


@pytest.mark.parametrize(("branch", "sign"), [("open", -1), ("crossed", +1)])
def test_norton_theta3_formula(branch, sign):
    # Norton's second quadratic, in tan(θ3/2): D t² + E t + F = 0 (written out independently)
    a, b, c, d = DESK.l2, DESK.l3, DESK.l4, DESK.l1
    K1, K4, K5 = d / a, d / b, (c**2 - d**2 - a**2 - b**2) / (2 * a * b)
    D = np.cos(SWEEP) - K1 + K4 * np.cos(SWEEP) + K5
    E = -2 * np.sin(SWEEP)
    F = K1 + (K4 - 1) * np.cos(SWEEP) + K5
    theta3 = 2 * np.arctan2(-E + sign * np.sqrt(E**2 - 4 * D * F), 2 * D)
    assert angle_difference(DESK.solve(SWEEP, branch=branch).theta3, theta3).max() < 1e-12


def test_open_parallelogram_is_a_parallelogram():
    # l2 = l4 and l1 = l3: on the open branch the rocker stays parallel to the crank (0 < θ2 < π)
    parallelogram = FourBar(crank=0.1, coupler=0.3, rocker=0.1, ground=0.3)
    theta2 = np.linspace(0.1, np.pi - 0.1, 50)
    open_ = parallelogram.solve(theta2)
    assert angle_difference(open_.theta4, theta2).max() < 1e-9
    assert angle_difference(open_.theta3, 0.0).max() < 1e-9
    crossed = parallelogram.solve(theta2, branch="crossed")
    assert angle_difference(crossed.theta4, theta2).min() > 0.1


def test_open_branch_desk_crank_up_has_B_above_the_ground():
    # Norton's picture: crank up, links not crossed, B above O2O4; crossed: B below
    joints_open = DESK.joints(np.pi / 2)
    joints_crossed = DESK.joints(np.pi / 2, branch="crossed")
    assert joints_open[2, 1] > 0 > joints_crossed[2, 1]


@pytest.mark.parametrize(("branch", "sign"), [("open", 1), ("crossed", -1)])
def test_branch_is_one_circuit_over_a_revolution(branch, sign):
    assert np.all(cross_sign(DESK, SWEEP, branch) == sign)
    theta4 = DESK.solve(SWEEP, branch=branch).theta4
    step = angle_difference(theta4[1:], theta4[:-1])
    assert step.max() < 0.05  # no jump to the other circuit (crank step is 0.0087 rad)


lengths = st.floats(min_value=0.05, max_value=1.0, allow_nan=False)


@given(lengths, lengths, lengths, lengths, st.floats(min_value=-np.pi, max_value=np.pi))
def test_random_linkages_close_the_loop_on_both_branches(l1, l2, l3, l4, theta2):
    linkage = FourBar(crank=l2, coupler=l3, rocker=l4, ground=l1)
    solution = linkage.solve(theta2, on_failure="nan")
    distance = np.hypot(l1 - l2 * np.cos(theta2), l2 * np.sin(theta2))
    reachable = abs(l3 - l4) + 1e-9 < distance < l3 + l4 - 1e-9
    clearly_unreachable = distance > l3 + l4 + 1e-9 or distance < abs(l3 - l4) - 1e-9
    if reachable or clearly_unreachable:
        assert solution.mask == clearly_unreachable
    assume(reachable)
    for branch, side in (("open", 1), ("crossed", -1)):
        solution = linkage.solve(theta2, branch=branch)
        residual = linkage.loop_residual(theta2, solution.theta3, solution.theta4)
        assert np.abs(residual).max() <= 1e-12
        assert cross_sign(linkage, theta2, branch) == side


@given(
    st.floats(min_value=0.05, max_value=0.3),
    st.floats(min_value=0.05, max_value=1.0),
    st.floats(min_value=0.05, max_value=1.0),
    st.floats(min_value=0.05, max_value=1.0),
)
def test_random_sweeps_stay_on_their_circuit(crank, coupler, rocker, ground):
    linkage = FourBar(crank=crank, coupler=coupler, rocker=rocker, ground=ground)
    intervals = linkage.input_range().intervals
    assume(intervals)
    start, end = intervals[0]
    assume(end > start)  # closing at one toggle angle only: no circuit to stay on (see the test below)
    margin = 1e-3 * (end - start)
    theta2 = np.linspace(start + margin, end - margin, 200)
    for branch, side in (("open", 1), ("crossed", -1)):
        solution = linkage.solve(theta2, branch=branch)
        assert np.all(cross_sign(linkage, theta2, branch) == side)
        residual = linkage.loop_residual(theta2, solution.theta3, solution.theta4)
        assert np.abs(residual).max() <= 1e-12


def test_a_linkage_that_closes_at_one_toggle_angle_only():
    # |AO4| = l1 + l2 … never below l2 − l1 = 0.20 = l3 + l4: the loop closes at θ2 = 0 alone, stretched
    linkage = FourBar(crank=0.25, coupler=0.15, rocker=0.05, ground=0.05)
    assert linkage.input_range().intervals == ((0.0, 0.0),)
    solution = linkage.solve(0.0)
    assert np.abs(linkage.loop_residual(0.0, solution.theta3, solution.theta4)).max() < 1e-15
    assert angle_difference(solution.theta3 - solution.theta4, np.pi) < 1e-12  # coupler and rocker collinear
    with pytest.raises(SingularJacobianError, match="toggle"):
        linkage.solve(0.0, omega2=1.0)


# ------------------------------------------------------------------- rates
@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_velocity_matches_finite_differences_and_sine_formulas(branch):
    omega2, h = 10.0, 1e-6
    solution = DESK.solve(SWEEP, omega2, branch=branch)
    ahead, behind = DESK.solve(SWEEP + h, branch=branch), DESK.solve(SWEEP - h, branch=branch)
    for name in ("theta3", "theta4"):
        derivative = np.angle(np.exp(1j * (getattr(ahead, name) - getattr(behind, name)))) / (2 * h)
        rate = getattr(solution, name.replace("theta", "omega"))
        np.testing.assert_allclose(rate, omega2 * derivative, atol=1e-6 * np.abs(rate).max())
    t2, t3, t4 = SWEEP, solution.theta3, solution.theta4
    omega3 = omega2 * DESK.l2 * np.sin(t4 - t2) / (DESK.l3 * np.sin(t3 - t4))
    omega4 = omega2 * DESK.l2 * np.sin(t2 - t3) / (DESK.l4 * np.sin(t4 - t3))
    np.testing.assert_allclose(solution.omega3, omega3, rtol=1e-12, atol=1e-12)
    np.testing.assert_allclose(solution.omega4, omega4, rtol=1e-12, atol=1e-12)


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_acceleration_matches_second_differences_of_position(branch):
    # θ2(t) = θ0 + ω t + α t²/2; α3 = d²θ3/dt² at t = 0 by a central second difference
    theta0, omega2, alpha2, h = np.linspace(-3, 3, 25), 7.0, -40.0, 1e-4

    def theta(t, name):
        return getattr(DESK.solve(theta0 + omega2 * t + alpha2 * t**2 / 2, branch=branch), name)

    solution = DESK.solve(theta0, omega2, alpha2, branch=branch)
    for name in ("theta3", "theta4"):
        forward = np.angle(np.exp(1j * (theta(h, name) - theta(0, name))))
        backward = np.angle(np.exp(1j * (theta(0, name) - theta(-h, name))))
        second = (forward - backward) / h**2
        rate = getattr(solution, name.replace("theta", "alpha"))
        np.testing.assert_allclose(rate, second, atol=1e-5 * np.abs(rate).max())


def test_rates_are_linear_in_the_input():
    # ω scales with ω2; α is α2·(ω/ω2) + ω2²·(α at α2 = 0)
    base = DESK.solve(SWEEP, 1.0, 0.0)
    pure_alpha = DESK.solve(SWEEP, 0.0, 1.0)
    both = DESK.solve(SWEEP, 3.0, -5.0)
    np.testing.assert_allclose(both.omega4, 3.0 * base.omega4, rtol=1e-12)
    expected = 9.0 * base.alpha3 - 5.0 * pure_alpha.alpha3
    np.testing.assert_allclose(both.alpha3, expected, rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(pure_alpha.alpha4, base.omega4, rtol=1e-12)


def test_broadcasting_of_angles_and_rates():
    theta2 = np.linspace(0, 1, 4)[:, None]
    omega2 = np.array([1.0, 2.0, 3.0])
    solution = DESK.solve(theta2, omega2)
    assert solution.theta3.shape == solution.omega4.shape == solution.alpha3.shape == (4, 3)
    np.testing.assert_allclose(solution.omega4[:, 2], 3 * solution.omega4[:, 0], rtol=1e-12)
    assert DESK.joints(theta2).shape == (4, 1, 4, 2)
    assert isinstance(DESK.solve(0.3).theta4, float)


# ------------------------------------------------------- derived quantities
@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_joints_keep_every_length(branch):
    joints = DESK.joints(SWEEP, branch=branch)
    O2, A, B, O4 = (joints[:, k] for k in range(4))
    for (p, q), length in zip([(O2, A), (A, B), (B, O4), (O4, O2)], [0.06, 0.18, 0.12, 0.20], strict=True):
        np.testing.assert_allclose(np.linalg.norm(q - p, axis=-1), length, rtol=1e-13)


def test_transmission_angle_by_the_law_of_cosines():
    # angle at B in triangle A-B-O4: cos μ = (l3² + l4² − |AO4|²) / (2 l3 l4), same on both branches
    squared = DESK.l1**2 + DESK.l2**2 - 2 * DESK.l1 * DESK.l2 * np.cos(SWEEP)
    mu = np.arccos((DESK.l3**2 + DESK.l4**2 - squared) / (2 * DESK.l3 * DESK.l4))
    for branch in ("open", "crossed"):
        np.testing.assert_allclose(DESK.transmission_angle(SWEEP, branch, acute=False), mu, atol=1e-12)
        acute = np.minimum(mu, np.pi - mu)
        np.testing.assert_allclose(DESK.transmission_angle(SWEEP, branch), acute, atol=1e-12)


def test_coupler_point_position_velocity_acceleration():
    p, delta, omega2, alpha2, h = 0.09, 0.5, 10.0, 30.0, 1e-4
    motion = DESK.coupler_point(SWEEP, p, delta, omega2, alpha2)
    # p = l3, δ = 0 is the pin B
    pin_B = DESK.coupler_point(SWEEP, DESK.l3, 0.0).position
    np.testing.assert_allclose(pin_B, DESK.joints(SWEEP)[:, 2], atol=1e-15)

    def position(t):
        return DESK.coupler_point(SWEEP + omega2 * t + alpha2 * t**2 / 2, p, delta).position

    velocity = (position(h) - position(-h)) / (2 * h)
    acceleration = (position(h) - 2 * position(0) + position(-h)) / h**2
    np.testing.assert_allclose(motion.velocity, velocity, atol=1e-6 * np.abs(motion.velocity).max())
    scale = np.abs(motion.acceleration).max()
    np.testing.assert_allclose(motion.acceleration, acceleration, atol=1e-5 * scale)


# ----------------------------------------------------------------- Grashof
@pytest.mark.parametrize(
    ("crank", "coupler", "rocker", "ground", "name", "shortest"),
    [
        (0.06, 0.18, 0.12, 0.20, "Grashof crank-rocker", "crank"),
        (0.18, 0.12, 0.06, 0.20, "Grashof crank-rocker", "rocker"),
        (0.12, 0.18, 0.20, 0.06, "Grashof double-crank", "ground"),
        (0.12, 0.06, 0.18, 0.20, "Grashof double-rocker", "coupler"),
        (0.10, 0.30, 0.10, 0.30, "change-point", "crank"),  # parallelogram
        (0.10, 0.30, 0.30, 0.10, "change-point", "ground"),  # kite (deltoid)
        (2.0, 4.0, 3.0, 5.0, "change-point", "crank"),  # 2 + 5 = 4 + 3
        (0.15, 0.10, 0.12, 0.20, "non-Grashof triple-rocker", "coupler"),
        (1.0, 1.0, 1.0, 3.5, "non-Grashof triple-rocker", "crank"),
    ],
)
def test_grashof_hand_enumerated(crank, coupler, rocker, ground, name, shortest):
    result = FourBar(crank=crank, coupler=coupler, rocker=rocker, ground=ground).grashof()
    assert result.name == name
    assert result.shortest == shortest
    assert result.is_grashof == (name != "non-Grashof triple-rocker")


def test_grashof_numbers_of_the_desk_linkage():
    result = DESK.grashof()
    assert (result.shortest, result.longest) == ("crank", "ground")
    assert abs(result.s_plus_l - 0.26) < 1e-15 and abs(result.p_plus_q - 0.30) < 1e-15


@given(lengths, lengths, lengths, lengths)
def test_full_rotation_agrees_with_grashof_rule(l1, l2, l3, l4):
    linkage = FourBar(crank=l2, coupler=l3, rocker=l4, ground=l1)
    result = linkage.grashof()
    assume(abs(result.s_plus_l - result.p_plus_q) > 1e-6)
    crank_turns = result.name in ("Grashof double-crank",) or (
        result.name == "Grashof crank-rocker" and result.shortest == "crank"
    )
    assert linkage.input_range().full_rotation == crank_turns


@pytest.mark.parametrize(
    "linkage",
    [
        FourBar(crank=0.15, coupler=0.10, rocker=0.12, ground=0.20),  # non-Grashof: one interval about 0
        FourBar(crank=0.15, coupler=0.18, rocker=0.04, ground=0.20),  # non-Grashof: about π
        FourBar(crank=0.12, coupler=0.06, rocker=0.18, ground=0.20),  # Grashof double-rocker: two
    ],
)
def test_input_range_limits_are_toggles(linkage):
    r = linkage.input_range()
    assert not r.full_rotation and r.intervals
    for start, end in r.intervals:
        inside = np.linspace(start, end, 50)[1:-1]
        assert not np.any(linkage.solve(inside, on_failure="nan").mask)
        assert np.all(linkage.solve(np.array([start - 1e-4, end + 1e-4]), on_failure="nan").mask)
    for toggle in r.toggle_angles:
        distance = np.hypot(linkage.l1 - linkage.l2 * np.cos(toggle), linkage.l2 * np.sin(toggle))
        extended, folded = linkage.l3 + linkage.l4, abs(linkage.l3 - linkage.l4)
        assert min(abs(distance - extended), abs(distance - folded)) < 1e-12
        at_rest = linkage.solve(toggle)  # assembles (B on the line A-O4) with zero rates
        assert at_rest.omega4 == 0.0
        with pytest.raises(SingularJacobianError, match="theta2="):
            linkage.solve(toggle, omega2=1.0)


def test_input_range_of_crank_rocker_and_impossible_linkage():
    assert DESK.input_range().full_rotation and DESK.input_range().toggle_angles == ()
    impossible = FourBar(crank=0.1, coupler=0.1, rocker=0.1, ground=1.0)
    assert impossible.input_range().intervals == ()
    with pytest.raises(UnreachableError):
        impossible.solve(0.0)


# -------------------------------------------------------------- bad input
@pytest.mark.parametrize("name", ["crank", "coupler", "rocker", "ground"])
@pytest.mark.parametrize("value", [0.0, -0.1, np.nan, np.inf, "long"])
def test_bad_lengths_are_named(name, value):
    kwargs = {"crank": 0.06, "coupler": 0.18, "rocker": 0.12, "ground": 0.20, name: value}
    with pytest.raises(InvalidGeometryError, match=name):
        FourBar(**kwargs)


def test_bad_labels_and_inputs():
    with pytest.raises(InvalidGeometryError, match="branch"):
        DESK.solve(0.1, branch="opne")
    with pytest.raises(InvalidGeometryError, match="branch"):
        DESK.joints(0.1, branch=1)
    with pytest.raises(InvalidGeometryError, match="on_failure"):
        DESK.solve(0.1, on_failure="ignore")
    with pytest.raises(InvalidGeometryError, match="theta2"):
        DESK.solve([0.0, np.nan])
    with pytest.raises(InvalidGeometryError, match="omega2"):
        DESK.solve(0.0, omega2=np.inf)
    with pytest.raises(InvalidGeometryError, match="p must"):
        DESK.coupler_point(0.0, p=-0.01, delta=0.0)
    with pytest.raises(dataclasses.FrozenInstanceError):
        DESK.crank = 1.0


def test_unreachable_inputs_named_raise_or_nan():
    rocker_input = FourBar(crank=0.15, coupler=0.10, rocker=0.12, ground=0.20)  # reaches |θ2| ≤ 1.3336
    with pytest.raises(UnreachableError, match=r"theta2=3\b"):
        rocker_input.solve(3.0)
    theta2 = np.array([0.0, 2.0, 0.5, -3.0, 1.0])
    message = r"theta2=2\.0 \(2 of 5 instants, first at index 1\)"
    with pytest.raises(UnreachableError, match=message) as info:
        rocker_input.solve(theta2)
    np.testing.assert_array_equal(info.value.mask, [False, True, False, True, False])
    solution = rocker_input.solve(theta2, omega2=1.0, on_failure="nan")
    np.testing.assert_array_equal(solution.mask, [False, True, False, True, False])
    assert np.all(np.isnan(solution.theta4[solution.mask]))
    assert np.all(np.isnan(solution.alpha3[solution.mask]))
    assert np.all(np.isfinite(solution.alpha3[~solution.mask]))


def test_singular_jacobian_in_nan_mode():
    linkage = FourBar(crank=0.15, coupler=0.10, rocker=0.12, ground=0.20)
    toggle = linkage.input_range().toggle_angles[1]
    with pytest.raises(SingularJacobianError, match=r"1 of 2 instants, first at index 1"):
        linkage.solve([0.0, toggle], omega2=2.0)
    solution = linkage.solve([0.0, toggle], omega2=2.0, on_failure="nan")
    assert solution.singular.tolist() == [False, True]
    assert np.isfinite(solution.omega4[0]) and np.isnan(solution.omega4[1])
    assert np.isfinite(solution.theta4[1])


def test_change_point_assembles_where_its_branches_meet():
    # l1 + l2 = l3 + l4: at θ2 = π coupler and rocker are in line, B = A + (l3, 0) lies on the x-axis
    change_point = FourBar(crank=0.06, coupler=0.18, rocker=0.08, ground=0.20)
    theta2 = np.linspace(0, 2 * np.pi, 241)  # contains π (index 120), where rounding makes B² − 4AC ≈ −1e-16
    for branch in ("open", "crossed"):
        joints = change_point.joints(theta2, branch=branch)
        np.testing.assert_allclose(joints[120, 2], [-0.06 + 0.18, 0.0], atol=1e-7)


# ---------------------------------------------------------------- extreme and degenerate inputs
def test_crank_pin_on_o4_with_equal_coupler_and_rocker_is_reported_not_nan():
    # A = O4 and l3 = l4: B may be anywhere on the circle of radius l3 about O4
    for linkage in (FourBar(1, 1, 1, 1), FourBar(0.4942090157781592, 1, 1, 0.4942090157781592)):
        assert linkage.input_range().full_rotation
        with pytest.raises(SingularJacobianError, match=r"not determined at theta2=0\b"):
            linkage.solve(0.0)
        flagged = linkage.solve([0.0, 1.0], on_failure="nan")
        assert flagged.singular.tolist() == [True, False] and not flagged.mask.any()
        assert np.isnan(flagged.theta4[0]) and np.isfinite(flagged.theta4[1])
        A, B = fourbar_pins(linkage.l1, linkage.l2, linkage.l3, linkage.l4, 1.0, "open")
        assert angle_difference(flagged.theta4[1], np.arctan2(B[1], B[0] - linkage.l1)) < 1e-12


@pytest.mark.parametrize("scale", [1e-200, 1e-100, 1e100, 1e200])
def test_the_scale_of_the_lengths_does_not_matter(scale):
    A, B = fourbar_pins(0.2, 0.06, 0.18, 0.12, 1.0, "open")   # circles at the desk scale
    scaled = FourBar(0.06 * scale, 0.18 * scale, 0.12 * scale, 0.2 * scale).solve(1.0, 10.0, 3.0)
    assert angle_difference(scaled.theta4, np.arctan2(B[1], B[0] - 0.2)) < 1e-12
    assert angle_difference(scaled.theta3, np.arctan2(*(B - A)[::-1])) < 1e-12
    reference = DESK.solve(1.0, 10.0, 3.0)   # angular rates do not depend on the scale either
    assert np.allclose([scaled.omega4, scaled.alpha4], [reference.omega4, reference.alpha4], rtol=1e-12)


def test_a_vanishing_crank_leaves_a_triangle():
    # l2 → 0: A sits on O2, and B closes the triangle O2 B O4 with sides l3, l4, l1
    theta4 = FourBar(1e-300, 0.18, 0.12, 0.2).solve(1.0).theta4
    cos_at_o4 = (0.12**2 + 0.2**2 - 0.18**2) / (2 * 0.12 * 0.2)   # law of cosines
    assert abs(theta4 - (np.pi - np.arccos(cos_at_o4))) < 1e-12


@pytest.mark.parametrize(
    "linkage", [FourBar(0.2, 0.1, 0.1001, 0.2), FourBar(0.25, 0.375, 0.37632995787983853, 0.25),
                FourBar(0.14, 0.12, 0.10, 0.20), FourBar(0.12, 0.06, 0.18, 0.20)]
)
def test_solve_accepts_every_angle_input_range_reports(linkage):
    for start, end in linkage.input_range().intervals:
        for branch in ("open", "crossed"):
            solution = linkage.solve(np.linspace(start, end, 50), branch=branch)
            assert np.all(np.isfinite(solution.theta4))


@given(
    lengths=st.lists(st.floats(0.05, 1.0), min_size=4, max_size=4),
    where=st.floats(0.0, 1.0),
)
def test_input_range_edges_and_inside_assemble(lengths, where):
    turns = (0, 2 * np.pi, -2 * np.pi)
    linkage = FourBar(*lengths)
    assume(abs(linkage.l1 - linkage.l2) > 1e-6 or abs(linkage.l3 - linkage.l4) > 1e-6)  # B undetermined
    intervals = linkage.input_range().intervals
    for start, end in intervals:
        inside = start + where * (end - start)
        for theta2 in (start, end, inside):
            joints = linkage.joints(theta2)
            assert abs(np.linalg.norm(joints[2] - joints[1]) - linkage.l3) < 1e-9
        outside = end + 1e-6   # just past a toggle the loop cannot close, unless another interval starts
        if not linkage.input_range().full_rotation and not any(
            a - 1e-6 <= outside + turn <= b + 1e-6 for a, b in intervals for turn in turns
        ):
            with pytest.raises(UnreachableError):
                linkage.solve(outside)


def test_one_mask_convention_and_results_that_convert():
    linkage = FourBar(0.15, 0.10, 0.12, 0.20)  # closes only for |θ2| ≤ 1.3336
    solution = linkage.solve([0.0, 2.0], 1.0, on_failure="nan")
    assert solution.reachable.tolist() == [True, False] and solution.mask.tolist() == [False, True]
    assert linkage.solve(0.3).reachable is True
    theta3, theta4, omega3, omega4, alpha3, alpha4 = DESK.solve(0.7, 10.0, 2.0)
    assert np.array(DESK.solve(0.7, 10.0, 2.0)).tolist() == [theta3, theta4, omega3, omega4, alpha3, alpha4]
    assert np.array(DESK.solve(SWEEP, 10.0)).shape == (6, SWEEP.size)
    position, velocity, acceleration = DESK.coupler_point(SWEEP, 0.05, 0.3, 10.0)
    assert np.array(DESK.coupler_point(SWEEP, 0.05, 0.3, 10.0)).shape == (3, SWEEP.size, 2)


@pytest.mark.parametrize("lengths", [(0.1, 0.2, 0.15, 0.15), (0.06, 0.14, 0.12, 0.2), (1, 1, 1, 1)])
def test_a_change_point_crank_turns_fully(lengths):
    # s + l = p + q: the crank passes the change point (coupler and rocker in line) and goes round
    linkage = FourBar(*lengths)
    assert linkage.grashof().name == "change-point" and linkage.input_range().full_rotation


# ------------------------------------------------------------- one instant, blocks, memory
LINKAGES = [DESK, FourBar(0.15, 0.10, 0.12, 0.20), FourBar(0.06, 0.18, 0.08, 0.20), FourBar(1, 1, 1, 1),
            FourBar(0.12, 0.06, 0.18, 0.20)]


@pytest.mark.parametrize("linkage", LINKAGES)
def test_one_instant_agrees_with_the_array_solve(linkage):
    # one angle and an array of them: the same values to a few ulps, the same masks, Python numbers for one
    toggles = linkage.input_range().toggle_angles
    angles = np.r_[np.linspace(-4, 4, 81), 0.0, np.pi, toggles, np.add.outer(toggles, [-1e-9, 1e-9]).ravel()]
    for branch in BRANCHES:
        for omega2, alpha2 in ((0.0, 0.0), (10.0, -3.0), (0.0, 2.0)):
            whole = linkage.solve(angles, omega2, alpha2, branch=branch, on_failure="nan")
            for k, angle in enumerate(angles.tolist()):
                one = linkage.solve(angle, omega2, alpha2, branch=branch, on_failure="nan")
                expected = np.array(whole)[:, k]
                # the angles: the sweep's continuous along it, one instant's in [−π, π]; equal modulo 2π,
                # to a few ulps; the rates from cos and sin of angles some turns apart (sin 2π ≠ 0 in
                # doubles), amplified near a toggle: the same to 1e-9 of their size or of ω2² = 100
                turns = np.round((np.array(one)[:2] - expected[:2]) / (2 * np.pi))
                expected[:2] += 2 * np.pi * turns
                np.testing.assert_allclose(np.array(one)[:2], expected[:2], rtol=1e-14, atol=1e-15,
                                           err_msg=f"{branch} {angle!r}")
                np.testing.assert_allclose(np.array(one)[2:], expected[2:], rtol=1e-9, atol=1e-7,
                                           err_msg=f"{branch} {angle!r}")
                assert (one.mask, one.singular, one.near_singular) == (whole.mask[k], whole.singular[k],
                                                                   whole.near_singular[k])
                assert isinstance(one.theta4, float) and isinstance(one.mask, bool)


def test_errors_name_the_first_bad_angle_of_any_block():
    # a sweep longer than the core's blocks of instants (2¹⁶), bad angles in the second and third block
    linkage = FourBar(0.15, 0.10, 0.12, 0.20)  # closes for |θ2| ≤ 1.3336
    angles = np.zeros(140_000)
    angles[[70_013, 135_022]] = 2.0
    with pytest.raises(UnreachableError, match=r"theta2=2\.0 \(2 of 140000 instants, first at index 70013\)"):
        linkage.solve(angles)
    angles[[70_013, 135_022]] = linkage.input_range().toggle_angles[1]
    with pytest.raises(SingularJacobianError, match=r"\(2 of 140000 instants, first at index 70013\)"):
        linkage.solve(angles, 1.0)
    assert linkage.solve(angles).omega4[70_013] == 0.0  # at rest a toggle is fine
    undetermined = np.r_[np.full(9, 1.0), 0.0]
    with pytest.raises(SingularJacobianError, match=r"not determined at theta2=0\b"):
        FourBar(1, 1, 1, 1).solve(undetermined)


def peak_bytes(function):
    tracemalloc.start()
    try:
        function()
        return tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()


@pytest.mark.parametrize("size", [200_000, 800_000])
def test_memory_per_angle_stays_a_few_arrays(size):
    # the results take 62 bytes per angle (six float64 arrays, the assembly as int8 per unknown, four bool
    # masks) and 8 the iteration counts; the rates are solved per block of the core, so what else the solve
    # holds at its peak is a few arrays of the positions (the sweep's order, σ, the angles made continuous)
    angles = np.linspace(0, 2 * np.pi, size)
    DESK.solve(angles[:2], 10.0, 5.0)  # the rates' derivation, once
    beyond = peak_bytes(lambda: DESK.solve(angles, 10.0, 5.0)) - 70 * size
    assert beyond < 100 * size + 4e6  # twelve float64 arrays, and the core's blocks' temporaries


def test_a_toggle_is_where_the_core_rule_finds_the_declared_loop_singular():
    # one rule: while moving, solve's singular mask is the core's is_singular at the solved position, for
    # one instant, for a one-angle block (which may skip the test: its discriminant proves no toggle) alike
    rng = np.random.default_rng(7)
    steps = np.logspace(-12, -1, 12)
    checked, toggles_met = 0, 0
    for lengths in np.exp(rng.uniform(np.log(1e-3), 0, (60, 4))):
        linkage = FourBar(*lengths)
        toggles = np.array(linkage.input_range().toggle_angles)
        for angle in np.r_[rng.uniform(-4, 4, 3), np.add.outer(toggles, np.r_[-steps, steps]).ravel()]:
            with np.errstate(all="ignore"):
                block = linkage.solve(np.array([angle]), 1.0, on_failure="nan")
                one = linkage.solve(float(angle), 1.0, on_failure="nan")
            if block.unreachable[0]:
                continue
            q = np.array([[block.theta3[0], block.theta4[0]]])
            core = bool(linkage.mechanism.is_singular(q, [[angle]])[0])
            assert bool(block.singular[0]) == one.singular == core, (lengths, angle)
            checked, toggles_met = checked + 1, toggles_met + core
    assert checked > 300 and toggles_met > 10


# ---------------------------------------------------------------- the machine is its declaration
def test_the_hand_closed_form_against_the_core_derivation_from_the_declaration():
    # two independent routes to the position: Norton's half-angle formula written by hand (solve) and
    # the core's own, derived from the declared loop (the quadratic reduce_loop finds, σ kept by the core)
    for linkage in (DESK, FourBar(0.12, 0.06, 0.18, 0.20), FourBar(0.05, 0.12, 0.15, 0.13)):
        theta2 = np.linspace(-3.0, 3.0, 61)
        hand = linkage.solve(theta2, on_failure="nan")
        keep = hand.reachable
        start = int(np.flatnonzero(keep)[0])
        first = {"theta3": hand.theta3[keep][start], "theta4": hand.theta4[keep][start]}
        core = linkage.mechanism.solve({"theta2": theta2[keep][start:]}, guess=first)
        assert angle_difference(core.position["theta3"], hand.theta3[keep][start:]).max() < 1e-12
        assert angle_difference(core.position["theta4"], hand.theta4[keep][start:]).max() < 1e-12
    # the joints are the declaration's points, O2, A, B, O4 in its order, at the hand solution
    joints = DESK.joints(SWEEP)
    A, B = fourbar_pins(0.20, 0.06, 0.18, 0.12, SWEEP, "open")
    np.testing.assert_allclose(joints[:, 1], A, atol=1e-15)
    np.testing.assert_allclose(joints[:, 2], B, atol=1e-12)
    assert list(DESK.mechanism.points) == ["O2", "A", "B", "O4"]


def test_the_motion_is_a_motion_of_the_declaration_with_independently_checked_rates():
    from course_lib.mechanism import Motion

    motion = DESK.motion(SWEEP, 10.0, 3.0)
    assert isinstance(motion, Motion) and set(motion.position) == {"theta3", "theta4"}
    assert motion.converged.all() and not motion.singular.any() and motion.inputs["theta2"] is not None
    # Norton's sine formulas, written here: ω3 = l2 ω2 sin(θ4 − θ2) / (l3 sin(θ3 − θ4)), ω4 likewise
    theta3, theta4 = motion.position["theta3"], motion.position["theta4"]
    omega3 = 0.06 * 10.0 * np.sin(theta4 - SWEEP) / (0.18 * np.sin(theta3 - theta4))
    omega4 = 0.06 * 10.0 * np.sin(theta3 - SWEEP) / (0.12 * np.sin(theta3 - theta4))
    np.testing.assert_allclose(motion.velocity["theta3"], omega3, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(motion.velocity["theta4"], omega4, rtol=1e-9, atol=1e-12)
    joints = DESK.mechanism.joints(motion)  # B where two circles meet, computed here
    _, B = fourbar_pins(0.20, 0.06, 0.18, 0.12, SWEEP, "open")
    np.testing.assert_allclose(joints["B"], B, atol=1e-12)


def test_one_failure_keyword_and_a_mask_named_for_what_it_marks():
    triple = FourBar(0.15, 0.10, 0.12, 0.20)
    new = triple.solve([0.0, 2.0], on_failure="nan")
    # the loop closes where |A O4| lies between |l3 − l4| and l3 + l4 (the triangle A, B, O4)
    reach = [abs(0.10 - 0.12) <= math.hypot(0.15 * math.cos(t) - 0.20, 0.15 * math.sin(t)) <= 0.10 + 0.12
             for t in (0.0, 2.0)]
    assert new.unreachable.tolist() == new.mask.tolist() == [not r for r in reach] == [False, True]
    calls = {"joints": lambda **kw: triple.joints(2.0, **kw)[2],  # B
             "transmission_angle": lambda **kw: triple.transmission_angle(2.0, **kw),
             "coupler_point": lambda **kw: triple.coupler_point(2.0, 0.1, 0.0, **kw).position,
             "motion": lambda **kw: triple.motion(2.0, **kw).position["theta4"]}
    for name, call in calls.items():
        with pytest.raises(UnreachableError):
            call()
        assert np.isnan(call(on_failure="nan")).all(), name
