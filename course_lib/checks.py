"""Checkers for the exercise notebooks and the lessons' "Try it" cells: take a student's answer,
return friendly feedback.

Each checker returns a :class:`Feedback` (``ok`` and a ``message``).  The message names
what looks wrong — a wrong branch or working mode, degrees instead of radians, a sign
error, missing ω² terms, millimetres instead of metres — and never prints the reference
value.  Equivalent answers are accepted: angles modulo 2π, algebraically equal sympy
expressions, an equation multiplied by a constant, either order where order does not
matter.  SI units (m, s) and radians throughout; nothing is printed.

>>> check_mobility({"links": 6, "full_joints": 7, "half_joints": 0, "mobility": 1}).ok
True
>>> print(check_mobility((5, 7, 0, -2)))
✘ Not yet: count the ground (the frame, bancada) as one of the links.
"""

from __future__ import annotations

import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import sympy as sp

from .fivebar import FiveBar
from .fourbar import FourBar
from .newton import newton
from .planar import wrap_angle
from .profile import first_turn_time, motor_profile
from .saw import Saw, analytic
from .symbolic import TIME, static

__all__ = [
    "Feedback",
    "check_mobility",
    "check_tilted_loop",
    "check_link_vector",
    "check_point_velocity",
    "check_redundant_parallelogram",
    "check_newton_update",
    "check_newton_iterations",
    "check_newton_cycle",
    "check_fourbar_newton_step",
    "check_seed_branch",
    "check_fourbar_theta4",
    "check_omega4_expression",
    "check_fourbar_rates",
    "check_toggle_angle",
    "check_saw_omega3_expression",
    "check_saw_position",
    "check_saw_slider_acceleration",
    "check_saw_linear_stage",
    "check_fivebar_forward",
    "check_fivebar_inverse",
    "check_fivebar_g",
    "check_fivebar_singularity",
    "check_crank_angle_for_rocker",
    "check_rocker_pin_speed",
    "check_motor_start",
    "check_saw_rates",
    "check_blade_peak_speed",
    "check_fivebar_theta4",
    "check_reach_height",
]

#: Absolute tolerance on angles (rad) and relative tolerance on other numbers.
ANGLE_TOL = 1e-6
RELATIVE_TOL = 1e-6


@dataclass(frozen=True)
class Feedback:
    """The verdict on one answer: ``ok`` and a message for the student.

    It prints (and displays in a notebook) as one line starting with ✔ or ✘;
    ``bool(feedback)`` is ``ok``.

    >>> Feedback(True, "Correct.")
    ✔ Correct.
    """

    ok: bool
    message: str

    def __str__(self) -> str:
        return ("✔ " if self.ok else "✘ ") + self.message

    def __repr__(self) -> str:
        return str(self)

    def __bool__(self) -> bool:
        return self.ok


# ---------------------------------------------------------------- shared helpers


def _right(message: str = "Correct.") -> Feedback:
    return Feedback(True, message)


def _wrong(message: str) -> Feedback:
    return Feedback(False, "Not yet: " + message)


def _unanswered(answer: Any) -> Feedback | None:
    blanks = isinstance(answer, tuple | list) and len(answer) > 0 and all(a is None for a in answer)
    if answer is None or answer is Ellipsis or blanks:
        return Feedback(False, "No answer yet: build your answer in the cell above, then run this check.")
    return None


def _as_vector(answer: Any, size: int, what: str) -> np.ndarray | Feedback:
    """The answer as a float array of ``size`` entries, or the feedback explaining why not
    (no answer yet, not numbers, wrong count, NaN)."""
    missing = _unanswered(answer)
    if missing is not None:
        return missing
    expected = "one plain number (a float)" if size == 1 else f"{size} plain numbers (floats)"
    if isinstance(answer, Mapping):
        return Feedback(False, f"Not yet: give {what} as {expected}, not a dict.")
    try:
        values = np.asarray(answer, dtype=float).ravel()
    except (TypeError, ValueError):
        return Feedback(False, f"Not yet: {what} should be {expected}; got {type(answer).__name__}.")
    if values.size != size:
        counted = "a single number" if values.size == 1 else f"{values.size} numbers"
        return Feedback(False, f"Not yet: {what} should be {expected}; got {counted}.")
    if not np.all(np.isfinite(values)):
        return Feedback(False, f"Not yet: {what} contains NaN or infinity.")
    return values


def _as_number(answer: Any, what: str) -> float | Feedback:
    if isinstance(answer, bool) or isinstance(answer, str):
        return Feedback(False, f"Not yet: {what} should be a number; got {answer!r}.")
    values = _as_vector(answer, 1, what)
    if isinstance(values, Feedback):
        return values
    return float(values[0])


def _close(value, reference, rtol: float = RELATIVE_TOL, atol: float = 1e-12) -> bool:
    value, reference = np.asarray(value, float), np.asarray(reference, float)
    return bool(np.all(np.abs(value - reference) <= atol + rtol * np.abs(reference)))


def _angles_close(value, reference, tol: float = ANGLE_TOL) -> bool:
    difference = wrap_angle(np.asarray(value, float) - np.asarray(reference, float))
    return bool(np.all(np.abs(difference) <= tol))


def _in_degrees(value, reference) -> bool:
    """True when ``value`` is ``reference`` written in degrees (modulo 360°)."""
    return _angles_close(np.radians(value), reference) and not _angles_close(value, reference)


def _choice(answer: Any, correct: str, why_not: Mapping[str, str], right: str) -> Feedback:
    """A multiple-choice answer: one letter among the keys of ``why_not`` plus ``correct``."""
    missing = _unanswered(answer)
    if missing is not None:
        return missing
    letters = sorted({*why_not, correct})
    if not isinstance(answer, str) or answer.strip().lower().strip("()") not in letters:
        return Feedback(False, f"Not yet: answer with one letter among {', '.join(letters)} (a string).")
    letter = answer.strip().lower().strip("()")
    if letter == correct:
        return _right(right)
    return _wrong(why_not[letter])


# ---------------------------------------------------------------- sympy helpers

def _plain(expr: Any) -> sp.Expr | Feedback:
    """sympify, θ(t) → θ, every symbol → a real symbol of the same name (assumptions ignored);
    the feedback instead when there is no answer yet or it is not an expression."""
    missing = _unanswered(expr)
    if missing is not None:
        return missing
    if isinstance(expr, str):
        return Feedback(False, "Not yet: build a sympy expression (not a string), e.g. with sp.symbols.")
    try:
        expr = sp.sympify(expr)
    except (sp.SympifyError, TypeError):
        return Feedback(False, f"Not yet: that is not a sympy expression; got {type(expr).__name__}.")
    if isinstance(expr, sp.Equality):
        expr = expr.lhs - expr.rhs
    if not isinstance(expr, sp.Expr):
        return Feedback(False, "Not yet: expected one sympy expression.")
    if expr.atoms(sp.Derivative):
        return Feedback(
            False,
            "Not yet: your expression still holds a Derivative(θ(t), t); write it with ω "
            "(course_lib.symbolic.d_dt does that) or with plain symbols.",
        )
    if expr.has(sp.zoo, sp.oo, -sp.oo, sp.nan):
        return Feedback(False, "Not yet: your expression is infinite or undefined — a division by zero?")
    expr = static(expr)
    return expr.xreplace({s: sp.Symbol(s.name, real=True) for s in expr.free_symbols if s != TIME})


def _symbols_named(names: Sequence[str]) -> dict[str, sp.Symbol]:
    return {name: sp.Symbol(name, real=True) for name in names}


def _unknown_symbols(expr: sp.Expr, allowed: Sequence[str]) -> Feedback | None:
    extra = sorted(s.name for s in expr.free_symbols if s.name not in allowed)
    if extra:
        return _wrong(
            f"your expression uses symbols the task does not define: {', '.join(extra)} "
            f"(allowed: {', '.join(allowed)})."
        )
    return None


