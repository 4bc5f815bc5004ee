"""course_lib.checks (exercise set 06): each checker accepts the right answer, computed here by an independent
route, in its equivalent forms, and rejects typical wrong answers with the right hint, never showing
the reference value; silly inputs give feedback, never a traceback.

Routes: the shaper built by hand from a circle and a line (the block on the ray O4 → A, C where
the circle of radius l5 about B meets y = h), that construction differentiated in time by sympy and by
central finite differences, the loops declared on ``Mechanism`` and solved by Newton, and a fine sweep of
crank angles for the lever's stops.
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
from course_lib.motion import Motion
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


def rates_by_sympy(theta2, omega2, alpha2):
    """(q̇, q̈) of (θ4, r4, θ5, x), the construction of ``by_hand`` written in sympy and differentiated in time
    along θ2(t) = θ2 + ω2 t + α2 t²/2 (C right of B)."""
    t = sp.Symbol("t", real=True)
    crank = theta2 + omega2 * t + alpha2 * t**2 / 2
    Ax, Ay = R2 * sp.cos(crank), D + R2 * sp.sin(crank)
    length = sp.sqrt(Ax**2 + Ay**2)
    Bx, By = L4 * Ax / length, L4 * Ay / length
    across = sp.sqrt(L5**2 - (H - By) ** 2)
    q = [sp.atan2(Ay, Ax), length, sp.atan2(H - By, across), Bx + across]
    return tuple(np.array([float(sp.diff(value, t, order).subs(t, 0)) for value in q]) for order in (1, 2))


ANGLES_TRIED = np.radians([0.0, 17.0, 60.0, 90.0, 151.0, 200.0, 265.0, 330.0])


def test_the_declarations_solve_is_the_drawing_built_by_hand():
    """The core's solve of ShaperDrawing's declaration against the circle and the line, on both assemblies."""
    theta2 = np.concatenate([ANGLES_TRIED, np.linspace(0, 2 * np.pi, 73)])
    for assembly, right in (("as drawn", True), ("C left of B", False), ({"theta5": +1}, False),
                            ({"x": -1, "r4": +1}, True)):
        motion = checks.SHAPER.solve(theta2, assembly=assembly)
        ours = np.array([motion.position[name] for name in ("theta4", "r4", "theta5", "x")])
        hand = np.array(by_hand(theta2, right))
        assert np.abs(np.angle(np.exp(1j * (ours[[0, 2]] - hand[[0, 2]])))).max() < 1e-12
        assert np.abs(ours[[1, 3]] - hand[[1, 3]]).max() < 1e-12
        assert set(np.ravel(motion.assembly["x"])) == {-1 if right else +1}  # σ: −sign(cos θ5)
        assert set(np.ravel(motion.assembly["r4"])) == {+1}  # σ: sign(r4)


def test_the_declarations_rates_are_the_construction_differentiated():
    for theta2, omega2, alpha2 in ((0.3, 8.0, 0.0), (2.0, -5.0, 12.0), (4.4, 10.0, -3.0),
                                   (np.pi / 3, 8.0, 0.0)):
        motion = checks.SHAPER.solve(theta2, omega2, alpha2)
        velocity = np.array([motion.velocity[name] for name in ("theta4", "r4", "theta5", "x")])
        acceleration = np.array([motion.acceleration[name] for name in ("theta4", "r4", "theta5", "x")])
        by_sympy = rates_by_sympy(theta2, omega2, alpha2)
        assert np.abs(velocity - by_sympy[0]).max() < 1e-12 * max(1.0, np.abs(by_sympy[0]).max())
        assert np.abs(acceleration - by_sympy[1]).max() < 1e-12 * max(1.0, np.abs(by_sympy[1]).max())
        v_fd, a_fd = ram_by_differences(theta2, omega2, alpha2)  # and a third route, to its h² error
        assert abs(velocity[3] - v_fd) < 1e-8 and abs(acceleration[3] - a_fd) < 1e-5


def test_the_declaration_is_the_shapers_loops_and_points():
    mechanism = checks.ShaperDrawing(crank=0.05, pivot_distance=0.12).mechanism
    assert [s.name for s in mechanism.unknowns] == ["theta4", "r4", "theta5", "x"]
    assert [s.name for s in mechanism.inputs] == ["theta2"]
    assert {s.name: v for s, v in mechanism.parameters.items()} == {"r2": 0.05, "d": 0.12, "l4": 0.30,
                                                                     "l5": 0.15, "h": 0.30}
    theta2 = 1.1
    motion = mechanism.solve({"theta2": theta2}, assembly={"r4": +1, "x": -1})
    joints = mechanism.joints(motion)
    A = np.array([0.05 * np.cos(theta2), 0.12 + 0.05 * np.sin(theta2)])
    assert np.abs(joints["A"] - A).max() < 1e-12 and np.abs(joints["O2"] - [0.0, 0.12]).max() == 0
    B, C = joints["B"], joints["C"]
    assert abs(np.hypot(*B) - 0.30) < 1e-12 and abs(B[0] * A[1] - B[1] * A[0]) < 1e-12  # on the ray O4 → A
    assert abs(np.hypot(*(C - B)) - 0.15) < 1e-12 and abs(C[1] - 0.30) < 1e-12
    assert joints["C"][0] > joints["B"][0]  # as drawn
    assert mechanism.links.named() == {"crank": ("O2", "A"), "lever": ("O4", "B"), "link": ("B", "C")}


def test_the_drawings_solve_is_its_declarations_solve():
    """One solver: ShaperDrawing.solve is the core's solve of its declaration, the same Motion to the bit."""
    theta2 = ANGLES_TRIED
    ours = checks.SHAPER.solve(theta2, 8.0, 2.0)
    core = checks.SHAPER.mechanism.solve({"theta2": theta2}, {"theta2": 8.0}, {"theta2": 2.0},
                                         assembly={"r4": +1, "x": -1})
    assert type(ours) is Motion and type(core) is Motion
    for part in ("position", "velocity", "acceleration", "assembly"):
        assert all(np.array_equal(getattr(ours, part)[name], getattr(core, part)[name])
                   for name in ("theta4", "r4", "theta5", "x")), part


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
    for arguments, name in (({"theta2": "x"}, "theta2"), ({"theta2": 1.0, "omega2": None}, "omega2"),
                            ({"theta2": 1.0, "alpha2": float("nan")}, "alpha2"),
                            ({"theta2": 1.0, "assembly": "crossed"}, "assembly")):
        with pytest.raises(InvalidGeometryError, match=name):
            checks.SHAPER.solve(**arguments)


