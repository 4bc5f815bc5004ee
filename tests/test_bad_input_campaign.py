"""The bad-input campaign of the surfaces the core, the drawings, the explorers and the checkers share: one
row per case, each a call and what it must give — a named course_lib error (its class, and the argument's
name in the message), a result verified by an independent route, or, for a checker, a ``Feedback`` with
✔ or ✘ — and every call returns or raises within seconds (a time bound per row: a hang fails its row).

Rows already held by the other tables are not repeated here: tests/test_bad_input.py (lengths, angles,
choices, Newton's settings over the machines), tests/test_bad_input_core.py (a parameter twice, a masked
input, tol and max_iter, the core's own names, motion_of, look-ups by name), tests/test_checks_bad_input.py
and tests/test_checks_task_arguments.py (silly answers, bad task arguments, the shaper's false passes),
tests/test_precision_arguments.py (Precision), tests/test_no_hang.py (huge answers, huge animations, Newton
following 1/x), tests/test_release_safety.py (the release's version, --ref, --output, archive entries, the
repository and hub addresses) and tests/test_worked_box.py (worked answers run in a box).

``python tests/test_bad_input_campaign.py`` prints the tally: named-or-correct, silent wrong, hangs, raw
tracebacks.
"""

from __future__ import annotations

import math
import signal
import sys
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import matplotlib

matplotlib.use("Agg")

import numpy as np  # noqa: E402
import pytest  # noqa: E402
import sympy as sp  # noqa: E402
from test_mechanism import LOOP, WIPER_POINTS, l1, l2, l3, l4, th2, th3, th4  # noqa: E402
from test_mechanism import WIPER_LENGTHS as NUMBERS  # noqa: E402

from course_lib import checks  # noqa: E402
from course_lib.checks import Precision  # noqa: E402
from course_lib.errors import CourseLibError, InvalidArgumentError, InvalidGeometryError  # noqa: E402
from course_lib.fivebar import FiveBar  # noqa: E402
from course_lib.fourbar import FourBar  # noqa: E402
from course_lib.mechanism import Mechanism  # noqa: E402
from course_lib.newton import newton, newton_batch  # noqa: E402
from course_lib.plotting import animate, draw  # noqa: E402
from course_lib.saw import Saw  # noqa: E402
from course_lib.slider_crank import OffsetSliderCrank  # noqa: E402
from course_lib.widgets import ExplorerSpec, _grid, _slider, build_explorer, explore  # noqa: E402

TIME_BOUND = 20  # seconds: a row still running then is a hang

# ---------------------------------------------------------------- the machines and declarations used
FB = FourBar(0.06, 0.18, 0.12, 0.20)
OTHER = FourBar(0.1, 0.3, 0.2, 0.35)
SCALED = FourBar(0.12, 0.36, 0.24, 0.40)  # FB twice as large: the same angles, other lengths
ROBOT = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
SAW = Saw(r1y=0.045, r2=0.075, r3=0.17)
SLIDER = OffsetSliderCrank(0.075, 0.170, 0.045)

# the wiper declared on the core, as tests/test_mechanism.py declares it, with its ground named
WIPER = Mechanism([LOOP], [th3, th4], [th2], NUMBERS, points=WIPER_POINTS, links=[("O2", "A"), ("A", "B"),
                                                                                   ("B", "O4")],
                  ground=["O2", "O4"])
WIDE = WIPER.with_parameters({l1: 0.35, l2: 0.1, l3: 0.3, l4: 0.2})  # the same loops, other numbers
SWEEP = np.linspace(0.0, 2 * np.pi, 13)
SW = WIPER.solve({th2: 0.7}, rates={th2: 2.0}, accelerations={th2: 1.0}, assembly={"theta4": 1})


def by_circles(crank, coupler, rocker, ground, theta2, sign=+1):
    """θ3, θ4 of a four-bar from B on two circles (about A, radius coupler; about O4, radius rocker)."""
    A = crank * np.array([np.cos(theta2), np.sin(theta2)])
    O4 = np.array([ground, 0.0])
    d = np.linalg.norm(O4 - A)
    along = (d * d + rocker * rocker - coupler * coupler) / (2 * d)
    across = math.sqrt(rocker * rocker - along * along)
    unit = (A - O4) / d
    B = O4 + along * unit + sign * across * np.array([-unit[1], unit[0]])
    return math.atan2(*(B - A)[::-1]), math.atan2(*(B - O4)[::-1])


THETA4 = {sign: by_circles(0.06, 0.18, 0.12, 0.20, 1.0, sign)[1] for sign in (+1, -1)}
OMEGA4 = FB.solve(1.0, 2.0).omega4  # at 1 m: the rates of a linkage scaled as a whole are the same


# ---------------------------------------------------------------- what a row expects
@dataclass
class Named:
    """A course_lib error of class ``kind`` whose message holds every one of ``says``."""
    kind: type | tuple
    says: tuple[str, ...]


@dataclass
class Correct:
    """A result that ``holds`` (an independent check of the value)."""
    holds: Callable[[Any], bool]


@dataclass
class Verdict:
    """A checker's ``Feedback`` with this ``ok``."""
    ok: bool


def named(kind, *says):
    return Named(kind, says)


ARG = InvalidArgumentError
GEO = InvalidGeometryError
ANY = CourseLibError
ROWS: dict[str, tuple[Callable[[], Any], Any]] = {}