def _probe_points(names: Sequence[str], count: int = 6) -> list[dict[str, float]]:
    """Random points: lengths in [0.5, 2], everything else in [−1.4, 1.4] (fixed seed)."""
    generator = np.random.default_rng(20240601)
    points = []
    for _ in range(count):
        point = {}
        for name in names:
            if re.fullmatch(r"l\d|r\d|r1y", name):
                point[name] = float(generator.uniform(0.5, 2.0))
            else:
                point[name] = float(generator.uniform(-1.4, 1.4))
        points.append(point)
    return points


def _evaluate(expr: sp.Expr, points: list[dict[str, float]]) -> np.ndarray:
    symbols = sorted(expr.free_symbols, key=lambda s: s.name)
    function = sp.lambdify(symbols, expr, modules="numpy")
    with np.errstate(all="ignore"):
        return np.array([complex(function(*(p[s.name] for s in symbols))) for p in points])


def _same(expr: sp.Expr, reference: sp.Expr, names: Sequence[str]) -> bool:
    """Algebraically equal, decided by evaluation: equal at random points in double precision,
    then at three of them with 40 significant digits.  Two different trigonometric-rational
    expressions do not agree to 30 digits at random points.  (``sympy.simplify`` is not used:
    its run time depends on the hash seed and can explode on these expressions.)"""
    points = _probe_points(names)
    a, b = _evaluate(expr, points), _evaluate(reference, points)
    if not np.allclose(a, b, rtol=1e-9, atol=1e-12):
        return False
    for point in points[:3]:
        values = {sp.Symbol(name, real=True): sp.Float(value, 40) for name, value in point.items()}
        difference = sp.N((expr - reference).xreplace(values), 40)
        scale = abs(sp.N(reference.xreplace(values), 40)) + 1
        if not abs(difference) < 1e-30 * scale:
            return False
    return True


def _proportional(expr: sp.Expr, reference: sp.Expr, names: Sequence[str]) -> bool:
    """expr = k·reference for a nonzero constant k (the same equation expr = 0)."""
    points = _probe_points(names)
    a, b = _evaluate(expr, points), _evaluate(reference, points)
    if np.any(np.abs(b) < 1e-9) or not np.all(np.isfinite(a)):
        return False
    ratio = a / b
    if abs(ratio[0]) < 1e-12 or not np.allclose(ratio, ratio[0], rtol=1e-9, atol=0):
        return False
    k = sp.nsimplify(ratio[0].real, rational=True) if abs(ratio[0].imag) < 1e-12 else None
    return k is not None and _same(expr, k * reference, names)


# ================================================================ ex01: loops and mobility

#: The six-bar of exercise 01: a four-bar O2-A-B-O4 plus a dyad B-C-O6 pinned at B.
_SIX_BAR = {"links": 6, "full_joints": 7, "half_joints": 0, "mobility": 1}


def check_mobility(answer) -> Feedback:
    """Exercise 01, task 1: counts (L, J1, J2) and mobility M of the six-bar with a triple pin at B.

    ``answer`` is a dict with keys ``links, full_joints, half_joints, mobility`` or a tuple
    (L, J1, J2, M).

    >>> check_mobility((6, 6, 0, 3)).ok
    False
    """
    missing = _unanswered(answer)
    if missing is not None:
        return missing
    keys = ("links", "full_joints", "half_joints", "mobility")
    if isinstance(answer, Mapping):
        if set(keys) - set(answer):
            return _wrong(f"the dict needs the keys {', '.join(keys)}.")
        values = [answer[key] for key in keys]
    else:
        values = list(answer) if isinstance(answer, list | tuple) else []
        if len(values) != 4:
            return _wrong("give (L, J1, J2, M) as a tuple of four integers, or a dict.")
    try:
        L, J1, J2, M = (int(v) for v in values)
    except (TypeError, ValueError):
        return _wrong("all four counts must be integers.")
    if any(int(v) != v for v in values):
        return _wrong("all four counts must be integers.")
    if L == _SIX_BAR["links"] - 1:
        return _wrong("count the ground (the frame, bancada) as one of the links.")
    if L != _SIX_BAR["links"]:
        return _wrong("recount the links: every rigid body, the ground included, counts once.")
    if J2 != 0:
        return _wrong("every joint here is a pin (one relative freedom): a full joint, not a half joint.")
    if J1 == _SIX_BAR["full_joints"] - 1:
        return _wrong(
            "at B three links meet (coupler, rocker and link 5): a pin joining three links counts "
            "as two full joints."
        )
    if J1 != _SIX_BAR["full_joints"]:
        return _wrong("recount the pins; where k links share one pin it counts as k − 1 joints.")
    if M != 3 * (L - 1) - 2 * J1 - J2:
        return _wrong("the counts are right, but M does not follow from them: M = 3(L − 1) − 2·J1 − J2.")
    return _right("Correct: one input (the crank) drives the whole six-bar.")


_LOOP_NAMES = ("l1", "l2", "l3", "l4", "theta1", "theta2", "theta3", "theta4")


def _tilted_loop(sign3: int = 1, ground_tilt: bool = True) -> list[sp.Expr]:
    s = _symbols_named(_LOOP_NAMES)
    cos, sin = sp.cos, sp.sin
    t1 = s["theta1"] if ground_tilt else sp.Integer(0)
    x = s["l2"] * cos(s["theta2"]) + sign3 * s["l3"] * cos(s["theta3"]) - s["l4"] * cos(s["theta4"])
    y = s["l2"] * sin(s["theta2"]) + sign3 * s["l3"] * sin(s["theta3"]) - s["l4"] * sin(s["theta4"])
    return [x - s["l1"] * cos(t1), y - s["l1"] * sin(t1)]


def check_tilted_loop(answer) -> Feedback:
    """Exercise 01, task 2: x and y components of R2 + R3 − R4 − R1 = 0 with the ground tilted by θ1.

    ``answer`` is a pair (x-component, y-component) of sympy expressions in l1…l4, θ1…θ4
    (each "= 0"; a component multiplied by a constant is the same equation).

    >>> import sympy as sp
    >>> l1, l2, l3, l4 = sp.symbols("l1:5")
    >>> t1, t2, t3, t4 = sp.symbols("theta1:5")
    >>> x = l2 * sp.cos(t2) + l3 * sp.cos(t3) - l4 * sp.cos(t4) - l1 * sp.cos(t1)
    >>> y = l2 * sp.sin(t2) + l3 * sp.sin(t3) - l4 * sp.sin(t4) - l1 * sp.sin(t1)
    >>> check_tilted_loop([x, y]).ok, check_tilted_loop([y, -x]).ok
    (True, True)
    """
    missing = _unanswered(answer)
    if missing is not None:
        return missing
    if isinstance(answer, sp.MatrixBase):
        answer = list(answer)
    if not isinstance(answer, list | tuple) or len(answer) != 2:
        return _wrong("give the two components as a list [x_component, y_component] (or a 2×1 Matrix).")
    components = [_plain(c) for c in answer]
    for c in components:
        if isinstance(c, Feedback):
            return c
    for c in components:
        extra = _unknown_symbols(c, _LOOP_NAMES)
        if extra is not None:
            return extra

    def matches(candidate):
        return any(
            all(_proportional(a, b, _LOOP_NAMES) for a, b in zip(pair, candidate, strict=True))
            for pair in (components, components[::-1])
        )

    if matches(_tilted_loop()):
        return _right("Correct: two scalar equations, one per component.")
    if matches(_tilted_loop(ground_tilt=False)):
        return _wrong("that is the loop with a horizontal ground; here R1 = l1(cos θ1, sin θ1) is tilted.")
    if matches(_tilted_loop(sign3=-1)):
        return _wrong(
            "a sign error: walking O2 → A → B adds R2 and R3; walking O2 → O4 → B adds R1 and R4, "
            "so R1 and R4 carry the minus sign."
        )
    return _wrong("compare each term with the walk O2 → A → B versus O2 → O4 → B (signs, lengths, angles).")