# ---------------------------------------------------------------- task 1: the loops


#: Task 1's right answer in every form the check accepts, as a student writes the answer cell (the names of
#: the notebook: th2 … x, r2 … h, R); each one also runs through the whole student copy
#: (tests/test_ex06_student_copy.py).
LOOPS_CELL = ("lever_loop = sp.Matrix([0, d]) + R(r2, th2) - R(r4, th4)\n"
              "ram_loop = R(l4, th4) + R(l5, th5) - sp.Matrix([x, h])\n")
ACCEPTED_LOOPS = {
    "two matrices": "loops = [lever_loop, ram_loop]",
    "a tuple, the other order": "loops = (ram_loop, lever_loop)",
    "signs and scales": "loops = [-lever_loop, 2.5 * ram_loop]",
    "walked the other way": "loops = [R(r4, th4) - sp.Matrix([0, d]) - R(r2, th2), "
                            "sp.Matrix([x, h]) - R(l4, th4) - R(l5, th5)]",
    "four rows": "loops = [*lever_loop, *ram_loop]",
    "four rows, shuffled": "loops = [ram_loop[1], lever_loop[0], ram_loop[0], lever_loop[1]]",
    "one 4×1 matrix": "loops = sp.Matrix([*lever_loop, *ram_loop])",
    "rows as Eq": "loops = [sp.Eq(r2 * sp.cos(th2), r4 * sp.cos(th4)), "
                  "sp.Eq(d + r2 * sp.sin(th2), r4 * sp.sin(th4)), "
                  "sp.Eq(x, l4 * sp.cos(th4) + l5 * sp.cos(th5)), ram_loop[1]]",
    "loops as Eq of matrices": "loops = [sp.Eq(R(r4, th4), sp.Matrix([0, d]) + R(r2, th2)), "
                               "sp.Eq(R(l4, th4) + R(l5, th5), sp.Matrix([x, h]))]",
    "rows combined": "loops = [lever_loop[0] + ram_loop[0], lever_loop[1], ram_loop[0], "
                     "ram_loop[1] - 3 * lever_loop[0]]",
    "no assumptions": "plain = {s: sp.Symbol(s.name) for s in (th2, th4, r4, th5, x, r2, d, l4, l5, h)}\n"
                      "loops = [loop.xreplace(plain) for loop in (lever_loop, ram_loop)]",
}