def row(label: str, call: Callable[[], Any], expect) -> None:
    assert label not in ROWS, label
    ROWS[label] = (call, expect)


# ---------------------------------------------------------------- a Motion of another machine
def _drawn_coupler(ax):
    line = next(line for line in ax.lines if line.get_gid() == "coupler")
    (xa, ya), (xb, yb) = line.get_xydata()[:2]
    return math.hypot(xb - xa, yb - ya)


OTHERS = {
    "FourBar(0.1, 0.3, 0.2, 0.35)": lambda: OTHER.solve(0.5),
    "a sweep of another": lambda: OTHER.solve(SWEEP),
    "another's, with rates": lambda: OTHER.solve(0.5, 2.0, 1.0),
}
for label, motion in OTHERS.items():
    row(f"draw(FB, {label})", lambda motion=motion: draw(FB, motion()), named(ARG, "motion", "close"))
    row(f"animate(FB, {label})", lambda motion=motion: animate(FB, motion(), max_frames=4),
        named(ARG, "motion", "close"))
    row(f"joints of FB from {label}", lambda motion=motion: FB.mechanism.joints(motion()),
        named(ARG, "motion", "close"))
row("explore(FB, a sweep of another)", lambda: explore(FB, OTHER.solve(SWEEP)), named(ARG, "motion", "close"))


def _is_fb_pose(joints):
    """FB's own pose at θ2 = 0.5 from its lengths alone: A on the crank circle, |AB| = l3, |O4B| = l4."""
    A, B, O4 = (np.asarray(joints[name]) for name in ("A", "B", "O4"))
    return (np.allclose(A, 0.06 * np.array([np.cos(0.5), np.sin(0.5)]), atol=1e-15)
            and abs(np.linalg.norm(B - A) - 0.18) < 1e-12 and abs(np.linalg.norm(B - O4) - 0.12) < 1e-12)


# a similar linkage's motion has FB's own angles (positions scale with the lengths, angles do not): it is
# FB's motion too, and is drawn at FB's lengths
row("joints of FB from a twice as large FB's motion: FB's pose",
    lambda: FB.mechanism.joints(SCALED.solve(0.5)),
    Correct(_is_fb_pose))
row("draw(FB, a twice as large FB's motion) draws a 0.18 m coupler",
    lambda: _drawn_coupler(draw(FB, SCALED.solve(0.5))), Correct(lambda length: abs(length - 0.18) < 1e-12))
row("explore(FB, a sweep twice as large): FB's own", lambda: explore(FB, SCALED.solve(SWEEP)).update(
    theta2_deg=30.0).status, Correct(lambda status: status == "ok"))
row("point_motion of FB from another's, with rates",
    lambda: FB.mechanism.point_motion(OTHER.solve(0.5, 2.0, 1.0)), named(ARG, "motion", "close"))
row("point_motion of the wiper from a wider wiper's",
    lambda: WIPER.point_motion(WIDE.solve({th2: 0.7}, rates={th2: 2.0}, assembly={"theta4": 1})),
    named(ARG, "motion", "close"))
row("joints of the wiper from a wider wiper's", lambda: WIPER.joints(WIDE.solve({th2: SWEEP})),
    named(ARG, "motion", "close"))
row("draw(wiper, a wider wiper's)", lambda: draw(WIPER, WIDE.solve({th2: 0.5})),
    named(ARG, "motion", "close"))
row("explore(wiper, a wider wiper's)", lambda: explore(WIPER, WIDE.solve({th2: SWEEP})),
    named(ARG, "motion", "close"))
row("draw(FB, the saw's motion)", lambda: draw(FB, SAW.motion(0.5)), named((ARG, GEO), "motion"))
row("draw(FB, the robot's motion)", lambda: draw(FB, ROBOT.forward(1.2, 1.9)), named((ARG, GEO), "motion"))
row("joints of the saw from FB's", lambda: SAW.mechanism.joints(FB.solve(0.5)), named((ARG, GEO), "motion"))
row("explore(the robot, FB's sweep)", lambda: explore(ROBOT, FB.solve(SWEEP)), named((ARG, GEO), "motion"))
row("draw(FB, not a motion: a dict of angles)", lambda: draw(FB, {"theta3": 0.1}), named(ANY, "points"))
row("explore(FB, None)", lambda: explore(FB, None), named((ARG, GEO), "motion", "None"))
row("explore(FB, one instant)", lambda: explore(FB, FB.solve(0.5)), named((ARG, GEO), "motion"))
# the machine's own motion is drawn at its own lengths (the coupler as long as declared)
row("draw(FB, FB's own) draws a 0.18 m coupler", lambda: _drawn_coupler(draw(FB, FB.solve(0.5))),
    Correct(lambda length: abs(length - 0.18) < 1e-12))
row("draw(FB, FB's crossed assembly) is its own",
    lambda: _drawn_coupler(draw(FB, FB.solve(0.5, assembly="crossed"))),
    Correct(lambda length: abs(length - 0.18) < 1e-12))

# ---------------------------------------------------------------- point_motion uses the motion's own rates
A_SPEED = 2.0 * 0.06  # |V_A| = ω2 l2 at the crank pin, from the crank alone


def _velocity_of(name, **options):
    return WIPER.point_motion(SW, **options)[name][1]


