"""Checkers of exercise set 03 (the four-bar); lesson 03's Try it uses check_fourbar_theta4."""
# ruff: noqa: F403, F405

import numpy as np

from ..errors import InvalidArgumentError
from ..fourbar import BRANCHES, FourBar
from .engine import *  # the feedback engine's helpers (engine.__all__)
from .engine import allowing  # a call the task gives the student, let through the watch on their function

__all__ = ["check_fourbar_theta4", "check_omega4_expression", "check_fourbar_rates", "check_toggle_angle"]


def _assembles(linkage: FourBar, theta2: float, omega2: float = 0.0, alpha2: float = 0.0, **_) -> None:
    """The four-bar closes at ``theta2`` on both branches, with rates there (not at a toggle while moving)."""
    task_possible(lambda: [tuple(linkage.solve(theta2, omega2, alpha2, branch=b)) for b in BRANCHES],
                  f"the four-bar cannot be assembled at theta2={theta2:.6g}"
                  + (f", or its rates at omega2={omega2:.6g}, alpha2={alpha2:.6g} are undefined there (a "
                     "toggle)" if omega2 or alpha2 else ""))


def _has_toggle(linkage: FourBar, **_) -> None:
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
        (lambda expr: bool(numbered), f"your ω4 has no {numbered}: keep {numbered} as symbols (a length put "
                                      "in as its number, or another link's length in its place, both give "
                                      "this) — ω4 in l2, l3, l4, θ2, θ3, θ4, ω2."),
    ], "differentiate the two loop components, then solve the linear 2×2 system for ω3, ω4.")


