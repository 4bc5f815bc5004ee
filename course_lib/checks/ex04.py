"""Checkers of exercise set 04 (the power saw)."""
# ruff: noqa: F403, F405

import itertools
import sys
from dataclasses import dataclass

import numpy as np

from ..errors import CourseLibError
from ..motion import Motion
from ..newton import NewtonResult
from ..saw import (
    COURSE_SAW,
    SEED_CODE,
    SEED_PRINTED,
    VARIANTS,
    Saw,
    SawMotion,
    analytic,
    position_jacobian,
    position_residual,
    system_jacobian,
    system_residual,
)
from .engine import *  # the feedback engine's helpers (engine.__all__)

__all__ = ["check_saw_omega3_expression", "check_saw_position", "check_saw_r1_sign",
           "check_saw_slider_acceleration", "check_saw_linear_stage"]


@reads()
def check_saw_omega3_expression(answer) -> Feedback:
    """Exercise 04, task 1: ω3 of the saw as a sympy expression in r2, r3, θ2, θ3, ω2.

    >>> import sympy as sp
    >>> r2, r3, t2, t3, w2 = sp.symbols("r2 r3 theta2 theta3 omega2")
    >>> check_saw_omega3_expression(-w2 * r2 * sp.cos(t2) / (r3 * sp.cos(t3))).ok
    True
    """
    import sympy as sp
    r1y, r2, r3, _, t2, t3, w2 = symbols = sp.symbols("r1y r2 r3 theta1 theta2 theta3 omega2", real=True)
    reference = -w2 * r2 * sp.cos(t2) / (r3 * sp.cos(t3))
    swapped = -w2 * r2 * sp.sin(t2) / (r3 * sp.sin(t3))
    return judge_expression(answer, symbols, [
        (reference, "Correct: ω3 = −ω2·r2·cos θ2 / (r3·cos θ3), from the derivative of Fy − Fc."),
        (lambda expr: expr.has(r1y) and not expr.has(t3),
         "your ω3 has θ3 eliminated (through r1y): the task asks for ω3 in r2, r3, θ2, θ3, ω2 — keep θ3, as "
         "the velocity equation gives it (cos θ3 in the denominator)."),
        (-reference, "a sign error: differentiate r2 sin θ2 + r3 sin θ3 = r1y (constant) and solve for ω3."),
        ([swapped, -swapped], "sin and cos are swapped: d(sin θ)/dt = ω cos θ."),
        (lambda expr: not expr.has(w2) and expr.has(r1y),
         "ω3 must be proportional to ω2; this looks like θ1's formula (the report's eq. 23 is labelled ω3 "
         "but repeats θ1's formula — don't copy that slip)."),
        (lambda expr: not expr.has(w2), "ω3 must be proportional to ω2: the velocity equations are."),
        (lambda expr: not expr.has(r2) or not expr.has(r3),
         "keep r2 and r3 as symbols (a length put in as its number, or left out, gives this): ω3 in r2, r3, "
         "θ2, θ3, ω2."),
    ], "use the y-equation without r1: r2 sin θ2 + r3 sin θ3 = r1y, differentiate in time.")


#: The Newton methods a task may grade, as the course names them: the solver that runs it, the unknowns its
#: iterates hold (the consecutive method's position stage: r1, θ1, θ3; the simultaneous one: all nine).
_METHODS = {"consecutive": ("solve_consecutive", 3), "simultaneous": ("solve_simultaneous", 9)}


@dataclass(frozen=True)
class _Solve:
    """A solve given as the answer: the nine values (or the position alone) it ends at, and the Newton
    iterates behind them (seed first; None for the closed form), what made them, in words."""

    values: np.ndarray
    iterates: np.ndarray | None
    method: str | None  # "consecutive" or "simultaneous" (its iterates), None when it is not known
    what: str


