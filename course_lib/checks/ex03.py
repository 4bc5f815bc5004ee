"""Checkers of exercise set 03 (the four-bar); lesson 03's Try it uses check_fourbar_theta4."""
# ruff: noqa: F403, F405

import numpy as np

from ..errors import InvalidArgumentError
from ..fourbar import BRANCHES, FourBar
from .engine import *  # the feedback engine's helpers (engine.__all__)

__all__ = ["check_fourbar_theta4", "check_omega4_expression", "check_fourbar_rates", "check_toggle_angle"]


def _assembles(linkage: FourBar, theta2: float, omega2: float = 0.0, alpha2: float = 0.0, **_) -> None:
    """The four-bar closes at ``theta2`` on both branches, with rates there (not at a toggle while moving)."""
    task_possible(lambda: [tuple(linkage.solve(theta2, omega2, alpha2, branch=b)) for b in BRANCHES],
                  f"the four-bar cannot be assembled at theta2={theta2:.6g}"
                  + (f", or its rates at omega2={omega2:.6g}, alpha2={alpha2:.6g} are undefined there (a "
                     "toggle)" if omega2 or alpha2 else ""))


def _has_toggle(linkage: FourBar) -> None:
    """The crank of ``linkage`` stops at a toggle angle (the task asks for the largest one)."""
    if not linkage.input_range().toggle_angles:
        raise InvalidArgumentError(f"linkage must be a four-bar whose crank stops at a toggle angle (a "
                                   f"non-Grashof one); got {linkage!r}, whose crank has none: no reference "
                                   "answer exists for this task")


#: Crank angles (rad) where a student's θ4 procedure is called besides the task's own: spread over the turn
FRESH_THETA2 = np.radians([10.0, 75.0, 160.0, 200.0, 250.0, 300.0, 345.0])


def _number_or_function(what: str):
    """A parser: the student's function as it is (a procedure to call), else one finite number."""
    read = number(what)
    return lambda answer: answer if callable(answer) and not isinstance(answer, type) else read(answer)


def _theta4(linkage: FourBar, theta2: float, branch: str) -> float | None:
    """θ4 of ``linkage`` at ``theta2`` on ``branch``; None where it does not close."""
    try:
        return float(linkage.solve(theta2, branch=branch).theta4)
    except Exception:
        return None


def _half_angle_roots(linkage: FourBar, cos_angle: float, sin_angle: float) -> list[float]:
    """Both roots θ4 = 2·atan((−b ± √(b² − 4ac))/2a) of the task's quadratic with cos θ2 taken at
    ``cos_angle`` (in a and c) and sin θ2 at ``sin_angle`` (in b): a slip that puts degrees in some of them;
    the finite ones."""
    l1, l2, l3, l4 = linkage.l1, linkage.l2, linkage.l3, linkage.l4
    K1, K2, K3 = l1 / l2, l1 / l4, (l2**2 - l3**2 + l4**2 + l1**2) / (2 * l2 * l4)
    cosine = np.cos(cos_angle)
    a, b, c = cosine - K1 - K2 * cosine + K3, -2 * np.sin(sin_angle), K1 - (K2 + 1) * cosine + K3
    with np.errstate(all="ignore"):
        roots = [2 * np.arctan((-b + sign * np.sqrt(b**2 - 4 * a * c)) / (2 * a)) for sign in (1, -1)]
    return [float(root) for root in roots if np.isfinite(root)]


