"""Tests for course_lib.checks: each checker accepts the right answer (computed here by an
independent route) and its equivalent forms, and rejects typical wrong answers with the
right hint — without ever showing the reference value."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.optimize
import sympy as sp
from feedback import course_newton_count, hides
from geometry import circle_intersections, course_inverse_angles, fourbar_pins

from course_lib import checks
from course_lib.fivebar import FiveBar
from course_lib.fourbar import FourBar
from course_lib.saw import Saw, analytic
from course_lib.slider_crank import OffsetSliderCrank

BENCH = FourBar(crank=0.07, coupler=0.20, rocker=0.15, ground=0.25)
MY_SAW = Saw(r1y=0.03, r2=0.06, r3=0.15)
ROBOT = FiveBar(l1=0.11, l2=0.15, l3=0.16, l4=0.12, l5=0.09)


def linear_solve(equations, unknowns):
    """Solve linear equations by Gaussian elimination (no sympy simplify: its run time depends on
    the hash seed)."""
    matrix, rhs = sp.linear_eq_to_matrix(equations, unknowns)
    return dict(zip(unknowns, matrix.LUsolve(rhs), strict=True))


def rejects(feedback, *words, hidden=()):
    assert not feedback.ok, feedback
    assert all(word in feedback.message for word in words), feedback
    assert hides(feedback, *hidden), feedback


def fourbar_by_circles(linkage, theta2, branch):
    A, B = fourbar_pins(linkage.l1, linkage.l2, linkage.l3, linkage.l4, theta2, branch)
    O4 = np.array([linkage.l1, 0.0])
    return np.arctan2(*(B - A)[::-1]), np.arctan2(*(B - O4)[::-1])


# ---------------------------------------------------------------- the Feedback object


def test_feedback_prints_one_line_with_a_mark():
    good, bad = checks.Feedback(True, "Correct."), checks.Feedback(False, "Not yet: x.")
    assert str(good) == repr(good) == "✔ Correct." and str(bad).startswith("✘ ")
    assert bool(good) and not bool(bad)
    with pytest.raises(AttributeError):
        good.ok = False


def test_unanswered_answers_are_named():
    for checker in (checks.check_mobility, checks.check_newton_cycle, checks.check_newton_update):
        feedback = checker(None)
        assert not feedback.ok and "No answer yet" in feedback.message


# ---------------------------------------------------------------- ex01


def test_mobility():
    assert checks.check_mobility((6, 7, 0, 6 * 3 - 3 - 14)).ok
    assert checks.check_mobility({"links": 6, "full_joints": 7, "half_joints": 0, "mobility": 1}).ok
    rejects(checks.check_mobility((5, 7, 0, -2)), "ground")
    rejects(checks.check_mobility((6, 6, 0, 3)), "three links", "two full joints")
    rejects(checks.check_mobility((6, 7, 0, 2)), "M = 3(L − 1)")


def test_tilted_loop():
    l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
    t1, t2, t3, t4 = sp.symbols("theta1:5", real=True)
    # complex-number route: l2 e^{iθ2} + l3 e^{iθ3} − l4 e^{iθ4} − l1 e^{iθ1}
    z = l2 * sp.exp(sp.I * t2) + l3 * sp.exp(sp.I * t3) - l4 * sp.exp(sp.I * t4) - l1 * sp.exp(sp.I * t1)
    x, y = (sp.expand_complex(part) for part in (sp.re(z), sp.im(z)))
    assert checks.check_tilted_loop([x, y]).ok
    assert checks.check_tilted_loop(sp.Matrix([-x, 2 * y])).ok  # same equations "= 0"
    assert checks.check_tilted_loop([y, x]).ok  # either order
    rejects(checks.check_tilted_loop([x.subs(t1, 0), y.subs(t1, 0)]), "horizontal ground")
    for length, vector in ((l1, "R1"), (l2, "R2"), (l3, "R3"), (l4, "R4")):  # each flipped, in either order
        slip = [x.subs(length, -length), y.subs(length, -length)]
        rejects(checks.check_tilted_loop(slip), "sign slip on " + vector)
        rejects(checks.check_tilted_loop(slip[::-1]), "sign slip on " + vector)
    # sin and cos swapped in both components is the right pair in the other order: accepted
    rejects(checks.check_tilted_loop([x, x]), "Not yet")
    rejects(checks.check_tilted_loop(["l2*cos(theta2)", "0"]), "sympy expression")
    rejects(checks.check_tilted_loop(x), "list")


def test_link_vector():
    # a crank of 0.06 m pointing straight up is (0, 0.06) m; at 30° it is 0.06·(√3/2, 1/2)
    check = checks.check_link_vector
    assert check((0.0, 0.06), 0.06, 90.0).ok and check([0.06 * 3**0.5 / 2, 0.03], 0.06, 30.0).ok
    rejects(check((0.06, 0.0), 0.06, 90.0), "swapped")
    rejects(check((0.0, 60.0), 0.06, 90.0), "metres")
    rejects(check((-0.448073616 * 0.06, 0.893996664 * 0.06), 0.06, 90.0), "degrees")  # cos 90 rad, sin 90 rad
    rejects(check((0.0, -0.06), 0.06, 90.0), "cos θ and sin θ", hidden=[0.06])
    assert check(None, 0.06, 90.0).message.startswith("No answer yet")
    rejects(check("0, 0.06", 0.06, 90.0), "plain numbers")


def test_point_velocity():
    length, degrees, speed = 0.080, 135.0, 12.0
    theta, h = np.radians(degrees), 1e-7

    def tip(t):  # clockwise: the angle decreases in time
        angle = theta - speed * t
        return length * np.array([np.cos(angle), np.sin(angle)])

    velocity = (tip(h) - tip(-h)) / (2 * h)
    assert checks.check_point_velocity(velocity, length, degrees, speed, clockwise=True).ok
    assert checks.check_point_velocity(list(velocity), length, degrees, speed, clockwise=True).ok
    rejects(checks.check_point_velocity(-velocity, length, degrees, speed, True), "sign", hidden=velocity)
    rejects(checks.check_point_velocity(velocity * 1000, length, degrees, speed, True), "mm/s")
    in_degrees = -speed * length * np.array([-np.sin(degrees), np.cos(degrees)])
    rejects(checks.check_point_velocity(in_degrees, length, degrees, speed, True), "degrees")
    rejects(checks.check_point_velocity(0.96, length, degrees, speed, True), "speed", "vector")
    # a complex entry in the pair is named as one; the (z.real, z.imag) hint is for one complex z only
    for pair in ([velocity[0] * 1j, velocity[1]], (velocity[0], sp.I * velocity[1]), np.array(velocity) * 1j):
        feedback = checks.check_point_velocity(pair, length, degrees, speed, True)
        rejects(feedback, "an entry is a complex number", "one real number")
        assert "z.real" not in feedback.message, feedback
    z = complex(*velocity)
    rejects(checks.check_point_velocity(z, length, degrees, speed, True), "(z.real, z.imag)")


def test_choice_questions():
    for checker, right in (
        (checks.check_redundant_parallelogram, "b"),
        (checks.check_newton_cycle, "a"),
        (checks.check_saw_linear_stage, "a"),
    ):
        assert checker(right).ok and checker(f" ({right.upper()}) ").ok
        wrong = [checker(letter) for letter in "abcd" if letter != right]
        assert all(not feedback.ok and len(feedback.message) > 30 for feedback in wrong)
        rejects(checker("e"), "one letter")
        rejects(checker(2), "one letter")


# ---------------------------------------------------------------- ex02


def test_newton_update():
    x = sp.Symbol("x")
    f = x**3 - 2 * x - 5
    assert checks.check_newton_update((2 * x**3 + 5) / (3 * x**2 - 2)).ok
    assert checks.check_newton_update(x - f / (3 * x**2 - 2)).ok
    rejects(checks.check_newton_update(x + f / (3 * x**2 - 2)), "sign error")
    rejects(checks.check_newton_update(x - (3 * x**2 - 2) / f), "upside down")
    rejects(checks.check_newton_update(f / (3 * x**2 - 2)), "step")
    rejects(checks.check_newton_update(x - f), "derivative")
    rejects(checks.check_newton_update(sp.Symbol("y") - 1), "symbols")


def test_newton_iterations():
    root, value, count = course_newton_count()
    assert abs(value - root) < 1e-12
    assert checks.check_newton_iterations((root, count)).ok
    assert checks.check_newton_iterations([root, np.int64(count)]).ok
    rejects(checks.check_newton_iterations((root, count + 1)), "seed", hidden=[count])
    rejects(checks.check_newton_iterations((root, count - 1)), "too few")
    rejects(checks.check_newton_iterations((2.0945, count)), "tolerance", hidden=[root])
    rejects(checks.check_newton_iterations((3.0, count)), "does not satisfy")


def test_fourbar_newton_step():
    theta2, seed = np.radians(40.0), np.array([0.5, 1.5])

    def loop(q):
        l1, l2, l3, l4 = 0.25, 0.07, 0.20, 0.15
        return np.array(
            [
                l2 * np.cos(theta2) + l3 * np.cos(q[0]) - l4 * np.cos(q[1]) - l1,
                l2 * np.sin(theta2) + l3 * np.sin(q[0]) - l4 * np.sin(q[1]),
            ]
        )

    h = 1e-6
    J = np.column_stack([(loop(seed + h * e) - loop(seed - h * e)) / (2 * h) for e in np.eye(2)])
    step = np.linalg.solve(J, -loop(seed))
    assert checks.check_fourbar_newton_step(step, BENCH, theta2, seed).ok
    rejects(checks.check_fourbar_newton_step(-step, BENCH, theta2, seed), "sign error", hidden=step)
    rejects(checks.check_fourbar_newton_step(seed + step, BENCH, theta2, seed), "new iterate")
    rejects(checks.check_fourbar_newton_step(step[::-1], BENCH, theta2, seed), "swapped")
    rejects(
        checks.check_fourbar_newton_step(np.linalg.solve(J.T, -loop(seed)), BENCH, theta2, seed), "transposed"
    )
    rejects(checks.check_fourbar_newton_step([1.0, 2.0, 3.0], BENCH, theta2, seed), "2 plain numbers")


def test_seed_branch():
    theta2, q = np.radians(40.0), np.array([2.5, 0.3])
    l1, l2, l3, l4 = 0.25, 0.07, 0.20, 0.15
    for _ in range(60):  # plain Newton, written out
        F = [
            l2 * np.cos(theta2) + l3 * np.cos(q[0]) - l4 * np.cos(q[1]) - l1,
            l2 * np.sin(theta2) + l3 * np.sin(q[0]) - l4 * np.sin(q[1]),
        ]
        J = [[-l3 * np.sin(q[0]), l4 * np.sin(q[1])], [l3 * np.cos(q[0]), -l4 * np.cos(q[1])]]
        q = q + np.linalg.solve(J, -np.array(F))
    A = l2 * np.array([np.cos(theta2), np.sin(theta2)])
    B = A + l3 * np.array([np.cos(q[0]), np.sin(q[0])])
    O4 = np.array([l1, 0.0])
    side = (O4 - A)[0] * (B - A)[1] - (O4 - A)[1] * (B - A)[0]  # open: B left of A → O4
    reached, other = ("open", "crossed") if side > 0 else ("crossed", "open")
    assert checks.check_seed_branch(reached, BENCH, theta2, (2.5, 0.3)).ok
    assert checks.check_seed_branch(reached.upper(), BENCH, theta2, (2.5, 0.3)).ok
    rejects(checks.check_seed_branch(other, BENCH, theta2, (2.5, 0.3)), "other assembly")
    rejects(checks.check_seed_branch("left", BENCH, theta2, (2.5, 0.3)), '"open" or "crossed"')


# ---------------------------------------------------------------- ex03


def test_fourbar_theta4():
    theta2 = np.radians(120.0)
    theta3, theta4 = fourbar_by_circles(BENCH, theta2, "crossed")
    open3, open4 = fourbar_by_circles(BENCH, theta2, "open")
    check = checks.check_fourbar_theta4
    assert check(theta4, BENCH, theta2, "crossed").ok
    assert check(theta4 + 2 * np.pi, BENCH, theta2, "crossed").ok and check(
        theta4 - 4 * np.pi, BENCH, theta2, "crossed"
    )
    rejects(check(open4, BENCH, theta2, "crossed"), "open assembly", hidden=[theta4])
    rejects(check(np.degrees(theta4), BENCH, theta2, "crossed"), "degrees", hidden=[theta4])
    rejects(check(theta3, BENCH, theta2, "crossed"), "θ3")
    rejects(check("1.2", BENCH, theta2, "crossed"), "number")


def test_omega4_expression():
    l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
    t2, t3, t4, w2, w3, w4 = sp.symbols("theta2 theta3 theta4 omega2 omega3 omega4", real=True)
    velocity = [
        -w2 * l2 * sp.sin(t2) - w3 * l3 * sp.sin(t3) + w4 * l4 * sp.sin(t4),
        w2 * l2 * sp.cos(t2) + w3 * l3 * sp.cos(t3) - w4 * l4 * sp.cos(t4),
    ]
    rates = linear_solve(velocity, [w3, w4])
    assert checks.check_omega4_expression(rates[w4]).ok
    assert checks.check_omega4_expression(sp.together(rates[w4])).ok
    textbook = w2 * l2 * sp.sin(t2 - t3) / (l4 * sp.sin(t4 - t3))  # Norton's form
    assert checks.check_omega4_expression(textbook).ok
    rejects(checks.check_omega4_expression(-rates[w4]), "sign error")
    rejects(checks.check_omega4_expression(rates[w3]), "ω3")
    rejects(checks.check_omega4_expression(rates[w4] / w2), "ω2")
    rejects(checks.check_omega4_expression(rates[w4] + sp.Symbol("q")), "symbols")
    # a length replaced by the bench's number: told to keep it a symbol, not to differentiate again
    for numbers, named in (({l2: 0.07}, "keep l2"), ({l4: 0.15}, "keep l4"),
                           ({l2: 0.07, l4: 0.15}, "keep l2 and l4")):
        feedback = checks.check_omega4_expression(rates[w4].subs(numbers))
        rejects(feedback, named, "as symbols")
        assert "differentiate" not in feedback.message, feedback
    assert checks.check_omega4_expression(rates[w4].subs(l3, 0.20)).ok  # l3 cancels out of ω4
    # l3 written where l4 belongs: named as the missing l4, without claiming a number was put in
    swapped = checks.check_omega4_expression(rates[w4].subs(l4, l3))
    rejects(swapped, "no l4", "another link's length in its place")


def _rates_by_sympy(linkage, theta2, omega2, alpha2, branch):
    """(ω4, α4) from the loop differentiated twice by sympy, at the circle-intersection position."""
    t = sp.Symbol("t")
    th2, th3, th4 = (sp.Function(name)(t) for name in ("th2", "th3", "th4"))
    l1, l2, l3, l4 = linkage.l1, linkage.l2, linkage.l3, linkage.l4
    loop = [
        l2 * sp.cos(th2) + l3 * sp.cos(th3) - l4 * sp.cos(th4) - l1,
        l2 * sp.sin(th2) + l3 * sp.sin(th3) - l4 * sp.sin(th4),
    ]
    position3, position4 = fourbar_by_circles(linkage, theta2, branch)
    w3, w4, a3, a4 = sp.symbols("w3 w4 a3 a4")
    values = {th2: theta2, th3: position3, th4: position4}
    first = {th2.diff(t): omega2, th3.diff(t): w3, th4.diff(t): w4}
    second = {th2.diff(t, 2): alpha2, th3.diff(t, 2): a3, th4.diff(t, 2): a4}
    velocity = [e.diff(t).subs(first).subs(values) for e in loop]
    omegas = linear_solve(velocity, [w3, w4])
    acceleration = [e.diff(t, 2).subs(second).subs(first).subs(values).subs(omegas) for e in loop]
    alphas = linear_solve(acceleration, [a3, a4])
    return float(omegas[w4]), float(alphas[a4]), float(omegas[w3])


def test_fourbar_rates():
    theta2, omega2, alpha2 = np.radians(200.0), 15.0, -40.0
    omega4, alpha4, omega3 = _rates_by_sympy(BENCH, theta2, omega2, alpha2, "open")
    other4, other_alpha4, _ = _rates_by_sympy(BENCH, theta2, omega2, alpha2, "crossed")
    check = checks.check_fourbar_rates
    assert check((omega4, alpha4), BENCH, theta2, omega2, alpha2, "open").ok
    assert check(np.array([omega4, alpha4]), BENCH, theta2, omega2, alpha2, "open").ok
    bare4 = _rates_by_sympy(BENCH, theta2, 0.0, alpha2, "open")[1]  # every ω² term gone
    rejects(check((omega4, bare4), BENCH, theta2, omega2, alpha2, "open"), "ω²", hidden=[alpha4])
    rejects(check((other4, other_alpha4), BENCH, theta2, omega2, alpha2, "open"), "crossed assembly")
    rejects(check((-omega4, alpha4), BENCH, theta2, omega2, alpha2, "open"), "wrong sign", hidden=[omega4])
    rejects(check((alpha4, omega4), BENCH, theta2, omega2, alpha2, "open"), "swapped")
    rejects(check((omega3, alpha4), BENCH, theta2, omega2, alpha2, "open"), "ω3")
    steady4 = _rates_by_sympy(BENCH, theta2, omega2, 0.0, "open")[1]  # α2 = 0, every ω² term kept
    feedback = check((omega4, steady4), BENCH, theta2, omega2, alpha2, "open")
    rejects(feedback, "α2 = 0", "α2 = -40 rad/s² is given", "slowing down", hidden=[alpha4])
    assert "once more" not in feedback.message, feedback
    flipped4 = _rates_by_sympy(BENCH, theta2, omega2, -alpha2, "open")[1]  # α2 entered with its sign flipped
    rejects(
        check((omega4, flipped4), BENCH, theta2, omega2, alpha2, "open"), "opposite sign", hidden=[alpha4]
    )


def test_toggle_angle():
    triple = FourBar(crank=0.14, coupler=0.12, rocker=0.10, ground=0.20)

    def stretch(theta2):  # |AO4| − (l3 + l4): zero where coupler and rocker are extended
        return np.hypot(0.20 - 0.14 * np.cos(theta2), 0.14 * np.sin(theta2)) - 0.22

    limit = scipy.optimize.brentq(stretch, 0.1, 3.0, xtol=1e-15)
    assert checks.check_toggle_angle((limit, "extended"), triple).ok
    assert checks.check_toggle_angle([limit, " Extended"], triple).ok
    rejects(checks.check_toggle_angle((np.degrees(limit), "extended"), triple), "degrees", hidden=[limit])
    rejects(checks.check_toggle_angle((-limit, "extended"), triple), "mirror")
    rejects(checks.check_toggle_angle((limit, "folded"), triple), "angle is right")
    rejects(checks.check_toggle_angle((1.0, "extended"), triple), "law of cosines", hidden=[limit])


# ---------------------------------------------------------------- ex04


def test_saw_omega3_expression():
    r1y, r2, r3, w2 = sp.symbols("r1y r2 r3 omega2", positive=True)
    t2, t3 = sp.symbols("theta2 theta3", real=True)
    rod_height = r2 * sp.sin(t2) + r3 * sp.sin(t3) - r1y  # = 0 along the motion
    # implicit differentiation: dθ3/dt = −(∂F/∂θ2 / ∂F/∂θ3)·ω2
    omega3 = -sp.diff(rod_height, t2) / sp.diff(rod_height, t3) * w2
    assert checks.check_saw_omega3_expression(omega3).ok
    assert checks.check_saw_omega3_expression(w2 * r2 * sp.cos(t2) / (-r3 * sp.cos(t3))).ok
    assert checks.check_saw_omega3_expression(sp.together(omega3 * r3 / r3)).ok
    rejects(checks.check_saw_omega3_expression(-omega3), "sign error")
    rejects(
        checks.check_saw_omega3_expression(omega3.subs({sp.cos(t2): sp.sin(t2), sp.cos(t3): sp.sin(t3)})),
        "swapped",
    )
    theta1_formula = sp.acot((r2 * sp.cos(t2) + r3 * sp.cos(t3)) / r1y)
    rejects(checks.check_saw_omega3_expression(theta1_formula), "ω2", "slip")


def _saw_by_slider_crank(theta2, omega2=0.0, alpha2=0.0):
    """(r1, θ1, θ3, a_r) from the Cartesian slider-crank: r1 = −√(x² + r1y²) (r1 < 0: slider on the left)."""
    motion = OffsetSliderCrank(crank=0.06, rod=0.15, offset=0.03).solve(theta2, omega2, alpha2, branch="left")
    x, v, a = float(motion.xC), float(motion.v_xC), float(motion.a_xC)
    rho = np.hypot(x, 0.03)
    r1, theta1 = -rho, np.arctan(0.03 / x)
    a_r = -(v**2 + x * a) / rho + x**2 * v**2 / rho**3
    return r1, theta1, float(motion.theta3), a_r


def test_saw_position():
    theta2 = np.radians(50.0)
    r1, theta1, theta3, _ = _saw_by_slider_crank(theta2)
    check = checks.check_saw_position
    assert check((r1, theta1, theta3), MY_SAW, theta2).ok
    equivalent = check((-r1, theta1 + np.pi, theta3 - 2 * np.pi), MY_SAW, theta2)
    assert equivalent.ok and "(−π/2, π/2]" in equivalent.message
    rejects(check((r1, theta1, np.pi - theta3), MY_SAW, theta2), "other assembly", hidden=[theta3])
    rejects(check((1000 * r1, theta1, theta3), MY_SAW, theta2), "millimetres", hidden=[r1])
    rejects(check((r1, np.degrees(theta1), np.degrees(theta3)), MY_SAW, theta2), "degrees")
    rejects(check((r1, theta1), MY_SAW, theta2), "3 plain numbers")


def test_saw_slider_acceleration():
    theta2, omega2, alpha2 = np.radians(50.0), 6.0, 4.0
    a_r = _saw_by_slider_crank(theta2, omega2, alpha2)[3]
    bare = _saw_by_slider_crank(theta2, 0.0, alpha2)[3]  # the ω² terms dropped
    check = checks.check_saw_slider_acceleration
    assert check(a_r, MY_SAW, theta2, omega2, alpha2).ok
    assert check(np.float32(a_r), MY_SAW, theta2, omega2, alpha2).ok
    rejects(check(bare, MY_SAW, theta2, omega2, alpha2), "ω²", hidden=[a_r])
    rejects(check(-a_r, MY_SAW, theta2, omega2, alpha2), "sign error", hidden=[a_r])
    rejects(check(1000 * a_r, MY_SAW, theta2, omega2, alpha2), "1000")
    # the slider's own acceleration ẍ (x = r1 cos θ1 of the Cartesian slider-crank), and the course's saw
    textbook = OffsetSliderCrank(crank=0.06, rod=0.15, offset=0.03)
    x_ddot = float(textbook.solve(theta2, omega2, alpha2, branch="left").a_xC)
    rejects(check(x_ddot, MY_SAW, theta2, omega2, alpha2), "ẍ", "a_r = d²r1/dt²", hidden=[a_r])
    course = analytic(theta2, omega2, alpha2)[6]
    rejects(check(course, MY_SAW, theta2, omega2, alpha2), "saw=my_saw", hidden=[a_r])
    rejects(checks.check_saw_position(analytic(theta2)[:3], MY_SAW, theta2), "saw=my_saw")


# ---------------------------------------------------------------- ex05


def _fivebar_points(theta1, theta4):
    P2 = np.array([0.11 * np.cos(theta1) + 0.045, 0.11 * np.sin(theta1)])
    P4 = np.array([0.12 * np.cos(theta4) - 0.045, 0.12 * np.sin(theta4)])
    return P2, P4


def test_fivebar_forward():
    theta1, theta4 = np.radians(70.0), np.radians(125.0)
    P2, P4 = _fivebar_points(theta1, theta4)
    first, second = circle_intersections(P2, 0.15, P4, 0.16)
    down = min(first, second, key=lambda p: p[1])
    up = max(first, second, key=lambda p: p[1])
    check = checks.check_fivebar_forward
    assert check(down, ROBOT, theta1, theta4, -1).ok and check(tuple(up), ROBOT, theta1, theta4, +1).ok
    rejects(check(up, ROBOT, theta1, theta4, -1), "arms up", hidden=down)
    rejects(check(1000 * down, ROBOT, theta1, theta4, -1), "millimetres")
    rejects(check(down[::-1], ROBOT, theta1, theta4, -1), "swapped")


def test_fivebar_inverse():
    x3, y3, lengths = 0.02, 0.21, (0.11, 0.15, 0.16, 0.12, 0.09)
    answer = course_inverse_angles(x3, y3, lengths, -1, +1)  # the course's half-angle coefficients
    other_sigma1 = course_inverse_angles(x3, y3, lengths, +1, +1)[0]
    other_sigma2 = course_inverse_angles(x3, y3, lengths, -1, -1)[1]
    check = checks.check_fivebar_inverse
    assert check(answer, ROBOT, x3, y3, (-1, +1)).ok
    assert check((answer[0] + 2 * np.pi, answer[1]), ROBOT, x3, y3, (-1, +1)).ok
    rejects(check((other_sigma1, answer[1]), ROBOT, x3, y3, (-1, +1)), "σ1", hidden=answer)
    rejects(check((answer[0], other_sigma2), ROBOT, x3, y3, (-1, +1)), "σ2")
    rejects(check(np.degrees(answer), ROBOT, x3, y3, (-1, +1)), "degrees", hidden=answer)
    rejects(check(answer[::-1], ROBOT, x3, y3, (-1, +1)), "swapped")


def test_fivebar_g():
    l1, l2, l3, l4, l5 = sp.symbols("l1:6", positive=True)
    t1, t4, X3, Y3 = sp.symbols("theta1 theta4 X3 Y3", real=True)
    ecl2 = (X3 - l1 * sp.cos(t1) - l5 / 2) ** 2 + (Y3 - l1 * sp.sin(t1)) ** 2 - l2**2
    ecl3 = (X3 - l4 * sp.cos(t4) + l5 / 2) ** 2 + (Y3 - l4 * sp.sin(t4)) ** 2 - l3**2
    linear = sp.expand(ecl2 - ecl3)
    g = -linear.coeff(Y3) / linear.coeff(X3)  # A·X3 + B·Y3 + C = 0 → X3 = −(B/A)·Y3 − C/A
    seeds_g = (-2 * l1 * sp.sin(t1) + 2 * l4 * sp.sin(t4)) / (2 * (l5 + l1 * sp.cos(t1) - l4 * sp.cos(t4)))
    assert sp.expand(sp.numer(sp.together(g - seeds_g))) == 0
    assert checks.check_fivebar_g(g).ok and checks.check_fivebar_g(seeds_g).ok
    rejects(checks.check_fivebar_g(-g), "sign error")
    rejects(checks.check_fivebar_g(1 / g), "X3, not Y3")
    rejects(checks.check_fivebar_g(2 * g), "factor 2")
    rejects(checks.check_fivebar_g(g + l2 - l2 + l3), "f (the constant term)")


def test_fivebar_singularity():
    theta1 = np.radians(100.0)
    P1 = np.array([0.045, 0.0])
    P3 = P1 + (0.11 + 0.15) * np.array([np.cos(theta1), np.sin(theta1)])  # leg 1 stretched
    P5 = np.array([-0.045, 0.0])
    P4 = circle_intersections(P5, 0.12, P3, 0.16)[1]
    theta4 = np.arctan2(*(P4 - P5)[::-1])
    check = checks.check_fivebar_singularity
    assert check("serial1", ROBOT, theta1, theta4, *P3).ok
    assert check("serial, leg 1", ROBOT, theta1, theta4, *P3).ok
    rejects(check("parallel", ROBOT, theta1, theta4, *P3), "not aligned")
    rejects(check("none", ROBOT, theta1, theta4, *P3), "one of them is zero")
    rejects(check("serial4", ROBOT, theta1, theta4, *P3), "other leg")
    rejects(check("type 2", ROBOT, theta1, theta4, *P3), "not aligned")          # type II: parallel
    assert check("Serial singularity of leg 1", ROBOT, theta1, theta4, *P3).ok
    assert check("type I, leg 1", ROBOT, theta1, theta4, *P3).ok
    rejects(check("sideways", ROBOT, theta1, theta4, *P3), "serial1")


def test_fivebar_parallel_singularity():
    theta1, theta4 = np.radians(15.0), 2.812965377804  # |P2 − P4| = l2 + l3 to ~1e-12
    P2, P4 = _fivebar_points(theta1, theta4)
    assert abs(np.linalg.norm(P2 - P4) - 0.31) < 1e-11
    P3 = P2 + 0.15 * (P4 - P2) / np.linalg.norm(P4 - P2)  # distal links in line
    check = checks.check_fivebar_singularity
    assert check("parallel", ROBOT, theta1, theta4, *P3).ok
    assert check("parallel singularity", ROBOT, theta1, theta4, *P3).ok and check("type II", ROBOT, theta1,
                                                                                     theta4, *P3).ok
    rejects(check("serial1", ROBOT, theta1, theta4, *P3), "not zero")
    rejects(check("none", ROBOT, theta1, theta4, *P3), "one of them is zero")


# ---------------------------------------------------------------- the lessons' "Try it" checkers


def test_crank_angle_for_rocker():
    theta4 = np.radians(135.0)
    B = np.array([BENCH.l1 + BENCH.l4 * np.cos(theta4), BENCH.l4 * np.sin(theta4)])
    # A lies on the crank circle and on the circle of radius l3 about B
    roots = [np.arctan2(A[1], A[0]) for A in circle_intersections([0.0, 0.0], BENCH.l2, B, BENCH.l3)]
    inside = [root for root in roots if 0 < root < np.pi]
    outside = [root for root in roots if not 0 < root < np.pi]
    assert len(inside) == 1 and len(outside) == 1
    check = checks.check_crank_angle_for_rocker
    assert check(inside[0], BENCH, theta4).ok
    rejects(check(outside[0], BENCH, theta4), "outside (0, π)", hidden=inside)
    rejects(check(np.degrees(inside[0]), BENCH, theta4), "degrees")
    rejects(check(inside[0] + 0.01, BENCH, theta4), "differs from l3", hidden=inside)
    rejects(check(None, BENCH, theta4), "No answer yet")
    rejects(check("1.2", BENCH, theta4), "should be a number")


def test_rocker_pin_speed():
    theta2, omega2, h = np.radians(120.0), 10.0, 1e-6
    # B from circle intersections at θ2 ± h: |dB/dθ2|·ω2 by central differences
    pins = []
    for angle in (theta2 - h, theta2 + h):
        theta4 = fourbar_by_circles(BENCH, angle, "open")[1]
        pins.append(BENCH.l4 * np.array([np.cos(theta4), np.sin(theta4)]))
    speed = np.linalg.norm(pins[1] - pins[0]) / (2 * h) * omega2
    check = checks.check_rocker_pin_speed
    assert check(speed, BENCH, theta2, omega2).ok
    rejects(check(-speed, BENCH, theta2, omega2), "magnitude")
    rejects(check(speed / BENCH.l4, BENCH, theta2, omega2), "rad/s", hidden=[speed])
    rejects(check(omega2 * BENCH.l2, BENCH, theta2, omega2), "crank pin A", hidden=[speed])
    rejects(check(1.5 * speed, BENCH, theta2, omega2), "|ω4|·l4", hidden=[speed])
    rejects(check(1000 * speed, BENCH, theta2, omega2), "mm/s", hidden=[speed])
    crossed = []
    for angle in (theta2 - h, theta2 + h):
        theta4 = fourbar_by_circles(BENCH, angle, "crossed")[1]
        crossed.append(BENCH.l4 * np.array([np.cos(theta4), np.sin(theta4)]))
    crossed_speed = np.linalg.norm(crossed[1] - crossed[0]) / (2 * h) * omega2
    rejects(check(crossed_speed, BENCH, theta2, omega2), "crossed assembly", hidden=[speed])


def test_motor_start_against_a_numerical_integration():
    import scipy.integrate

    A = 8.0

    def alpha(t, T):  # rise, hold, fall over thirds of T
        return A * np.clip(np.minimum(3 * t / T, 3 - 3 * t / T), 0.0, 1.0) if t < T else 0.0

    def turn(T):  # θ2(T) = ∫0^T (T − t) α(t) dt
        return scipy.integrate.quad(lambda t: (T - t) * alpha(t, T), 0, T, points=[T / 3, 2 * T / 3])[0]

    T = scipy.optimize.brentq(lambda T: turn(T) - 2 * np.pi, 0.5, 5.0, xtol=1e-13)
    omega = scipy.integrate.quad(lambda t: alpha(t, T), 0, T, points=[T / 3, 2 * T / 3])[0]
    rpm = omega * 60 / (2 * np.pi)
    check = checks.check_motor_start
    assert check((T, rpm), A).ok and check((round(T, 3), round(rpm, 2)), A).ok  # 4 significant figures
    rejects(check((round(T, 2), round(rpm, 1)), A), "right to 3 significant figures", "give more digits",
            hidden=[T, rpm])
    rejects(check((T, omega), A), "rad/s", hidden=[T, rpm])
    rejects(check((T, 1.1 * rpm), A), "2·A·T/3", hidden=[T, rpm])
    rejects(check((np.sqrt(6 * np.pi / 5), rpm), A), "T is not right", hidden=[T, rpm])
    rejects(check(T, A), "2 plain numbers")


def test_saw_rates_against_finite_differences():
    theta2, omega2, h = np.pi / 2, 6.472, 1e-6
    ahead, behind = (np.asarray(analytic(theta2 + s * h, saw=MY_SAW))[:3] for s in (1, -1))
    rates = (ahead - behind) / (2 * h) * omega2  # (ṙ1, θ̇1, θ̇3) by central differences
    check = checks.check_saw_rates
    assert check(rates, MY_SAW, theta2, omega2).ok
    rejects(check(-rates, MY_SAW, theta2, omega2), "sign", hidden=rates)
    rejects(check(rates[::-1], MY_SAW, theta2, omega2), "order", hidden=rates)
    for order in ([1, 0, 2], [0, 2, 1], [2, 0, 1]):  # every other order of the components
        rejects(check(rates[order], MY_SAW, theta2, omega2), "wrong order", hidden=rates)
    rejects(check(rates * 1.01, MY_SAW, theta2, omega2), "matrix J", hidden=rates)
    rejects(check(rates[:2], MY_SAW, theta2, omega2), "3 plain numbers")


def test_blade_peak_speed_against_the_textbook_slider_crank():
    omega2 = 6.472
    textbook = OffsetSliderCrank(MY_SAW.r2, MY_SAW.r3, MY_SAW.r1y)
    grid = np.linspace(0, 2 * np.pi, 3601)
    start = grid[np.argmax(np.abs(textbook.solve(grid, omega2, branch="left").v_xC))]
    best = scipy.optimize.minimize_scalar(
        lambda t: -abs(float(textbook.solve(t, omega2, branch="left").v_xC)),
        bracket=(start - 0.01, start + 0.01),
    )
    peak = -best.fun
    check = checks.check_blade_peak_speed
    assert check(peak, MY_SAW, omega2).ok and check(float(f"{peak:.3g}"), MY_SAW, omega2).ok
    assert check(-peak, MY_SAW, omega2).ok
    rejects(check(MY_SAW.r2 * omega2, MY_SAW, omega2), "crank pin", hidden=[peak])
    rejects(check(1.05 * peak, MY_SAW, omega2), "fine grid", hidden=[peak])


def test_fivebar_theta4_against_circle_intersections():
    x3, y3 = -0.03, 0.2
    P5 = np.array([-ROBOT.l5 / 2, 0.0])
    # σ2 = +1: elbow 4 to the left of P5 → P3; σ2 = −1: to the right
    left, right = circle_intersections(P5, ROBOT.l4, [x3, y3], ROBOT.l3)
    theta4 = {+1: np.arctan2(*(left - P5)[::-1]), -1: np.arctan2(*(right - P5)[::-1])}
    check = checks.check_fivebar_theta4
    for sigma in (1, -1):
        assert check(theta4[sigma] + 2 * np.pi, ROBOT, x3, y3, sigma).ok
        rejects(check(theta4[-sigma], ROBOT, x3, y3, sigma), "other sign", hidden=[theta4[sigma]])
        rejects(check(np.degrees(theta4[sigma]), ROBOT, x3, y3, sigma), "degrees")
    rejects(check(theta4[-1] + 0.1, ROBOT, x3, y3, -1), "a2, b2, c2", hidden=[theta4[-1]])


def test_reach_height_against_bisection():
    x3 = -0.03

    def reachable(y):
        return bool(ROBOT.inverse(x3, y, on_failure="nan").reachable)

    low, high = 0.1, 0.4
    assert reachable(low) and not reachable(high)
    for _ in range(60):
        middle = (low + high) / 2
        low, high = (middle, high) if reachable(middle) else (low, middle)
    # ROBOT's leg 1 (l1 + l2 = 0.26, motor at +l5/2) and leg 4 (l3 + l4 = 0.28, motor at −l5/2)
    leg4 = np.sqrt((ROBOT.l3 + ROBOT.l4) ** 2 - (x3 + ROBOT.l5 / 2) ** 2)
    assert low < leg4
    check = checks.check_reach_height
    assert check(low, ROBOT, x3).ok
    rejects(check(low * 1000, ROBOT, x3), "millimetres")
    rejects(check(leg4, ROBOT, x3), "leg 4 stretches", hidden=[low])
    rejects(check(low + 0.01, ROBOT, x3), "farther from the line", hidden=[low])


def test_the_newton_update_read_as_a_teacher_reads_it():
    """Either side of sp.Eq may hold the new iterate's own symbol; x on the left is the old iterate; the
    cubic's roots (what sp.solve gives) are not the update — each named, never sent to the wrong hint."""
    x = sp.Symbol("x")
    update = (2 * x**3 + 5) / (3 * x**2 - 2)  # x − f/f′ for f = x³ − 2x − 5, simplified by hand
    assert checks.check_newton_update(sp.Eq(sp.Symbol("x_next"), update)).ok
    assert checks.check_newton_update(sp.Eq(update, sp.Symbol("x_new"))).ok
    rejects(checks.check_newton_update(sp.Eq(x, update)), "x alone on one side", "current iterate")
    rejects(checks.check_newton_update(sp.Eq(update, x)), "x alone on one side", "current iterate")
    rejects(checks.check_newton_update(sp.solve(x**3 - 2 * x - 5, x)), "the cubic's roots")


