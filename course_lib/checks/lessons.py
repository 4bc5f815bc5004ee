"""Checkers of the lessons' "Try it" cells (lessons 00, 03 and 08 use exercise checkers)."""
# ruff: noqa: F403, F405

import itertools

import numpy as np

from ..errors import InvalidArgumentError
from ..fivebar import FiveBar
from ..fourbar import BRANCHES, FourBar
from ..planar import polar, wrap_angle
from ..profile import first_turn_time, motor_profile
from ..saw import Saw, analytic
from .engine import *  # the feedback engine's helpers (engine.__all__)

__all__ = ["check_crank_angle_for_rocker", "check_rocker_pin_speed", "check_motor_start", "check_saw_rates",
           "check_blade_peak_speed", "check_fivebar_theta4", "check_reach_height"]


def _crank_roots(linkage: FourBar, theta4: float) -> np.ndarray:
    """The two crank angles (rad, in (−π, π]) that put the rocker at ``theta4``; NaN where none does."""
    B = polar(linkage.l4, theta4) + [linkage.l1, 0.0]
    # A = l2(cos θ2, sin θ2) lies l3 from B: |B|² + l2² − 2 l2 |B| cos(θ2 − φ) = l3², φ the direction of B
    cosine = (B @ B + linkage.l2**2 - linkage.l3**2) / (2 * linkage.l2 * np.linalg.norm(B))
    reach = np.arccos(np.clip(cosine, -1, 1)) if abs(cosine) <= 1 + 1e-12 else np.nan
    return wrap_angle(np.arctan2(B[1], B[0]) + np.array([1, -1]) * reach, nan_ok=True)


def _rocker_reached(linkage: FourBar, theta4: float) -> None:
    """Some crank angle in (0, π) puts the rocker at ``theta4``."""
    if not any(0 < root < np.pi for root in _crank_roots(linkage, theta4)):
        raise InvalidArgumentError(f"no crank angle in (0, π) puts the rocker of {linkage!r} at "
                                   f"theta4={theta4:.6g}: no reference answer exists for this task")


def _assembles(linkage: FourBar, theta2: float, omega2: float, branch: str) -> None:
    """The four-bar closes at ``theta2`` on both branches, with rates there."""
    task_possible(lambda: [tuple(linkage.solve(theta2, omega2, branch=b)) for b in ("open", "crossed")],
                  f"the four-bar cannot be assembled at theta2={theta2:.6g}, or its rates at "
                  f"omega2={omega2:.6g} are undefined there (a toggle)")


def _saw_closes(saw: Saw, theta2: float, omega2: float) -> None:
    """The saw closes at ``theta2``, with rates there."""
    task_possible(lambda: analytic(theta2, omega2, 0.0, saw=saw),
                  f"the saw cannot close at theta2={theta2:.6g} (the rod r3 cannot reach the slider line "
                  "there, or stands perpendicular to it)")


#: The crank angles of a turn where the blade's speed is sampled.
_TURN = np.linspace(0.0, 2 * np.pi, 20001)


def _saw_turns(saw: Saw, omega2: float) -> None:
    """The saw closes at every crank angle of a turn."""
    task_possible(lambda: analytic(_TURN, omega2, 0.0, saw=saw),
                  f"the saw {saw!r} cannot turn a full revolution (the rod r3 cannot reach the slider line "
                  "at some theta2, or stands perpendicular to it)")


def _pen_reached(robot: FiveBar, x3: float, y3: float, sigma2: int) -> None:
    """Both legs of ``robot`` reach the pen at (``x3``, ``y3``)."""
    task_possible(lambda: [tuple(robot.inverse(x3, y3, modes=(1, s))) for s in (1, -1)],
                  f"the five-bar cannot reach x3={x3:.6g}, y3={y3:.6g}")


def _line_reached(robot: FiveBar, x3: float) -> None:
    """Both legs of ``robot`` reach the line X = ``x3`` (each stretches somewhere on it)."""
    for leg, length, motor in (("1", robot.l1 + robot.l2, robot.l5 / 2),
                               ("4", robot.l3 + robot.l4, -robot.l5 / 2)):
        if not abs(x3 - motor) < length:
            raise InvalidArgumentError(f"leg {leg} of {robot!r} cannot reach the line x3={x3:.6g} (its motor "
                                       f"is {abs(x3 - motor):.6g} m from it, the leg {length:.6g} m long): "
                                       "no reference answer exists for this task")


