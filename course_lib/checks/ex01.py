"""Checkers of exercise set 01 (vector loops and mobility) and of lesson 00's Try it."""
# ruff: noqa: F403, F405

import numpy as np

from ..planar import cross_k, polar
from .engine import *  # the feedback engine's helpers (engine.__all__)

__all__ = ["check_mobility", "check_tilted_loop", "check_link_vector", "check_point_velocity",
           "check_redundant_parallelogram"]


@reads(fields("(L, J1, J2, M) as a tuple of four integers, or a dict", *map(integer, ("L", "J1", "J2", "M")),
              keys=("links", "full_joints", "half_joints", "mobility")))
def check_mobility(answer) -> Feedback:
    """Exercise 01, task 1: counts (L, J1, J2) and mobility M of the six-bar, as a tuple or a dict.

    >>> check_mobility((6, 6, 0, 3)).ok
    False
    """
    L, J1, J2, M = answer
    return first([
        (L == 5, "count the ground (the frame, bancada) as one of the links."),
        (L != 6, "recount the links: every rigid body, the ground included, counts once."),
        (J2 != 0, "every joint here is a pin (one relative freedom): a full joint, not a half joint."),
        (J1 == 6, "at B three links meet (coupler, rocker and link 5): a pin joining three links counts as "
                  "two full joints."),
        (J1 != 7, "recount the pins; where k links share one pin it counts as k − 1 joints."),
        (M != 3 * (L - 1) - 2 * J1 - J2, "the counts are right, but M does not follow from them: "
                                         "M = 3(L − 1) − 2·J1 − J2."),
    ], "Correct: one input (the crank) drives the whole six-bar.")


@reads()
def check_tilted_loop(answer) -> Feedback:
    """Exercise 01, task 2: the x and y components of R2 + R3 − R4 − R1 = 0, ground tilted by θ1 (sympy).

    >>> import sympy as sp
    >>> l1, l2, l3, l4, t1, t2, t3, t4 = sp.symbols("l1:5 theta1:5")
    >>> check_tilted_loop([l2 * sp.sin(t2) + l3 * sp.sin(t3) - l4 * sp.sin(t4) - l1 * sp.sin(t1),
    ...                    l2 * sp.cos(t2) + l3 * sp.cos(t3) - l4 * sp.cos(t4) - l1 * sp.cos(t1)]).ok
    True
    """
    import sympy as sp
    l1, l2, l3, l4, t1, t2, t3, t4 = symbols = sp.symbols("l1:5 theta1:5", real=True)

    def loop(signs=(1, 1, -1, -1), t1=t1):  # R2 + R3 − R4 − R1, each vector with its sign
        terms = list(zip(signs, (l2, l3, l4, l1), (t2, t3, t4, t1), strict=True))
        return tuple(sum(sign * length * f(angle) for sign, length, angle in terms) for f in (sp.cos, sp.sin))

    names = ("R2 (the crank, O2 → A)", "R3 (the coupler, A → B)", "R4 (the rocker, O4 → B)",
             "R1 (the ground, O2 → O4)")
    flipped = [(loop(tuple(-s if j == k else s for j, s in enumerate((1, 1, -1, -1)))),
                f"a sign slip on {name}: the loop holds with that vector pointing the other way. Walking "
                "O2 → A → B adds R2 and R3; walking O2 → O4 → B adds R1 and R4, so R1 and R4 carry the minus "
                "sign, in both components.") for k, name in enumerate(names)]
    return judge_expression(answer, symbols, [
        (loop(), "Correct: two scalar equations, one per component."),
        (loop(t1=0), "that is the loop with a horizontal ground; here R1 = l1(cos θ1, sin θ1) is tilted."),
        *flipped,
    ], "compare each term with the walk O2 → A → B versus O2 → O4 → B (signs, lengths, angles).",
        system="the two components as a list [x_component, y_component] (or a 2×1 Matrix)")