def R(length, angle):
    return sp.Matrix([length * sp.cos(angle), length * sp.sin(angle)])


def loops_from(source: str):
    """The ``loops`` an answer cell defines, run with the notebook's names."""
    names = {"sp": sp, "R": R, "th2": th2, "th4": th4, "r4": r4, "th5": th5, "x": x, "r2": r2, "d": d,
             "l4": l4, "l5": l5, "h": h}
    exec(LOOPS_CELL + source, names)
    return names["loops"]


@pytest.mark.parametrize("source", ACCEPTED_LOOPS.values(), ids=ACCEPTED_LOOPS)
def test_loops_in_any_equivalent_form_are_accepted(source):
    answer = loops_from(source)
    accepts(checks.check_shaper_loops(answer))
    # and Task 2 declares them as given: the core solves them to the drawing
    motion = Mechanism(answer, [th4, r4, th5, x], [th2], LENGTHS).solve({th2: 1.0}, guess=GUESS)
    solved = np.array([motion.position[name] for name in ("theta4", "r4", "theta5", "x")])
    assert np.abs(solved - np.array(by_hand(1.0))).max() < 1e-12


def test_right_loops_in_a_form_task_2_cannot_declare_are_named():
    """Each right, but Mechanism(loops, …) of Task 2 refuses it as given: the check says what form to use."""
    t2, t4, t5 = time_symbols("theta2", "theta4", "theta5")
    declared = Mechanism([LEVER_LOOP, RAM_LOOP], [th4, r4, th5, x], [th2], LENGTHS)
    for answer, words in (
            ([list(LEVER_LOOP), list(RAM_LOOP)], ("2×1 matrix", "list inside the list")),
            ([LEVER_LOOP, [RAM_LOOP[0], RAM_LOOP[1]]], ("list inside the list",)),
            ([loop.subs(LENGTHS) for loop in (LEVER_LOOP, RAM_LOOP)],
             ("hold no r2, d, l4, l5, h", "symbols")),
            ([LEVER_LOOP, RAM_LOOP.subs(h, H)], ("hold no h",)),
            ([loop.xreplace({th2: t2, th4: t4, th5: t5}) for loop in (LEVER_LOOP, RAM_LOOP)],
             ("functions of time",)),
            (declared, ("that is a Mechanism", "Task 2 declares"))):
        rejects(checks.check_shaper_loops(answer), *words)


def test_walking_the_ram_loop_the_other_way_and_solving_for_x_are_accepted():
    rise = h - l4 * sp.sin(th4)
    closed_x = x - l4 * sp.cos(th4) - sp.sqrt(l5**2 - rise**2)  # holds on the drawn assembly only
    accepts(checks.check_shaper_loops([LEVER_LOOP, sp.Matrix([closed_x, RAM_LOOP[1]])]))
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


DECLARED = declared_shaper()


def position_check(position, theta2, declaration=DECLARED, guess=GUESS):
    """Task 2's check as its cell calls it: the declaration, its guess and the position."""
    return checks.check_shaper_position((declaration, guess, position), theta2)


