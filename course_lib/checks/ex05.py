"""Checkers of exercise set 05 (the five-bar robot); lesson 08's Try it uses check_fivebar_forward."""
# ruff: noqa: F403, F405

import re

import numpy as np

from ..errors import InvalidArgumentError
from ..fivebar import WORKING_MODES, FiveBar
from ..planar import wrap_angle
from .engine import *  # the feedback engine's helpers (engine.__all__)
from .engine import allowing  # a call the task gives the student, let through the watch on their function

#: Positions of the end effector: to 6 decimals in metres.
MICROMETRES = Precision(6, decimals=True)

__all__ = ["check_fivebar_forward", "check_fivebar_inverse", "check_fivebar_g", "check_fivebar_singularity"]


def _assembles(robot: FiveBar, theta1: float, theta4: float, **_) -> None:
    """The five-bar closes at the crank angles ``theta1``, ``theta4`` (in both assembly modes)."""
    task_possible(lambda: [tuple(robot.forward(theta1, theta4, mode=m)) for m in (1, -1)],
                  f"the five-bar cannot be assembled at theta1={theta1:.6g}, theta4={theta4:.6g}")


def _reaches(robot: FiveBar, x3: float, y3: float, **_) -> None:
    """Both legs of the five-bar reach the point (``x3``, ``y3``) (in every working mode)."""
    task_possible(lambda: [tuple(robot.inverse(x3, y3, modes=m)) for m in WORKING_MODES],
                  f"the five-bar cannot reach x3={x3:.6g}, y3={y3:.6g}")


def _posed(robot: FiveBar, theta1: float, theta4: float, x3: float, y3: float) -> None:
    """(``x3``, ``y3``) is the end effector of ``robot`` at ``theta1``, ``theta4``: each distal link has its
    length there (to a millionth of the robot's size)."""
    elbow1 = (robot.l5 / 2 + robot.l1 * np.cos(theta1), robot.l1 * np.sin(theta1))  # P2, P4: the elbows
    elbow4 = (-robot.l5 / 2 + robot.l4 * np.cos(theta4), robot.l4 * np.sin(theta4))
    gaps = (abs(np.hypot(x3 - elbow1[0], y3 - elbow1[1]) - robot.l2),
            abs(np.hypot(x3 - elbow4[0], y3 - elbow4[1]) - robot.l3))
    size = max(robot.l1, robot.l2, robot.l3, robot.l4, robot.l5)
    if not max(gaps) <= 1e-6 * size:
        link = "l2" if gaps[0] > gaps[1] else "l3"
        raise InvalidArgumentError(f"x3, y3 must be the end effector of the robot at theta1, theta4 (as "
                                   f"robot.forward(theta1, theta4, mode) gives it); got x3={x3:.6g}, "
                                   f"y3={y3:.6g}, {max(gaps):.3g} m off the distal link {link} at "
                                   f"theta1={theta1:.6g}, theta4={theta4:.6g}: no reference answer exists "
                                   "for this task")


#: Crank angles (θ1, θ4), rad, where a student's forward procedure is called besides the task's own
FRESH_CRANKS = np.radians([(45.0, 135.0), (60.0, 100.0), (90.0, 150.0), (30.0, 120.0), (80.0, 80.0),
                           (110.0, 170.0)])


def _number_pair_or_function(what: str):
    """A parser: the student's function as it is (a procedure to call), else two finite numbers."""
    read = vector(2, what)
    return lambda answer: answer if callable(answer) and not isinstance(answer, type) else read(answer)


def _closes(robot: FiveBar, theta1: float, theta4: float) -> bool:
    """Whether both assemblies exist at (θ1, θ4), away from D = 0 (where X3 = g·Y3 + f has no slope)."""
    try:
        [tuple(robot.forward(theta1, theta4, mode=m)) for m in (1, -1)]
    except Exception:
        return False
    size = max(robot.l1, robot.l2, robot.l3, robot.l4, robot.l5)
    return bool(abs(robot.forward_coefficients(theta1, theta4)["D"]) > 0.05 * size)



def _numbers_alone(verdict: Feedback, method: str | None, why: str) -> Feedback:
    """The verdict on plain numbers; where the task asks for a method (``method`` given), right numbers are
    told ``why`` they are not the task (they do not show how they were found)."""
    return wrong(why) if verdict.ok and method is not None else verdict