def test_a_right_step_formed_with_an_inverse_is_not_told_it_was_not():
    bench = FourBar(0.07, 0.20, 0.15, 0.25)
    seed, theta2 = np.array([0.5, 1.6]), np.radians(40.0)
    F, J = bench.loop_residual(theta2, *seed), bench.loop_jacobian(*seed)
    feedback = checks.check_fourbar_newton_step(-np.linalg.inv(J) @ F, bench, theta2, seed)
    assert feedback.ok and "solved without forming" not in feedback.message


def test_the_saws_omega3_with_theta3_eliminated_is_named():
    r1y, r2, r3, t2, w2 = sp.symbols("r1y r2 r3 theta2 omega2")
    eliminated = -w2 * r2 * sp.cos(t2) / (-r3 * sp.sqrt(1 - ((r1y - r2 * sp.sin(t2)) / r3) ** 2))
    rejects(checks.check_saw_omega3_expression(eliminated), "θ3 eliminated", "keep θ3")
    rejects(checks.check_saw_omega3_expression(-r2 * sp.cos(t2) / r3), "proportional to ω2")


@pytest.mark.parametrize(("said", "read"), [
    ("serial1", "serial1"), ("Serial singularity of leg 1", "serial1"), ("serial (type I) leg 1", "serial1"),
    ("type I, leg 4", "serial4"), ("type II", "parallel"), ("parallel (type-2)", "parallel"),
    ("parallel singularity", "parallel"), ("no singularity", "none"), ("type I", "serial")])
def test_a_singularity_named_as_a_student_names_it(said, read):
    from course_lib.checks.ex05 import _singularity_word

    assert _singularity_word(said) == read