def test_position_from_the_construction_and_from_newton_is_accepted():
    theta2 = np.radians(60.0)
    reference = by_hand(theta2)
    accepts(position_check(reference, theta2))
    accepts(position_check(np.round(reference, 4), theta2))  # to the 4 decimals asked
    accepts(position_check(np.array(reference) + [2 * np.pi, 0, -2 * np.pi, 0], theta2))
    motion = DECLARED.solve({th2: theta2}, guess=GUESS)
    accepts(position_check(motion.position, theta2))
    accepts(position_check(motion, theta2))
    accepts(position_check({th4: reference[0], r4: reference[1], th5: reference[2], x: reference[3]}, theta2))
    by_names = {"r2": R2, "d": D, "l4": L4, "l5": L5, "h": H}
    reordered = Mechanism([RAM_LOOP, LEVER_LOOP], [x, th5, r4, th4], [th2], by_names)
    accepts(position_check(reference, theta2, reordered, {"theta4": 1.2, "r4": 0.2, "theta5": 0.1, "x": 0.2}))
    flipped = (reference[0] + np.pi, -reference[1], reference[2], reference[3])
    assert "r4 < 0" in position_check(flipped, theta2).message


def test_right_numbers_without_the_declaration_are_not_a_tick():
    """The method: the position read off the given drawing (its pin, end, ram_pin) is not the task."""
    theta2 = np.radians(60.0)
    reference = by_hand(theta2)
    hidden = reference
    lever_only = Mechanism([LEVER_LOOP], [th4, r4], [th2], {r2: R2, d: D})  # lesson 12's shaper
    for declaration, guess, words in (
            (None, None, ("declare the shaper", "not only the four numbers")),
            (None, GUESS, ("declare the shaper",)),
            ("shaper", GUESS, ("should be your declaration", "str")),
            (DECLARED, None, ("store the guess",)),
            (DECLARED, [1.2, 0.2, 0.1, 0.2], ("guess should be a dict", "list")),
            (lever_only, {th4: 1.2, r4: 0.2}, ("unknowns are theta4, r4",)),
            (Mechanism([LEVER_LOOP, RAM_LOOP], [th4, r4, th5, th2], [x], LENGTHS), GUESS, ("unknowns",)),
            (DECLARED.with_parameters({"d": 0.16}), GUESS, ("parameter d is not the drawing's",)),
            (DECLARED.with_parameters({"h": 0.31, "l5": 0.16}), GUESS, ("parameters l5, h are not",)),
            (DECLARED.with_parameters({name: 1000 * value for name, value in zip(
                "r2 d l4 l5 h".split(), (R2, D, L4, L5, H), strict=True)}),
             {th4: 1.2, r4: 200.0, th5: 0.1, x: 200.0}, ("millimetres",)),
            (DECLARED, {th4: 1.2, r4: 0.2, th5: 3.0, x: 0.0}, ("other assembly", "C left of B")),
            (DECLARED, {th4: 1.2, r4: 0.2}, ("could not be solved", "guess")),
            (Mechanism([LEVER_LOOP, RAM_LOOP], [th4, r4, th5, x], [th2], {**LENGTHS, l4: 0.3 + 1e-6}), GUESS,
             ("parameter l4",)),
            (Mechanism([LEVER_LOOP, RAM_LOOP.subs(h, sp.Symbol("height"))], [th4, r4, th5, x], [th2],
                       {r2: R2, d: D, l4: L4, l5: L5, "height": 0.31}), GUESS, ("not the drawn shaper",))):
        rejects(position_check(reference, theta2, declaration, guess), *words, hidden=hidden)
    rejects(checks.check_shaper_position(reference, theta2), "grades your declaration", hidden=hidden)
    rejects(checks.check_shaper_position(DECLARED.solve({th2: theta2}, guess=GUESS), theta2),
            "grades your declaration", hidden=hidden)