def check_link_vector(answer, length: float, angle_degrees: float) -> Feedback:
    """Lesson 00, Try it: the vector (x, y) in metres of a link of ``length`` (m) at ``angle_degrees``.

    >>> check_link_vector((0.0, 0.06), 0.06, 90.0).ok
    True
    """
    values = _as_vector(answer, 2, "the vector (x, y)")
    if isinstance(values, Feedback):
        return values
    theta = float(np.radians(angle_degrees))
    reference = length * np.array([np.cos(theta), np.sin(theta)])
    scale = dict(rtol=1e-6, atol=1e-9 * length)
    if np.allclose(values, reference, **scale):
        return _right("Correct: R = l (cos θ, sin θ).")
    if np.allclose(values[::-1], reference, **scale):
        return _wrong("x and y are swapped: x goes with cos θ, y with sin θ.")
    if np.allclose(values / 1000.0, reference, **scale) or np.allclose(values / 100.0, reference, **scale):
        return _wrong("the length is in metres, not mm or cm.")
    if np.allclose(values, length * np.array([np.cos(angle_degrees), np.sin(angle_degrees)]), **scale):
        return _wrong("the angle went into cos/sin in degrees; numpy's trigonometric functions take radians.")
    return _wrong("R = l (cos θ î + sin θ ĵ): evaluate cos θ and sin θ for the given angle.")


def check_point_velocity(
    answer, length: float, angle_degrees: float, speed: float, clockwise: bool
) -> Feedback:
    """Exercise 01, task 3: velocity (vx, vy) in m/s of the tip of a link of ``length`` (m) at
    ``angle_degrees`` (as the statement gives it), turning at ``speed`` (rad/s, > 0) about a
    fixed pivot, ``clockwise`` or not.

    >>> check_point_velocity([-0.6, 0.0], 0.1, 90.0, 6.0, clockwise=False).ok
    True
    """
    missing = _unanswered(answer)
    if missing is not None:
        return missing
    theta = float(np.radians(angle_degrees))
    omega = -abs(speed) if clockwise else abs(speed)
    if np.ndim(answer) == 0 and not isinstance(answer, str):
        speed = _as_number(answer, "the speed")
        if not isinstance(speed, Feedback) and _close(abs(speed), abs(omega) * length):
            return _wrong("l·|ω| is only the speed; the velocity is a vector (vx, vy) = ω k̂ × R.")
        return _wrong("give the velocity as a vector (vx, vy) in m/s.")
    values = _as_vector(answer, 2, "the velocity")
    if isinstance(values, Feedback):
        return values
    reference = omega * length * np.array([-np.sin(theta), np.cos(theta)])
    scale = dict(rtol=1e-6, atol=1e-9 * max(abs(omega) * length, 1e-300))
    if np.allclose(values, reference, **scale):
        return _right("Correct: the tip moves perpendicular to the link with speed l·|ω|.")
    if np.allclose(values / 1000.0, reference, **scale):
        return _wrong("that looks like mm/s: the length is in metres, so the velocity is in m/s.")
    degrees_used = omega * length * np.array([-np.sin(np.degrees(theta)), np.cos(np.degrees(theta))])
    if np.allclose(values, degrees_used, **scale):
        return _wrong("the angle went into sin/cos in degrees; numpy's trigonometric functions take radians.")
    if np.allclose(values, -reference, **scale):
        return _wrong(
            "a sign error: clockwise rotation means ω < 0, and k̂ × R turns R by +90° (counter-clockwise)."
        )
    if np.allclose(values[::-1], reference, **scale):
        return _wrong("the components are swapped: give (vx, vy).")
    if np.allclose(
        np.abs(values), np.abs(omega * length * np.array([np.cos(theta), np.sin(theta)])), **scale
    ):
        return _wrong("that vector is along the link; the velocity is perpendicular to it (k̂ × R).")
    return _wrong("use v = ω k̂ × R with R = l(cos θ, sin θ): k̂ × (x, y) = (−y, x).")


def check_redundant_parallelogram(answer) -> Feedback:
    """Exercise 01, task 4: why the parallelogram with a mid-height bar moves although M = 0.

    >>> check_redundant_parallelogram("b").ok
    True
    """
    return _choice(
        answer,
        "b",
        {
            "a": "the ground was counted once, correctly: L = 5 includes it, and M = 3·4 − 2·6 = 0 is the "
            "right Gruebler count. The count is fine; its assumption is not.",
            "c": "ideal pins have no clearance in this course; the motion is a real, finite motion.",
            "d": "a pin is a full joint (one relative rotation); making them half joints would not explain "
            "why this particular geometry moves and a slightly different one locks.",
        },
        "Correct: with CD equal and parallel to O2O4, the two pins at C and D repeat constraints the "
        "parallelogram already imposes. Gruebler assumes independent equations, so it undercounts.",
    )


# ================================================================ ex02: Newton–Raphson

_X = sp.Symbol("x", real=True)
_WALLIS = _X**3 - 2 * _X - 5  # Newton's own example


def check_newton_update(answer) -> Feedback:
    """Exercise 02, task 1: the Newton update x_{n+1} as a sympy expression in x for f = x³ − 2x − 5.

    >>> import sympy as sp
    >>> x = sp.Symbol("x")
    >>> check_newton_update((2 * x**3 + 5) / (3 * x**2 - 2)).ok
    True
    """
    expr = _plain(answer)
    if isinstance(expr, Feedback):
        return expr
    extra = _unknown_symbols(expr, ("x",))
    if extra is not None:
        return extra
    f, df = _WALLIS, sp.diff(_WALLIS, _X)
    if _same(expr, _X - f / df, ("x",)):
        return _right("Correct: x − f/f' (for this cubic it simplifies to (2x³ + 5)/(3x² − 2)).")
    if _same(expr, _X + f / df, ("x",)):
        return _wrong("a sign error: the tangent reaches zero at x − f/f', not x + f/f'.")
    if _same(expr, _X - df / f, ("x",)):
        return _wrong("the fraction is upside down: divide f by its derivative f'.")
    if _same(expr, f / df, ("x",)) or _same(expr, -f / df, ("x",)):
        return _wrong("that is the step Δx (up to sign); the update is x_{n+1} = x_n + Δx.")
    if _same(expr, _X - f, ("x",)):
        return _wrong("the derivative is missing: Newton divides f by f'.")
    return _wrong("set the tangent line f(x) + f'(x)(x_{n+1} − x) to zero and solve for x_{n+1}.")


def check_newton_iterations(answer) -> Feedback:
    """Exercise 02, task 2: (root, iterations) of Newton on x³ − 2x − 5 = 0 from x0 = 2, stopping
    when |x_{n+1} − x_n| < 1e-6 (iterations = updates x_n → x_{n+1}).

    >>> check_newton_iterations((2.0945514815423265, 4)).ok
    True
    """
    missing = _unanswered(answer)
    if missing is not None:
        return missing
    if not isinstance(answer, list | tuple) or len(answer) != 2:
        return _wrong("give a pair (root, iterations).")
    root = _as_number(answer[0], "the root")
    if isinstance(root, Feedback):
        return root
    iterations = answer[1]
    if isinstance(iterations, bool) or not float(np.asarray(iterations, dtype=float)) == int(
        np.asarray(iterations, dtype=float)
    ):
        return _wrong("the number of iterations is a whole number.")
    iterations = int(iterations)
    reference = newton(sp.lambdify(_X, _WALLIS), 2.0, jac=sp.lambdify(_X, sp.diff(_WALLIS, _X)))
    reference_root, reference_count = reference.x, reference.iterations
    if not abs(root - reference_root) < 1e-6:
        if abs(float(_WALLIS.subs(_X, root))) < 1e-3:
            return _wrong("close, but not within the tolerance: keep iterating until |Δx| < 1e-6.")
        return _wrong("that root does not satisfy x³ − 2x − 5 = 0; check f and f' in your loop.")
    if iterations == reference_count + 1:
        return _wrong("one iteration too many: the seed x0 is not an iteration; count the updates.")
    if iterations == reference_count - 1:
        return _wrong("one iteration too few: the last update is the one whose step falls below 1e-6.")
    if iterations != reference_count:
        return _wrong("the root is right, but recount the updates x_n → x_{n+1} until |Δx| < 1e-6.")
    return _right("Correct: quadratic convergence — a handful of updates from a good seed.")