def _forward_verdict(answer, robot: FiveBar, theta1: float, theta4: float, mode: int, function: bool = False
                     ) -> Feedback:
    """(x3, y3) at (``theta1``, ``theta4``) judged against assembly ``mode``'s, with the known slips named;
    ``function``: the value is what the student's function returned (one slip more: the angles converted
    with np.radians inside)."""
    reference, other = (np.array(tuple(robot.forward(theta1, theta4, mode=m))) for m in (mode, -mode))
    x3, y3 = reference
    in_degrees = robot.forward(*np.degrees([theta1, theta4]), mode=mode, on_failure="nan")
    twice = robot.forward(*np.radians([theta1, theta4]), mode=mode, on_failure="nan") if function else None
    k = robot.forward_coefficients(theta1, theta4)
    with np.errstate(all="ignore"):  # the notes' slip: +b where X3 = g·Y3 + f takes Y3 (lesson 08, §7)
        slipped = float(k["g"] * (k["b"] + mode * np.sqrt(k["b"] ** 2 - 4 * k["a"] * k["c"])) / (2 * k["a"])
                        + k["f"])
    names = {1: "arms up (σ = +1)", -1: "arms down (σ = −1)"}
    return diagnose(answer, MICROMETRES, [
        (reference, "Correct."),
        (other, f"that is the {names[-mode]} assembly; the task asks for {names[mode]}."),
        (1000 * reference, "that looks like millimetres; give metres."),
        (reference[::-1], "the coordinates are swapped: give (x3, y3)."),
        (np.array(tuple(in_degrees)), "the crank angles went into cos/sin in degrees; use radians."),
        *([(np.array(tuple(twice)), "your function converts the angles with np.radians, but it is "
                                    "called with θ1, θ4 in radians already: use them as they come.")]
          if function else []),
        ((slipped, y3), "y3 is right, but x3 is not: X3 = g·Y3 + f takes that same Y3, "
                        "(−b + σ√(b² − 4ac))/2a; with +b there (the slip of one line of the course notes, "
                        "lesson 08 §7) X3 moves by g·b/a."),
        ((-x3, y3), "y3 is right, but x3 has the wrong sign: recheck the signs in f and g of X3 = g·Y3 + f."),
        ((x3, -y3), "x3 is right, but y3 has the wrong sign: recheck the signs of b and of the root in "
                    "Y3 = (−b + σ√(b² − 4ac))/2a."),
        ((None, y3), "y3 is right, but x3 is off: compute X3 = g·Y3 + f from that same Y3, with f and g as "
                     "the task writes them."),
        ((x3, None), "x3 is right, but y3 is off: recheck a, b and c of the quadratic in Y3."),
    ], "from X3 = g·Y3 + f and a·Y3² + b·Y3 + c = 0, take Y3 = (−b + σ√(b² − 4ac))/2a.")


def _where(theta1: float, theta4: float) -> str:
    return (f"θ1 = {theta1:.6g} rad ({np.degrees(theta1) % 360:.6g}°), θ4 = {theta4:.6g} rad "
            f"({np.degrees(theta4) % 360:.6g}°)")


@reads(_number_pair_or_function("(x3, y3)"), task={"robot": FiveBar, "theta1": "rad", "theta4": "rad",
                                                   "mode": (1, -1), "method": (None, "quadratic")},
       possible=_assembles)