def _rates_verdict(answer, linkage: FourBar, theta2: float, omega2: float, alpha2: float, branch: str
                   ) -> Feedback:
    """(ω4, α4) at one instant judged against ``branch``'s, with the known slips named."""
    other_branch = "crossed" if branch == "open" else "open"
    this, other = (linkage.solve(theta2, omega2, alpha2, branch=b) for b in (branch, other_branch))
    omega4, alpha4 = this.omega4, this.alpha4
    return diagnose(answer, FIGURES, [
        ((omega4, alpha4), "Correct (on the Jacobian route, one J solves both the velocity and the "
                           "acceleration equations)."),
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


def _function_or(read):
    """A parser: the student's function as it is (a procedure to call), else what ``read`` reads."""
    return lambda answer: answer if callable(answer) and not isinstance(answer, type) else read(answer)


#: Instants (θ2 rad, ω2 rad/s, α2 rad/s²) where a student's rates procedure is called besides the task's: the
#: crank spread over the turn, turning either way, speeding up, slowing down or at constant speed
FRESH_INSTANTS = tuple((float(np.radians(degrees)), omega2, alpha2) for degrees, omega2, alpha2 in (
    (75.0, 8.0, 30.0), (160.0, -12.0, 25.0), (250.0, 20.0, 0.0), (300.0, -5.0, -60.0), (345.0, 10.0, -15.0)))


def _jacobian_rates(linkage: FourBar, theta2: float, theta3: float, theta4: float, omega2: float,
                    alpha2: float) -> tuple[float, float]:
    """(ω4, α4) by J·(ω3, ω4) = b and J·(α3, α4) = b′ at the given θ3, θ4 (which need not close the loop:
    a slip that keeps the task's position)."""
    l2, l3, l4 = linkage.l2, linkage.l3, linkage.l4
    s2, c2, s3, c3, s4, c4 = (f(angle) for angle in (theta2, theta3, theta4) for f in (np.sin, np.cos))
    jacobian = np.array([[-l3 * s3, l4 * s4], [l3 * c3, -l4 * c4]])
    omega3, omega4 = np.linalg.solve(jacobian, [omega2 * l2 * s2, -omega2 * l2 * c2])
    b_prime = [alpha2 * l2 * s2 + omega2**2 * l2 * c2 + omega3**2 * l3 * c3 - omega4**2 * l4 * c4,
               -alpha2 * l2 * c2 + omega2**2 * l2 * s2 + omega3**2 * l3 * s3 - omega4**2 * l4 * s4]
    return float(omega4), float(np.linalg.solve(jacobian, b_prime)[1])


def _instant(theta2: float, omega2: float, alpha2: float) -> str:
    return f"{_where(theta2)}, ω2 = {omega2:g} rad/s, α2 = {alpha2:g} rad/s²"


def _rates_at(linkage: FourBar, theta2: float, omega2: float, alpha2: float, branch: str):
    """The solve of ``branch`` at one instant; None where it does not close or its rates are undefined."""
    try:
        motion = linkage.solve(theta2, omega2, alpha2, branch=branch)
    except Exception:
        return None
    return motion if np.all(np.isfinite(tuple(motion))) else None


@reads(_function_or(vector(2, "(ω4, α4)")), task={"linkage": FourBar, "theta2": "rad", "omega2": "rad/s",
                                                  "alpha2": "rad/s²", "branch": BRANCHES,
                                                  "method": (None, "Jacobian")}, possible=_assembles)
def check_fourbar_rates(answer, linkage: FourBar, theta2: float, omega2: float, alpha2: float, branch: str,
                        method: str | None = None) -> Feedback:
    """Exercise 03, task 3: (ω4, α4) of the rocker (rad/s, rad/s², to 4 significant figures) at ``theta2`` on
    ``branch`` — two numbers, or the student's function of (θ2, θ3, θ4, ω2, α2) that computes them, called
    here with the position of ``branch`` at the task's instant and at the instants :data:`FRESH_INSTANTS`
    where the linkage closes.  With ``method="Jacobian"`` (exercise 03) only such a function passes, and only
    one that calls none of course_lib's solves but ``linkage.loop_jacobian`` (J is given; ``linkage.solve``
    gives the rates without b and b′).

    >>> check_fourbar_rates((0.0, 0.0), FourBar(0.07, 0.20, 0.15, 0.25), 3.5, 15.0, -40.0, "open").ok
    False
    """
    if not callable(answer):
        verdict = _rates_verdict(answer, linkage, theta2, omega2, alpha2, branch)
        if verdict.ok and method is not None:
            return wrong("the numbers are right, but the task asks for the Jacobian solve itself: give your "
                         "function of (θ2, θ3, θ4, ω2, α2) that writes b and b′ and solves J·(ω3, ω4) = b "
                         "and J·(α3, α4) = b′ (the check calls it at other instants too). Numbers alone do "
                         "not show how they were found — linkage.solve(θ2, ω2, α2) gives them without J.")
        return verdict
    position = linkage.solve(theta2, branch=branch)
    theta3, theta4 = float(position.theta3), float(position.theta4)
    instants = [(theta2, omega2, alpha2)] + [
        (t2, w2, a2) for t2, w2, a2 in FRESH_INSTANTS
        if not angles_close(t2, theta2) and _rates_at(linkage, t2, w2, a2, branch) is not None]
    motions = [linkage.solve(t2, w2, a2, branch=branch) for t2, w2, a2 in instants]
    calls = [(t2, float(m.theta3), float(m.theta4), w2, a2) for (t2, w2, a2), m in zip(instants, motions,
                                                                                        strict=True)]
    name = getattr(answer, "__name__", "")
    called = (f"function {name}(theta2, theta3, theta4, omega2, alpha2)" if name.isidentifier()
              else "function")
    solves = allowing(solver_code(FourBar), lambda: linkage.loop_jacobian(theta3, theta4))
    values = procedure(answer, calls, solves, called, vector(2, "(ω4, α4)"),
                       given="(θ2, θ3, θ4, ω2, α2) as floats — the angles in rad, ω2 in rad/s, α2 in rad/s², "
                             "θ3 and θ4 of the solved position — one call per instant")
    if isinstance(values, Feedback):
        solving = "calls FourBar.solve" in values.message or "calls FourBar.motion" in values.message
        return Feedback(False, values.message + (" The position comes in as its arguments theta3, theta4: "
                                                 "the check solves it." if solving else ""))
    verdict = _rates_verdict(values[0], linkage, theta2, omega2, alpha2, branch)
    if not verdict.ok:
        return wrong(f"your {called} at the task's instant ({_instant(theta2, omega2, alpha2)}): "
                     + verdict.message.removeprefix("Not yet: "))
    for (t2, w2, a2), motion, value in zip(instants[1:], motions[1:], values[1:], strict=True):
        if FIGURES.agrees(value, (motion.omega4, motion.alpha4)):
            continue
        where = _instant(t2, w2, a2)
        if all(FIGURES.agrees(other, values[0]) for other in values[1:]):
            return wrong(f"your {called} returns the same (ω4, α4) at every instant: compute b, b′ and J "
                         "from its arguments, not from the task's numbers.")
        given_rates = _rates_at(linkage, t2, omega2, alpha2, branch)
        if given_rates is not None and FIGURES.agrees(value, (given_rates.omega4, given_rates.alpha4)):
            return wrong(f"at {where} your {called} gives the rates for the task's ω2 = {omega2:g} rad/s and "
                         f"α2 = {alpha2:g} rad/s²: use its arguments omega2 and alpha2.")
        if FIGURES.agrees(value, _jacobian_rates(linkage, t2, theta3, theta4, w2, a2)):  # J at the task's
            return wrong(f"at {where} your {called} uses θ3, θ4 of the task's position (or a J built from "
                         "them): build J and b′ from its arguments theta3 and theta4.")
        there = _rates_verdict(value, linkage, t2, w2, a2, branch)
        return wrong(f"your {called} is right at the task's instant but not at {where}: "
                     + there.message.removeprefix("Not yet: "))
    return right(f"Correct (to {FIGURES}): your {called} gives ω4 and α4 of the {branch} assembly at the "
                 f"task's instant and at {len(calls) - 1} other instants (on the Jacobian route, one J "
                 "solves both the velocity and the acceleration equations).")


def _toggle_verdict(answer, linkage: FourBar) -> Feedback:
    """(θ2_max, "extended" or "folded") of ``linkage`` judged, with the known slips named."""
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


#: Linkages (l1 ground, l2 crank, l3 coupler, l4 rocker; m) whose crank stops before π, where a student's
#: limit procedure is called besides the task's: three whose limit is beyond π/2, three with a folded (lower)
#: toggle too
FRESH_LINKAGES = ((0.30, 0.10, 0.12, 0.15), (0.10, 0.25, 0.12, 0.18), (0.25, 0.20, 0.30, 0.12),
                  (0.18, 0.16, 0.09, 0.14), (0.12, 0.20, 0.05, 0.22))


def _lengths(linkage: FourBar) -> tuple[float, float, float, float]:
    return float(linkage.l1), float(linkage.l2), float(linkage.l3), float(linkage.l4)


def _largest_toggle(l1: float, l2: float, l3: float, l4: float) -> float | None:
    """The largest toggle angle of the four-bar of these lengths, if it stops before π; else None."""
    try:
        toggles = FourBar(crank=l2, coupler=l3, rocker=l4, ground=l1).input_range().toggle_angles
    except Exception:
        return None
    return max(toggles) if toggles and max(toggles) < np.pi else None


def _reach(l1: float, l2: float, reach: float) -> float:
    """θ2 in [0, π] where |AO4| = ``reach`` by the law of cosines; NaN where |AO4| never equals it."""
    with np.errstate(invalid="ignore"):
        return float(np.arccos((l1**2 + l2**2 - reach**2) / (2 * l1 * l2)))


def _linkage(lengths) -> str:
    return "the linkage l1, l2, l3, l4 = " + ", ".join(f"{length:g}" for length in lengths) + " m"


#: The answer of exercise 03, task 4: the limit and how the links lie there
_TOGGLE_PAIR = fields('a pair (theta2_max, "extended" or "folded")', number("θ2_max"),
                      word(("extended", "folded"), 'the second entry is the string "extended" or "folded".'))


@reads(_function_or(_TOGGLE_PAIR), task={"linkage": FourBar, "method": (None, "law of cosines")},
       possible=_has_toggle)
def check_toggle_angle(answer, linkage: FourBar, method: str | None = None) -> Feedback:
    """Exercise 03, task 4: the largest crank angle (rad, to 4 decimals) of a non-Grashof ``linkage`` and
    whether coupler and rocker lie "extended" or "folded" there — that pair, or the student's function of the
    lengths (l1, l2, l3, l4) (m) that returns it, called here with the task's linkage and the linkages
    :data:`FRESH_LINKAGES`.  With ``method="law of cosines"`` (exercise 03) only such a function passes, and
    only one that calls none of course_lib's four-bar methods (``linkage.input_range()`` gives the limit
    without the triangle O2–A–O4).

    >>> check_toggle_angle((float(np.arccos(0.235)), "extended"), FourBar(0.15, 0.10, 0.12, 0.20)).ok
    True
    """
    if not callable(answer):
        verdict = _toggle_verdict(answer, linkage)
        if verdict.ok and method is not None:
            return wrong('the angle and the word are right, but the task asks for the law of cosines itself: '
                         "give your function of the lengths (l1, l2, l3, l4) that returns (θ2_max, "
                         '"extended" or "folded") from the triangle O2–A–O4 (the check calls it for other '
                         "linkages too). A pair alone does not show how it was found — linkage.input_range() "
                         "gives the limit without the triangle.")
        return verdict
    task = _lengths(linkage)
    linkages = [task] + [lengths for lengths in FRESH_LINKAGES if not np.allclose(lengths, task, rtol=1e-9)
                         and _largest_toggle(*lengths) is not None]
    name = getattr(answer, "__name__", "")
    called = f"function {name}(l1, l2, l3, l4)" if name.isidentifier() else "function"
    values = procedure(answer, linkages, solver_code(FourBar), called, _TOGGLE_PAIR,
                       given="the lengths (l1, l2, l3, l4) in m as floats — ground, crank, coupler, rocker — "
                             "one call per linkage")
    if isinstance(values, Feedback):
        return values
    for index, (lengths, (value, how)) in enumerate(zip(linkages, values, strict=True)):
        limit = _largest_toggle(*lengths)
        if DECIMALS.agrees(value, limit, angles=True) and how == "extended":
            continue
        which = "the task's linkage" if index == 0 else _linkage(lengths)
        if index and all(DECIMALS.agrees(other[0], values[0][0], angles=True) for other in values[1:]):
            return wrong(f"your {called} returns the same θ2_max for every linkage: compute it from its "
                         "arguments l1, l2, l3, l4, not from the task's numbers.")
        l1, l2, l3, l4 = lengths
        if DECIMALS.agrees(value, _reach(l1, l2, abs(l3 - l4)), angles=True):
            return wrong(f"for {which} your {called} gives the crank angle where |AO4| = |l3 − l4| (coupler "
                         "and rocker folded), the smallest one there: the largest is where |AO4| = l3 + l4.")
        in_order = _largest_toggle(l4, l1, l2, l3)  # the arguments read as FourBar's (crank, …, ground)
        if in_order is not None and DECIMALS.agrees(value, in_order, angles=True):
            return wrong(f"for {which} your {called} gives the limit of the linkage whose crank, coupler, "
                         "rocker and ground are l1, l2, l3, l4 (FourBar's order): it is called with l1 the "
                         "ground, l2 the crank, l3 the coupler and l4 the rocker.")
        there = _toggle_verdict((value, how), FourBar(crank=l2, coupler=l3, rocker=l4, ground=l1))
        return wrong((f"what your {called} returns for the task's linkage: " if index == 0 else
                      f"your {called} is right for the task's linkage but not for {which}: ")
                     + there.message.removeprefix("Not yet: "))
    return right(f"Correct (to {DECIMALS}, angles modulo 2π): your {called} gives the largest crank angle, "
                 f"and how coupler and rocker lie there, for the task's linkage and {len(linkages) - 1} "
                 "other linkages: coupler and rocker are collinear there (a toggle), det J = 0, and the "
                 "crank must turn back.")