def check_newton_cycle(answer) -> Feedback:
    """Exercise 02, task 3: why Newton on x³ − 2x + 2 from x0 = 0 never converges.

    >>> check_newton_cycle("a").ok
    True
    """
    return _choice(
        answer,
        "a",
        {
            "b": "f'(x) = 3x² − 2 is not zero at the iterates 0 and 1, so every step is defined; look at "
            "the history.",
            "c": "the iterates stay bounded (look at err.result.history): nothing runs off to infinity.",
            "d": "a cubic always has a real root (plot it); Newton just never gets near it from 0.",
        },
        "Correct: 0 → 1 → 0 → 1 … a 2-cycle. The tangent at 0 points to 1 and the tangent at 1 back to 0.",
    )


def _fourbar_loop(linkage: FourBar, theta2: float, x: np.ndarray) -> np.ndarray:
    return np.asarray(linkage.loop_residual(theta2, x[0], x[1]), float)


def check_fourbar_newton_step(answer, linkage: FourBar, theta2: float, seed) -> Feedback:
    """Exercise 02, task 4: the first Newton step Δx = (Δθ3, Δθ4) (rad) for the four-bar loop at
    crank angle ``theta2`` (rad) from ``seed`` = (θ3, θ4).

    >>> import numpy as np
    >>> bar = FourBar(0.07, 0.20, 0.15, 0.25)
    >>> F = bar.loop_residual(0.7, 0.5, 1.5); J = bar.loop_jacobian(0.5, 1.5)
    >>> check_fourbar_newton_step(np.linalg.solve(J, -F), bar, 0.7, (0.5, 1.5)).ok
    True
    """
    values = _as_vector(answer, 2, "the step Δx")
    if isinstance(values, Feedback):
        return values
    seed = np.asarray(seed, float)
    F = _fourbar_loop(linkage, theta2, seed)
    J = np.asarray(linkage.loop_jacobian(*seed), float)
    step = np.linalg.solve(J, -F)
    if _close(values, step, rtol=1e-6, atol=1e-9):
        return _right("Correct: J·Δx = −F, solved without forming J⁻¹.")
    if _close(values, seed + step, rtol=1e-6, atol=1e-9):
        return _wrong("that is the new iterate x1 = x0 + Δx; the task asks for the step Δx itself.")
    if _close(values, -step, rtol=1e-6, atol=1e-9):
        return _wrong("a sign error: the step solves J·Δx = −F (minus the residual).")
    if _close(values, step[::-1], rtol=1e-6, atol=1e-9):
        return _wrong("the entries are swapped: order them (Δθ3, Δθ4) like the unknowns.")
    if _close(values, np.linalg.solve(J.T, -F), rtol=1e-6, atol=1e-9):
        return _wrong("the Jacobian is transposed: row i holds ∂F_i/∂θ3, ∂F_i/∂θ4.")
    F_degrees = _fourbar_loop(linkage, np.degrees(theta2), seed)
    if _close(values, np.linalg.solve(J, -F_degrees), rtol=1e-6, atol=1e-9):
        return _wrong("θ2 went into the loop in degrees; convert it with np.radians.")
    return _wrong("check F (the two loop components at the seed) and J = ∂F/∂(θ3, θ4), then solve J·Δx = −F.")


def check_seed_branch(answer, linkage: FourBar, theta2: float, seed) -> Feedback:
    """Exercise 02, task 5: which assembly ("open" or "crossed") Newton reaches from ``seed``.

    >>> bar = FourBar(0.07, 0.20, 0.15, 0.25)
    >>> check_seed_branch("crossed", bar, 0.7, (-0.8, -2.0)).ok
    True
    """
    missing = _unanswered(answer)
    if missing is not None:
        return missing
    if not isinstance(answer, str) or answer.strip().lower() not in ("open", "crossed"):
        return _wrong('answer "open" or "crossed" (a string).')
    from .newton import newton  # the course's Newton, with the course's stopping rule

    result = newton(
        lambda x: _fourbar_loop(linkage, theta2, x),
        np.asarray(seed, float),
        jac=lambda x: np.asarray(linkage.loop_jacobian(*x), float),
    )
    reached = next(
        (
            branch
            for branch in ("open", "crossed")
            if _angles_close(result.x[1], linkage.solve(theta2, branch=branch).theta4, 1e-6)
        ),
        None,
    )
    if answer.strip().lower() == reached:
        return _right(
            "Correct: the seed, not the equations, picks the assembly — compare your θ4 with the "
            "closed form of each branch."
        )
    return _wrong(
        "that is the other branch. Solve from the seed, then compare θ4 with FourBar.solve(θ2, "
        'branch="open") and branch="crossed" (angles modulo 2π).'
    )


# ================================================================ ex03: the four-bar


def _angle_feedback(value: float, reference: float, alternatives: Mapping[str, float]) -> Feedback | None:
    """Shared diagnosis for an angle answer: right (mod 2π), another known angle, or degrees."""
    if _angles_close(value, reference):
        return _right("Correct (angles are compared modulo 2π).")
    for message, other in alternatives.items():
        if _angles_close(value, other):
            return _wrong(message)
    if _in_degrees(value, reference):
        return _wrong("that is the right angle in degrees; the course (and course_lib) works in radians.")
    for message, other in alternatives.items():
        if _in_degrees(value, other):
            return _wrong("that is in degrees — and " + message)
    return None


def check_fourbar_theta4(answer, linkage: FourBar, theta2: float, branch: str) -> Feedback:
    """Exercise 03, task 1: the rocker angle θ4 (rad) at crank angle ``theta2`` on ``branch``.

    >>> bar = FourBar(0.07, 0.20, 0.15, 0.25)
    >>> check_fourbar_theta4(bar.solve(2.0, branch="crossed").theta4 + 2 * np.pi, bar, 2.0, "crossed").ok
    True
    """
    value = _as_number(answer, "θ4")
    if isinstance(value, Feedback):
        return value
    other = "crossed" if branch == "open" else "open"
    this, that = linkage.solve(theta2, branch=branch), linkage.solve(theta2, branch=other)
    verdict = _angle_feedback(
        value,
        this.theta4,
        {
            f"that is θ4 of the {other} branch; the task asks for the {branch} one (the other root of "
            "the half-angle quadratic).": that.theta4,
            "that is the coupler angle θ3; the task asks for the rocker angle θ4.": this.theta3,
            f"that is θ3 of the {other} branch; the task asks for the rocker angle θ4 of the {branch} "
            "branch.": that.theta3,
        },
    )
    return (
        verdict
        if verdict is not None
        else _wrong("recheck the half-angle coefficients A, B, C and which root (±√) you took.")
    )


_RATE_NAMES = ("l2", "l3", "l4", "theta2", "theta3", "theta4", "omega2")


def _omega_expressions():
    s = _symbols_named(_RATE_NAMES)
    omega4 = (
        s["omega2"]
        * s["l2"]
        * sp.sin(s["theta2"] - s["theta3"])
        / (s["l4"] * sp.sin(s["theta4"] - s["theta3"]))
    )
    omega3 = (
        s["omega2"]
        * s["l2"]
        * sp.sin(s["theta4"] - s["theta2"])
        / (s["l3"] * sp.sin(s["theta3"] - s["theta4"]))
    )
    return omega3, omega4


def check_omega4_expression(answer) -> Feedback:
    """Exercise 03, task 2: ω4 as a sympy expression in l2, l3, l4, θ2, θ3, θ4, ω2.

    >>> import sympy as sp
    >>> l2, l4, t2, t3, t4, w2 = sp.symbols("l2 l4 theta2 theta3 theta4 omega2")
    >>> check_omega4_expression(w2 * l2 * sp.sin(t2 - t3) / (l4 * sp.sin(t4 - t3))).ok
    True
    """
    expr = _plain(answer)
    if isinstance(expr, Feedback):
        return expr
    extra = _unknown_symbols(expr, _RATE_NAMES)
    if extra is not None:
        return extra
    omega3, omega4 = _omega_expressions()
    if _same(expr, omega4, _RATE_NAMES):
        return _right("Correct: ω4 = ω2·l2·sin(θ2 − θ3) / (l4·sin(θ4 − θ3)) in some equivalent form.")
    if _same(expr, -omega4, _RATE_NAMES):
        return _wrong("a sign error: recheck the signs of the velocity equations (the minus on R4).")
    if _same(expr, omega3, _RATE_NAMES) or _same(expr, -omega3, _RATE_NAMES):
        return _wrong("that is ω3, the coupler's angular velocity; the task asks for the rocker's ω4.")
    w2 = sp.Symbol("omega2", real=True)
    if _same(expr * w2, omega4, _RATE_NAMES):
        return _wrong("the factor ω2 is missing: the velocity equations are proportional to the input speed.")
    return _wrong("differentiate the two loop components, then solve the linear 2×2 system for ω3, ω4.")


