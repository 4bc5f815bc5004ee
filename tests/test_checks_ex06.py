"""course_lib.checks (exercise set 06): each checker accepts the right answer, computed here by an independent
route, in its equivalent forms, and rejects typical wrong answers with the right hint, never showing
the reference value; silly inputs give feedback, never a traceback.

Routes: the shaper built by hand from a circle and a line (the block on the ray O4 → A, C where
the circle of radius l5 about B meets y = h), central finite differences of that construction in
time, the loops declared on ``Mechanism`` and solved by Newton, and a fine sweep of crank angles for
the lever's stops.
"""

from __future__ import annotations

import itertools

import numpy as np
import pytest
import sympy as sp
from feedback import hides
from test_checks_bad_input import SILLY as SHARED_SILLY

from course_lib import checks
from course_lib.errors import InvalidGeometryError
from course_lib.mechanism import Mechanism
from course_lib.symbolic import time_symbols

R2, D, L4, L5, H = 0.06, 0.15, 0.30, 0.15, 0.30  # the drawing of exercise 06 (m)
th2, th4, r4, th5, x = sp.symbols("theta2 theta4 r4 theta5 x", real=True)
r2, d, l4, l5, h = sp.symbols("r2 d l4 l5 h", positive=True)
LENGTHS = {r2: R2, d: D, l4: L4, l5: L5, h: H}
LEVER_LOOP = sp.Matrix([r2 * sp.cos(th2) - r4 * sp.cos(th4), d + r2 * sp.sin(th2) - r4 * sp.sin(th4)])
RAM_LOOP = sp.Matrix([l4 * sp.cos(th4) + l5 * sp.cos(th5) - x, l4 * sp.sin(th4) + l5 * sp.sin(th5) - h])
GUESS = {th4: 1.0, r4: 0.2, th5: 0.1, x: 0.2}
SILLY = [None, [None, None], ..., "theta4", b"x", 42, 3.5, True, float("nan"), [], {}, {"a": 1}, object(),
         [1, 2, 3], [[1, 2], [3]], np.zeros((3, 3)), sp.Symbol("q"), set(), [object()] * 4]


def by_hand(theta2, right: bool = True):
    """(θ4, r4, θ5, x) of the drawn shaper from a ray and a circle meeting a line."""
    theta2 = np.asarray(theta2, float)
    A = np.stack([R2 * np.cos(theta2), D + R2 * np.sin(theta2)], axis=-1)
    r4_value = np.linalg.norm(A, axis=-1)
    B = L4 * A / r4_value[..., None]
    across = np.sqrt(L5**2 - (H - B[..., 1]) ** 2)
    C = np.stack([B[..., 0] + (across if right else -across), np.full_like(B[..., 0], H)], axis=-1)
    theta5 = np.arctan2(C[..., 1] - B[..., 1], C[..., 0] - B[..., 0])
    return np.arctan2(A[..., 1], A[..., 0]), r4_value, theta5, C[..., 0]


def ram_by_differences(theta2, omega2, alpha2=0.0, step=1e-5):
    """Ram (ẋ, ẍ) by central differences of the construction along θ2(t) = θ2 + ω2 t + α2 t²/2."""
    at = [by_hand(theta2 + omega2 * t + alpha2 * t**2 / 2)[3] for t in (-step, 0.0, step)]
    return (at[2] - at[0]) / (2 * step), (at[2] - 2 * at[1] + at[0]) / step**2


def accepts(feedback):
    assert isinstance(feedback, checks.Feedback) and feedback.ok, feedback
    assert str(feedback).startswith("✔")


def rejects(feedback, *words, hidden=()):
    assert isinstance(feedback, checks.Feedback) and not feedback.ok, feedback
    assert str(feedback).startswith("✘")
    assert all(word in feedback.message for word in words), feedback
    assert hides(feedback, *hidden), feedback


# ---------------------------------------------------------------- the reference itself