def _solve(answer) -> "_Solve | Feedback | None":
    """The answer read as a solve — a saw Motion (from a solver or the closed form), a NewtonResult, or a
    table of Newton iterates (rows of 3 or 9 numbers, the seed first) — or None for plain numbers."""
    if isinstance(answer, Motion):
        if not isinstance(answer, SawMotion):
            return wrong(f"that is a {type(answer).__name__}, a solve of another machine; the task is about "
                         "the saw (my_saw).")
        values = np.asarray(answer.x, dtype=float)
        if values.ndim != 1:
            return wrong(f"that Motion holds {values.shape[0]} crank angles; the task asks for one.")
        stages = getattr(answer, "stages", None) or {}
        if "position" in stages:
            return _Solve(values, np.asarray(stages["position"].history, float), "consecutive",
                          "the Motion solve_consecutive returns")
        if "simultaneous" in stages:
            return _Solve(values, np.asarray(stages["simultaneous"].history, float), "simultaneous",
                          "the Motion solve_simultaneous returns")
        return _Solve(values, None, None, "a Motion of the closed form (my_saw.motion), which holds no "
                                          "Newton iterations")
    if isinstance(answer, NewtonResult):
        iterates, what = answer.history, "a NewtonResult"
    elif isinstance(answer, list | tuple | np.ndarray) and _rows(answer) and len(answer) > 1:
        iterates, what = answer, "your iterates"
    elif _is_matrix(answer) and answer.shape[0] > 1 and answer.shape[1] in (3, 9):  # one row per iterate
        iterates, what = answer.tolist(), "your iterates"
    else:
        return None
    iterates = np.array(iterates, dtype=float) if not isinstance(iterates, np.ndarray) or \
        iterates.dtype.kind not in "iuf" else iterates.astype(float)
    if iterates.ndim == 3 and 1 in iterates.shape[1:]:  # each iterate a column or a row (sympy Matrices)
        iterates = iterates.reshape(len(iterates), -1)
    if iterates.ndim != 2 or iterates.shape[1] not in (3, 9) or not np.all(np.isfinite(iterates)):
        return wrong(f"{what} should be the Newton iterates, one row of 3 numbers (r1, θ1, θ3) or of the "
                     f"nine unknowns per iteration, the seed first; got shape {iterates.shape}.")
    method = "consecutive" if iterates.shape[1] == 3 else "simultaneous"
    values = iterates[-1] if method == "simultaneous" else np.concatenate([iterates[-1], np.full(6, np.nan)])
    return _Solve(values, iterates, method, what)


def _rows(answer) -> bool:
    """Whether ``answer`` is a table: rows of numbers of one length (a ragged list is not)."""
    try:
        shape = np.shape(answer)
    except ValueError:  # a ragged nested list: numpy refuses its shape
        return False
    return len(shape) == 2 or len(shape) == 3 and 1 in shape[1:]  # rows, or columns / rows as matrices


def _is_matrix(answer) -> bool:
    """Whether ``answer`` is a sympy Matrix (read without importing sympy where it is not loaded)."""
    sympy = sys.modules.get("sympy")
    return sympy is not None and isinstance(answer, sympy.MatrixBase)


def _newton_work(solve: "_Solve | None", method: str, saw: Saw, theta2: float, omega2: float = 0.0,
                 alpha2: float = 0.0) -> Feedback | None:
    """Why ``solve`` does not show the asked Newton method (``method``) at work; None when it does: iterates
    from the report's seed, each step a Newton step J(x_k)·Δx = −F(x_k) of the course's equations (in its
    "loop" or "substituted" form), recomputed here at the student's own iterates, run until converged."""
    solver, size = _METHODS[method]
    asked = (f"the task asks for {method} Newton–Raphson: store the solve itself — what {solver} returns, a "
             "Motion that keeps its Newton iterations — or your own iterates, the report's seed first")
    if solve is None:
        return wrong(f"the numbers are right, but {asked}; numbers alone do not show how they were found.")
    if solve.iterates is None:
        return wrong(f"the numbers are right, but that is {solve.what}; {asked}.")
    if solve.method != method:
        return wrong(f"the numbers are right, but they come from {solve.method} Newton ({solve.what}); "
                     f"{asked}.")
    seeds = [SEED_PRINTED[:size], SEED_CODE[:size]]
    if not any(np.allclose(solve.iterates[0], seed, rtol=0, atol=1e-12) for seed in seeds):
        if any(np.allclose(solve.iterates[0], seed, rtol=0, atol=1e-6) for seed in seeds):
            return wrong(f"{solve.what} start from the report's seed only to about 7 digits (float32 "
                         "numbers, or a seed typed rounded): keep the seed exactly as the report prints it, "
                         "in float64.")
        return wrong(f"{solve.what} start from {np.round(solve.iterates[0], 6).tolist()}, not from the "
                     f"report's seed {seeds[0].tolist()}: {asked}.")
    reading = _reading(solve, saw, theta2, omega2, alpha2)
    if reading is None:
        unread = _unreadable(solve)
        if unread is not None:
            return unread
        k = max(_first_off(solve.iterates, saw, theta2, omega2, alpha2, variant) for variant in VARIANTS)
        return wrong(f"step {k} of {solve.what} is not a Newton step of the saw's equations: from iterate "
                     f"{k - 1} Newton goes to x + Δx with J(x)·Δx = −F(x) ({asked}).")
    if reading.slips == [f"ω2 = {-omega2:.6g} rad/s"] and not reading.left and reading.rounded is None:
        return wrong(f"{solve.what} are Newton's steps of the saw's equations at ω2 = {-omega2:.6g} rad/s; "
                     f"the task's motor turns at ω2 = {omega2:.6g} rad/s: the sign of ω2 is flipped (a_r "
                     "holds ω2 only squared, so it comes out right all the same).")
    if reading.off:
        return wrong("the numbers are right to the task's precision, but " + reading.words(solve.what))
    return None