def _alpha_without_omega2_terms(linkage: FourBar, theta2, theta3, theta4, alpha2):
    """α3, α4 if the ω² (centripetal) terms are dropped from the acceleration equations."""
    J = np.asarray(linkage.loop_jacobian(theta3, theta4), float)
    b = np.array([alpha2 * linkage.l2 * np.sin(theta2), -alpha2 * linkage.l2 * np.cos(theta2)])
    return np.linalg.solve(J, b)


def check_fourbar_rates(
    answer, linkage: FourBar, theta2: float, omega2: float, alpha2: float, branch: str
) -> Feedback:
    """Exercise 03, task 3: (ω4, α4) of the rocker (rad/s, rad/s²) at ``theta2`` on ``branch``.

    >>> bar = FourBar(0.07, 0.20, 0.15, 0.25)
    >>> s = bar.solve(3.5, 15.0, -40.0)
    >>> check_fourbar_rates((s.omega4, s.alpha4), bar, 3.5, 15.0, -40.0, "open").ok
    True
    """
    values = _as_vector(answer, 2, "(ω4, α4)")
    if isinstance(values, Feedback):
        return values
    omega4, alpha4 = values
    this = linkage.solve(theta2, omega2, alpha2, branch=branch)
    other_branch = "crossed" if branch == "open" else "open"
    other = linkage.solve(theta2, omega2, alpha2, branch=other_branch)
    omega_ok = _close(omega4, this.omega4, atol=1e-9)
    alpha_ok = _close(alpha4, this.alpha4, atol=1e-9)
    if omega_ok and alpha_ok:
        return _right("Correct: the same Jacobian J solves both the velocity and the acceleration equations.")
    if _close(omega4, this.alpha4, atol=1e-9) and _close(alpha4, this.omega4, atol=1e-9):
        return _wrong("the two are swapped: give (ω4, α4).")
    if _close(omega4, other.omega4, atol=1e-9) and _close(alpha4, other.alpha4, atol=1e-9):
        return _wrong(
            f"those are the rates of the {other_branch} branch; the task is on the {branch} branch."
        )
    if not omega_ok:
        if _close(omega4, -this.omega4, atol=1e-9):
            return _wrong("ω4 has the wrong sign: check the signs in the velocity equations (−ω4 l4 …).")
        if _close(omega4, this.omega3, atol=1e-9):
            return _wrong("that ω is the coupler's ω3; the rocker's is ω4.")
        return _wrong("ω4 is off: solve J·(ω3, ω4) = −ω2·∂F/∂θ2 at the solved position.")
    _, alpha4_bare = _alpha_without_omega2_terms(linkage, theta2, this.theta3, this.theta4, alpha2)
    if _close(alpha4, alpha4_bare, atol=1e-9):
        return _wrong(
            "ω4 is right, but α4 misses the ω² (centripetal) terms: A_k = α_k k̂ × R_k − ω_k² R_k for "
            "every link, including ω2², ω3² and ω4²."
        )
    if _close(alpha4, -this.alpha4, atol=1e-9):
        return _wrong("ω4 is right, but α4 has the wrong sign.")
    if _close(alpha4, linkage.solve(theta2, omega2, -alpha2, branch=branch).alpha4, atol=1e-9):
        return _wrong(
            "ω4 is right, but α4 is that of a crank whose α2 has the opposite sign: check the sign of the "
            "α2 k̂ × R2 terms when you move them to the right-hand side."
        )
    return _wrong(
        "ω4 is right; α4 is off — differentiate the velocity equations once more (with the ω² terms)."
    )


def check_toggle_angle(answer, linkage: FourBar) -> Feedback:
    """Exercise 03, task 4: (θ2_max in rad, "extended" or "folded") — the largest crank angle the
    non-Grashof ``linkage`` reaches, and how coupler and rocker lie there.

    >>> bar = FourBar(crank=0.14, coupler=0.12, rocker=0.10, ground=0.20)
    >>> check_toggle_angle((float(np.arccos(0.2)), "extended"), bar).ok
    True
    """
    missing = _unanswered(answer)
    if missing is not None:
        return missing
    if not isinstance(answer, list | tuple) or len(answer) != 2:
        return _wrong('give a pair (theta2_max, "extended" or "folded").')
    value = _as_number(answer[0], "θ2_max")
    if isinstance(value, Feedback):
        return value
    how = answer[1]
    if not isinstance(how, str) or how.strip().lower() not in ("extended", "folded"):
        return _wrong('the second entry is the string "extended" or "folded".')
    l1, l2, l3, l4 = linkage.l1, linkage.l2, linkage.l3, linkage.l4
    cos_extended = (l1**2 + l2**2 - (l3 + l4) ** 2) / (2 * l1 * l2)
    cos_folded = (l1**2 + l2**2 - (l3 - l4) ** 2) / (2 * l1 * l2)
    limits = []
    if -1 < cos_extended < 1:
        limits.append((float(np.arccos(cos_extended)), "extended"))
    if -1 < cos_folded < 1:
        limits.append((2 * np.pi - float(np.arccos(cos_folded)), "folded"))
    reference, state = limits[0]
    if _in_degrees(value, reference):
        return _wrong("that is the limit in degrees; give it in radians.")
    if _close(value, -reference, atol=1e-9):
        return _wrong("that is the mirror-image limit (θ2 < 0); the task asks for the largest θ2.")
    if not _close(value, reference, atol=1e-9):
        return _wrong(
            "at the limit |AO4| = l3 + l4 or |l3 − l4|; use the law of cosines "
            "|AO4|² = l1² + l2² − 2 l1 l2 cos θ2."
        )
    if how.strip().lower() != state:
        return _wrong(
            "the angle is right, but look at the picture there: which of l3 + l4 and |l3 − l4| binds?"
        )
    return _right(
        "Correct: coupler and rocker are collinear there (a toggle), det J = 0, and the crank must turn back."
    )


# ================================================================ ex04: the power saw

_SAW_NAMES = ("r1y", "r2", "r3", "theta1", "theta2", "theta3", "omega2")


def check_saw_omega3_expression(answer) -> Feedback:
    """Exercise 04, task 1: ω3 of the saw as a sympy expression in r2, r3, θ2, θ3, ω2.

    >>> import sympy as sp
    >>> r2, r3, t2, t3, w2 = sp.symbols("r2 r3 theta2 theta3 omega2")
    >>> check_saw_omega3_expression(-w2 * r2 * sp.cos(t2) / (r3 * sp.cos(t3))).ok
    True
    """
    expr = _plain(answer)
    if isinstance(expr, Feedback):
        return expr
    extra = _unknown_symbols(expr, _SAW_NAMES)
    if extra is not None:
        return extra
    s = _symbols_named(_SAW_NAMES)
    reference = -s["omega2"] * s["r2"] * sp.cos(s["theta2"]) / (s["r3"] * sp.cos(s["theta3"]))
    if _same(expr, reference, _SAW_NAMES):
        return _right("Correct: ω3 = −ω2·r2·cos θ2 / (r3·cos θ3), from the derivative of Fy − Fc.")
    if _same(expr, -reference, _SAW_NAMES):
        return _wrong("a sign error: differentiate r2 sin θ2 + r3 sin θ3 = r1y (constant) and solve for ω3.")
    swapped = -s["omega2"] * s["r2"] * sp.sin(s["theta2"]) / (s["r3"] * sp.sin(s["theta3"]))
    if _same(expr, swapped, _SAW_NAMES) or _same(expr, -swapped, _SAW_NAMES):
        return _wrong("sin and cos are swapped: d(sin θ)/dt = ω cos θ.")
    if "omega2" not in {sym.name for sym in expr.free_symbols}:
        return _wrong(
            "ω3 must be proportional to ω2 (the report's eq. 23 is labelled ω3 but repeats θ1's formula — "
            "don't copy that slip)."
        )
    return _wrong("use the y-equation without r1: r2 sin θ2 + r3 sin θ3 = r1y, differentiate in time.")