def test_the_checkers_shaper_is_the_drawing_built_by_hand():
    theta2 = np.linspace(0, 2 * np.pi, 73)
    for assembly, right in ((+1, True), (-1, False)):
        ours = np.array(checks.SHAPER.configuration(theta2, assembly))
        hand = np.array(by_hand(theta2, right))
        assert np.abs(np.angle(np.exp(1j * (ours[[0, 2]] - hand[[0, 2]])))).max() < 1e-12
        assert np.abs(ours[[1, 3]] - hand[[1, 3]]).max() < 1e-12


def test_the_reference_rates_are_central_differences_of_the_construction():
    for theta2, omega2, alpha2 in ((0.3, 8.0, 0.0), (2.0, -5.0, 12.0), (4.4, 10.0, -3.0)):
        velocity, acceleration = checks.SHAPER.rates(theta2, omega2, alpha2)
        v_fd, a_fd = ram_by_differences(theta2, omega2, alpha2)
        assert abs(velocity[3] - v_fd) < 1e-8 and abs(acceleration[3] - a_fd) < 1e-5


def test_the_stops_stroke_and_time_ratio_match_a_fine_sweep():
    theta2 = np.linspace(-np.pi / 2, 3 * np.pi / 2, 2_000_001)
    theta4, _, _, ram = by_hand(theta2)
    low, high = theta2[np.argmin(theta4)], theta2[np.argmax(theta4)]
    slow = (low - high) % (2 * np.pi)
    slow = max(slow, 2 * np.pi - slow)
    stops = np.sort(np.mod(checks.SHAPER.limit_angles(), 2 * np.pi))
    assert np.allclose(np.sort(np.mod([low, high], 2 * np.pi)), stops, atol=1e-5)
    assert abs(slow / (2 * np.pi - slow) - checks.SHAPER.time_ratio()) < 1e-5
    assert abs(np.ptp(ram) - checks.SHAPER.stroke()) < 1e-9
    assert abs(checks.SHAPER.stroke() - 2 * L4 * R2 / D) < 1e-12  # the chord of B's arc


def test_drawings_that_are_no_quick_return_are_refused():
    with pytest.raises(InvalidGeometryError, match="crank"):
        checks.ShaperDrawing(crank=0.2, pivot_distance=0.15)
    with pytest.raises(InvalidGeometryError, match="ram_height"):
        checks.ShaperDrawing(ram_height=0.6)
    with pytest.raises(InvalidGeometryError, match="pivot_distance"):
        checks.check_quick_return_time_ratio(2.0, 0.1, 0.05)


# ---------------------------------------------------------------- task 1: the loops


def test_loops_in_any_equivalent_form_are_accepted():
    lever, ram = list(LEVER_LOOP), list(RAM_LOOP)
    t2, t4, t5 = time_symbols("theta2", "theta4", "theta5")
    in_time = [loop.xreplace({th2: t2, th4: t4, th5: t5}) for loop in (LEVER_LOOP, RAM_LOOP)]
    plain = {s: sp.Symbol(s.name) for s in (th2, th4, r4, th5, x, r2, d, l4, l5, h)}
    declared = Mechanism([LEVER_LOOP, RAM_LOOP], [th4, r4, th5, x], [th2], LENGTHS)
    for answer in ([LEVER_LOOP, RAM_LOOP], (RAM_LOOP, LEVER_LOOP), [-LEVER_LOOP, 2.5 * RAM_LOOP],
                   lever + ram, [ram[1], lever[0], ram[0], lever[1]], sp.Matrix([*lever, *ram]),
                   [sp.Eq(r2 * sp.cos(th2), r4 * sp.cos(th4)), sp.Eq(d + r2 * sp.sin(th2), r4 * sp.sin(th4)),
                    sp.Eq(x, l4 * sp.cos(th4) + l5 * sp.cos(th5)), ram[1]],
                   [lever[0] + ram[0], lever[1], ram[0], ram[1] - 3 * lever[0]],  # combined rows
                   [loop.subs(LENGTHS) for loop in (LEVER_LOOP, RAM_LOOP)],  # numbers for the lengths
                   [loop.xreplace(plain) for loop in (LEVER_LOOP, RAM_LOOP)],  # no assumptions
                   in_time, declared):
        accepts(checks.check_shaper_loops(answer))