def _crank_pin(theta2, omega2, alpha2):
    """A's velocity and acceleration from ω k̂ × r and α k̂ × r − ω² r, r = l2 (cos θ2, sin θ2)."""
    r = 0.06 * np.array([np.cos(theta2), np.sin(theta2)])
    across = np.array([-r[1], r[0]])
    return omega2 * across, alpha2 * across - omega2 ** 2 * r


row("point_motion(SW): V_A from the motion's own ω2", lambda: _velocity_of("A"),
    Correct(lambda v: np.allclose(v, _crank_pin(0.7, 2.0, 1.0)[0], rtol=1e-12, atol=1e-15)))
row("point_motion(SW): A_A from the motion's own α2", lambda: WIPER.point_motion(SW)["A"][2],
    Correct(lambda a: np.allclose(a, _crank_pin(0.7, 2.0, 1.0)[1], rtol=1e-12, atol=1e-15)))
row("point_motion(SW): |V_B| = ω4 l4", lambda: np.linalg.norm(_velocity_of("B")),
    Correct(lambda speed: abs(speed - abs(SW.velocity["theta4"]) * 0.12) < 1e-12))
row("point_motion(SW, rates={th2: 2.0}): the same rates pass",
    lambda: _velocity_of("A", rates={th2: 2.0}), Correct(lambda v: np.isclose(np.linalg.norm(v), A_SPEED)))
row("point_motion(SW, rates={'theta2': 2.0}): by name", lambda: _velocity_of("A", rates={"theta2": 2.0}),
    Correct(lambda v: np.isclose(np.linalg.norm(v), A_SPEED)))
for rate in (3.0, 0.0, -2.0, 2.0001):
    row(f"point_motion(SW, rates={{th2: {rate}}})",
        lambda rate=rate: WIPER.point_motion(SW, rates={th2: rate}),
        named(ARG, "rates", "theta2"))
for rate in (math.nan, math.inf, "2.0", None, 1j):
    row(f"point_motion(SW, rates={{th2: {rate!r}}})",
        lambda rate=rate: WIPER.point_motion(SW, rates={th2: rate}), named(ANY, "rates"))
row("point_motion(SW, rates={'theta9': 2.0})", lambda: WIPER.point_motion(SW, rates={"theta9": 2.0}),
    named(ANY, "rates", "theta9"))
row("point_motion(SW, rates=[2.0])", lambda: WIPER.point_motion(SW, rates=[2.0]), named(ANY, "rates"))
row("point_motion(SW, accelerations={th2: 5.0})", lambda: WIPER.point_motion(SW, accelerations={th2: 5.0}),
    named(ARG, "accelerations"))
row("point_motion(SW, accelerations={th2: 1.0}) passes",
    lambda: WIPER.point_motion(SW, accelerations={th2: 1.0})["A"][2],
    Correct(lambda a: np.allclose(a, _crank_pin(0.7, 2.0, 1.0)[1], rtol=1e-12, atol=1e-15)))
row("point_motion(None)", lambda: WIPER.point_motion(None), named(ANY, "motion"))
row("point_motion of a positions-only solve", lambda: WIPER.point_motion(WIPER.solve({th2: 0.7})),
    named(ANY, "rates"))

# ---------------------------------------------------------------- check_shaper_loops: every row checked
from test_checks_ex06 import LEVER_LOOP, RAM_LOOP  # noqa: E402

LEVER, RAM = list(LEVER_LOOP), list(RAM_LOOP)
th2s = sp.Symbol("theta2", real=True)
SHAPER_ROWS = {
    "the loops themselves": ([*LEVER, *RAM], True),
    "a row negated": ([-LEVER[0], LEVER[1], *RAM], True),
    "a constant added to the lever's x": ([LEVER[0] + sp.Rational(1, 100), LEVER[1], *RAM], False),
    "sin for cos in the lever's x": ([LEVER[0].subs(sp.cos(th2s), sp.sin(th2s)), LEVER[1], *RAM], False),
    "a row repeated for another": ([LEVER[0], LEVER[0], *RAM], False),
    "three rows": ([*LEVER, RAM[0]], False),
    "five rows": ([*LEVER, *RAM, LEVER[0] + RAM[0]], False),
    "the ram's rows only": ([*RAM], False),
    "every row squared": ([row_ ** 2 for row_ in (*LEVER, *RAM)], False),
    "the lever times sin θ2": ([LEVER[0] * sp.sin(th2s), LEVER[1], *RAM], False),
    "zero rows": ([], False),
    "numbers": ([1.0, 2.0, 3.0, 4.0], False),
}
for label, (rows, ok) in SHAPER_ROWS.items():
    row(f"check_shaper_loops: {label}", lambda rows=rows: checks.check_shaper_loops(rows), Verdict(ok))

