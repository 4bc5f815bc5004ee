"""Checkers of exercise set 04 (the power saw)."""
# ruff: noqa: F403, F405

import numpy as np

from ..saw import COURSE_SAW, Saw, analytic
from .engine import *  # the feedback engine's helpers (engine.__all__)

__all__ = ["check_saw_omega3_expression", "check_saw_position", "check_saw_slider_acceleration",
           "check_saw_linear_stage"]


@reads()
def check_saw_omega3_expression(answer) -> Feedback:
    """Exercise 04, task 1: ω3 of the saw as a sympy expression in r2, r3, θ2, θ3, ω2.

    >>> import sympy as sp
    >>> r2, r3, t2, t3, w2 = sp.symbols("r2 r3 theta2 theta3 omega2")
    >>> check_saw_omega3_expression(-w2 * r2 * sp.cos(t2) / (r3 * sp.cos(t3))).ok
    True
    """
    import sympy as sp
    _, r2, r3, _, t2, t3, w2 = symbols = sp.symbols("r1y r2 r3 theta1 theta2 theta3 omega2", real=True)
    reference = -w2 * r2 * sp.cos(t2) / (r3 * sp.cos(t3))
    swapped = -w2 * r2 * sp.sin(t2) / (r3 * sp.sin(t3))
    return judge_expression(answer, symbols, [
        (reference, "Correct: ω3 = −ω2·r2·cos θ2 / (r3·cos θ3), from the derivative of Fy − Fc."),
        (-reference, "a sign error: differentiate r2 sin θ2 + r3 sin θ3 = r1y (constant) and solve for ω3."),
        ([swapped, -swapped], "sin and cos are swapped: d(sin θ)/dt = ω cos θ."),
        (lambda expr: not expr.has(w2), "ω3 must be proportional to ω2 (the report's eq. 23 is labelled ω3 "
                                        "but repeats θ1's formula — don't copy that slip)."),
    ], "use the y-equation without r1: r2 sin θ2 + r3 sin θ3 = r1y, differentiate in time.")


def _closes(saw: Saw, theta2: float, omega2: float = 0.0, alpha2: float = 0.0) -> None:
    """The saw closes at ``theta2`` (the rod reaches the slider line, not perpendicular to it)."""
    task_possible(lambda: analytic(theta2, omega2, alpha2, saw=saw),
                  f"the saw cannot close at theta2={theta2:.6g} (the rod r3 cannot reach the slider line "
                  "there, or stands perpendicular to it)")


@reads(vector(3, "(r1, θ1, θ3)"), task={"saw": Saw, "theta2": "rad"}, possible=_closes)
def check_saw_position(answer, saw: Saw, theta2: float) -> Feedback:
    """Exercise 04, task 2: (r1 in m, θ1, θ3 in rad), to 4 decimals, at crank angle ``theta2``; the same
    vector r1 written as (−r1, θ1 + π) passes too.

    >>> check_saw_position(analytic(0.9, saw=Saw())[:3], Saw(), 0.9).ok
    True
    """
    r1, theta1, theta3 = analytic(theta2, saw=saw)[:3]
    mirror = np.pi - theta3
    degrees = ((1, theta1), (2, theta3), (1, theta1 + np.pi))
    return diagnose(answer, DECIMALS, [
        ((r1, theta1, theta3), "Correct: r1 < 0 with θ1 in (−π/2, π/2], as the course writes it."),
        ((-r1, theta1 + np.pi, theta3),
         Feedback(True, "Correct — the same vector r1, written with r1 > 0 and θ1 + π. The course keeps "
                        "θ1 in (−π/2, π/2], which makes r1 negative here.")),
        (lambda v: saw != COURSE_SAW and DECIMALS.agrees(v, analytic(theta2, saw=COURSE_SAW)[:3],
                                                         angles=(False, True, True)),
         "that is the course's saw, not this one: pass saw=my_saw to the solver."),
        (lambda v: DECIMALS.agrees(abs(v[0]) / 1000.0, abs(r1)), "r1 looks like millimetres; give lengths in "
                                                                 "metres."),
        (lambda v: DECIMALS.agrees(v[2], mirror, angles=True) or in_degrees(v[2], mirror, DECIMALS),
         "θ3 is on the other branch: asin gives the rod pointing right, but the saw's rod points left, "
         "θ3 = π − asin((r1y − r2 sin θ2)/r3)."),
        (lambda v: any(in_degrees(v[i], angle, DECIMALS) for i, angle in degrees),
         "an angle is in degrees; give θ1 and θ3 in radians."),
        (lambda v: not DECIMALS.agrees(v[2], theta3, angles=True), "θ3 is off: Fy − Fc gives r2 sin θ2 + "
                                                                   "r3 sin θ3 = r1y."),
    ], "θ3 is right; recheck r1 and θ1 from r1 sin θ1 = r1y and r1 cos θ1 = r2 cos θ2 + r3 cos θ3.",
        angles=(False, True, True))