def test_walking_the_ram_loop_the_other_way_and_solving_for_x_are_accepted():
    rise = h - l4 * sp.sin(th4)
    closed_x = x - l4 * sp.cos(th4) - sp.sqrt(l5**2 - rise**2)  # holds on the drawn assembly only
    accepts(checks.check_shaper_loops([LEVER_LOOP, [closed_x, RAM_LOOP[1]]]))
    walked_back = sp.Matrix([x, h]) - l4 * sp.Matrix([sp.cos(th4), sp.sin(th4)]) - l5 * sp.Matrix(
        [sp.cos(th5), sp.sin(th5)])
    accepts(checks.check_shaper_loops([LEVER_LOOP, walked_back]))


@pytest.mark.parametrize(("answer", "words"), [
    ([sp.Matrix([LEVER_LOOP[0], r2 * sp.sin(th2) - r4 * sp.sin(th4)]), RAM_LOOP], ("equation 2", "(0, d)")),
    ([LEVER_LOOP.subs(r4, l4), RAM_LOOP], ("equation 1", "l4 in the loop through the block")),
    ([LEVER_LOOP, sp.Matrix([RAM_LOOP[0], l4 * sp.sin(th4) + l5 * sp.sin(th5)])], ("equation 4", "y = h")),
    ([LEVER_LOOP, RAM_LOOP.subs(l4, r4)], ("equation 3", "B is the end of the lever")),
    ([LEVER_LOOP, RAM_LOOP.subs(l5, -l5)], ("sign slip", "link vector (B → C)")),
    ([sp.Matrix([-r2 * sp.cos(th2) - r4 * sp.cos(th4), d - r2 * sp.sin(th2) - r4 * sp.sin(th4)]), RAM_LOOP],
     ("sign slip", "crank vector")),
    ([sp.Matrix([r2 * sp.cos(th2) + r4 * sp.cos(th4), d + r2 * sp.sin(th2) - r4 * sp.sin(th4)]), RAM_LOOP],
     ("equation 1", "sign slip")),  # the lever's or the crank's: one relative sign
    ([sp.Matrix([r2 * sp.sin(th2) - r4 * sp.cos(th4), d + r2 * sp.cos(th2) - r4 * sp.sin(th4)]), RAM_LOOP],
     ("equation 1", "not satisfied")),
    ([LEVER_LOOP, LEVER_LOOP], ("do not fix",)),
    ([LEVER_LOOP[0] ** 2, LEVER_LOOP[1], *RAM_LOOP], ("do not fix",)),
    ([LEVER_LOOP, [RAM_LOOP[0], 0]], ("equation 4 is a number", "does not change when the shaper moves")),
    ([LEVER_LOOP], ("four scalar equations", "you gave 2", "only one loop")),
    ([LEVER_LOOP, RAM_LOOP, RAM_LOOP], ("you gave 6",)),
    ([LEVER_LOOP, RAM_LOOP + sp.Matrix([sp.Symbol("l3"), 0])], ("equation 3", "does not define: l3")),
    ([LEVER_LOOP, [sp.Function("f")(th4), RAM_LOOP[1]]], ("could not be evaluated",)),
    ([LEVER_LOOP, [sp.Eq(x, x), RAM_LOOP[1]]], ("equation 3 is True",)),
    ([LEVER_LOOP, [sp.Derivative(x, th2), RAM_LOOP[1]]], ("equation 3 holds a derivative",)),
    ([LEVER_LOOP, ["x - l4*cos(theta4)", RAM_LOOP[1]]], ("equation 3", "not a string")),
    ([LEVER_LOOP, [None, RAM_LOOP[1]]], ("equation 3", "None")),
])
def test_wrong_loops_are_named(answer, words):
    rejects(checks.check_shaper_loops(answer), *words)


# ---------------------------------------------------------------- task 2: the position


def declared_shaper():
    return Mechanism([LEVER_LOOP, RAM_LOOP], [th4, r4, th5, x], [th2], LENGTHS)