def _theta4_verdict(answer: float, linkage: FourBar, theta2: float, branch: str, function: bool = False
                    ) -> Feedback:
    """θ4 (rad) at ``theta2`` judged against ``branch``'s, with the known slips named; ``function``: the
    value is what the student's function returned (one slip more: θ2 converted with np.radians inside)."""
    other = "crossed" if branch == "open" else "open"
    this, that = linkage.solve(theta2, branch=branch), linkage.solve(theta2, branch=other)
    degrees = np.degrees(theta2)
    slips = [(_half_angle_roots(linkage, degrees, degrees),
              f"θ2 went into cos θ2 and sin θ2 of a, b, c in degrees (cos {degrees:.6g} instead of cos "
              f"{theta2:.6g}): numpy's cos and sin take radians, np.radians converts."),
             (_half_angle_roots(linkage, theta2, degrees),
              f"θ2 went into sin θ2 of b in degrees (sin {degrees:.6g} instead of sin {theta2:.6g}), while a "
              "and c take cos θ2 in radians: convert it once, with np.radians, and use it everywhere."),
             (_half_angle_roots(linkage, degrees, theta2),
              f"θ2 went into cos θ2 of a and c in degrees (cos {degrees:.6g} instead of cos {theta2:.6g}), "
              "while b takes sin θ2 in radians: convert it once, with np.radians, and use it everywhere.")]
    if function:
        slips.append((_half_angle_roots(linkage, np.radians(theta2), np.radians(theta2)),
                      "your function converts θ2 with np.radians, but it is called with θ2 in radians "
                      "already (as course_lib's functions are): use theta2 as it comes."))
    return angle_verdict(answer, this.theta4, [
        (that.theta4, f"that is θ4 of the {other} assembly; the task asks for the {branch} one (the other "
                      "root of the half-angle quadratic)."),
        (this.theta3, "that is the coupler angle θ3; the task asks for the rocker angle θ4."),
        (that.theta3, f"that is θ3 of the {other} assembly; the task asks for the rocker angle θ4 of "
                      f"the {branch} assembly."),
        *((roots, hint) for roots, hint in slips if roots),
    ], "recheck the half-angle coefficients (a, b, c) and which root (±√) you took.")


def _where(theta2: float) -> str:
    return f"θ2 = {theta2:.6g} rad ({np.degrees(theta2) % 360:.6g}°)"


@reads(_number_or_function("θ4"), task={"linkage": FourBar, "theta2": "rad", "branch": BRANCHES,
                                        "method": (None, "half-angle")}, possible=_assembles)
def check_fourbar_theta4(answer, linkage: FourBar, theta2: float, branch: str, method: str | None = None
                         ) -> Feedback:
    """Exercise 03, task 1 and lesson 03's Try it: the rocker angle θ4 (rad, to 4 decimals) at crank angle
    ``theta2`` on ``branch`` — a number, or the student's function of θ2 (rad) that computes it, called here
    at ``theta2`` and at the crank angles :data:`FRESH_THETA2` where the linkage closes.  With
    ``method="half-angle"`` (exercise 03) only such a function passes, and only one that calls none of
    course_lib's solves (``linkage.solve`` gives the number without the quadratic).

    >>> bar = FourBar(0.07, 0.20, 0.15, 0.25)
    >>> check_fourbar_theta4(bar.solve(2.0, branch="crossed").theta4 + 2 * np.pi, bar, 2.0, "crossed").ok
    True
    >>> check_fourbar_theta4(lambda t: bar.solve(t, branch="crossed").theta4, bar, 2.0, "crossed").ok
    False
    """
    if not callable(answer):
        verdict = _theta4_verdict(answer, linkage, theta2, branch)
        if verdict.ok and method is not None:
            return wrong("the number is right, but the task asks for the half-angle quadratic itself: give "
                         "your function of θ2 that computes θ4 from a, b, c (the check calls it at other "
                         "crank angles too). A number alone does not show how it was found — linkage.solve "
                         "gives it without the quadratic.")
        return verdict
    probes = [theta2] + [angle for angle in FRESH_THETA2 if not angles_close(angle, theta2)
                         and all(_theta4(linkage, angle, b) is not None for b in BRANCHES)]
    name = getattr(answer, "__name__", "")
    called = f"function {name}(theta2)" if name.isidentifier() else "function"
    values = procedure(answer, [(angle,) for angle in probes], solver_code(FourBar), called, number("θ4"))
    if isinstance(values, Feedback):
        return values
    verdict = _theta4_verdict(values[0], linkage, theta2, branch, function=True)
    if not verdict.ok:
        return wrong(f"your {called} at the task's {_where(theta2)}: "
                     + verdict.message.removeprefix("Not yet: "))
    for angle, value in zip(probes[1:], values[1:], strict=True):
        if not DECIMALS.agrees(value, _theta4(linkage, angle, branch), angles=True):
            if all(DECIMALS.agrees(other, values[0], angles=True) for other in values[1:]):
                return wrong(f"your {called} returns the same θ4 at every crank angle: compute a, b, c "
                             "and the root from its argument theta2, not from the task's "
                             f"{np.degrees(theta2):.6g}°.")
            there = _theta4_verdict(value, linkage, angle, branch, function=True)
            return wrong(f"your {called} is right at the task's θ2 but not at {_where(angle)}: "
                         + there.message.removeprefix("Not yet: "))
    return right(f"Correct (to {DECIMALS}, angles modulo 2π): your {called} gives θ4 of the {branch} "
                 f"assembly at the task's θ2 and at {len(probes) - 1} other crank angles.")