@reads(vector(2, "the vector (x, y)"), task={"length": "positive m", "angle_degrees": "degrees"})
def check_link_vector(answer, length: float, angle_degrees: float) -> Feedback:
    """Lesson 00, Try it: the vector (x, y) in metres, to 4 significant figures, of a link of ``length`` (m)
    at ``angle_degrees``.

    >>> check_link_vector((0.0, 0.06), 0.06, 90.0).ok
    True
    """
    reference = polar(length, np.radians(angle_degrees))
    return diagnose(answer, FIGURES.of_size(reference), [
        (reference, "Correct: R = l (cos θ, sin θ)."),
        (reference[::-1], "x and y are swapped: x goes with cos θ, y with sin θ."),
        ([1000 * reference, 100 * reference], "the length is in metres, not mm or cm."),
        (polar(length, angle_degrees), "the angle went into cos/sin in degrees; numpy's trigonometric "
                                       "functions take radians."),
    ], "R = l (cos θ î + sin θ ĵ): evaluate cos θ and sin θ for the given angle.")


@reads(vector((1, 2), "the velocity (vx, vy)"), task={"length": "positive m", "angle_degrees": "degrees",
                                                     "speed": "positive rad/s", "clockwise": bool})
def check_point_velocity(answer, length: float, angle_degrees: float, speed: float, clockwise: bool
                         ) -> Feedback:
    """Exercise 01, task 3: velocity (vx, vy) in m/s, to 4 significant figures, of a link's tip turning at
    ``speed`` (rad/s, > 0).

    >>> check_point_velocity([-0.6, 0.0], 0.1, 90.0, 6.0, clockwise=False).ok
    True
    """
    omega = -abs(speed) if clockwise else abs(speed)
    tip = polar(length, np.radians(angle_degrees))
    reference = omega * cross_k(tip)
    matches = FIGURES.of_size(reference)
    return diagnose(answer, matches, [
        (reference, "Correct: the tip moves perpendicular to the link with speed l·|ω|."),
        (lambda values: values.size == 1 and FIGURES.agrees(abs(values[0]), abs(omega) * length),
         "l·|ω| is only the speed; the velocity is a vector (vx, vy) = ω k̂ × R."),
        (lambda values: values.size == 1, "give the velocity as a vector (vx, vy) in m/s."),
        (1000 * reference, "that looks like mm/s: the length is in metres, so the velocity is in m/s."),
        (omega * cross_k(polar(length, angle_degrees)), "the angle went into sin/cos in degrees; numpy's "
                                                        "trigonometric functions take radians."),
        (-reference, "a sign error: clockwise rotation means ω < 0, and k̂ × R turns R by +90° "
                     "(counter-clockwise)."),
        (reference[::-1], "the components are swapped: give (vx, vy)."),
        (lambda values: matches.agrees(np.abs(values), np.abs(omega * tip)),
         "that vector is along the link; the velocity is perpendicular to it (k̂ × R)."),
    ], "use v = ω k̂ × R with R = l(cos θ, sin θ): k̂ × (x, y) = (−y, x).")


def check_redundant_parallelogram(answer) -> Feedback:
    """Exercise 01, task 4: why the parallelogram with a mid-height bar moves although M = 0.

    >>> check_redundant_parallelogram("b").ok
    True
    """
    return choice(answer, "b", {
        "a": "the ground is counted once: L = 5 is the ground, the two cranks, the coupler and CD. And a "
             "link fewer would not give 1 either: 3·(4 − 1) − 2·6 = −3. No recount of the links gives the "
             "one freedom the linkage shows.",
        "c": "the course's pins are ideal, with no clearance (Gruebler's count assumes so too), and the "
             "motion here is a full turn of the cranks, not a rattle.",
        "d": "a pin allows one relative motion, a rotation: a full joint. A half joint allows two (roll and "
             "slide); counted so, C and D give M = 3·4 − 2·4 − 2 = 2, two freedoms — but one crank angle "
             "sets this whole linkage.",
    }, "Correct: with CD equal and parallel to O2O4, the two pins at C and D repeat constraints the "
       "parallelogram already imposes. Gruebler assumes independent equations, so it undercounts.")