def test_a_guess_that_flips_the_ram_over_the_turn_is_named():
    """Right at 60°, but from θ2 = 0 (where Task 4's sweep starts) the guess lands C left of B."""
    theta2 = np.radians(60.0)
    guess = {th4: 0.8, r4: 0.2, th5: 2.0, x: 0.1}
    at_60 = DECLARED.solve({th2: theta2}, guess=guess).position
    assert abs(at_60["x"] - by_hand(theta2)[3]) < 1e-12  # as drawn at 60°
    at_0 = DECLARED.solve({th2: np.radians([0.0, 60.0])}, guess=guess).position
    assert abs(at_0["x"][0] - by_hand(0.0, right=False)[3]) < 1e-12  # C left of B, from θ2 = 0
    rejects(position_check(by_hand(theta2), theta2, DECLARED, guess), "over a turn", "C is left of B there",
            hidden=by_hand(theta2))


def test_wrong_positions_are_named():
    theta2 = np.radians(60.0)
    theta4, r4_value, theta5, ram = by_hand(theta2)
    hidden = (theta4, r4_value, theta5, ram)
    check = position_check
    rejects(check(by_hand(theta2, right=False), theta2), "other assembly", hidden=hidden)
    in_degrees = np.degrees([theta4, 0, theta5, 0]) + [0, r4_value, 0, ram]
    rejects(check(in_degrees, theta2), "degrees", hidden=hidden)
    rejects(check((theta4, 1000 * r4_value, theta5, 1000 * ram), theta2), "millimetres", hidden=hidden)
    rejects(check(by_hand(60.0), theta2), "np.radians", hidden=hidden)
    rejects(check((r4_value, theta4, theta5, ram), theta2), "wrong order", hidden=hidden)
    rejects(check((ram, theta5, r4_value, theta4), theta2), "wrong order", hidden=hidden)
    rejects(check((theta4, r4_value, theta5 + 0.1, ram), theta2), "θ5 and x are not", hidden=hidden)
    rejects(check((theta4 + 0.1, r4_value, theta5, ram), theta2), "θ4 and r4 are not", hidden=hidden)
    rejects(check((theta4, r4_value, theta5, -ram), theta2), "x has the wrong sign", hidden=hidden)
    rejects(check((theta4, r4_value, -theta5, ram), theta2), "θ5 has the wrong sign", hidden=hidden)
    rejects(check(np.round(hidden, 3), theta2), "give more digits", hidden=hidden)
    rejects(check(DECLARED.solve({th2: 1.0}, guess=GUESS), theta2), "solved at θ2 = 1.0000 rad",
            hidden=hidden)
    rejects(check(DECLARED.solve({th2: [1.0, 2.0]}, guess=GUESS), theta2), "theta4", hidden=hidden)
    rejects(check({"theta4": theta4}, theta2), "the dict needs the keys theta4, r4, theta5, x")
    rejects(check([theta4, r4_value, float("nan"), ram], theta2), "theta5", "NaN")
    rejects(check([theta4, r4_value, "0.1", ram], theta2), "theta5", "string")
    rejects(check(None, theta2), "theta4")


# ---------------------------------------------------------------- task 3: the ram's rates