@dataclass(frozen=True)
class _Reading:
    """What Newton iterates are: Newton's steps of the saw's equations at ``slips`` (what differs from the
    task's saw, θ2, ω2, α2; none: the task's own), ``rounded`` to that many decimals (None: not), and
    ``left``, how far one more Newton step from the last iterate would move an unknown (0 when converged)."""

    slips: list
    rounded: int | None
    left: float

    @property
    def off(self) -> bool:
        """Whether they are anything but the task's own Newton steps, unrounded and converged."""
        return bool(self.slips or self.left or self.rounded is not None)

    def words(self, what: str) -> str:
        """The reading in words, after "the numbers are …, but " or on its own."""
        parts = []
        if self.slips:
            parts.append(f"{what} are Newton's steps of the saw's equations at {'; '.join(self.slips)}, not "
                         "the task's")
        if self.left:
            parts.append(f"{'the run' if parts else what} stopped before converging (one more Newton "
                         f"step from the last iterate moves an unknown by {self.left:.1e}): iterate until "
                         "the step is below the tolerance")
        if self.rounded is not None:
            parts.append(f"{'they' if parts else what} look rounded to {self.rounded} decimals: keep the "
                         "iterates unrounded (the check takes each Newton step again from them)")
        return "; ".join(parts) + "."


#: One more Newton step from the last iterate moving no unknown by more than this (times their size, at least
#: 1) marks a run as converged: the course's tolerance.
_CONVERGED = 1e-6


def _equations(iterates, saw, theta2, omega2, alpha2, variant):
    """F and J of the saw's equations whose unknowns the iterates hold (3: the position; 9: all)."""
    if iterates.shape[1] == 3:
        return (lambda x: position_residual(x, theta2, saw=saw, variant=variant),
                lambda x: position_jacobian(x, saw=saw, variant=variant))
    return (lambda x: system_residual(x, theta2, omega2, alpha2, saw=saw, variant=variant),
            lambda x: system_jacobian(x, saw=saw, variant=variant))


def _first_off(iterates: np.ndarray, saw: Saw, theta2: float, omega2: float, alpha2: float,
               variant: str, slack: float = 0.0) -> int | None:
    """The first step (from 1) of ``iterates`` (rows of 3 or 9 unknowns) that is not a Newton step
    J(x)·Δx = −F(x) of the saw's equations in form ``variant`` at these motor values (to ``slack`` times the
    size of the iterate it reaches more, for rounded iterates); None if every one is."""
    equations = _equations(iterates, saw, theta2, omega2, alpha2, variant)
    with np.errstate(all="ignore"):
        for k, (x, following) in enumerate(zip(iterates[:-1], iterates[1:], strict=True), start=1):
            step = _step(*equations, x)
            if step is None:
                return k
            room = slack * max(1.0, float(np.max(np.abs(following))))
            if not np.max(np.abs(following - x - step)) <= 1e-9 + room + 1e-6 * np.max(np.abs(step)):
                return k
    return None


def _step(residual, jacobian, x) -> np.ndarray | None:
    """Newton's step Δx from ``x``, J(x)·Δx = −F(x); None where J cannot be solved with."""
    with np.errstate(all="ignore"):
        try:
            return np.linalg.solve(jacobian(x), -residual(x))
        except (np.linalg.LinAlgError, CourseLibError):
            return None


def _left(iterates, saw, theta2, omega2, alpha2, variant) -> float:
    """How far one more Newton step from the last iterate moves an unknown, 0 below the course's tolerance."""
    x = iterates[-1]
    step = _step(*_equations(iterates, saw, theta2, omega2, alpha2, variant), x)
    moved = 0.0 if step is None else float(np.max(np.abs(step)))
    return moved if moved > _CONVERGED * max(1.0, float(np.max(np.abs(x)))) else 0.0