@reads()
def check_omega4_expression(answer) -> Feedback:
    """Exercise 03, task 2: ω4 as a sympy expression in l2, l3, l4, θ2, θ3, θ4, ω2.

    >>> import sympy as sp
    >>> l2, l4, t2, t3, t4, w2 = sp.symbols("l2 l4 theta2 theta3 theta4 omega2")
    >>> check_omega4_expression(w2 * l2 * sp.sin(t2 - t3) / (l4 * sp.sin(t4 - t3))).ok
    True
    """
    import sympy as sp
    l2, l3, l4, t2, t3, t4, w2 = symbols = sp.symbols("l2 l3 l4 theta2 theta3 theta4 omega2", real=True)
    omega4 = w2 * l2 * sp.sin(t2 - t3) / (l4 * sp.sin(t4 - t3))
    omega3 = w2 * l2 * sp.sin(t4 - t2) / (l3 * sp.sin(t3 - t4))
    read = plain(answer, [symbol.name for symbol in symbols])
    held = set() if isinstance(read, Feedback) else {symbol.name for symbol in read.free_symbols}
    numbered = " and ".join(name for name in ("l2", "l4") if name not in held)  # a length given as its number
    return judge_expression(answer, symbols, [
        (omega4, "Correct: ω4 = ω2·l2·sin(θ2 − θ3) / (l4·sin(θ4 − θ3)) in some equivalent form."),
        (-omega4, "a sign error: recheck the signs of the velocity equations (the minus on R4)."),
        ([omega3, -omega3], "that is ω3, the coupler's angular velocity; the task asks for the rocker's ω4."),
        (omega4 / w2, "the factor ω2 is missing: the velocity equations are proportional to the input "
                      "speed."),
        (lambda expr: bool(numbered), f"your ω4 has no {numbered}: keep {numbered} (and the other lengths) "
                                      "as symbols — the task asks for ω4 in l2, l3, l4, θ2, θ3, θ4, ω2, "
                                      "not at the linkage's numbers."),
    ], "differentiate the two loop components, then solve the linear 2×2 system for ω3, ω4.")


@reads(vector(2, "(ω4, α4)"), task={"linkage": FourBar, "theta2": "rad", "omega2": "rad/s",
                                   "alpha2": "rad/s²", "branch": BRANCHES}, possible=_assembles)