def test_ram_rates_by_differences_and_by_the_core_are_accepted():
    theta2, omega2 = np.radians(60.0), 8.0
    accepts(checks.check_ram_motion(ram_by_differences(theta2, omega2), theta2, omega2))
    accepts(checks.check_ram_motion(ram_by_differences(theta2, omega2, 5.0), theta2, omega2, 5.0))
    motion = declared_shaper().solve({th2: theta2}, rates={th2: omega2}, guess=GUESS)
    ram = (motion.velocity["x"], motion.acceleration["x"])
    accepts(checks.check_ram_motion(ram, theta2, omega2))
    accepts(checks.check_ram_motion({"v_x": ram[0], "a_x": ram[1]}, theta2, omega2))
    accepts(checks.check_ram_motion(motion, theta2, omega2))  # the Motion itself
    accepts(checks.check_ram_motion([float(f"{value:.4g}") for value in ram], theta2, omega2))  # 4 figures
    accepts(checks.check_ram_motion(np.array(ram), theta2, omega2))


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
    rejects(check((acceleration, velocity), theta2, omega2), "wrong order", hidden=hidden)
    rejects(check((float(f"{acceleration:.3g}"), float(f"{velocity:.4g}")), theta2, omega2), "wrong order",
            hidden=hidden)
    rejects(check((float(f"{velocity:.3g}"), float(f"{acceleration:.4g}")), theta2, omega2),
            "give more digits", hidden=hidden)
    rejects(check((velocity, -acceleration), theta2, omega2), "velocity is right", "wrong sign",
            hidden=hidden)
    # the task's numbers, to 4 figures, with a_x's sign flipped: its sign is named (no "constant ω2" story)
    flipped = check((float(f"{velocity:.4g}"), float(f"{-acceleration:.4g}")), theta2, omega2)
    rejects(flipped, "acceleration has the wrong sign", hidden=hidden)
    assert "Even at constant" not in flipped.message, flipped
    at_rest = declared_shaper().solve({th2: theta2}, guess=GUESS)
    rejects(check(at_rest, theta2, omega2), "holds no rates", hidden=hidden)
    elsewhere = declared_shaper().solve({th2: 1.0}, rates={th2: omega2}, accelerations={th2: 0.0},
                                        guess=GUESS)
    rejects(check(elsewhere, theta2, omega2), "solved at θ2 = 1.0000 rad", hidden=hidden)
    lever_only = Mechanism([LEVER_LOOP], [th4, r4], [th2], {r2: R2, d: D}).solve({th2: theta2}, {th2: omega2},
                                                                                guess={th4: 1.2, r4: 0.2})
    rejects(check(lever_only, theta2, omega2), "no unknown x", hidden=hidden)
    rejects(check(declared_shaper(), theta2, omega2), "that is your declaration", hidden=hidden)
    rejects(check((velocity, None), theta2, omega2), "a_x", "None")
    rejects(check(("-0.6468", acceleration), theta2, omega2), "v_x", "string")


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
    for cutting in ("left", "Left", "to the left", " LEFT ", "-x", "−x"):
        accepts(checks.check_ram_stroke(((stroke, sweep_ratio(R2, D, 720)), cutting)))
    accepts(checks.check_ram_stroke(([stroke, sweep_ratio(R2, D, 100_000)], "left")))
    rounded = np.array([float(f"{stroke:.3g}"), float(f"{sweep_ratio(R2, D, 720):.3g}")])  # 3 figures
    accepts(checks.check_ram_stroke((rounded, "left")))


def cutting_by_hand():
    """The way C moves on the slow stroke: the crank's long arc between the stops found on a fine grid (where
    θ4 is largest and smallest), C by hand at its middle and a little after it."""
    theta2 = np.linspace(0, 2 * np.pi, 200_000, endpoint=False)
    theta4 = by_hand(theta2)[0]
    low, high = theta2[np.argmin(theta4)], theta2[np.argmax(theta4)]
    arc = (high - low) % (2 * np.pi)  # counter-clockwise from the stop at θ4's smallest to its largest
    start, slow = (low, arc) if arc > np.pi else (high, 2 * np.pi - arc)
    middle = start + slow / 2
    return "left" if by_hand(middle + 1e-4)[3] < by_hand(middle)[3] else "right"


def test_the_cutting_stroke_moves_the_ram_left():
    assert cutting_by_hand() == "left"  # the hand route says so; the check must agree
    stroke, ratio = 2 * L4 * R2 / D, sweep_ratio(R2, D, 100_000)
    accepts(checks.check_ram_stroke(((stroke, ratio), cutting_by_hand())))
    for cutting in ("right", "+x", "Right"):
        rejects(checks.check_ram_stroke(((stroke, ratio), cutting)), "cutting is not", "slow stroke")
    for cutting, words in ((None, ("cutting is still None",)), (-1, ("a string", "got -1")),
                           ("up", ("a string", "'up'")), (True, ("a string",))):
        rejects(checks.check_ram_stroke(((stroke, ratio), cutting)), *words)