def test_position_from_the_construction_and_from_newton_is_accepted():
    theta2 = np.radians(60.0)
    reference = by_hand(theta2)
    accepts(checks.check_shaper_position(reference, theta2))
    accepts(checks.check_shaper_position(np.array(reference) + [2 * np.pi, 0, -2 * np.pi, 0], theta2))
    motion = declared_shaper().solve({th2: theta2}, guess=GUESS)
    accepts(checks.check_shaper_position(motion.position, theta2))
    accepts(checks.check_shaper_position(motion, theta2))
    accepts(checks.check_shaper_position({th4: reference[0], r4: reference[1], th5: reference[2],
                                          x: reference[3]}, theta2))
    flipped = (reference[0] + np.pi, -reference[1], reference[2], reference[3])
    assert "r4 < 0" in checks.check_shaper_position(flipped, theta2).message


def test_wrong_positions_are_named():
    theta2 = np.radians(60.0)
    theta4, r4_value, theta5, ram = by_hand(theta2)
    hidden = (theta4, r4_value, theta5, ram)
    check = checks.check_shaper_position
    rejects(check(by_hand(theta2, right=False), theta2), "other assembly", hidden=hidden)
    in_degrees = np.degrees([theta4, 0, theta5, 0]) + [0, r4_value, 0, ram]
    rejects(check(in_degrees, theta2), "degrees", hidden=hidden)
    rejects(check((theta4, 1000 * r4_value, theta5, 1000 * ram), theta2), "millimetres", hidden=hidden)
    rejects(check(by_hand(60.0), theta2), "np.radians", hidden=hidden)
    rejects(check((r4_value, theta4, theta5, ram), theta2), "wrong order", hidden=hidden)
    rejects(check((theta4, r4_value, theta5 + 0.1, ram), theta2), "θ5 and x are not", hidden=hidden)
    rejects(check((theta4 + 0.1, r4_value, theta5, ram), theta2), "θ4 and r4 are not", hidden=hidden)
    rejects(check({"theta4": theta4}, theta2), "the dict needs the keys theta4, r4, theta5, x")
    rejects(check([theta4, r4_value, float("nan"), ram], theta2), "theta5", "NaN")
    rejects(check([theta4, r4_value, "0.1", ram], theta2), "theta5", "string")


# ---------------------------------------------------------------- task 3: the ram's rates


def test_ram_rates_by_differences_and_by_the_core_are_accepted():
    theta2, omega2 = np.radians(60.0), 8.0
    accepts(checks.check_ram_motion(ram_by_differences(theta2, omega2), theta2, omega2))
    accepts(checks.check_ram_motion(ram_by_differences(theta2, omega2, 5.0), theta2, omega2, 5.0))
    motion = declared_shaper().solve({th2: theta2}, rates={th2: omega2}, guess=GUESS)
    ram = (motion.velocity["x"], motion.acceleration["x"])
    accepts(checks.check_ram_motion(ram, theta2, omega2))
    accepts(checks.check_ram_motion({"v_x": ram[0], "a_x": ram[1]}, theta2, omega2))


def test_wrong_ram_rates_are_named():
    theta2, omega2 = np.radians(60.0), 8.0
    motion = declared_shaper().solve({th2: theta2}, rates={th2: omega2}, guess=GUESS)
    velocity, acceleration = ram_by_differences(theta2, omega2)
    hidden = (velocity, acceleration)
    check = checks.check_ram_motion
    rejects(check((motion.velocity["r4"], motion.acceleration["r4"]), theta2, omega2), "block", hidden=hidden)
    rejects(check((motion.velocity["theta4"], motion.acceleration["theta4"]), theta2, omega2), "lever",
            hidden=hidden)
    rejects(check((1000 * velocity, 1000 * acceleration), theta2, omega2), "mm/s", hidden=hidden)
    rejects(check((-velocity, acceleration), theta2, omega2), "counter-clockwise", hidden=hidden)
    rejects(check(ram_by_differences(60.0, omega2), theta2, omega2), "np.radians", hidden=hidden)
    rejects(check((velocity, 0.0), theta2, omega2), "velocity is right", hidden=hidden)
    rejects(check((velocity + 0.1, acceleration), theta2, omega2), "velocity is not right", hidden=hidden)
    rejects(check(velocity, theta2, omega2), "2 numbers")