def _rounded(iterates: np.ndarray) -> int | None:
    """The decimals ``iterates`` (after the seed) were rounded to, if they look rounded (to at most 10)."""
    rest = iterates[1:]
    for decimals in range(1, 11):
        scaled = rest * 10.0**decimals
        if np.all(np.abs(scaled - np.round(scaled)) <= 1e-6 + 8 * np.finfo(float).eps * np.abs(scaled)):
            return decimals
    return None


def _single(iterates: np.ndarray) -> bool:
    """Whether the iterates after the seed are float32 numbers (each exactly a float32)."""
    rest = iterates[1:]
    return bool(np.all(rest.astype(np.float32).astype(float) == rest))


def _reading(solve: "_Solve", saw: Saw, theta2: float, omega2: float = 0.0, alpha2: float = 0.0
             ) -> _Reading | None:
    """The solve's iterates read as a teacher would: Newton's steps of the saw's equations at the task's saw,
    θ2, ω2, α2 — or at the course's saw, θ2 taken in degrees, ω2 or α2 of the other sign — rounded or not,
    converged or not; None where they are Newton's steps of none of these."""
    iterates = solve.iterates
    if iterates is None or len(iterates) < 2:
        return None
    decimals = _rounded(iterates)
    if decimals is not None and decimals < 3:  # too coarse to tell Newton's steps from others
        return None
    slack = 0.0 if decimals is None else 10 * 10.0**-decimals  # times the size of each iterate
    saws = [(saw, None)]
    if saw != COURSE_SAW:
        saws.append((COURSE_SAW, "the course's saw (pass saw=my_saw)"))
    degrees = np.degrees(theta2)
    angles = [(theta2, None), (degrees, f"θ2 = {degrees:.6g} rad (the crank angle in degrees; the task's θ2 "
                                        f"is {theta2:.6g} rad: np.radians)")]
    flips = [((omega2, alpha2), [])]
    if iterates.shape[1] == 9:
        w, a = f"ω2 = {-omega2:.6g} rad/s", f"α2 = {-alpha2:.6g} rad/s²"
        flipped = (((-omega2, alpha2), [w]), ((omega2, -alpha2), [a]), ((-omega2, -alpha2), [w, a]))
        flips += [(rates, slips) for rates, slips in flipped if rates != (omega2, alpha2)]
    for (that_saw, saw_slip), (angle, angle_slip), (rates, rate_slips) in itertools.product(saws, angles,
                                                                                           flips):
        for variant in VARIANTS:
            if _first_off(iterates, that_saw, angle, *rates, variant, slack) is None:
                slips = [slip for slip in (saw_slip, angle_slip) if slip] + rate_slips
                left = _left(iterates, that_saw, angle, *rates, variant)
                rounding = slack / 10 * max(1.0, float(np.max(np.abs(iterates[-1]))))  # a unit of the last
                return _Reading(slips, decimals, left if left > rounding else 0.0)
    return None


def _explained(solve: "_Solve | None", saw: Saw, theta2: float, omega2: float = 0.0,
               alpha2: float = 0.0) -> Feedback | None:
    """Why a solve's Newton iterates end at a wrong value, read from the iterates themselves
    (:func:`_reading`); None where they say nothing the value's own diagnosis does not."""
    if solve is None or solve.iterates is None or len(solve.iterates) < 2:
        return None
    reading = _reading(solve, saw, theta2, omega2, alpha2)
    if reading is None:
        return _unreadable(solve)
    return wrong(reading.words(solve.what)) if reading.off else None


def _unreadable(solve: "_Solve") -> Feedback | None:
    """Why iterates that are no one's Newton steps may still be the student's Newton run: float32 numbers, or
    rounded ones (too coarse for :func:`_reading` to read); None where they are neither."""
    why = ("after the seed are float32 numbers (about 7 digits): keep them in float64"
           if _single(solve.iterates) else None)
    decimals = _rounded(solve.iterates)
    if why is None and decimals is not None:
        why = f"look rounded to {decimals} decimals: keep them unrounded"
    return None if why is None else wrong(f"{solve.what} {why} (the check takes each Newton step again "
                                          "from them).")


