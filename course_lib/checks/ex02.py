"""Checkers of exercise set 02 (Newton–Raphson)."""
# ruff: noqa: F403, F405

import numpy as np

from ..errors import InvalidArgumentError
from ..fourbar import BRANCHES, FourBar
from ..newton import NewtonResult, newton
from .engine import *  # the feedback engine's helpers (engine.__all__)

__all__ = ["check_newton_update", "check_newton_iterations", "check_newton_cycle",
           "check_fourbar_newton_step", "check_seed_branch"]


def _wallis(x):
    """Newton's own example f(x) = x³ − 2x − 5 and its derivative (of a number or a sympy symbol)."""
    return x**3 - 2 * x - 5, 3 * x**2 - 2


@reads()
def check_newton_update(answer) -> Feedback:
    """Exercise 02, task 1: the Newton update x_{n+1} as a sympy expression in x for f = x³ − 2x − 5.

    >>> import sympy as sp
    >>> check_newton_update((2 * sp.Symbol("x")**3 + 5) / (3 * sp.Symbol("x")**2 - 2)).ok
    True
    """
    import sympy as sp
    x = sp.Symbol("x", real=True)
    f, df = _wallis(x)
    if isinstance(answer, sp.Equality) and "x" in (getattr(answer.lhs, "name", None),
                                                   getattr(answer.rhs, "name", None)):
        return wrong("an equation with x alone on one side: x is the current iterate, not the next one. Give "
                     "the update itself (an expression in x), or sp.Eq(x_new, …) with a new symbol.")
    if isinstance(answer, list | tuple) and 0 < len(answer) <= 10 and all(
            getattr(root, "free_symbols", None) == set() and abs(complex(_wallis(root)[0])) < 1e-9
            for root in answer):
        return wrong("those are the cubic's roots (what sp.solve(f, x) gives); the task asks for the update "
                     "formula x_{n+1} in x, the step from any x.")
    return judge_expression(answer, (x,), [
        (x - f / df, "Correct: x − f/f' (for this cubic it simplifies to (2x³ + 5)/(3x² − 2))."),
        (x + f / df, "a sign error: the tangent reaches zero at x − f/f', not x + f/f'."),
        (x - df / f, "the fraction is upside down: divide f by its derivative f'."),
        ([f / df, -f / df], "that is the step Δx (up to sign); the update is x_{n+1} = x_n + Δx."),
        (x - f, "the derivative is missing: Newton divides f by f'."),
    ], "set the tangent line f(x) + f'(x)(x_{n+1} − x) to zero and solve for x_{n+1}.")


_ROOT_AND_COUNT = fields("a pair (root, iterations)", number("the root"), integer("the number of iterations"))


def _root_and_count(answer):
    """The pair (root, iterations), and the run itself when it is given (a NewtonResult is
    (result.x, result.iterations)), else None."""
    run = answer if isinstance(answer, NewtonResult) else None
    read = _ROOT_AND_COUNT((run.x, run.iterations) if run is not None else answer)
    return read if isinstance(read, Feedback) else (*read, run)


@reads(_root_and_count)
def check_newton_iterations(answer) -> Feedback:
    """Exercise 02, task 2: (root to 6 decimals, number of updates) of Newton on x³ − 2x − 5 = 0 from 2,
    |Δx| < 1e-6; the NewtonResult of the run passes too.

    >>> check_newton_iterations((2.0945514815423265, 4)).ok
    True
    """
    root, count, run = answer
    reference = newton(lambda x: _wallis(x)[0], 2.0, jac=lambda x: _wallis(x)[1])
    six = Precision(6, decimals=True)
    far, n = not six.agrees(root, reference.x), reference.iterations
    short = six.more_digits(root, reference.x) if far else None
    if short is not None:  # the root rounded to fewer decimals than asked: not a method error
        return short
    return first([
        (far and abs(root - reference.x) <= 1.5e-6,
         "within a unit of the sixth decimal, but not the root rounded to 6 decimals: check how the last "
         "digit is rounded."),
        (far and abs(np.polyval([1, 0, -2, -5], root)) < 1e-3, "close, but not within the tolerance: keep "
                                                               "iterating until |Δx| < 1e-6."),
        (far, "that root does not satisfy x³ − 2x − 5 = 0; check f and f' in your loop."),
        (run is not None and count != n, f"your run stopped {'after' if count > n else 'before'} the first "
                                         "update whose step |Δx| is below 1e-6, where the task stops: call "
                                         "newton with tol=1e-6."),
        (count == n + 1, "one iteration too many: the seed x0 is not an iteration; count the updates."),
        (count == n - 1, "one iteration too few: the last update is the one whose step falls below 1e-6."),
        (count != n, "the root is right, but recount the updates x_n → x_{n+1} until |Δx| < 1e-6."),
    ], "Correct: quadratic convergence — a handful of updates from a good seed.")