def check_saw_position(answer, saw: Saw, theta2: float) -> Feedback:
    """Exercise 04, task 2: (r1 in m, θ1 in rad, θ3 in rad) of ``saw`` at crank angle ``theta2``.

    The course keeps θ1 in (−π/2, π/2] so r1 < 0 here; (−r1, θ1 + π) describes the same
    vector and is accepted with a remark.

    >>> saw = Saw(r1y=0.03, r2=0.06, r3=0.15)
    >>> check_saw_position(analytic(0.9, saw=saw)[:3], saw, 0.9).ok
    True
    """
    values = _as_vector(answer, 3, "(r1, θ1, θ3)")
    if isinstance(values, Feedback):
        return values
    r1, theta1, theta3 = values
    reference = analytic(theta2, saw=saw)[:3]
    ref_r1, ref_theta1, ref_theta3 = reference
    length_ok = _close(r1, ref_r1, atol=1e-9)
    if length_ok and _angles_close(theta1, ref_theta1) and _angles_close(theta3, ref_theta3):
        return _right("Correct: r1 < 0 with θ1 in (−π/2, π/2], as the course writes it.")
    if (
        _close(r1, -ref_r1, atol=1e-9)
        and _angles_close(theta1, ref_theta1 + np.pi)
        and _angles_close(theta3, ref_theta3)
    ):
        return _right(
            "Correct — the same vector r1, written with r1 > 0 and θ1 + π. The course keeps "
            "θ1 in (−π/2, π/2], which makes r1 negative here."
        )
    if _close(r1 / 1000.0, ref_r1, atol=1e-9) or _close(r1 / 1000.0, -ref_r1, atol=1e-9):
        return _wrong("r1 looks like millimetres; give lengths in metres.")
    mirror = np.pi - ref_theta3  # the other root of sin θ3 = (r1y − r2 sin θ2)/r3
    if _angles_close(theta3, mirror) or _in_degrees(theta3, mirror):
        return _wrong(
            "θ3 is on the other branch: asin gives the rod pointing right, but the saw's rod points left, "
            "θ3 = π − asin((r1y − r2 sin θ2)/r3)."
        )
    if (
        _in_degrees(theta1, ref_theta1)
        or _in_degrees(theta3, ref_theta3)
        or _in_degrees(theta1, ref_theta1 + np.pi)
    ):
        return _wrong("an angle is in degrees; give θ1 and θ3 in radians.")
    if not _angles_close(theta3, ref_theta3):
        return _wrong("θ3 is off: Fy − Fc gives r2 sin θ2 + r3 sin θ3 = r1y.")
    return _wrong(
        "θ3 is right; recheck r1 and θ1 from r1 sin θ1 = r1y and r1 cos θ1 = r2 cos θ2 + r3 cos θ3."
    )


def check_saw_slider_acceleration(answer, saw: Saw, theta2: float, omega2: float, alpha2: float) -> Feedback:
    """Exercise 04, task 3: a_r (m/s²), the acceleration along r1, at the given motor state.

    >>> saw = Saw(r1y=0.03, r2=0.06, r3=0.15)
    >>> check_saw_slider_acceleration(analytic(0.9, 6.0, 4.0, saw=saw)[6], saw, 0.9, 6.0, 4.0).ok
    True
    """
    value = _as_number(answer, "a_r")
    if isinstance(value, Feedback):
        return value
    x = analytic(theta2, omega2, alpha2, saw=saw)
    reference = x[6]
    if _close(value, reference, atol=1e-9):
        return _right("Correct: a_r holds the α2 terms and every ω² term (r1 ω1², r2 ω2², r3 ω3²).")
    if _close(value, reference / 1000.0, atol=1e-9) or _close(value, reference * 1000.0, atol=1e-9):
        return _wrong("a factor 1000: lengths in metres give a_r in m/s².")
    if _close(value, -reference, atol=1e-9):
        return _wrong("a sign error: a_r is along r1, and r1 < 0 here (the course's convention).")
    # the same formulas with every ω² and the 2·v_r·ω1 term dropped (only the α2 terms remain)
    bare = analytic(theta2, 0.0, alpha2, saw=saw)[6]
    if _close(value, bare, atol=1e-9):
        return _wrong(
            "that keeps only the α2 terms: the ω² (centripetal) terms — r1 ω1², r2 ω2², r3 ω3² — are "
            "missing, and at speed they dominate."
        )
    if _close(value, x[3], atol=1e-9):
        return _wrong("that is the velocity v_r; the task asks for the acceleration a_r.")
    return _wrong(
        "differentiate the position equations twice (or use the velocity solution) and solve for a_r."
    )


def check_saw_linear_stage(answer) -> Feedback:
    """Exercise 04, task 4: why the velocity stage always takes two Newton iterations.

    >>> check_saw_linear_stage("a").ok
    True
    """
    return _choice(
        answer,
        "a",
        {
            "b": "the seed can be anything — the task changed it and the count stayed two; the first "
            "step lands exactly on the solution from any seed.",
            "c": "the velocity Jacobian is the position Jacobian (it depends on r1, θ1, θ3), not I.",
            "d": "the tolerance is the same 1e-6 for every stage.",
        },
        "Correct: the velocity equations are linear in (v_r, ω1, ω3), so the first Newton step is exact; "
        "the second step is ~0 and only confirms the stopping rule.",
    )


# ================================================================ ex05: the five-bar robot


def check_fivebar_forward(answer, robot: FiveBar, theta1: float, theta4: float, mode: int) -> Feedback:
    """Exercise 05, task 1: the end effector (x3, y3) in metres for crank angles θ1, θ4 in working
    mode σ = ``mode`` (+1 arms up, −1 arms down).

    >>> robot = FiveBar(0.11, 0.16, 0.17, 0.12, 0.09)
    >>> check_fivebar_forward(tuple(robot.forward(1.2, 2.2, -1)), robot, 1.2, 2.2, -1).ok
    True
    """
    values = _as_vector(answer, 2, "(x3, y3)")
    if isinstance(values, Feedback):
        return values
    reference = np.array(tuple(robot.forward(theta1, theta4, mode=mode)))
    other = np.array(tuple(robot.forward(theta1, theta4, mode=-mode)))
    scale = dict(atol=1e-9)
    if _close(values, reference, **scale):
        return _right("Correct.")
    names = {1: "arms up (σ = +1)", -1: "arms down (σ = −1)"}
    if _close(values, other, **scale):
        return _wrong(f"that is the {names[-mode]} assembly; the task asks for {names[mode]}.")
    if _close(values / 1000.0, reference, **scale):
        return _wrong("that looks like millimetres; give metres.")
    if _close(values[::-1], reference, **scale):
        return _wrong("the coordinates are swapped: give (x3, y3).")
    in_degrees = robot.forward(np.degrees(theta1), np.degrees(theta4), mode=mode, on_unreachable="nan")
    if _close(values, np.array(tuple(in_degrees)), **scale):
        return _wrong("the crank angles went into cos/sin in degrees; use radians.")
    return _wrong("from X3 = g·Y3 + f and a·Y3² + b·Y3 + c = 0, take Y3 = (−b + σ√(b² − 4ac))/2a.")