# ---------------------------------------------------------------- checkers: a bad task is the instructor's
TASKS = {
    "check_fourbar_theta4 linkage=FourBar class": (
        lambda: checks.check_fourbar_theta4(1.0, FourBar, 1.0, "open"), "linkage"),
    "check_fourbar_theta4 theta2=[1.0, 2.0]": (
        lambda: checks.check_fourbar_theta4(1.0, FB, [1.0, 2.0], "open"), "theta2"),
    "check_fourbar_theta4 theta2=1j": (lambda: checks.check_fourbar_theta4(1.0, FB, 1j, "open"), "theta2"),
    "check_fourbar_theta4 branch=None": (lambda: checks.check_fourbar_theta4(1.0, FB, 1.0, None), "branch"),
    "check_fourbar_theta4 branch=1": (lambda: checks.check_fourbar_theta4(1.0, FB, 1.0, 1), "branch"),
    "check_fourbar_theta4 branch='Up'": (lambda: checks.check_fourbar_theta4(1.0, FB, 1.0, "Up"), "branch"),
    "check_fivebar_forward robot=None": (
        lambda: checks.check_fivebar_forward((0.0, 0.2), None, 1.2, 1.9, 1), "robot"),
    "check_fivebar_forward mode=0": (lambda: checks.check_fivebar_forward((0.0, 0.2), ROBOT, 1.2, 1.9, 0),
                                     "mode"),
    "check_fivebar_forward mode='up'": (
        lambda: checks.check_fivebar_forward((0.0, 0.2), ROBOT, 1.2, 1.9, "up"), "mode"),
    "check_fivebar_forward theta1=-inf": (
        lambda: checks.check_fivebar_forward((0.0, 0.2), ROBOT, -math.inf, 1.9, 1), "theta1"),
    "check_saw_position saw=None": (lambda: checks.check_saw_position((0.1, 0.0, 0.0), None, 0.5), "saw"),
    "check_saw_position theta2='0.5'": (lambda: checks.check_saw_position((0.1, 0.0, 0.0), SAW, "0.5"),
                                        "theta2"),
    "check_saw_position a saw that cannot close": (
        lambda: checks.check_saw_position((0.1, 0.0, 0.0), Saw(r1y=0.03, r2=0.06, r3=0.08), -math.pi / 2),
        "theta2"),
    "check_seed_branch seed='(1, 2)'": (lambda: checks.check_seed_branch("open", FB, 1.0, "(1, 2)"), "seed"),
    "check_seed_branch seed=(nan, 1)": (lambda: checks.check_seed_branch("open", FB, 1.0, (math.nan, 1.0)),
                                        "seed"),
    "check_toggle_angle linkage=None": (lambda: checks.check_toggle_angle(1.0, None), "linkage"),
    "check_rocker_pin_speed omega2='10'": (lambda: checks.check_rocker_pin_speed(1.0, FB, 1.0, "10"),
                                           "omega2"),
}
for label, (call, name) in TASKS.items():
    row(label, call, named(ARG, name))

# ---------------------------------------------------------------- Precision
NAN_PRECISION = [
    ("Precision(math.nan)", lambda: Precision(math.nan), named(ARG, "digits", "nan")),
    ("Precision(1e300)", lambda: Precision(1e300), named(ARG, "digits")),
    ("Precision(2**64)", lambda: Precision(2 ** 64), named(ARG, "digits")),
    ("Precision(4j)", lambda: Precision(4j), named(ARG, "digits")),
    ("Precision(np.int8(4)) is 4 digits", lambda: Precision(np.int8(4)).digits, Correct(lambda d: d == 4)),
    ("Precision(4).agrees(nan, nan) is False", lambda: Precision(4).agrees(math.nan, math.nan),
     Correct(lambda x: x is False)),
    ("Precision(4).agrees(inf, 1.0) is False", lambda: Precision(4).agrees(math.inf, 1.0),
     Correct(lambda x: x is False)),
    ("Precision(4).agrees(1.0, nan) is False: nothing agrees with NaN",
     lambda: Precision(4).agrees(1.0, math.nan), Correct(lambda x: x is False)),
    ("Precision(4).agrees([1, 2], [1, 2, 3]) is False", lambda: Precision(4).agrees([1, 2], [1, 2, 3]),
     Correct(lambda x: x is False)),
    ("Precision(4).agrees(0.12344, 0.1234) is True", lambda: Precision(4).agrees(0.12344, 0.1234),
     Correct(lambda x: x is True)),
    ("Precision(4).agrees(0.1236, 0.1234) is False", lambda: Precision(4).agrees(0.1236, 0.1234),
     Correct(lambda x: x is False)),
    ("Precision(4).typed(nan)", lambda: Precision(4).typed(math.nan), named(ARG, "value")),
    ("Precision(4).typed({1.0})", lambda: Precision(4).typed({1.0}), named(ARG, "value")),
    ("Precision(4).typed(0.5) is 1", lambda: Precision(4).typed(0.5), Correct(lambda n: n == 1)),
    ("Precision(4).of_size(nan)", lambda: Precision(4).of_size(math.nan), named(ARG, "vector")),
    ("Precision(4).of_size([[1.0], [2.0, 3.0]])", lambda: Precision(4).of_size([[1.0], [2.0, 3.0]]),
     named(ARG, "vector")),
    ("Precision(4).unit(None)", lambda: Precision(4).unit(None), named(ARG, "reference")),
    ("Precision(4).more_digits(None, 0.5)", lambda: Precision(4).more_digits(None, 0.5), named(ARG, "value")),
    ("Precision(4).fewer('0.5', 0.5) is 0: text never agrees", lambda: Precision(4).fewer("0.5", 0.5),
     Correct(lambda n: n == 0)),
    ("Precision(4).typed(5.0) is 1", lambda: Precision(4).typed(5.0), Correct(lambda n: n == 1)),
    ("Precision(4).typed([0.5, 0.25]) is 2", lambda: Precision(4).typed([0.5, 0.25]),
     Correct(lambda n: n == 2)),
    ("Precision(2, decimals=True).typed(3.0) is 0", lambda: Precision(2, decimals=True).typed(3.0),
     Correct(lambda n: n == 0)),
]
for label, call, expect in NAN_PRECISION:
    row(label, call, expect)