@reads(number("θ2"), task={"linkage": FourBar, "theta4": "rad"}, possible=_rocker_reached)
def check_crank_angle_for_rocker(answer, linkage: FourBar, theta4: float) -> Feedback:
    """Lesson 02: the crank angle θ2 in (0, π) (rad, to 4 decimals) that puts the rocker at ``theta4``.

    >>> bar = FourBar(crank=0.10, coupler=0.25, rocker=0.20, ground=0.30)
    >>> check_crank_angle_for_rocker(1.0, bar, bar.solve(1.0).theta4).ok
    True
    """
    roots = _crank_roots(linkage, theta4)
    inside = [float(root) for root in roots if 0 < root < np.pi]
    outside = [float(root) for root in roots if not 0 < root < np.pi]
    return diagnose(answer, DECIMALS, [
        (inside, "Correct: the crank pin A is exactly l3 from the rocker pin B."),
        (lambda v: any(in_degrees(v, root, DECIMALS) for root in inside),
         "that is the right angle in degrees; newton and course_lib work in radians."),
        (outside, "that angle closes the loop, but it is outside (0, π): start Newton from a seed in that "
                  "range (the other root is the rocker's second pass through that angle in the same turn)."),
        (lambda v: any(in_degrees(v, root, DECIMALS) for root in outside),
         "that is in degrees — and it is the other root, outside (0, π): give radians, and start Newton from "
         "a seed in (0, π)."),
    ], "at that θ2 the distance |B − A| differs from l3. A lies on the crank circle (radius l2 about O2) and "
       "on the circle of radius l3 about B: solve |B − A(θ2)| − l3 = 0 for θ2 with B at the given θ4, e.g. "
       "by Newton from a seed in (0, π).", angles=True)


@reads(number("the speed of B"),
       task={"linkage": FourBar, "theta2": "rad", "omega2": "rad/s", "branch": BRANCHES}, possible=_assembles)
def check_rocker_pin_speed(answer, linkage: FourBar, theta2: float, omega2: float, branch: str = "open"
                           ) -> Feedback:
    """Lesson 04: the speed |V_B| (m/s, to 4 significant figures) of the rocker pin B at ``theta2`` (rad)
    and ``omega2`` (rad/s).

    >>> check_rocker_pin_speed(-1.0, FourBar(0.10, 0.25, 0.20, 0.30), 1.0, 10.0).message
    'Not yet: a speed is a magnitude: it cannot be negative.'
    """
    other = "crossed" if branch == "open" else "open"
    speed, crossed = (abs(linkage.solve(theta2, omega2, branch=b).omega4) * linkage.l4
                      for b in (branch, other))
    in_degrees = linkage.solve(np.degrees(theta2), omega2, branch=branch, on_failure="nan").omega4
    return diagnose(answer, FIGURES, [
        (speed, "Correct: B moves perpendicular to the rocker at |ω4|·l4."),
        (lambda value: value < 0, "a speed is a magnitude: it cannot be negative."),
        (speed * 1000, "that looks like mm/s; give the speed in m/s (lengths in metres)."),
        (crossed, f"that is the speed of B on the {other} assembly; the lesson's linkage is on the {branch} "
                  "assembly."),
        (speed / linkage.l4, "that is |ω4| in rad/s: multiply by the rocker length l4."),
        (abs(omega2) * linkage.l2, "that is the speed of the crank pin A (ω2·l2); the task asks for the "
                                   "rocker pin B."),
        (abs(in_degrees) * linkage.l4, "θ2 went into solve in degrees; convert with np.radians."),
    ], "solve for ω4 at the given θ2 (radians) and ω2, then |V_B| = |ω4|·l4.")


@reads(vector(2, "(T, rpm)"), task={"alpha_max": "positive rad/s²"})
def check_motor_start(answer, alpha_max: float) -> Feedback:
    """Lesson 05: (T in s, final speed in rpm), each to 4 significant figures, of the start-up over the first
    turn, peak ``alpha_max`` (rad/s²).

    >>> print(check_motor_start((1.9416, 61.80), 5.0))
    ✔ Correct on both.
    >>> print(check_motor_start((1.94, 61.8), 5.0))
    ✘ Not yet: right to 3 significant figures; the task asks for 4 significant figures: give more digits.
    """
    T = first_turn_time(alpha_max)
    omega = float(motor_profile(2 * T, alpha_max).omega2)
    rpm = omega * 60 / (2 * np.pi)
    return diagnose(answer, FIGURES, [
        ((T, rpm), "Correct on both."),
        ((T, omega), "T is right. Your speed looks like rad/s: convert with 60/(2π)."),
        ((T, None), "T is right; the final speed is 2·A·T/3 in rad/s — then convert to rpm."),
    ], f"T is not right yet: solve θ2(T) = A·T²/3 = 2π with A = {alpha_max:g} rad/s².")


@reads(vector(3, "(v_r, ω1, ω3)"), task={"saw": Saw, "theta2": "rad", "omega2": "rad/s"},
       possible=_saw_closes)