def check_fivebar_inverse(answer, robot: FiveBar, x3: float, y3: float, modes: tuple[int, int]) -> Feedback:
    """Exercise 05, task 2: crank angles (θ1, θ4) in rad that put the end effector at (x3, y3)
    in working mode ``modes`` = (σ1, σ2).  Angles are compared modulo 2π.

    >>> robot = FiveBar(0.11, 0.16, 0.17, 0.12, 0.09)
    >>> check_fivebar_inverse(tuple(robot.inverse(0.01, 0.2, (1, -1))), robot, 0.01, 0.2, (1, -1)).ok
    True
    """
    values = _as_vector(answer, 2, "(θ1, θ4)")
    if isinstance(values, Feedback):
        return values
    sigma1, sigma2 = modes
    solutions = {
        (s1, s2): np.array(tuple(robot.inverse(x3, y3, modes=(s1, s2)))) for s1 in (1, -1) for s2 in (1, -1)
    }
    reference = solutions[(sigma1, sigma2)]
    if _angles_close(values, reference):
        return _right("Correct: working mode (σ1, σ2) = " + f"({sigma1:+d}, {sigma2:+d}).")
    if _in_degrees(values, reference):
        return _wrong("those are the right angles in degrees; give radians.")
    if _angles_close(values[::-1], reference):
        return _wrong("the angles are swapped: give (θ1, θ4).")
    for (s1, s2), other in solutions.items():
        if (s1, s2) != (sigma1, sigma2) and _angles_close(values, other):
            wrong = [name for name, mine, asked in (("σ1", s1, sigma1), ("σ2", s2, sigma2)) if mine != asked]
            return _wrong(
                f"that is working mode ({s1:+d}, {s2:+d}): the sign {' and '.join(wrong)} of the square "
                "root is the other one."
            )
    first_ok = _angles_close(values[0], reference[0])
    if first_ok:
        return _wrong("θ1 is right; recheck θ4 with the coefficients a2, b2, c2 of leg 4.")
    if _angles_close(values[1], reference[1]):
        return _wrong("θ4 is right; recheck θ1 with the coefficients a1, b1, c1 of leg 1.")
    return _wrong("use θ = 2·atan((−b + σ√(b² − 4ac))/2a) with the half-angle coefficients of each leg.")


_FIVEBAR_NAMES = ("l1", "l2", "l3", "l4", "l5", "theta1", "theta4")


def check_fivebar_g(answer) -> Feedback:
    """Exercise 05, task 3: the slope g in X3 = g·Y3 + f (EcL2 − EcL3 solved for X3).

    >>> import sympy as sp
    >>> l1, l4, l5, t1, t4 = sp.symbols("l1 l4 l5 theta1 theta4")
    >>> check_fivebar_g((l4 * sp.sin(t4) - l1 * sp.sin(t1)) / (l5 + l1 * sp.cos(t1) - l4 * sp.cos(t4))).ok
    True
    """
    expr = _plain(answer)
    if isinstance(expr, Feedback):
        return expr
    extra = _unknown_symbols(expr, _FIVEBAR_NAMES)
    if extra is not None:
        return extra
    s = _symbols_named(_FIVEBAR_NAMES)
    D = s["l5"] + s["l1"] * sp.cos(s["theta1"]) - s["l4"] * sp.cos(s["theta4"])
    g = (-2 * s["l1"] * sp.sin(s["theta1"]) + 2 * s["l4"] * sp.sin(s["theta4"])) / (2 * D)
    if _same(expr, g, _FIVEBAR_NAMES):
        return _right(
            "Correct: the seeds' g = (−2 l1 sin θ1 + 2 l4 sin θ4) / (2 (l5 + l1 cos θ1 − l4 cos θ4))."
        )
    if _same(expr, -g, _FIVEBAR_NAMES):
        return _wrong(
            "a sign error: move the Y3 term to the right-hand side before dividing by the X3 coefficient."
        )
    if _same(expr, 1 / g, _FIVEBAR_NAMES) or _same(expr, -1 / g, _FIVEBAR_NAMES):
        return _wrong("that is dY3/dX3; solve the linear equation for X3, not Y3.")
    if _same(expr, 2 * g, _FIVEBAR_NAMES) or _same(expr, g / 2, _FIVEBAR_NAMES):
        return _wrong("off by a factor 2: both the X3 and the Y3 coefficients carry the factor 2.")
    if "l2" in {sym.name for sym in expr.free_symbols} or "l3" in {sym.name for sym in expr.free_symbols}:
        return _wrong("l2 and l3 belong to f (the constant term), not to the slope g.")
    return _wrong("expand EcL2 − EcL3: the squares X3², Y3² cancel, leaving an equation linear in X3 and Y3.")


_SINGULARITIES = {
    "serial1": "serial, leg 1",
    "serial4": "serial, leg 4",
    "parallel": "parallel",
    "none": "none",
}


def check_fivebar_singularity(
    answer, robot: FiveBar, theta1: float, theta4: float, x3: float, y3: float
) -> Feedback:
    """Exercise 05, task 4: which singularity the robot is in — "serial1" (leg 1 stretched or
    folded), "serial4", "parallel" (distal links aligned) or "none".

    >>> robot = FiveBar(0.11, 0.16, 0.17, 0.12, 0.09)
    >>> x3, y3 = robot.forward(1.2, 2.2, 1)
    >>> check_fivebar_singularity("none", robot, 1.2, 2.2, x3, y3).ok
    True
    """
    missing = _unanswered(answer)
    if missing is not None:
        return missing
    key = re.sub(r"[\s_\-,()]|leg", "", answer.lower()) if isinstance(answer, str) else None
    if key not in _SINGULARITIES:
        return _wrong('answer one of "serial1", "serial4", "parallel" or "none" (a string).')
    measures = robot.singularity_measures(theta1, theta4, x3, y3)
    tol = 1e-6
    found = [
        name
        for name, value in (
            ("serial1", measures.serial_leg1),
            ("serial4", measures.serial_leg4),
            ("parallel", measures.parallel),
        )
        if abs(value) < tol
    ] or ["none"]
    if key in found:
        explain = {
            "serial1": "leg 1 is stretched or folded: the point is on the boundary of leg 1's reach, two "
            "inverse solutions (σ1 = ±1) merge, and the end effector cannot move along l1–l2.",
            "serial4": "leg 4 is stretched or folded: two inverse solutions (σ2 = ±1) merge.",
            "parallel": "the distal links are aligned: the two forward solutions (arms up/down) merge "
            "and the "
            "end effector can move with the motors locked.",
            "none": "all three measures are away from zero.",
        }
        return _right("Correct: " + explain[key])
    if key == "none":
        return _wrong("compute robot.singularity_measures(...): one of them is zero here.")
    if "serial" in key and any("serial" in name for name in found):
        return _wrong("a serial singularity, yes — but of the other leg.")
    if key == "parallel":
        return _wrong("the distal links l2 and l3 are not aligned here; look at the crank–distal angles.")
    return _wrong("that measure is not zero here; compute all three with robot.singularity_measures(...).")


# ================================================================ the lessons' "Try it" cells


def check_crank_angle_for_rocker(answer, linkage: FourBar, theta4: float) -> Feedback:
    """Lesson 02: the crank angle θ2 in (0, π) (rad) at which ``linkage`` has its rocker at ``theta4``.

    Judged by the loop itself: the crank pin A must be exactly l3 from the rocker pin B.

    >>> bar = FourBar(crank=0.10, coupler=0.25, rocker=0.20, ground=0.30)
    >>> theta4 = bar.solve(1.0).theta4
    >>> check_crank_angle_for_rocker(1.0, bar, theta4).ok, check_crank_angle_for_rocker(1.1, bar, theta4).ok
    (True, False)
    """
    value = _as_number(answer, "θ2")
    if isinstance(value, Feedback):
        return value
    B = np.array([linkage.l1 + linkage.l4 * np.cos(theta4), linkage.l4 * np.sin(theta4)])

    def gap(theta2: float) -> float:
        A = linkage.l2 * np.array([np.cos(theta2), np.sin(theta2)])
        return abs(float(np.linalg.norm(B - A)) - linkage.l3)

    closes = gap(value) < 1e-9
    if closes and 0.0 < value < np.pi:
        return _right("Correct: the crank pin A is exactly l3 from the rocker pin B.")
    if closes:
        return _wrong(
            "that angle closes the loop, but it is outside (0, π): start Newton from a seed in that range "
            "(the other root is the other assembly)."
        )
    if gap(np.radians(value)) < 1e-9:
        return _wrong("that is the right angle in degrees; newton and course_lib work in radians.")
    return _wrong(f"|B − A| differs from l3 by {gap(value):.1e} m: solve |B − A(θ2)| − l3 = 0 with B at θ4.")