def check_fourbar_rates(answer, linkage: FourBar, theta2: float, omega2: float, alpha2: float, branch: str
                        ) -> Feedback:
    """Exercise 03, task 3: (ω4, α4) of the rocker (rad/s, rad/s², to 4 significant figures) at ``theta2`` on
    ``branch``.

    >>> check_fourbar_rates((0.0, 0.0), FourBar(0.07, 0.20, 0.15, 0.25), 3.5, 15.0, -40.0, "open").ok
    False
    """
    other_branch = "crossed" if branch == "open" else "open"
    this, other = (linkage.solve(theta2, omega2, alpha2, branch=b) for b in (branch, other_branch))
    omega4, alpha4 = this.omega4, this.alpha4
    return diagnose(answer, FIGURES, [
        ((omega4, alpha4), "Correct: the same Jacobian J solves both the velocity and the acceleration "
                           "equations."),
        ((alpha4, omega4), "the two are swapped: give (ω4, α4)."),
        ((other.omega4, other.alpha4), f"those are the rates of the {other_branch} assembly; the task is "
                                       f"on the {branch} assembly."),
        ((omega4, linkage.solve(theta2, 0.0, alpha2, branch=branch).alpha4),
         "ω4 is right, but α4 misses the ω² (centripetal) terms: A_k = α_k k̂ × R_k − ω_k² R_k for every "
         "link, including ω2², ω3² and ω4²."),
        ((omega4, linkage.solve(theta2, omega2, 0.0, branch=branch).alpha4),
         f"ω4 is right, but α4 is that of a crank turning at constant speed (α2 = 0): α2 = {alpha2:g} rad/s² "
         "is given" + (" (the crank is slowing down)" if alpha2 * omega2 < 0 else "")
         + ", so keep its α2 k̂ × R2 terms."),
        ((omega4, -alpha4), "ω4 is right, but α4 has the wrong sign."),
        ((omega4, linkage.solve(theta2, omega2, -alpha2, branch=branch).alpha4),
         "ω4 is right, but α4 is that of a crank whose α2 has the opposite sign: check the sign of the "
         "α2 k̂ × R2 terms when you move them to the right-hand side."),
        ((omega4, None), "ω4 is right; α4 is off — differentiate the velocity equations once more (with the "
                         "ω² terms)."),
        ((-omega4, None), "ω4 has the wrong sign: check the signs in the velocity equations (−ω4 l4 …)."),
        ((this.omega3, None), "that ω is the coupler's ω3; the rocker's is ω4."),
    ], "ω4 is off: solve J·(ω3, ω4) = −ω2·∂F/∂θ2 at the solved position.")


@reads(fields('a pair (theta2_max, "extended" or "folded")', number("θ2_max"),
              word(("extended", "folded"), 'the second entry is the string "extended" or "folded".')),
       task={"linkage": FourBar}, possible=_has_toggle)
def check_toggle_angle(answer, linkage: FourBar) -> Feedback:
    """Exercise 03, task 4: the largest crank angle (rad, to 4 decimals) of a non-Grashof ``linkage`` and
    whether coupler and rocker lie "extended" or "folded" there.

    >>> check_toggle_angle((float(np.arccos(0.235)), "extended"), FourBar(0.15, 0.10, 0.12, 0.20)).ok
    True
    """
    value, how = answer
    limit = max(linkage.input_range().toggle_angles)
    state = "extended" if limit < np.pi else "folded"  # |AO4| = l3 + l4 below π
    angle = diagnose(value, DECIMALS, [
        (limit, ""),
        (lambda v: in_degrees(v, limit, DECIMALS), "that is the limit in degrees; give it in radians."),
        (-limit, "that is the mirror-image limit (θ2 < 0); the task asks for the largest θ2."),
    ], "at the limit |AO4| = l3 + l4 or |l3 − l4|; use the law of cosines "
       "|AO4|² = l1² + l2² − 2 l1 l2 cos θ2.", angles=True)
    return angle if not angle.ok else first([
        (how != state, "the angle is right, but not how the links lie there: draw the linkage at that "
                       "angle (draw(linkage, linkage.solve(θ2))) — which of l3 + l4 and |l3 − l4| does |AO4| "
                       "equal?"),
    ], "Correct: coupler and rocker are collinear there (a toggle), det J = 0, and the crank must turn back.")