# ---------------------------------------------------------------- the core over 1e-90 … 1e90
for scale in (1e-90, 1e-78, 1e-40, 1e-12, 1e12, 1e40, 1e78, 1e85, 1e90):
    row(f"FourBar scaled by {scale:g}: θ4 as at 1",
        lambda scale=scale: FourBar(0.06 * scale, 0.18 * scale, 0.12 * scale, 0.20 * scale).solve(1.0).theta4,
        Correct(lambda theta4: abs(theta4 - THETA4[+1]) < 1e-9 or abs(theta4 - THETA4[-1]) < 1e-9))
    row(f"the wiper declared at {scale:g}: θ4 as at 1",
        lambda scale=scale: WIPER.with_parameters({k: v * scale for k, v in NUMBERS.items()}).solve(
            {th2: 1.0}, assembly={"theta4": 1}).position["theta4"],
        Correct(lambda theta4: min(abs(theta4 - THETA4[+1]), abs(theta4 - THETA4[-1])) < 1e-9))
for scale in (1e-90, 1e90):
    row(f"FourBar scaled by {scale:g}: ω4 scales not", lambda scale=scale: FourBar(
        0.06 * scale, 0.18 * scale, 0.12 * scale, 0.20 * scale).solve(1.0, 2.0).omega4,
        Correct(lambda omega4: abs(omega4 - OMEGA4) < 1e-9 * abs(OMEGA4)))
for scale in (1e-300, 1e300):
    row(f"FourBar scaled by {scale:g}: θ4 as at 1", lambda scale=scale: FourBar(
        0.06 * scale, 0.18 * scale, 0.12 * scale, 0.20 * scale).solve(1.0).theta4,
        Correct(lambda theta4: min(abs(theta4 - THETA4[+1]), abs(theta4 - THETA4[-1])) < 1e-9))

# ---------------------------------------------------------------- a parameter twice, masked arrays, settings
L1_AGAIN = sp.Symbol("l1")  # the same name, another Symbol (no assumption)
row("a parameter as two Symbols of one name", lambda: Mechanism([LOOP], [th3, th4], [th2],
                                                                 {**NUMBERS, L1_AGAIN: 0.3}),
    named(ANY, "l1"))
row("with_parameters gives l1 twice", lambda: WIPER.with_parameters({l1: 0.2, "l1": 0.3}), named(ANY, "l1"))
row("with_parameters of an unknown parameter", lambda: WIPER.with_parameters({"l9": 0.2}), named(ANY, "l9"))
row("a parameter for an unknown", lambda: Mechanism([LOOP], [th3, th4], [th2], {**NUMBERS, th3: 0.1}),
    named(ANY, "theta3"))
row("a parameter left out", lambda: Mechanism([LOOP], [th3, th4], [th2], {l1: 0.2, l2: 0.06, l3: 0.18}),
    named(ANY, "l4"))
row("a parameter given as text", lambda: Mechanism([LOOP], [th3, th4], [th2], {**NUMBERS, l1: "0.2"}),
    named(ANY, "l1"))
row("a parameter given as NaN", lambda: Mechanism([LOOP], [th3, th4], [th2], {**NUMBERS, l1: math.nan}),
    named(ANY, "l1"))
MASKED = np.ma.masked_array([0.1, 0.2], mask=[False, True])
row("a masked rate", lambda: WIPER.solve({th2: [0.1, 0.2]}, rates={th2: MASKED}), named(ANY, "rates", "mask"))
row("a masked guess", lambda: WIPER.solve({th2: 1.0}, guess={th3: np.ma.masked_array(0.4, mask=True),
                                                            th4: 1.6}), named(ANY, "guess"))
row("FourBar.solve of a masked θ2", lambda: FB.solve(MASKED), named(ANY, "theta2", "mask"))
row("FiveBar.forward of a masked θ1", lambda: ROBOT.forward(MASKED, 1.9), named(ANY, "theta1", "mask"))
row("a masked array with nothing masked is refused too", lambda: WIPER.solve(
    {th2: np.ma.masked_array([1.0], mask=[False])}), named(GEO, "theta2", "masked"))
for value in (0, 0.0, math.inf, None, 1j, [1e-9]):
    row(f"solve tol={value!r}", lambda value=value: WIPER.solve({th2: 1.0}, tol=value), named(ARG, "tol"))
for value in (0, math.nan, None, True, 1e10):
    row(f"solve max_iter={value!r}", lambda value=value: WIPER.solve({th2: 1.0}, max_iter=value),
        named(ARG, "max_iter"))
row("solve max_iter=1e3, a whole number, is taken", lambda: WIPER.solve(
    {th2: 1.0}, max_iter=1e3, assembly={"theta4": 1}).position["theta4"],
    Correct(lambda theta4: min(abs(theta4 - THETA4[+1]), abs(theta4 - THETA4[-1])) < 1e-12))
row("motion_of an unknown named 'theta9'", lambda: WIPER.motion_of({"theta3": 0.1, "theta9": 0.2},
                                                                   {"theta2": 1.0}), named(ANY, "theta9"))
row("motion_of without theta4", lambda: WIPER.motion_of({"theta3": 0.1}, {"theta2": 1.0}),
    named(ANY, "theta4"))