def check_newton_cycle(answer) -> Feedback:
    """Exercise 02, task 3: why Newton on x³ − 2x + 2 from x0 = 0 never converges.

    >>> check_newton_cycle("a").ok
    True
    """
    return choice(answer, "a", {
        "b": "f'(x) = 3x² − 2 is not zero at the iterates 0 and 1, so every step is defined; look at the "
             "history.",
        "c": "the iterates stay bounded (look at err.result.history): nothing runs off to infinity.",
        "d": "a cubic always has a real root (plot it); Newton just never gets near it from 0.",
    }, "Correct: 0 → 1 → 0 → 1 … a 2-cycle. The tangent at 0 points to 1 and the tangent at 1 back to 0.")


#: The task arguments of a Newton step of the four-bar loop, by kind (engine.task_argument).
_NEWTON_TASK = {"linkage": FourBar, "theta2": "rad", "seed": "pair rad"}


def _step_exists(linkage: FourBar, theta2: float, seed: np.ndarray) -> None:
    """A Newton step from ``seed`` exists: the loop Jacobian there is not singular (θ3 = θ4 modulo π)."""
    J = linkage.loop_jacobian(*seed)
    if not np.linalg.cond(J) < 1e10:
        raise InvalidArgumentError(f"the loop Jacobian is singular at seed={tuple(seed.tolist())} (θ3 and θ4 "
                                   "in line), so the Newton step from it is undefined: no reference answer "
                                   "exists for this task")


def _branch_reached(linkage: FourBar, theta2: float, seed: np.ndarray) -> None:
    """Newton from ``seed`` converges, at a crank angle ``theta2`` where the loop closes."""
    task_possible(lambda: [linkage.solve(theta2, branch=b).theta4 for b in BRANCHES],
                  f"the four-bar cannot be assembled at theta2={theta2:.6g}")
    task_possible(lambda: newton(lambda x: linkage.loop_residual(theta2, *x), seed,
                                 jac=lambda x: linkage.loop_jacobian(*x)).x,
                  f"Newton does not converge from seed={tuple(seed.tolist())} at theta2={theta2:.6g}")


@reads(vector(2, "the step Δx"), task=_NEWTON_TASK, possible=_step_exists)
def check_fourbar_newton_step(answer, linkage: FourBar, theta2: float, seed) -> Feedback:
    """Exercise 02, task 4: the first Newton step (Δθ3, Δθ4) (rad, to 4 significant figures) of the four-bar
    loop from ``seed``.

    >>> check_fourbar_newton_step((0.0, 0.0), FourBar(0.07, 0.20, 0.15, 0.25), 0.7, (0.5, 1.5)).ok
    False
    """
    seed = np.asarray(seed, float)
    F, J = linkage.loop_residual(theta2, *seed), linkage.loop_jacobian(*seed)
    step = np.linalg.solve(J, -F)
    return diagnose(answer, FIGURES, [
        (step, "Correct: Δx solves J·Δx = −F (np.linalg.solve finds it without forming J⁻¹)."),
        (seed + step, "that is the new iterate x1 = x0 + Δx; the task asks for the step Δx itself."),
        (-step, "a sign error: the step solves J·Δx = −F (minus the residual)."),
        (step[::-1], "the entries are swapped: order them (Δθ3, Δθ4) like the unknowns."),
        (np.linalg.solve(J.T, -F), "the Jacobian is transposed: row i holds ∂F_i/∂θ3, ∂F_i/∂θ4."),
        (np.linalg.solve(J, -linkage.loop_residual(np.degrees(theta2), *seed)),
         "θ2 went into the loop in degrees; convert it with np.radians."),
    ], "check F (the two loop components at the seed) and J = ∂F/∂(θ3, θ4), then solve J·Δx = −F.")


@reads(word(BRANCHES, 'answer "open" or "crossed" (a string).'), task=_NEWTON_TASK, possible=_branch_reached)
def check_seed_branch(answer, linkage: FourBar, theta2: float, seed) -> Feedback:
    """Exercise 02, task 5: which assembly ("open" or "crossed") Newton reaches from ``seed``.

    >>> check_seed_branch("crossed", FourBar(0.07, 0.20, 0.15, 0.25), 0.7, (-0.8, -2.0)).ok
    True
    """
    theta4 = newton(lambda x: linkage.loop_residual(theta2, *x), np.asarray(seed, float),
                    jac=lambda x: linkage.loop_jacobian(*x)).x[1]
    reached = [b for b in BRANCHES if angles_close(theta4, linkage.solve(theta2, branch=b).theta4)]
    return first([(answer not in reached,
                   "that is the other assembly. Solve from the seed, then compare θ4 with FourBar.solve(θ2, "
                   'assembly="open") and assembly="crossed" (angles modulo 2π).')],
                 "Correct: the seed, not the equations, picks the assembly — compare your θ4 with the closed "
                 "form of each assembly.")