def check_fivebar_forward(answer, robot: FiveBar, theta1: float, theta4: float, mode: int,
                          method: str | None = None) -> Feedback:
    """Exercise 05, task 1 and lesson 08's Try it: the end effector (x3, y3) in m, to 6 decimals (a
    micrometre), in assembly mode ``mode`` (+1 arms up, −1 arms down) — two numbers, or the student's
    function of (θ1, θ4) (rad) that computes them, called here at the task's angles and at the crank angles
    :data:`FRESH_CRANKS` where the robot closes.  With ``method="quadratic"`` (exercise 05) only such a
    function passes, and only one that calls none of course_lib's solves (``robot.forward`` gives the point,
    ``robot.forward_coefficients`` f, g, a, b, c, without the derivation's work).

    >>> check_fivebar_forward((0.0, 0.0), FiveBar(0.11, 0.16, 0.17, 0.12, 0.09), 1.2, 2.2, -1).ok
    False
    """
    if not callable(answer):
        return _numbers_alone(_forward_verdict(answer, robot, theta1, theta4, mode), method,
                              "the numbers are right, but the task asks for the derivation's work: give your "
                              "function of (θ1, θ4) that computes D, f, g, a, b, c and the root (the check "
                              "calls it at other crank angles too). Numbers alone do not show how they were "
                              "found — robot.forward gives them without the quadratic.")
    probes = [(theta1, theta4)] + [(t1, t4) for t1, t4 in FRESH_CRANKS if _closes(robot, t1, t4)
                                   and not angles_close((t1, t4), (theta1, theta4))]
    name = getattr(answer, "__name__", "")
    called = f"function {name}(theta1, theta4)" if name.isidentifier() else "function"
    values = procedure(answer, probes, solver_code(FiveBar), called, vector(2, "(x3, y3)"))
    if isinstance(values, Feedback):
        return values
    verdict = _forward_verdict(values[0], robot, theta1, theta4, mode, function=True)
    if not verdict.ok:
        return wrong(f"your {called} at the task's {_where(theta1, theta4)}: "
                     + verdict.message.removeprefix("Not yet: "))
    for (t1, t4), value in zip(probes[1:], values[1:], strict=True):
        if not MICROMETRES.agrees(value, tuple(robot.forward(t1, t4, mode=mode))):
            if all(MICROMETRES.agrees(other, values[0]) for other in values[1:]):
                return wrong(f"your {called} returns the same point at every crank angle: compute D, f, g, "
                             "a, b, c from its arguments theta1, theta4, not from the task's angles.")
            there = _forward_verdict(value, robot, t1, t4, mode, function=True)
            return wrong(f"your {called} is right at the task's angles but not at {_where(t1, t4)}: "
                         + there.message.removeprefix("Not yet: "))
    return right(f"Correct (to {MICROMETRES}): your {called} gives the end effector at the task's angles "
                 f"and at {len(probes) - 1} other pairs of crank angles.")


def _inverse_verdict(answer, robot: FiveBar, x3: float, y3: float, modes: tuple[int, int]) -> Feedback:
    """(θ1, θ4) at the end effector (``x3``, ``y3``) judged against working mode ``modes``'s, with the known
    slips named."""
    solutions = {m: np.array(tuple(robot.inverse(x3, y3, modes=m))) for m in WORKING_MODES}
    theta1, theta4 = reference = solutions[modes]

    def other_mode(m):
        flipped = [s for s, mine, want in zip(("σ1", "σ2"), m, modes, strict=True) if mine != want]
        if len(flipped) == 2:
            return (f"that is working mode ({m[0]:+d}, {m[1]:+d}): the signs σ1 and σ2 before the square "
                    "roots are both the other ones.")
        return (f"that is working mode ({m[0]:+d}, {m[1]:+d}): the sign {flipped[0]} before the square root "
                "is the other one.")

    return diagnose(answer, DECIMALS, [
        (reference, "Correct: working mode (σ1, σ2) = " + f"({modes[0]:+d}, {modes[1]:+d})."),
        (lambda v: in_degrees(v, reference, DECIMALS),
         "those are the right angles in degrees; give radians."),
        (reference[::-1], "the angles are swapped: give (θ1, θ4)."),
        *((angles, other_mode(m)) for m, angles in solutions.items() if m != modes),
        ((theta1, None), "θ1 is right; recheck θ4 with the coefficients a2, b2, c2 of leg 4."),
        ((None, theta4), "θ4 is right; recheck θ1 with the coefficients a1, b1, c1 of leg 1."),
    ], "use θ = 2·atan((−b + σ√(b² − 4ac))/2a) with the half-angle coefficients of each leg.", angles=True)


#: End effector points (x3, y3), m, where a student's inverse procedure is called besides the task's: spread
#: over the workspace, each leg's two roots apart
FRESH_POINTS = ((0.0, 0.18), (-0.05, 0.22), (0.06, 0.15), (-0.03, 0.12), (0.10, 0.12), (-0.10, 0.10))