row("motion_of text", lambda: WIPER.motion_of({"theta3": "0.1", "theta4": 0.2}, {"theta2": 1.0}),
    named(ANY, "theta3"))
row("motion_of values that close the loops converge", lambda: WIPER.motion_of(
    {"theta3": by_circles(0.06, 0.18, 0.12, 0.20, 1.0)[0], "theta4": THETA4[+1]}, {"theta2": 1.0}).converged,
    Correct(lambda converged: bool(converged) is True))


# ---------------------------------------------------------------- an explorer's readout
def _readout_of(readout):
    turn = WIPER.solve({th2: SWEEP}, assembly={"theta4": 1})
    return explore(WIPER, turn, readout=readout).update(theta2_deg=30.0)


row("explore readout returning a string: one line, not one character per line",
    lambda: _readout_of(lambda now: "theta4 shown").lines, Correct(lambda lines: lines == ("theta4 shown",)))
row("explore readout returning None", lambda: _readout_of(lambda now: None),
    Correct(lambda readout: readout.status == "error" and "readout" in readout.text))
row("explore readout returning a number", lambda: _readout_of(lambda now: 3.0),
    Correct(lambda readout: readout.status == "error" and "readout" in readout.text))
row("explore readout raising", lambda: _readout_of(lambda now: 1 / 0),
    Correct(lambda readout: readout.status == "error"))
row("explore readout='lines'", lambda: _readout_of("lines"), named(ARG, "readout"))
row("explore rates='fast'", lambda: explore(WIPER, WIPER.solve({th2: SWEEP}), rates="fast"),
    named(ANY, "rates"))
row("explore size=(0, 3)", lambda: explore(WIPER, WIPER.solve({th2: SWEEP}), size=(0, 3)), named(ARG, "size"))
row("explore title=None", lambda: explore(WIPER, WIPER.solve({th2: SWEEP}), title=None), named(ARG, "title"))
row("explore an unsolved sweep", lambda: explore(FB, FourBar(0.02, 0.02, 0.02, 0.5).solve(SWEEP,
                                                                                            on_failure="nan")),
    named(ANY, "motion"))

# ---------------------------------------------------------------- raw tracebacks, each now a named error
EMPTY = Correct(lambda motion: all(np.shape(motion.position[name]) == np.shape(motion.inputs["theta2"])
                                    and np.size(motion.position[name]) == 0 for name in ("theta3", "theta4")))
row("solve on an empty sweep: an empty motion", lambda: WIPER.solve({th2: []}), EMPTY)
row("solve on an empty array: an empty motion", lambda: WIPER.solve({th2: np.array([])}), EMPTY)
row("FourBar.solve([]): an empty motion", lambda: FB.solve([]), EMPTY)
row("FourBar.solve(np.empty((0, 3))): an empty motion", lambda: FB.solve(np.empty((0, 3))), EMPTY)
row("solve with no inputs", lambda: WIPER.solve({}), named(ANY, "theta2"))
row("solve with inputs=None", lambda: WIPER.solve(None), named(ANY, "inputs"))
row("solve with an unknown input", lambda: WIPER.solve({"theta9": 1.0}), named(ANY, "theta9"))
row("a result by its Symbol", lambda: SW[th4], Correct(lambda v: v == SW.position["theta4"]))
row("a result by an unknown Symbol", lambda: SW[sp.Symbol("theta9")], named(ARG, "theta9"))
row("a result by a number", lambda: SW[0], named(ARG, "0"))
row("a result by None", lambda: SW[None], named(ARG, "None"))
row("FourBar.solve(1.0)['theta4'] is θ4", lambda: FB.solve(1.0)["theta4"],
    Correct(lambda v: abs(v - THETA4[+1]) < 1e-12 or abs(v - THETA4[-1]) < 1e-12))
row("FourBar.solve(1.0).omega4 of a positions-only solve is 0 (at rest)", lambda: FB.solve(1.0).omega4,
    Correct(lambda v: v == 0.0))
row("velocity of a positions-only core solve is None", lambda: WIPER.solve({th2: 1.0}).velocity,
    Correct(lambda v: v is None))
for value in (np.array([1, -1]), [1], 1j, 2, 0, 1.5, "open", None, math.nan, True):
    row(f"assembly={{'theta4': {value!r}}}",
        lambda value=value: WIPER.solve({th2: 1.0}, assembly={"theta4": value}),
        named((ARG, GEO), "assembly"))
for value in (np.array([1, -1]), 1j, 2, "up", [1, -1], math.nan):
    row(f"FourBar.solve assembly={value!r}", lambda value=value: FB.solve(1.0, assembly=value),
        named((ARG, GEO), "assembly"))
row("assembly of an unknown named 'theta9'", lambda: WIPER.solve({th2: 1.0}, assembly={"theta9": 1}),
    named((ARG, GEO), "theta9"))
row("assembly=[1] (not a mapping)", lambda: WIPER.solve({th2: 1.0}, assembly=[1]),
    named((ARG, GEO), "assembly"))
SIN = sp.Symbol("_sin_theta3")
row("an unknown named _sin_theta3", lambda: Mechanism([LOOP.subs(th3, SIN)], [SIN, th4], [th2], NUMBERS),
    named(ANY, "_sin_theta3"))
row("an input named _u", lambda: Mechanism([LOOP.subs(th2, sp.Symbol("_u"))], [th3, th4], [sp.Symbol("_u")],
                                           NUMBERS), named(ANY, "_u"))
