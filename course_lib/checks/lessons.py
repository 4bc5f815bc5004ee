"""Checkers of the lessons' "Try it" cells (lessons 00, 03 and 08 use exercise checkers)."""
# ruff: noqa: F403, F405

import numpy as np

from ..fivebar import FiveBar
from ..fourbar import FourBar
from ..planar import polar
from ..profile import first_turn_time, motor_profile
from ..saw import Saw, analytic
from .engine import *  # the feedback engine's helpers (engine.__all__)

__all__ = ["check_crank_angle_for_rocker", "check_rocker_pin_speed", "check_motor_start", "check_saw_rates",
           "check_blade_peak_speed", "check_fivebar_theta4", "check_reach_height"]


@reads(number("θ2"))
def check_crank_angle_for_rocker(answer, linkage: FourBar, theta4: float) -> Feedback:
    """Lesson 02: the crank angle θ2 in (0, π) (rad) that puts the rocker at ``theta4``.

    >>> bar = FourBar(crank=0.10, coupler=0.25, rocker=0.20, ground=0.30)
    >>> check_crank_angle_for_rocker(1.0, bar, bar.solve(1.0).theta4).ok
    True
    """
    B = polar(linkage.l4, theta4) + [linkage.l1, 0.0]

    def closes(theta2: float) -> bool:
        return abs(np.linalg.norm(B - polar(linkage.l2, theta2)) - linkage.l3) < 1e-9

    loop_closes = closes(answer)
    return first([
        (not loop_closes and closes(np.radians(answer)), "that is the right angle in degrees; newton and "
                                                         "course_lib work in radians."),
        (not loop_closes, "at that θ2 the distance |B − A| differs from l3. A lies on the crank circle "
                          "(radius l2 about O2) and on the circle of radius l3 about B: solve "
                          "|B − A(θ2)| − l3 = 0 for θ2 with B at the given θ4, e.g. by Newton from a seed in "
                          "(0, π)."),
        (not 0.0 < answer < np.pi, "that angle closes the loop, but it is outside (0, π): start Newton from "
                                   "a seed in that range (the other root is the other assembly)."),
    ], "Correct: the crank pin A is exactly l3 from the rocker pin B.")


@reads(number("the speed of B"))
def check_rocker_pin_speed(answer, linkage: FourBar, theta2: float, omega2: float, branch: str = "open"
                           ) -> Feedback:
    """Lesson 04: the speed |V_B| (m/s) of the rocker pin B at ``theta2`` (rad) and ``omega2`` (rad/s).

    >>> check_rocker_pin_speed(-1.0, FourBar(0.10, 0.25, 0.20, 0.30), 1.0, 10.0).message
    'Not yet: a speed is a magnitude: it cannot be negative.'
    """
    omega4 = abs(linkage.solve(theta2, omega2, branch=branch).omega4)
    in_degrees = linkage.solve(np.degrees(theta2), omega2, branch=branch, on_unreachable="nan").omega4
    return diagnose(answer, close, [
        (omega4 * linkage.l4, "Correct: B moves perpendicular to the rocker at |ω4|·l4."),
        (lambda value: value < 0, "a speed is a magnitude: it cannot be negative."),
        (omega4, "that is |ω4| in rad/s: multiply by the rocker length l4."),
        (abs(omega2) * linkage.l2, "that is the speed of the crank pin A (ω2·l2); the task asks for the "
                                   "rocker pin B."),
        (abs(in_degrees) * linkage.l4, "θ2 went into solve in degrees; convert with np.radians."),
    ], "solve for ω4 at the given θ2 (radians) and ω2, then |V_B| = |ω4|·l4.")


@reads(vector(2, "(T, rpm)"))
def check_motor_start(answer, alpha_max: float) -> Feedback:
    """Lesson 05: (T in s, final rpm) of the start-up over the first turn, peak ``alpha_max`` (rad/s²).

    >>> check_motor_start((1.9416, 61.8), 5.0).ok
    True
    """
    T_answer, speed = answer
    T = first_turn_time(alpha_max)
    omega = float(motor_profile(2 * T, alpha_max).omega2)
    return first([
        (not close(T_answer, T, rtol=1e-3), f"T is not right yet: solve θ2(T) = A·T²/3 = 2π with A = "
                                            f"{alpha_max:g} rad/s²."),
        (close(speed, omega, rtol=1e-3), "T is right. Your speed looks like rad/s: convert with 60/(2π)."),
        (not close(speed, omega * 60 / (2 * np.pi), rtol=1e-3),
         "T is right; the final speed is 2·A·T/3 in rad/s — then convert to rpm."),
    ], "Correct on both.")