def test_wrong_strokes_and_ratios_are_named():
    stroke, ratio = np.ptp(by_hand(np.linspace(0, 2 * np.pi, 200_001))[3]), sweep_ratio(R2, D, 200_000)
    hidden = (stroke, ratio)

    def check(numbers, cutting="left"):
        return checks.check_ram_stroke((numbers, cutting))

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
    rejects(check((ratio, stroke)), "wrong order", hidden=hidden)
    rejects(check((float(f"{ratio:.3g}"), float(f"{stroke:.3g}"))), "wrong order", hidden=hidden)
    assert float(f"{stroke:.2g}") == 0.24  # the stroke is 0.24 m exactly: 2 figures are all of it
    rejects(check((stroke, float(f"{ratio:.2g}"))), "give more digits", hidden=hidden)
    rejects(check((stroke, float("nan"))), "NaN", hidden=hidden)
    rejects(check((stroke, "1.71")), "string", hidden=hidden)
    rejects(check(None), "None", hidden=hidden)
    rejects(checks.check_ram_stroke((stroke, ratio)), "((stroke, time_ratio), stops, cutting)", hidden=hidden)
    sweep = declared_shaper().solve({th2: np.radians(np.arange(0, 360, 5.0))}, guess=GUESS)
    rejects(checks.check_ram_stroke(sweep), "not the Motion", hidden=hidden)
    rejects(check(sweep), "not the Motion", hidden=hidden)


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
            (checks.check_ram_stroke((answer, "left")), (2 * L4 * R2 / D, sweep_ratio(R2, D, 100_000))),
            (position_check(answer, theta2), by_hand(theta2)),
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


# ---------------------------------------------------------------- answers as students type them