def check_rocker_pin_speed(
    answer, linkage: FourBar, theta2: float, omega2: float, branch: str = "open"
) -> Feedback:
    """Lesson 04: the speed |V_B| (m/s) of the rocker pin B at crank angle ``theta2`` (rad) and crank
    speed ``omega2`` (rad/s).

    >>> bar = FourBar(crank=0.10, coupler=0.25, rocker=0.20, ground=0.30)
    >>> check_rocker_pin_speed(-1.0, bar, 1.0, 10.0).message
    'Not yet: a speed is a magnitude: it cannot be negative.'
    """
    value = _as_number(answer, "the speed of B")
    if isinstance(value, Feedback):
        return value
    omega4 = abs(linkage.solve(theta2, omega2, branch=branch).omega4)
    if _close(value, omega4 * linkage.l4):
        return _right("Correct: B moves perpendicular to the rocker at |ω4|·l4.")
    if value < 0:
        return _wrong("a speed is a magnitude: it cannot be negative.")
    if _close(value, omega4):
        return _wrong("that is |ω4| in rad/s: multiply by the rocker length l4.")
    if _close(value, abs(omega2) * linkage.l2):
        return _wrong("that is the speed of the crank pin A (ω2·l2); the task asks for the rocker pin B.")
    in_degrees = linkage.solve(np.degrees(theta2), omega2, branch=branch, on_unreachable="nan").omega4
    if np.isfinite(in_degrees) and _close(value, abs(in_degrees) * linkage.l4):
        return _wrong("θ2 went into solve in degrees; convert with np.radians.")
    return _wrong("solve for ω4 at the given θ2 (radians) and ω2, then |V_B| = |ω4|·l4.")


def check_motor_start(answer, alpha_max: float) -> Feedback:
    """Lesson 05: (T in s, final speed in rpm) of the rise–hold–fall start-up with peak acceleration
    ``alpha_max`` (rad/s²) over the first revolution.

    >>> check_motor_start((1.9416, 61.8), 5.0).ok
    True
    """
    values = _as_vector(answer, 2, "(T, rpm)")
    if isinstance(values, Feedback):
        return values
    T_answer, speed = values
    T = first_turn_time(alpha_max)
    omega = float(motor_profile(2 * T, alpha_max).omega2)  # the constant speed after T
    rpm = omega * 60 / (2 * np.pi)
    if not _close(T_answer, T, rtol=1e-3):
        return _wrong(f"T is not right yet: solve θ2(T) = A·T²/3 = 2π with A = {alpha_max:g} rad/s².")
    if _close(speed, omega, rtol=1e-3):
        return _wrong("T is right. Your speed looks like rad/s: convert with 60/(2π).")
    if not _close(speed, rpm, rtol=1e-3):
        return _wrong("T is right; the final speed is 2·A·T/3 in rad/s — then convert to rpm.")
    return _right("Correct on both.")


def check_saw_rates(answer, saw: Saw, theta2: float, omega2: float) -> Feedback:
    """Lesson 06: the rates (V_r in m/s, ω1, ω3 in rad/s) of ``saw`` at ``theta2`` (rad) and ``omega2``
    (rad/s), α2 = 0.

    >>> check_saw_rates([0.0, 0.0, 0.0], Saw(), 0.0, 1.0).ok
    False
    """
    values = _as_vector(answer, 3, "(V_r, ω1, ω3)")
    if isinstance(values, Feedback):
        return values
    truth = analytic(theta2, omega2, 0.0, saw=saw)[3:6]
    if _close(values, truth, atol=1e-9):
        return _right("Correct: a single linear solve gives the rates.")
    if _close(values, -truth, atol=1e-9):
        return _wrong("every sign is flipped: the right-hand side is minus the ω2 terms.")
    if _close(values[[0, 2, 1]], truth, atol=1e-9) or _close(values[::-1], truth, atol=1e-9):
        return _wrong("the right numbers in the wrong order: give (V_r, ω1, ω3).")
    return _wrong("check the matrix J at the position and the ω2 terms of the velocity equations.")


def check_blade_peak_speed(answer, saw: Saw, omega2: float) -> Feedback:
    """Lesson 07: the largest blade (slider) speed |ẋ| (m/s) over a revolution at constant ``omega2``
    (rad/s).  Three significant digits are enough.

    >>> check_blade_peak_speed(0.075 * 6.472, Saw(), 6.472).ok
    False
    """
    value = _as_number(answer, "the blade speed")
    if isinstance(value, Feedback):
        return value
    x = analytic(np.linspace(0.0, 2 * np.pi, 20001), omega2, 0.0, saw=saw)
    r1, theta1, v_r, omega1 = x[:, 0], x[:, 1], x[:, 3], x[:, 4]
    peak = np.abs(v_r * np.cos(theta1) - r1 * omega1 * np.sin(theta1)).max()
    if _close(abs(value), peak, rtol=2e-3):
        return _right("Correct." if value > 0 else "Correct in size; a speed is usually given positive.")
    if _close(value, saw.r2 * abs(omega2), rtol=2e-3):
        return _wrong("that is the crank pin's speed r2·ω2; the blade moves a little faster at its peak.")
    if _close(value, np.abs(v_r).max(), rtol=2e-3):
        return _wrong("that is the largest |V_r|, the rate of the length r1; the blade's speed is "
                      "ẋ = V_r cos θ1 − r1 ω1 sin θ1.")
    return _wrong(
        f"use ω2 = {omega2:.4g} rad/s and the slider speed V_r cos θ1 − r1 ω1 sin θ1 over a fine grid."
    )


def check_fivebar_theta4(answer, robot: FiveBar, x3: float, y3: float, sigma2: int) -> Feedback:
    """Lesson 09: the crank angle θ4 (rad) of leg 4 that puts the pen at (x3, y3) with σ2 = ``sigma2``.

    >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
    >>> check_fivebar_theta4(robot.inverse(0.0, 0.2, (1, -1)).theta4 - 2 * np.pi, robot, 0.0, 0.2, -1).ok
    True
    """
    value = _as_number(answer, "θ4")
    if isinstance(value, Feedback):
        return value
    this, that = (robot.inverse(x3, y3, modes=(1, s)) for s in (sigma2, -sigma2))
    verdict = _angle_feedback(
        value,
        this.theta4,
        {
            f"that is σ2 = {-sigma2:+d}: take the other sign of the square root.": that.theta4,
            "that is θ1 of leg 1; the task asks for θ4 (coefficients a2, b2, c2).": this.theta1,
        },
    )
    return verdict if verdict is not None else _wrong(
        f"recompute a2, b2, c2 with l3, l4, l5 and X3 = {x3:g}, Y3 = {y3:g}, then θ4 = 2·atan(root)."
    )


def check_reach_height(answer, robot: FiveBar, x3: float) -> Feedback:
    """Lesson 10: the height Y3 (m) at which the pen, moving up the line X = ``x3``, first stretches a leg.

    >>> check_reach_height(0.24, FiveBar(0.10, 0.15, 0.15, 0.10, 0.08), -0.03).ok
    True
    """
    value = _as_number(answer, "the height Y3")
    if isinstance(value, Feedback):
        return value
    half = robot.l5 / 2
    heights = {
        "1": np.sqrt((robot.l1 + robot.l2) ** 2 - (x3 - half) ** 2),
        "4": np.sqrt((robot.l3 + robot.l4) ** 2 - (x3 + half) ** 2),
    }
    first = min(heights, key=heights.get)
    other = "4" if first == "1" else "1"
    if _close(value, heights[first], atol=1e-9):
        return _right(f"Correct: leg {first} stretches first.")
    if _close(value, heights[other], atol=1e-9):
        return _wrong(f"that is where leg {other} stretches; the other leg gets there first.")
    if _close(value / 1000.0, heights[first], atol=1e-9):
        return _wrong("that looks like millimetres; give metres.")
    return _wrong("a leg is stretched when the pen is (proximal + distal length) from its motor; the leg "
                  "whose motor is farther from the line stretches first.")