def _closes(saw: Saw, theta2: float, omega2: float = 0.0, alpha2: float = 0.0, **_) -> None:
    """The saw closes at ``theta2`` (the rod reaches the slider line, not perpendicular to it)."""
    task_possible(lambda: analytic(theta2, omega2, alpha2, saw=saw),
                  f"the saw cannot close at theta2={theta2:.6g} (the rod r3 cannot reach the slider line "
                  "there, or stands perpendicular to it)")


def _numbers(answer, picks: slice | int, parse, theta2: float):
    """(the numbers a task judges, the solve they come from): from a solve (:func:`_solve`) its values at
    ``picks``, else the answer read by ``parse``; the feedback instead when neither reads (or a Motion is
    solved at another crank angle than the task's ``theta2``)."""
    solve = _solve(answer)
    if isinstance(solve, Feedback):
        return solve, None
    if solve is None:
        return parse(answer), None
    solved_at = answer.inputs.get("theta2") if isinstance(answer, Motion) else None
    if solved_at is not None and not angles_close(solved_at, theta2):
        slip = in_degrees(solved_at, theta2)
        degrees = " (the angle went into the solver in degrees: np.radians)" if slip else ""
        return wrong(f"that Motion is solved at θ2 = {float(solved_at):.6g} rad; the task's crank angle is "
                     f"θ2 = {theta2:.6g} rad{degrees}."), solve
    values = solve.values[picks]
    if not np.all(np.isfinite(values)):
        return wrong(f"{solve.what} hold only r1, θ1, θ3; the task asks for a_r, one of the nine unknowns: "
                     "iterate the nine at once (the 9×9 system)."), solve
    return (float(values) if np.ndim(values) == 0 else values), solve


def _graded(verdict: Feedback, solve, method, saw, theta2, omega2=0.0, alpha2=0.0) -> Feedback:
    """The verdict on the numbers, and with ``method`` the method's own: right numbers without the asked
    Newton work are not ✔."""
    if not verdict.ok:
        why = _explained(solve, saw, theta2, omega2, alpha2)
        return verdict if why is None else why
    if method is None:
        return verdict
    work = _newton_work(solve, method, saw, theta2, omega2, alpha2)
    if work is not None:
        return work
    runs = len(solve.iterates) - 1
    return Feedback(True, f"{verdict.message} By {method} Newton from the report's seed: {runs} iterations.")


@reads(task={"saw": Saw, "theta2": "rad", "method": (None, "consecutive")}, possible=_closes)
def check_saw_position(answer, saw: Saw, theta2: float, method: str | None = None) -> Feedback:
    """Exercise 04, task 2: (r1 in m, θ1, θ3 in rad), to 4 decimals, at crank angle ``theta2``; the same
    vector r1 written as (−r1, θ1 + π) passes too.  A solve passes as the answer (a saw Motion, a
    NewtonResult, or Newton iterates seed first: its last position); with ``method="consecutive"`` only a
    solve that shows the consecutive Newton's position stage from the report's seed does.

    >>> check_saw_position(analytic(0.9, saw=Saw())[:3], Saw(), 0.9).ok
    True
    >>> check_saw_position(Saw().motion(0.9), Saw(), 0.9, method="consecutive").ok  # the closed form
    False
    """
    numbers, solve = _numbers(answer, slice(0, 3), vector(3, "(r1, θ1, θ3)"), theta2)
    if isinstance(numbers, Feedback):
        return numbers
    return _graded(_position_verdict(numbers, saw, theta2), solve, method, saw, theta2)


def _position_verdict(answer: np.ndarray, saw: Saw, theta2: float) -> Feedback:
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
         "θ3 is on the other assembly: asin gives the rod pointing right, but the saw's rod points left, "
         "θ3 = π − asin((r1y − r2 sin θ2)/r3)."),
        (lambda v: any(in_degrees(v[i], angle, DECIMALS) for i, angle in degrees),
         "an angle is in degrees; give θ1 and θ3 in radians."),
        (lambda v: not DECIMALS.agrees(v[2], theta3, angles=True), "θ3 is off: Fy − Fc gives r2 sin θ2 + "
                                                                   "r3 sin θ3 = r1y."),
    ], "θ3 is right; recheck r1 and θ1 from r1 sin θ1 = r1y and r1 cos θ1 = r2 cos θ2 + r3 cos θ3.",
        angles=(False, True, True))