def _modes_apart(robot: FiveBar, x3: float, y3: float) -> bool:
    """Whether every working mode reaches (x3, y3), each leg's two roots more than 0.1 rad apart (away from
    a serial singularity, where the modes merge)."""
    try:
        solutions = {m: np.array(tuple(robot.inverse(x3, y3, modes=m))) for m in WORKING_MODES}
    except Exception:
        return False
    leg1 = abs(float(wrap_angle(solutions[(1, 1)][0] - solutions[(-1, 1)][0])))
    leg4 = abs(float(wrap_angle(solutions[(1, 1)][1] - solutions[(1, -1)][1])))
    return min(leg1, leg4) > 0.1


def _point(x3: float, y3: float) -> str:
    return f"(x3, y3) = ({x3:.6g}, {y3:.6g}) m"


@reads(_number_pair_or_function("(θ1, θ4)"), task={"robot": FiveBar, "x3": "m", "y3": "m",
                                                   "modes": WORKING_MODES, "method": (None, "half-angle")},
       possible=_reaches)
def check_fivebar_inverse(answer, robot: FiveBar, x3: float, y3: float, modes: tuple[int, int],
                          method: str | None = None) -> Feedback:
    """Exercise 05, task 2: crank angles (θ1, θ4) in rad, to 4 decimals, putting the end effector at (x3, y3)
    in working mode ``modes`` — two numbers, or the student's function of (x3, y3) (m) that computes them,
    called here at the task's point and at the points :data:`FRESH_POINTS` where the modes are apart.  With
    ``method="half-angle"`` (exercise 05) only such a function passes, and only one that calls none of
    course_lib's solves but ``robot.inverse_coefficients`` (the task gives the coefficients;
    ``robot.inverse`` gives the angles without the half-angle roots).

    >>> check_fivebar_inverse((0.0, 0.0), FiveBar(0.11, 0.16, 0.17, 0.12, 0.09), 0.01, 0.2, (1, -1)).ok
    False
    """
    modes = tuple(modes)
    if not callable(answer):
        return _numbers_alone(_inverse_verdict(answer, robot, x3, y3, modes), method,
                              "the angles are right, but the task asks for the half-angle roots themselves: "
                              "give your function of (x3, y3) that takes each leg's a, b, c and computes θ = "
                              "2·atan((−b + σ√(b² − 4ac))/2a) with the working mode's σ (the check calls it "
                              "at other points too). Numbers alone do not show how they were found — "
                              "robot.inverse gives them without the roots.")
    points = [(x3, y3)] + [point for point in FRESH_POINTS if not np.allclose(point, (x3, y3), atol=1e-9)
                           and _modes_apart(robot, *point)]
    name = getattr(answer, "__name__", "")
    called = f"function {name}(x3, y3)" if name.isidentifier() else "function"
    solves = allowing(solver_code(FiveBar), lambda: robot.inverse_coefficients(x3, y3))
    values = procedure(answer, points, solves, called, vector(2, "(θ1, θ4)"),
                       given="the end effector (x3, y3) in m as floats, one call per point")
    if isinstance(values, Feedback):
        return values
    for index, (point, value) in enumerate(zip(points, values, strict=True)):
        if DECIMALS.agrees(value, tuple(robot.inverse(*point, modes=modes)), angles=True):
            continue
        if index and all(DECIMALS.agrees(other, values[0], angles=True) for other in values[1:]):
            return wrong(f"your {called} returns the same angles at every point: compute the coefficients "
                         "from its arguments x3, y3, not from the task's point.")
        there = _inverse_verdict(value, robot, *point, modes)
        return wrong((f"your {called} at the task's {_point(*point)}: " if index == 0 else
                      f"your {called} is right at the task's point but not at {_point(*point)}: ")
                     + there.message.removeprefix("Not yet: "))
    return right(f"Correct (to {DECIMALS}, angles modulo 2π): your {called} gives the crank angles of "
                 f"working mode (σ1, σ2) = ({modes[0]:+d}, {modes[1]:+d}) at the task's point and at "
                 f"{len(points) - 1} other points.")