@reads(number("a_r"), task={"saw": Saw, "theta2": "rad", "omega2": "rad/s", "alpha2": "rad/s²"},
       possible=_closes)
def check_saw_slider_acceleration(answer, saw: Saw, theta2: float, omega2: float, alpha2: float) -> Feedback:
    """Exercise 04, task 3: a_r (m/s², to 4 significant figures), the second derivative of the signed length
    r1 (not the slider's own acceleration ẍ), at the given motor state.

    >>> check_saw_slider_acceleration(analytic(0.9, 6.0, 4.0, saw=Saw())[6], Saw(), 0.9, 6.0, 4.0).ok
    True
    """
    x = analytic(theta2, omega2, alpha2, saw=saw)
    r1, theta1, _, v_r, omega1, _, a_r, alpha1, _ = x
    slider = (a_r * np.cos(theta1) - 2 * v_r * omega1 * np.sin(theta1)
              - r1 * (alpha1 * np.sin(theta1) + omega1**2 * np.cos(theta1)))  # ẍ of x = r1 cos θ1
    return diagnose(answer, FIGURES, [
        (x[6], "Correct: a_r holds the α2 terms and every ω² term (r1 ω1², r2 ω2², r3 ω3²)."),
        ([x[6] / 1000.0, x[6] * 1000.0], "a factor 1000: lengths in metres give a_r in m/s²."),
        (-x[6], "a sign error: a_r is along r1, and r1 < 0 here (the course's convention)."),
        (analytic(theta2, 0.0, alpha2, saw=saw)[6],
         "that keeps only the α2 terms: the ω² (centripetal) terms — r1 ω1², r2 ω2², r3 ω3² — are missing, "
         "and at speed they dominate."),
        (x[3], "that is the velocity v_r; the task asks for the acceleration a_r."),
        (lambda v: saw != COURSE_SAW
         and FIGURES.agrees(v, analytic(theta2, omega2, alpha2, saw=COURSE_SAW)[6]),
         "that is the course's saw, not this one: pass saw=my_saw to the solver."),
        (slider, "that is ẍ, the slider's own acceleration along its line; the task asks for a_r = d²r1/dt², "
                 "the rate of the signed length r1 (the slider moves along x while r1 also turns)."),
    ], "differentiate the position equations twice (or use the velocity solution) and solve for a_r.")


def check_saw_linear_stage(answer) -> Feedback:
    """Exercise 04, task 4: why the velocity stage always takes two Newton iterations.

    >>> check_saw_linear_stage("a").ok
    True
    """
    return choice(answer, "a", {
        "b": "the seed can be anything — the task changed it and the count stayed two; the first step lands "
             "exactly on the solution from any seed.",
        "c": "the velocity Jacobian is the position Jacobian (it depends on r1, θ1, θ3), not I.",
        "d": "the tolerance is the same 1e-6 for every stage.",
    }, "Correct: the velocity equations are linear in (v_r, ω1, ω3), so the first Newton step is exact; the "
       "second step is ~0 and only confirms the stopping rule.")