def check_saw_r1_sign(answer) -> Feedback:
    """Exercise 04, task 2: why r1 comes out negative at θ2 = 50° (a letter).

    >>> check_saw_r1_sign("a").ok, check_saw_r1_sign("d").ok
    (True, False)
    """
    return choice(answer, "a", {
        "b": "a length to the left is not negative by itself: the same vector r1 is written with r1 > 0 and "
             "θ1 + π just as well. What fixes the sign is the range the course keeps θ1 in.",
        "c": "the solve converged (its residuals are below the tolerance); r1 is a signed coordinate along "
             "the direction θ1, not a distance, and its sign goes with the range of θ1.",
        "d": "the seed does not set the sign: r1 > 0 with the same θ1 (sin θ1 < 0) would give r1 sin θ1 < 0, "
             "below O2, off the slider line r1 sin θ1 = r1y > 0. A run that ends at r1 > 0 ends at θ1 + π, "
             "the same vector.",
    }, "Correct: with θ1 in (−π/2, π/2], cos θ1 ≥ 0, and the slider lies left of O2 (r1 cos θ1 = r2 cos θ2 "
       "+ r3 cos θ3 < 0), so r1 < 0; written with θ1 + π the same vector has r1 > 0.")


@reads(task={"saw": Saw, "theta2": "rad", "omega2": "rad/s", "alpha2": "rad/s²",
             "method": (None, "simultaneous")}, possible=_closes)
def check_saw_slider_acceleration(answer, saw: Saw, theta2: float, omega2: float, alpha2: float,
                                  method: str | None = None) -> Feedback:
    """Exercise 04, task 3: a_r (m/s², to 4 significant figures), the second derivative of the signed length
    r1 (not the slider's own acceleration ẍ), at the given motor state.  A solve passes as the answer (a saw
    Motion, a NewtonResult, or Newton iterates of the nine unknowns seed first); with
    ``method="simultaneous"`` only a solve that shows the 9×9 Newton from the report's seed does.

    >>> check_saw_slider_acceleration(analytic(0.9, 6.0, 4.0, saw=Saw())[6], Saw(), 0.9, 6.0, 4.0).ok
    True
    """
    numbers, solve = _numbers(answer, 6, number("a_r"), theta2)
    if isinstance(numbers, Feedback):
        return numbers
    return _graded(_acceleration_verdict(numbers, saw, theta2, omega2, alpha2), solve, method, saw, theta2,
                   omega2, alpha2)


def _acceleration_verdict(answer: float, saw: Saw, theta2: float, omega2: float, alpha2: float) -> Feedback:
    x = analytic(theta2, omega2, alpha2, saw=saw)
    r1, theta1, _, v_r, omega1, _, a_r, alpha1, _ = x
    slider = (a_r * np.cos(theta1) - 2 * v_r * omega1 * np.sin(theta1)
              - r1 * (alpha1 * np.sin(theta1) + omega1**2 * np.cos(theta1)))  # ẍ of x = r1 cos θ1
    return diagnose(answer, FIGURES, [
        (x[6], "Correct: a_r holds the α2 terms and every ω² term (r1 ω1², r2 ω2², r3 ω3²)."),
        ([x[6] / 1000.0, x[6] * 1000.0], "a factor 1000: lengths in metres give a_r in m/s²."),
        (-x[6], "a sign error: a_r is along r1, and r1 < 0 here (the course's convention)."),
        (analytic(theta2, 0.0, 0.0, saw=saw)[6], "that is a_r with the crank at rest (ω2 = α2 = 0): solve at "
                                                 "the task's ω2 and α2 too."),
        (analytic(theta2, 0.0, alpha2, saw=saw)[6],
         "that keeps only the α2 terms: the ω² (centripetal) terms — r1 ω1², r2 ω2², r3 ω3² — are missing, "
         "and at speed they dominate."),
        (lambda v: alpha2 != 0 and FIGURES.agrees(v, analytic(theta2, omega2, 0.0, saw=saw)[6]),
         "that is a_r with α2 = 0: the motor's angular acceleration α2 is part of the task's state; pass it "
         "to the solve too."),
        (lambda v: omega2 != alpha2 and FIGURES.agrees(v, analytic(theta2, alpha2, omega2, saw=saw)[6]),
         "that is a_r with ω2 and α2 swapped: give the solve ω2 (rad/s) then α2 (rad/s²)."),
        (lambda v: alpha2 != 0 and FIGURES.agrees(v, analytic(theta2, omega2, -alpha2, saw=saw)[6]),
         "that is a_r with α2 of the other sign: give the solve the task's α2, sign and all (rad/s²)."),
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