@reads()
def check_fivebar_g(answer) -> Feedback:
    """Exercise 05, task 3: the slope g in X3 = g·Y3 + f (EcL2 − EcL3 solved for X3).

    >>> import sympy as sp
    >>> l1, l4, l5, t1, t4 = sp.symbols("l1 l4 l5 theta1 theta4")
    >>> check_fivebar_g((l4 * sp.sin(t4) - l1 * sp.sin(t1)) / (l5 + l1 * sp.cos(t1) - l4 * sp.cos(t4))).ok
    True
    """
    import sympy as sp
    l1, l2, l3, l4, l5, t1, t4 = symbols = sp.symbols("l1 l2 l3 l4 l5 theta1 theta4", real=True)
    g = (-2 * l1 * sp.sin(t1) + 2 * l4 * sp.sin(t4)) / (2 * (l5 + l1 * sp.cos(t1) - l4 * sp.cos(t4)))
    return judge_expression(answer, symbols, [
        (g, "Correct: the course's g = (−2 l1 sin θ1 + 2 l4 sin θ4) / (2 (l5 + l1 cos θ1 − l4 cos θ4))."),
        (-g, "a sign error: move the Y3 term to the right-hand side before dividing by the X3 coefficient."),
        ([1 / g, -1 / g], "that is dY3/dX3; solve the linear equation for X3, not Y3."),
        ([2 * g, g / 2], "off by a factor 2: both the X3 and the Y3 coefficients carry the factor 2."),
        (lambda expr: expr.has(l2, l3), "l2 and l3 belong to f (the constant term), not to the slope g."),
    ], "expand EcL2 − EcL3: the squares X3², Y3² cancel, leaving an equation linear in X3 and Y3.")


#: The answers, in the order of FiveBar.singularity_measures, and what each means.
_SINGULARITIES = {
    "serial1": "leg 1 is stretched or folded: the point is on the boundary of leg 1's reach, two inverse "
               "solutions (σ1 = ±1) merge, and the end effector cannot move along l1–l2.",
    "serial4": "leg 4 is stretched or folded: two inverse solutions (σ2 = ±1) merge.",
    "parallel": "the distal links are aligned: the two forward solutions (arms up/down) merge and the end "
                "effector can move with the motors locked.",
    "none": "all three measures are away from zero.",
}


def _singularity_word(text: str) -> str:
    """A student's name of a singularity, read as one of _SINGULARITIES: "serial singularity of leg 1",
    "type I, leg 4", "type II", "parallel singularity", "no singularity" … (type I is serial, type II
    parallel)."""
    read = re.sub(r"[^a-z0-9]", "", text.lower())
    for filler in ("singularity", "singular", "leg", "ofthe", "of", "at"):
        read = read.replace(filler, "")
    if "parallel" in read:  # "parallel (type II)": the type is the same word
        read = re.sub(r"type(ii|2)", "", read)
    if "serial" in read:
        read = re.sub(r"type(?:i|1)(?!i)", "", read)
    read = re.sub(r"^type(ii|2)$", "parallel", read)
    read = re.sub(r"^type(i|1)(?=[14]?$)", "serial", read)
    return "none" if read in ("no", "none", "nothing") else read


@reads(word(tuple(_SINGULARITIES), 'answer one of "serial1", "serial4", "parallel" or "none" (a string).',
            clean=_singularity_word),
       task={"robot": FiveBar, "theta1": "rad", "theta4": "rad", "x3": "m", "y3": "m"}, possible=_posed)
def check_fivebar_singularity(answer, robot: FiveBar, theta1: float, theta4: float, x3: float, y3: float
                              ) -> Feedback:
    """Exercise 05, task 4: "serial1", "serial4", "parallel" or "none": the robot's singularity.

    >>> robot = FiveBar(0.11, 0.16, 0.17, 0.12, 0.09)
    >>> check_fivebar_singularity("none", robot, 1.2, 2.2, *robot.forward(1.2, 2.2, 1)).ok
    True
    """
    measures = zip(_SINGULARITIES, robot.singularity_measures(theta1, theta4, x3, y3), strict=False)
    found = [name for name, value in measures if abs(value) < 1e-6] or ["none"]
    return first([
        (answer == "none", "compute robot.singularity_measures(...): one of them is zero here."),
        ("serial" in answer and any("serial" in name for name in found),
         "a serial singularity, yes — but of the other leg."),
        (answer == "parallel", "the distal links l2 and l3 are not aligned here; look at the crank–distal "
                               "angles."),
        (True, "that measure is not zero here; compute all three with robot.singularity_measures(...)."),
    ] if answer not in found else [], "Correct: " + _SINGULARITIES[answer])