row("a declaration holding an Integral", lambda: Mechanism(
    [sp.Matrix([LOOP[0] + sp.Integral(th3, (th2, 0, 1)), LOOP[1]])], [th3, th4], [th2], NUMBERS),
    named(ANY, "Integral"))
row("a declaration holding an undefined Function", lambda: Mechanism(
    [sp.Matrix([LOOP[0] + sp.Function("f")(th3), LOOP[1]])], [th3, th4], [th2], NUMBERS), named(ANY, "f"))
row("a declaration holding a Derivative", lambda: Mechanism(
    [sp.Matrix([LOOP[0] + sp.Derivative(sp.Function("g")(th2), th2), LOOP[1]])], [th3, th4], [th2], NUMBERS),
    named(ANY, "Derivative"))
row("a declaration holding I", lambda: Mechanism([sp.Matrix([LOOP[0] + sp.I, LOOP[1]])], [th3, th4], [th2],
                                                 NUMBERS), named(ANY, "loop"))
row("a declaration holding zoo", lambda: Mechanism([sp.Matrix([LOOP[0] + sp.zoo, LOOP[1]])], [th3, th4],
                                                   [th2], NUMBERS), named(ANY, "loop"))
row("a declaration of text", lambda: Mechanism(["theta3 - theta2"], [th3], [th2]), named(ANY, "loops"))
row("unknowns as text", lambda: Mechanism([LOOP], "theta3, theta4", [th2], NUMBERS), named(ANY, "unknowns"))
row("an unknown that is also an input", lambda: Mechanism([LOOP], [th3, th4], [th4], NUMBERS),
    named(ANY, "theta4"))


# ---------------------------------------------------------------- build_explorer's specification
def _spec(**changes):
    spec = dict(name="crank", controls={"theta_deg": _slider("θ (°)", 30.0, -180.0, 180.0, 1.0)},
                size=(3.0, 3.0),
                panels=lambda figure: (_grid(figure.add_subplot(), xlim=(-1, 1), ylim=(-1, 1)), {}, {}),
                linkage={"links": {"crank": ("O", "A")}},
                draw=lambda stage, state, changed: stage.solved(
                    {"O": (0.0, 0.0), "A": (np.cos(np.radians(state["theta_deg"])), 0.0)}, ["turned"]))
    spec.update(changes)
    return ExplorerSpec(**spec)


row("build_explorer of a sound specification", lambda: build_explorer(_spec()).update(theta_deg=60.0).lines,
    Correct(lambda lines: lines == ("turned",)))
SPECS = {
    "spec=None": (None, "spec"),
    "spec={}": ({}, "spec"),
    "panels=None": (_spec(panels=None), "panels"),
    "panels returning None": (_spec(panels=lambda figure: None), "panels"),
    "panels returning two things": (_spec(panels=lambda figure: (figure.add_subplot(), {})), "panels"),
    "panels returning no axes": (_spec(panels=lambda figure: (None, {}, {})), "panels"),
    "size=(0, 3)": (_spec(size=(0, 3)), "size"),
    "size=(1e5, 1e5)": (_spec(size=(1e5, 1e5)), "size"),
    "size=(nan, 3)": (_spec(size=(math.nan, 3)), "size"),
    "size=(-1, 3)": (_spec(size=(-1, 3)), "size"),
    "size='big'": (_spec(size="big"), "size"),
    "size=3": (_spec(size=3), "size"),
    "controls=None": (_spec(controls=None), "controls"),
    "controls of numbers": (_spec(controls={"theta_deg": 30.0}), "controls"),
    "linkage=None": (_spec(linkage=None), "linkage"),
    "linkage without links": (_spec(linkage={}), "linkage"),
    "linkage with an unknown option": (_spec(linkage={"links": {"crank": ("O", "A")}, "colour": "red"}),
                                       "linkage"),
    "draw=None": (_spec(draw=None), "draw"),
    "name=None": (_spec(name=None), "name"),
    "geometry_artists naming no artist": (_spec(geometry_artists=("nothing",)), "geometry_artists"),
    "geometry_keys naming no control": (_spec(geometry_keys=("nothing",)), "geometry_keys"),
}
for label, (spec, name) in SPECS.items():
    row(f"build_explorer {label}", lambda spec=spec: build_explorer(spec), named(ARG, name))
row("build_explorer draw returning None: an error readout",
    lambda: build_explorer(_spec(draw=lambda stage, state, changed: None)).last,
    Correct(lambda readout: readout.status == "error" and "draw" in readout.text))
row("build_explorer draw returning text: an error readout",
    lambda: build_explorer(_spec(draw=lambda stage, state, changed: "fine")).last,
    Correct(lambda readout: readout.status == "error" and "draw" in readout.text))

# ---------------------------------------------------------------- no hang: every call within seconds
row("newton on 1/x = 1e-9 from 1: x = 1e9", lambda: newton(lambda x: 1 / x - 1e-9, 1.0,
                                                         jac=lambda x: -1 / x ** 2).x,
    Correct(lambda x: abs(x - 1e9) < 1e-3))
row("newton on 1/x = 0 from 1", lambda: newton(lambda x: 1 / x, 1.0, jac=lambda x: -1 / x ** 2),
    named(ANY, "x"))