# ---------------------------------------------------------------- task 4 and lesson 12: stroke, time ratio


def sweep_ratio(crank, distance, count):
    """Slow over fast crank angle between the lever's stops, found on ``count`` samples by hand."""
    theta2 = np.linspace(0, 2 * np.pi, count, endpoint=False)
    theta4 = np.arctan2(distance + crank * np.sin(theta2), crank * np.cos(theta2))
    turned = (theta2[np.argmax(theta4)] - theta2[np.argmin(theta4)]) % (2 * np.pi)
    return max(turned, 2 * np.pi - turned) / min(turned, 2 * np.pi - turned)


def test_stroke_and_time_ratio_from_a_sweep_are_accepted():
    theta2 = np.radians(np.arange(0, 360, 0.5))
    stroke = np.ptp(by_hand(theta2)[3])
    accepts(checks.check_ram_stroke((stroke, sweep_ratio(R2, D, 720))))
    accepts(checks.check_ram_stroke([stroke, sweep_ratio(R2, D, 100_000)]))


def test_wrong_strokes_and_ratios_are_named():
    stroke, ratio = np.ptp(by_hand(np.linspace(0, 2 * np.pi, 200_001))[3]), sweep_ratio(R2, D, 200_000)
    hidden = (stroke, ratio)
    check = checks.check_ram_stroke
    rejects(check((1000 * stroke, ratio)), "millimetres", hidden=hidden)
    rejects(check((stroke / 2, ratio)), "half the stroke", hidden=hidden)
    rejects(check((-stroke, ratio)), "positive", hidden=hidden)
    rejects(check((stroke * 1.1, ratio)), "stroke is not right", hidden=hidden)
    rejects(check((stroke, 1 / ratio)), "fast stroke over the slow one", hidden=hidden)
    slow_degrees = 360 * ratio / (1 + ratio)
    rejects(check((stroke, slow_degrees)), "crank angle", hidden=hidden)
    rejects(check((stroke, np.radians(360 - slow_degrees))), "crank angle", hidden=hidden)
    rejects(check((stroke, ratio * 1.02)), "close", hidden=hidden)
    rejects(check((stroke, ratio * 1.3)), "not the time ratio", hidden=hidden)


def test_the_lesson_time_ratio():
    crank, distance = 0.05, 0.08
    reference = sweep_ratio(crank, distance, 400_000)
    accepts(checks.check_quick_return_time_ratio(reference, crank, distance))
    fine_grid = np.float64(sweep_ratio(crank, distance, 36_000))
    accepts(checks.check_quick_return_time_ratio(fine_grid, crank, distance))
    rejects(checks.check_quick_return_time_ratio(sweep_ratio(crank, distance, 360), crank, distance),
            "close, but not to 3 significant figures", hidden=(reference,))  # a 1° grid, not interpolated
    accepts(checks.check_quick_return_time_ratio(2.51, crank, distance))  # 3 significant figures
    rejects(checks.check_quick_return_time_ratio(2.5, crank, distance), "right to 2 significant figures",
            "give more digits", hidden=(reference,))
    rejects(checks.check_quick_return_time_ratio(1 / reference, crank, distance), "slow over fast",
            hidden=(reference,))
    rejects(checks.check_quick_return_time_ratio(reference + 0.5, crank, distance), "not the time ratio",
            hidden=(reference,))
    accepts(checks.check_quick_return_time_ratio(2.0, 0.05, 0.10))  # β = 30°: 240° against 120°


# ---------------------------------------------------------------- anything at all