def check_saw_rates(answer, saw: Saw, theta2: float, omega2: float) -> Feedback:
    """Lesson 06: the rates (v_r in m/s, ω1, ω3 in rad/s), to 4 significant figures, at ``theta2`` (rad),
    ``omega2`` (rad/s), α2 = 0.

    >>> check_saw_rates([0.0, 0.0, 0.0], Saw(), 0.0, 1.0).ok
    False
    """
    truth = analytic(theta2, omega2, 0.0, saw=saw)[3:6]
    orders = [truth[list(order)] for order in itertools.permutations(range(3)) if order != (0, 1, 2)]
    return diagnose(answer, FIGURES, [
        (truth, "Correct: a single linear solve gives the rates."),
        (-truth, "every sign is flipped: the right-hand side is minus the ω2 terms."),
        (orders, "the right numbers in the wrong order: give (v_r, ω1, ω3), the order of the unknowns "
                 "(r1, θ1, θ3)."),
        ([-order for order in orders], "the right sizes, but in the wrong order and with every sign flipped: "
                                       "give (v_r, ω1, ω3), and the right-hand side is minus the ω2 terms."),
        ((None, truth[1], truth[2]), "ω1 and ω3 are right; v_r is not: it is the rate of the signed length "
                                     "r1 (negative here), dr1/dt."),
    ], "check the matrix J at the position and the ω2 terms of the velocity equations.")


@reads(number("the blade speed"), task={"saw": Saw, "omega2": "nonzero rad/s"}, possible=_saw_turns)
def check_blade_peak_speed(answer, saw: Saw, omega2: float) -> Feedback:
    """Lesson 07: the largest blade speed |ẋ| (m/s, to 3 significant figures) over a turn at constant
    ``omega2`` (rad/s).

    >>> check_blade_peak_speed(0.075 * 6.472, Saw(), 6.472).ok
    False
    """
    r1, theta1, _, v_r, omega1 = analytic(_TURN, omega2, 0.0, saw=saw)[:, :5].T
    peak = np.abs(v_r * np.cos(theta1) - r1 * omega1 * np.sin(theta1)).max()
    return diagnose(answer, Precision(3), [
        (peak, "Correct."),
        (-peak, Feedback(True, "Correct in size; a speed is usually given positive.")),
        (1000 * peak, "that looks like mm/s; give the speed in m/s."),
        (saw.r2 * abs(omega2), "that is the crank pin's speed r2·ω2; the blade moves a little faster at its "
                               "peak."),
        (np.abs(v_r).max(), "that is the largest |v_r|, the rate of the length r1; the blade's speed is "
                            "ẋ = v_r cos θ1 − r1 ω1 sin θ1."),
    ], f"use ω2 = {omega2:.4g} rad/s and the slider speed ẋ = v_r cos θ1 − r1 ω1 sin θ1 over a fine grid.")


@reads(number("θ4"), task={"robot": FiveBar, "x3": "m", "y3": "m", "sigma2": (1, -1)}, possible=_pen_reached)
def check_fivebar_theta4(answer, robot: FiveBar, x3: float, y3: float, sigma2: int) -> Feedback:
    """Lesson 09: the crank angle θ4 (rad, to 4 decimals) of leg 4 that puts the pen at (x3, y3) with
    σ2 = ``sigma2``.

    >>> check_fivebar_theta4(0.0, FiveBar(0.10, 0.15, 0.15, 0.10, 0.08), 0.0, 0.2, -1).ok
    False
    """
    this, that = (robot.inverse(x3, y3, modes=(1, s)) for s in (sigma2, -sigma2))
    theta1 = [robot.inverse(x3, y3, modes=(s, sigma2)).theta1 for s in (1, -1)]  # leg 1, either σ1
    return angle_verdict(answer, this.theta4, [
        (that.theta4, f"that is σ2 = {-sigma2:+d}: take the other sign of the square root."),
        (theta1, "that is θ1 of leg 1; the task asks for θ4 (coefficients a2, b2, c2)."),
    ], f"recompute a2, b2, c2 with l3, l4, l5 and X3 = {x3:g}, Y3 = {y3:g}, then θ4 = 2·atan(root).")


@reads(number("the height Y3"), task={"robot": FiveBar, "x3": "m"}, possible=_line_reached)
def check_reach_height(answer, robot: FiveBar, x3: float) -> Feedback:
    """Lesson 10: the height Y3 (m, to 4 decimals) at which the pen, moving up the line X = ``x3``, first
    stretches a leg.

    >>> check_reach_height(0.24, FiveBar(0.10, 0.15, 0.15, 0.10, 0.08), -0.03).ok
    True
    """
    reach = {"1": (robot.l1 + robot.l2, robot.l5 / 2), "4": (robot.l3 + robot.l4, -robot.l5 / 2)}
    heights = {leg: np.sqrt(length**2 - (x3 - motor) ** 2) for leg, (length, motor) in reach.items()}
    leg, other = sorted(heights, key=heights.get)
    return diagnose(answer, DECIMALS, [
        (heights[leg], f"Correct: leg {leg} stretches first."),
        (heights[other], f"that is where leg {other} stretches; the other leg gets there first."),
        (1000 * heights[leg], "that looks like millimetres; give metres."),
    ], "a leg is stretched when the pen is (proximal + distal length) from its motor; the leg whose motor is "
       "farther from the line stretches first.")