@reads(vector(3, "(V_r, ω1, ω3)"))
def check_saw_rates(answer, saw: Saw, theta2: float, omega2: float) -> Feedback:
    """Lesson 06: the rates (V_r in m/s, ω1, ω3 in rad/s) at ``theta2`` (rad), ``omega2`` (rad/s), α2 = 0.

    >>> check_saw_rates([0.0, 0.0, 0.0], Saw(), 0.0, 1.0).ok
    False
    """
    truth = analytic(theta2, omega2, 0.0, saw=saw)[3:6]
    return diagnose(answer, near, [
        (truth, "Correct: a single linear solve gives the rates."),
        (-truth, "every sign is flipped: the right-hand side is minus the ω2 terms."),
        ([truth[[0, 2, 1]], truth[::-1]], "the right numbers in the wrong order: give (V_r, ω1, ω3)."),
    ], "check the matrix J at the position and the ω2 terms of the velocity equations.")


@reads(number("the blade speed"))
def check_blade_peak_speed(answer, saw: Saw, omega2: float) -> Feedback:
    """Lesson 07: the largest blade speed |ẋ| (m/s, to 0.2 %) over a turn at constant ``omega2`` (rad/s).

    >>> check_blade_peak_speed(0.075 * 6.472, Saw(), 6.472).ok
    False
    """
    r1, theta1, _, v_r, omega1 = analytic(np.linspace(0.0, 2 * np.pi, 20001), omega2, 0.0, saw=saw)[:, :5].T
    peak = np.abs(v_r * np.cos(theta1) - r1 * omega1 * np.sin(theta1)).max()
    return diagnose(answer, lambda value, candidate: close(value, candidate, rtol=2e-3), [
        (peak, "Correct."),
        (-peak, Feedback(True, "Correct in size; a speed is usually given positive.")),
        (saw.r2 * abs(omega2), "that is the crank pin's speed r2·ω2; the blade moves a little faster at its "
                               "peak."),
        (np.abs(v_r).max(), "that is the largest |V_r|, the rate of the length r1; the blade's speed is "
                            "ẋ = V_r cos θ1 − r1 ω1 sin θ1."),
    ], f"use ω2 = {omega2:.4g} rad/s and the slider speed V_r cos θ1 − r1 ω1 sin θ1 over a fine grid.")


@reads(number("θ4"))
def check_fivebar_theta4(answer, robot: FiveBar, x3: float, y3: float, sigma2: int) -> Feedback:
    """Lesson 09: the crank angle θ4 (rad) of leg 4 that puts the pen at (x3, y3) with σ2 = ``sigma2``.

    >>> check_fivebar_theta4(0.0, FiveBar(0.10, 0.15, 0.15, 0.10, 0.08), 0.0, 0.2, -1).ok
    False
    """
    this, that = (robot.inverse(x3, y3, modes=(1, s)) for s in (sigma2, -sigma2))
    return angle_verdict(answer, this.theta4, [
        (that.theta4, f"that is σ2 = {-sigma2:+d}: take the other sign of the square root."),
        (this.theta1, "that is θ1 of leg 1; the task asks for θ4 (coefficients a2, b2, c2)."),
    ], f"recompute a2, b2, c2 with l3, l4, l5 and X3 = {x3:g}, Y3 = {y3:g}, then θ4 = 2·atan(root).")


@reads(number("the height Y3"))
def check_reach_height(answer, robot: FiveBar, x3: float) -> Feedback:
    """Lesson 10: the height Y3 (m) at which the pen, moving up the line X = ``x3``, first stretches a leg.

    >>> check_reach_height(0.24, FiveBar(0.10, 0.15, 0.15, 0.10, 0.08), -0.03).ok
    True
    """
    reach = {"1": (robot.l1 + robot.l2, robot.l5 / 2), "4": (robot.l3 + robot.l4, -robot.l5 / 2)}
    heights = {leg: np.sqrt(length**2 - (x3 - motor) ** 2) for leg, (length, motor) in reach.items()}
    leg, other = sorted(heights, key=heights.get)
    return diagnose(answer, near, [
        (heights[leg], f"Correct: leg {leg} stretches first."),
        (heights[other], f"that is where leg {other} stretches; the other leg gets there first."),
        (1000 * heights[leg], "that looks like millimetres; give metres."),
    ], "a leg is stretched when the pen is (proximal + distal length) from its motor; the leg whose motor is "
       "farther from the line stretches first.")