def typed_answers():
    """(label, check, answer, ✔?, words): each checker of the set and lesson 12's Try it, given the right
    answer rounded as the task states, in mm or degrees, swapped, with one sign flipped, as a Motion, and NaN,
    None or text; the references from the routes above."""
    theta2, omega2 = np.radians(60.0), 8.0
    q = np.array(by_hand(theta2))
    v, a = ram_by_differences(theta2, omega2)
    stroke, ratio = 2 * L4 * R2 / D, sweep_ratio(R2, D, 200_000)
    lesson = sweep_ratio(0.05, 0.08, 400_000)
    motion = DECLARED.solve({th2: theta2}, rates={th2: omega2}, accelerations={th2: 0.0}, guess=GUESS)
    sweep = DECLARED.solve({th2: np.radians(np.arange(0.0, 360.0, 10.0))}, guess=GUESS)
    deg = {s: s * sp.pi / 180 for s in (th2, th4, th5)}

    def position(answer):
        return position_check(answer, theta2)

    def ram(answer):
        return checks.check_ram_motion(answer, theta2, omega2)

    def stroke_check(numbers, cutting="left"):
        return checks.check_ram_stroke((numbers, cutting))

    def try_it(answer):
        return checks.check_quick_return_time_ratio(answer, 0.05, 0.08)

    def figures(values, digits):
        return [float(f"{value:.{digits}g}") for value in np.atleast_1d(values)]

    loops = checks.check_shaper_loops
    return [
        ("loops: a sign flipped", loops, [LEVER_LOOP, RAM_LOOP.subs(l4, -l4)], False, ("sign slip", "lever")),
        ("loops: in degrees", loops, [LEVER_LOOP.xreplace(deg), RAM_LOOP.xreplace(deg)], False, ("degrees",)),
        ("loops: swapped", loops, [RAM_LOOP, LEVER_LOOP], True, ()),
        ("loops: a Motion", loops, motion, False, ("Motion",)),
        ("loops: NaN", loops, float("nan"), False, ("is a number",)),
        ("loops: text", loops, "r2*cos(theta2) - r4*cos(theta4)", False, ("not as text",)),
        ("position: 4 decimals", position, np.round(q, 4), True, ()),
        ("position: 3 decimals", position, np.round(q, 3), False, ("give more digits",)),
        ("position: mm", position, q * [1, 1000, 1, 1000], False, ("millimetres",)),
        ("position: degrees", position, np.round(q * [180 / np.pi, 1, 180 / np.pi, 1], 2), False,
         ("degrees",)),
        ("position: swapped", position, q[[1, 0, 2, 3]], False, ("wrong order",)),
        ("position: r4 sign", position, q * [1, -1, 1, 1], False, ("r4 has the wrong sign",)),
        ("position: the Motion", position, motion, True, ()),
        ("position: a sweep", position, sweep, False, ("theta4",)),
        ("position: NaN", position, [q[0], q[1], np.nan, q[3]], False, ("NaN",)),
        ("position: None", position, None, False, ("None",)),
        ("position: text", position, [str(value) for value in q], False, ("string",)),
        ("ram: 4 figures", ram, figures((v, a), 4), True, ()),
        ("ram: 3 figures", ram, figures((v, a), 3), False, ("give more digits",)),
        ("ram: mm/s", ram, (1000 * v, 1000 * a), False, ("mm/s",)),
        ("ram: θ2 in degrees", ram, ram_by_differences(60.0, omega2), False, ("np.radians",)),
        ("ram: swapped", ram, figures((a, v), 4), False, ("wrong order",)),
        ("ram: v sign", ram, (-v, a), False, ("counter-clockwise",)),
        ("ram: a sign", ram, (v, -a), False, ("velocity is right",)),
        ("ram: the Motion", ram, motion, True, ()),
        ("ram: NaN", ram, (v, np.nan), False, ("NaN",)),
        ("ram: None", ram, (v, None), False, ("None",)),
        ("ram: text", ram, ("-0.6468", "-1.230"), False, ("string",)),
        ("stroke: 3 figures", stroke_check, figures((stroke, ratio), 3), True, ()),
        ("stroke: 2 figures", stroke_check, figures((stroke, ratio), 2), False, ("give more digits",)),
        ("stroke: mm", stroke_check, (1000 * stroke, ratio), False, ("millimetres",)),
        ("stroke: ratio in degrees", stroke_check, (stroke, 360 * ratio / (1 + ratio)), False,
         ("crank angle",)),
        ("stroke: swapped", stroke_check, figures((ratio, stroke), 3), False, ("wrong order",)),
        ("stroke: stroke sign", stroke_check, (-stroke, ratio), False, ("positive",)),
        ("stroke: ratio sign", stroke_check, (stroke, -ratio), False, ("positive",)),
        ("stroke: the other way", stroke_check, (stroke, 1 / ratio), False, ("slow over fast",)),
        ("stroke: a Motion", stroke_check, sweep, False, ("not the Motion",)),
        ("stroke: NaN", stroke_check, (stroke, np.nan), False, ("NaN",)),
        ("stroke: None", stroke_check, (None, ratio), False, ("None",)),
        ("stroke: text", stroke_check, ("0.24", "1.71"), False, ("string",)),
        ("stroke: cutting wrong", lambda answer: stroke_check(answer, "right"), (stroke, ratio), False,
         ("cutting is not",)),
        ("Try it: 3 figures", try_it, figures(lesson, 3)[0], True, ()),
        ("Try it: 2 figures", try_it, figures(lesson, 2)[0], False, ("give more digits",)),
        ("Try it: in degrees", try_it, 360 * lesson / (1 + lesson), False, ("crank angle",)),
        ("Try it: sign", try_it, -lesson, False, ("positive",)),
        ("Try it: fast over slow", try_it, 1 / lesson, False, ("slow over fast",)),
        ("Try it: a Motion", try_it, sweep, False, ("Motion",)),
        ("Try it: NaN", try_it, np.nan, False, ("NaN",)),
        ("Try it: text", try_it, "2.51", False, ("string",)),
    ]


TYPED = typed_answers()


@pytest.mark.parametrize("case", TYPED, ids=[case[0] for case in TYPED])
def test_answers_as_students_type_them(case):
    """No false ✔, a named cause, never a traceback."""
    _, check, answer, ok, words = case
    feedback = check(answer)
    if ok:
        accepts(feedback)
    else:
        rejects(feedback, *words)
        assert "could not be checked" not in feedback.message, feedback