def all_checkers(answer):
    theta2 = np.radians(60.0)
    velocity, acceleration = ram_by_differences(theta2, 8.0)
    return [(checks.check_shaper_loops(answer), ()),
            (checks.check_shaper_position(answer, theta2), by_hand(theta2)),
            (checks.check_ram_motion(answer, theta2, 8.0), (velocity, acceleration)),
            (checks.check_ram_stroke(answer), (2 * L4 * R2 / D, sweep_ratio(R2, D, 100_000))),
            (checks.check_quick_return_time_ratio(answer, 0.05, 0.08), (sweep_ratio(0.05, 0.08, 100_000),))]


@pytest.mark.parametrize("answer", SILLY + list(SHARED_SILLY.values()),
                         ids=[f"ours-{k}" for k in range(len(SILLY))] + list(SHARED_SILLY))
def test_silly_answers_get_feedback_not_a_traceback(answer):
    """Ours and the table every checker of course_lib.checks meets (tests/test_checks_bad_input.py)."""
    for feedback, references in all_checkers(answer):
        assert isinstance(feedback, checks.Feedback) and not feedback.ok, (answer, feedback)
        assert feedback.message.strip() and "could not be checked" not in feedback.message, feedback
        assert hides(feedback, *references), feedback


def test_no_answer_yet_is_said_as_such():
    for feedback in (checks.check_shaper_loops(None), checks.check_shaper_position(None, 1.0),
                     checks.check_ram_motion((None, None), 1.0, 8.0), checks.check_ram_stroke(None),
                     checks.check_quick_return_time_ratio(None, 0.05, 0.08)):
        assert str(feedback).startswith("✘ No answer yet")


# ---------------------------------------------------------------- task 1: which vector a sign slip turned

VECTORS = {"crank vector (O2 → A)": {r2: -r2}, "block's vector along the lever (O4 → A)": {r4: -r4},
           "frame vector (O4 → O2)": {d: -d}, "lever vector (O4 → B)": {l4: -l4},
           "link vector (B → C)": {l5: -l5}, "ram's vector (O4 → C)": {x: -x, h: -h}}


@pytest.mark.parametrize("vector", VECTORS)
def test_a_flipped_vector_is_named_whatever_the_order_of_the_components(vector):
    rows = [row.xreplace(VECTORS[vector]) for row in (*LEVER_LOOP, *RAM_LOOP)]  # that vector walked backwards
    for order in itertools.permutations(range(4)):
        rejects(checks.check_shaper_loops([rows[k] for k in order]), "sign slip", vector)


def test_a_sign_slip_in_one_component_names_the_component():
    rows = [r2 * sp.cos(th2) + r4 * sp.cos(th4), LEVER_LOOP[1], *RAM_LOOP]  # −r4 cos θ4 written with +
    for order in itertools.permutations(range(4)):
        where = f"equation {order.index(0) + 1} alone"
        feedback = checks.check_shaper_loops([rows[k] for k in order])
        rejects(feedback, "sign slip", where, "both of its components")


def test_loops_written_as_equations_pass_the_check_and_solve_in_the_core():
    def R(length, angle):
        return length * sp.Matrix([sp.cos(angle), sp.sin(angle)])

    per_component = [sp.Eq(r4 * sp.cos(th4), r2 * sp.cos(th2)), sp.Eq(r4 * sp.sin(th4), d + r2 * sp.sin(th2)),
                     sp.Eq(l4 * sp.cos(th4) + l5 * sp.cos(th5), x),
                     sp.Eq(l4 * sp.sin(th4) + l5 * sp.sin(th5), h)]
    as_matrices = [sp.Eq(R(r4, th4), sp.Matrix([0, d]) + R(r2, th2)),
                   sp.Eq(R(l4, th4) + R(l5, th5), sp.Matrix([x, h]))]
    for loops in (per_component, as_matrices):
        accepts(checks.check_shaper_loops(loops))
        motion = Mechanism(loops, [th4, r4, th5, x], [th2], LENGTHS).solve({th2: 1.0}, guess=GUESS)
        solved = np.array([motion.position[name] for name in ("theta4", "r4", "theta5", "x")])
        assert np.abs(solved - np.array(by_hand(1.0))).max() < 1e-12