row("newton_batch on 1/x = 0 from 1: none converged", lambda: newton_batch(
    lambda x: 1 / x, np.ones((3, 1)), jac=lambda x: (-1 / x ** 2)[..., None]).converged,
    Correct(lambda converged: not np.any(converged)))
row("newton with a residual of 10⁶ entries", lambda: newton(lambda x: x - 1.0, np.zeros(10 ** 6)),
    named(ANY, "x0"))
row("animate 10⁴ frames", lambda: animate(FB, FB.solve(np.linspace(0, 6, 10_000)), max_frames=10_000),
    named(ARG, "max_frames"))
row("animate at dpi 600", lambda: animate(FB, FB.solve(SWEEP), dpi=600), named(ARG, "dpi"))
row("animate at dpi 1e9", lambda: animate(FB, FB.solve(SWEEP), dpi=1e9), named(ARG, "dpi"))
row("animate size=(1e5, 1e5)", lambda: animate(FB, FB.solve(SWEEP), size=(1e5, 1e5)), named(ARG, "size"))
row("draw size=(1e5, 1e5)", lambda: draw(FB, FB.solve(0.5), size=(1e5, 1e5)), named(ARG, "size"))
row("check_newton_update on 10⁷ numbers", lambda: checks.check_newton_update(np.ones(10 ** 7)),
    Verdict(False))
row("check_omega4_expression on 10⁶ symbols", lambda: checks.check_omega4_expression(
    sp.Add(*sp.symbols("x0:1000000"))), Verdict(False))
row("check_fivebar_g on 10⁵ symbols", lambda: checks.check_fivebar_g(sp.Add(*sp.symbols("y0:100000"))),
    Verdict(False))
row("check_fivebar_g on a deep power tower", lambda: checks.check_fivebar_g(
    sp.Pow(sp.Symbol("x"), sp.Pow(sp.Symbol("x"), sp.Pow(sp.Symbol("x"), 99999)))), Verdict(False))
row("check_mobility on a 10⁶-digit int", lambda: checks.check_mobility(10 ** 100_000), Verdict(False))
row("check_newton_iterations on a list of 10⁶ items", lambda: checks.check_newton_iterations([1.0] * 10 ** 6),
    Verdict(False))
row("Precision(4).typed of 10⁷ numbers", lambda: Precision(4).typed(np.ones(10 ** 7)), named(ARG, "value"))


# ---------------------------------------------------------------- the runner
class Hang(Exception):
    pass


def _alarm(signum, frame):
    raise Hang(f"still running after {TIME_BOUND} s")


def outcome(call, expect) -> tuple[str, str]:
    """("ok" | "silent" | "hang" | "raw" | "unnamed", detail) of one row."""
    previous = signal.signal(signal.SIGALRM, _alarm)
    signal.alarm(TIME_BOUND)
    try:
        result = call()
    except Hang as err:
        return "hang", str(err)
    except CourseLibError as err:
        if isinstance(expect, Named) and isinstance(err, expect.kind):
            missing = [text for text in expect.says if text not in str(err)]
            if not missing:
                return "ok", ""
            return "unnamed", f"{type(err).__name__}: {err} (lacks {missing})"
        return "unnamed", f"{type(err).__name__}: {err}"
    except Exception as err:  # noqa: BLE001 — every other exception is a raw traceback
        return "raw", f"{type(err).__name__}: {err}"[:400]
    finally:
        signal.alarm(0)
        signal.signal(signal.SIGALRM, previous)
        import matplotlib.pyplot as plt

        plt.close("all")
    if isinstance(expect, Correct):
        try:
            holds = expect.holds(result)
        except Exception as err:  # noqa: BLE001
            return "silent", f"{result!r}"[:200] + f" ({type(err).__name__}: {err})"
        return ("ok", "") if holds else ("silent", f"{result!r}"[:300])
    if isinstance(expect, Verdict):
        if isinstance(result, checks.Feedback) and result.ok is expect.ok and str(result)[0] in "✔✘":
            return "ok", ""
        return "silent", f"{result!r}"[:300]
    return "silent", f"returned {result!r}"[:300]


#: Rows the core still fails, each with why (strict: once fixed, such a row fails until it leaves this list)
LEFT: dict[str, str] = {}


@pytest.mark.parametrize("label", [
    pytest.param(label, marks=pytest.mark.xfail(strict=True, reason=LEFT[label])) if label in LEFT else label
    for label in ROWS])
def test_a_bad_input_is_named_or_answered_correctly(label):
    call, expect = ROWS[label]
    kind, detail = outcome(call, expect)
    assert kind == "ok", f"{kind}: {detail}"


def test_the_campaign_is_large():
    assert len(ROWS) >= 150, len(ROWS)


if __name__ == "__main__":
    import warnings

    warnings.filterwarnings("error", category=RuntimeWarning, module="course_lib.*")  # as pyproject's pytest
    tally: dict[str, list[str]] = {}
    for label, (call, expect) in ROWS.items():
        kind, detail = outcome(call, expect)
        tally.setdefault(kind, []).append(f"{label} — {detail}")
    total = len(ROWS)
    good = len(tally.get("ok", []))
    print(f"rows {total}; named-or-correct {good} ({100 * good / total:.1f} %)")
    for kind in ("silent", "hang", "raw", "unnamed"):
        print(f"{kind}: {len(tally.get(kind, []))}")
        for line in tally.get(kind, []):
            print("   ", line)
    sys.exit(0)
