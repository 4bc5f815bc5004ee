"""Newton–Raphson for scalars, small systems, and many independent systems at once.

The stopping rule is the course's: stop when the step ‖x_{n+1} − x_n‖ < ``tol``.
A residual check is added so that a tiny step far from a root is not mistaken
for convergence: ‖F(x_{n+1})‖ must also be ≤ ``residual_tol`` (default ``tol``).
Linear steps are taken with ``numpy.linalg.solve``; no inverse is ever formed.

>>> from course_lib.newton import newton
>>> result = newton(lambda x: x**2 - 2.0, 1.0, jac=lambda x: 2.0 * x)
>>> round(result.x, 12), result.iterations, result.converged
(1.414213562373, 5, True)
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .errors import ConvergenceError, InvalidGeometryError, SingularJacobianError

__all__ = [
    "NewtonResult",
    "BatchNewtonResult",
    "newton",
    "newton_batch",
    "finite_difference_jacobian",
    "singular_jacobian_text",
]

#: A Jacobian whose 2-norm condition number exceeds this is treated as singular.
MAX_CONDITION = 1e12


def singular_jacobian_text(condition: float) -> str:
    """How a rejected Jacobian is described: by the bound it broke, not by round-off digits.

    The condition number of an exactly singular matrix is inf on one machine and 4e16 on another,
    so only the bound is stated.

    >>> singular_jacobian_text(float("inf"))
    'singular (condition number > 1e+12)'
    """
    return f"singular (condition number > {MAX_CONDITION:.0e})"


@dataclass(frozen=True)
class NewtonResult:
    """What one Newton run did.

    Attributes
    ----------
    x : the last iterate (a float for a scalar problem, else an array of shape (n,)).
    converged : True when the step and residual tests both passed.
    iterations : number of updates x_n → x_{n+1} performed.
    history : x_0 followed by every iterate, shape (iterations + 1, n).
    step_norms : ‖x_{n+1} − x_n‖ (2-norm) for each iteration, shape (iterations,).
    step_components : |x_{n+1} − x_n| per variable, shape (iterations, n).
    residual_norms : ‖F(x_k)‖ for k = 0 … iterations, shape (iterations + 1,).
    """

    x: float | np.ndarray
    converged: bool
    iterations: int
    history: np.ndarray
    step_norms: np.ndarray
    step_components: np.ndarray
    residual_norms: np.ndarray


@dataclass(frozen=True)
class BatchNewtonResult:
    """What a batched Newton run did, one entry per system.

    Attributes
    ----------
    x : last iterates, shape (N, n).
    converged : per-system convergence, shape (N,).
    iterations : updates performed per system, shape (N,).
    singular : systems stopped because their Jacobian became (numerically) singular.
    step_norms : the last step norm per system, shape (N,).
    residual_norms : ‖F(x)‖ at the last iterate per system, shape (N,).
    """

    x: np.ndarray
    converged: np.ndarray
    iterations: np.ndarray
    singular: np.ndarray
    step_norms: np.ndarray
    residual_norms: np.ndarray


def finite_difference_jacobian(
    F: Callable[[np.ndarray], np.ndarray], x: np.ndarray, fx: np.ndarray | None = None
) -> np.ndarray:
    """Central-difference Jacobian of ``F`` at ``x``.

    ``x`` may be (n,) or a batch (N, n); ``F`` must map the same shape to the
    same shape.  The step is ε^(1/3)·max(1, |x_j|) per variable.  ``fx`` is
    accepted for signature symmetry and ignored (central differences do not
    reuse F(x)).

    >>> import numpy as np
    >>> J = finite_difference_jacobian(lambda v: np.array([v[0] * v[1], v[0]]), np.array([2.0, 3.0]))
    >>> np.round(J, 8).tolist()
    [[3.0, 2.0], [1.0, 0.0]]
    """
    x = np.asarray(x, dtype=float)
    n = x.shape[-1]
    h = np.finfo(float).eps ** (1 / 3) * np.maximum(1.0, np.abs(x))
    columns = []
    for j in range(n):
        step = np.zeros_like(x)
        step[..., j] = h[..., j]
        difference = np.asarray(F(x + step), float) - np.asarray(F(x - step), float)
        columns.append(difference / (2 * h[..., j : j + 1]))
    return np.stack(columns, axis=-1)


def _as_system(F, jac, scalar):
    """Wrap scalar callables so the loop below only deals with vectors and matrices."""
    if scalar:

        def F_vec(x):
            return np.atleast_1d(np.asarray(F(x[0]), dtype=float))

        if jac is None:
            return F_vec, lambda x: finite_difference_jacobian(F_vec, x)
        return F_vec, lambda x: np.asarray(jac(x[0]), dtype=float).reshape(1, 1)

    def F_vec(x):
        return np.asarray(F(x), dtype=float).reshape(-1)

    if jac is None:
        return F_vec, lambda x: finite_difference_jacobian(F_vec, x)
    return F_vec, lambda x: np.asarray(jac(x), dtype=float)


def _hadamard_ratio(J: np.ndarray) -> np.ndarray:
    """|det J| / Π‖row of J‖ per matrix of a stack (N, n, n): 1 for orthogonal rows, 0 when singular.

    Written out for n ≤ 3 (the mechanisms' sizes), where it is several times faster than
    ``numpy.linalg.det`` on a stack.

    >>> float(_hadamard_ratio(np.array([[[2.0, 0.0], [0.0, 3.0]]]))[0])
    1.0
    """
    N, n = J.shape[0], J.shape[-1]
    if n > 3:
        return np.abs(np.linalg.det(J)) / np.prod(np.linalg.norm(J, axis=-1), axis=-1)
    # a[n·i + j] is the contiguous column of entries J[:, i, j]
    a = np.ascontiguousarray(J.reshape(N, n * n).T)
    squares = a * a
    if n == 1:
        return np.abs(a[0]) / np.sqrt(squares[0])
    if n == 2:
        det = a[0] * a[3] - a[1] * a[2]
        rows = (squares[0] + squares[1]) * (squares[2] + squares[3])
        return np.abs(det) / np.sqrt(rows)
    det = a[0] * (a[4] * a[8] - a[5] * a[7]) - a[1] * (a[3] * a[8] - a[5] * a[6]) + a[2] * (
        a[3] * a[7] - a[4] * a[6]
    )
    rows = (squares[0] + squares[1] + squares[2]) * (squares[3] + squares[4] + squares[5])
    return np.abs(det) / np.sqrt(rows * (squares[6] + squares[7] + squares[8]))


def _check_settings(tol, max_iter):
    if not (np.isfinite(tol) and tol > 0):
        raise InvalidGeometryError(f"tol must be a positive number; got {tol!r}")
    if int(max_iter) != max_iter or max_iter < 1:
        raise InvalidGeometryError(f"max_iter must be a positive integer; got {max_iter!r}")


def newton(
    F: Callable,
    x0: float | np.ndarray,
    jac: Callable | None = None,
    tol: float = 1e-6,
    max_iter: int = 50,
    residual_tol: float | None = None,
) -> NewtonResult:
    """Solve F(x) = 0 by Newton–Raphson from the seed ``x0``.

    ``x0`` may be a number (then ``F`` and ``jac`` take and return numbers) or a
    vector of n unknowns (then ``F`` returns n residuals and ``jac`` the n×n
    Jacobian).  Without ``jac`` a central-difference Jacobian is used.

    Each iteration solves J(x_n)·Δx = −F(x_n) and sets x_{n+1} = x_n + Δx.
    It stops when ‖Δx‖ < ``tol`` and ‖F(x_{n+1})‖ ≤ ``residual_tol``.

    Raises
    ------
    SingularJacobianError : J(x_n) is singular or its condition number exceeds 1e12.
    ConvergenceError : ``max_iter`` updates without converging, or a non-finite iterate;
        ``err.result`` is the ``NewtonResult`` so far.

    >>> import numpy as np
    >>> F = lambda v: np.array([v[0] ** 2 + v[1] ** 2 - 1.0, v[0] - v[1]])
    >>> result = newton(F, np.array([1.0, 0.5]))
    >>> np.round(result.x, 9).tolist(), result.converged
    ([0.707106781, 0.707106781], True)
    """
    _check_settings(tol, max_iter)
    residual_tol = tol if residual_tol is None else float(residual_tol)
    scalar = np.ndim(x0) == 0
    x = np.atleast_1d(np.asarray(x0, dtype=float)).copy()
    if x.ndim != 1 or not np.all(np.isfinite(x)):
        raise InvalidGeometryError(f"x0 must be a finite number or 1-D vector; got {x0!r}")
    F_vec, jac_vec = _as_system(F, jac, scalar)

    history = [x.copy()]
    steps: list[np.ndarray] = []
    fx = F_vec(x)
    if fx.shape != x.shape:
        raise InvalidGeometryError(
            f"F must return {x.size} residuals for {x.size} unknowns; got shape {fx.shape}"
        )
    residuals = [float(np.linalg.norm(fx))]

    def result(converged: bool) -> NewtonResult:
        history_array = np.array(history)
        step_array = np.array(steps).reshape(-1, x.size)
        return NewtonResult(
            x=float(history_array[-1, 0]) if scalar else history_array[-1].copy(),
            converged=converged,
            iterations=len(steps),
            history=history_array[:, 0] if scalar else history_array,
            step_norms=np.linalg.norm(step_array, axis=1),
            step_components=np.abs(step_array[:, 0] if scalar else step_array),
            residual_norms=np.array(residuals),
        )

    for _ in range(int(max_iter)):
        J = jac_vec(x)
        condition = np.linalg.cond(J) if np.all(np.isfinite(J)) else np.inf
        if not condition < MAX_CONDITION:
            where = float(x[0]) if scalar else x.tolist()
            raise SingularJacobianError(
                f"the Jacobian is {singular_jacobian_text(condition)} at x={where}; "
                "Newton cannot take a step from here: try another seed",
                x=where,
                condition_number=condition,
            )
        with np.errstate(over="ignore", invalid="ignore"):  # divergence is reported below
            step = np.linalg.solve(J, -fx)
            x = x + step
            fx = F_vec(x)
            history.append(x.copy())
            steps.append(step)
            residuals.append(float(np.linalg.norm(fx)))
        if not (np.all(np.isfinite(x)) and np.all(np.isfinite(fx))):
            raise ConvergenceError(
                f"Newton diverged: a non-finite value appeared after {len(steps)} iterations",
                result=result(False),
            )
        if np.linalg.norm(step) < tol and residuals[-1] <= residual_tol:
            return result(True)

    last = result(False)
    raise ConvergenceError(
        f"Newton did not converge in max_iter={max_iter} iterations "
        f"(last step {last.step_norms[-1]:.3g}, residual {last.residual_norms[-1]:.3g})",
        result=last,
    )


def _row_norms(a: np.ndarray) -> np.ndarray:
    """The 2-norm of each row of an (N, n) array."""
    return np.sqrt(np.einsum("ij,ij->i", a, a))


def newton_batch(
    F: Callable[[np.ndarray], np.ndarray],
    x0: np.ndarray,
    jac: Callable[[np.ndarray], np.ndarray] | bool | None = None,
    tol: float = 1e-6,
    max_iter: int = 50,
    residual_tol: float | None = None,
) -> BatchNewtonResult:
    """Solve N independent systems F(x_i) = 0 at once, one vectorized loop.

    ``x0`` has shape (N, n); ``F`` maps the whole (N, n) array of iterates to
    (N, n) residuals and ``jac`` to (N, n, n) Jacobians (row i of the output
    depends only on row i of the input).  ``jac=True`` means that ``F`` returns
    the pair (residuals, Jacobians), so that the two can share their work (as
    ``jac=True`` in ``scipy.optimize.root``).  Each system stops on its own by the
    same rule as :func:`newton`; rows that have stopped are no longer updated.
    Nothing is raised for a system that fails: see ``converged`` and
    ``singular`` in the result.

    >>> import numpy as np
    >>> targets = np.array([[2.0], [9.0]])
    >>> result = newton_batch(lambda x: x**2 - targets, np.ones((2, 1)), jac=lambda x: 2 * x[:, :, None])
    >>> np.round(result.x[:, 0], 9).tolist(), result.converged.tolist(), result.iterations.tolist()
    ([1.414213562, 3.0], [True, True], [5, 6])
    >>> both = newton_batch(lambda x: (x**2 - targets, 2 * x[:, :, None]), np.ones((2, 1)), jac=True)
    >>> bool(np.array_equal(both.x, result.x)), both.iterations.tolist()
    (True, [5, 6])
    """
    _check_settings(tol, max_iter)
    residual_tol = tol if residual_tol is None else float(residual_tol)
    x = np.array(x0, dtype=float)
    if x.ndim != 2 or not np.all(np.isfinite(x)):
        raise InvalidGeometryError(f"x0 must be a finite (N, n) array; got shape {np.shape(x0)}")
    N = x.shape[0]
    if jac is True:
        evaluate = F
    else:
        jacobian = (lambda xs: finite_difference_jacobian(F, xs)) if jac is None or jac is False else jac

        def evaluate(xs):
            return F(xs), lambda: jacobian(xs)  # the Jacobian only when a step follows

    converged = np.zeros(N, dtype=bool)
    singular = np.zeros(N, dtype=bool)
    iterations = np.zeros(N, dtype=int)
    step_norms = np.full(N, np.inf)
    rows = np.arange(N)  # the systems still iterating

    with np.errstate(all="ignore"):  # rows that failed may hold NaN; they are masked out
        fx, J = evaluate(x)
        fx = np.asarray(fx, float)
        residual_norms = _row_norms(fx)
        for _ in range(int(max_iter)):
            whole = rows.size == N  # while every row iterates, slices avoid fancy-indexed copies
            J = np.asarray(J() if callable(J) else J, float)
            if not whole:
                J = J[rows]
            bad = ~(_hadamard_ratio(J) > 1.0 / MAX_CONDITION)
            if bad.any():
                singular[rows[bad]] = True
                rows, J, whole = rows[~bad], J[~bad], False
                if rows.size == 0:
                    break
            sel = slice(None) if whole else rows
            step = np.linalg.solve(J, -fx[sel][:, :, None])[:, :, 0]
            x[sel] += step
            iterations[sel] += 1
            steps = _row_norms(step)
            fx, J = evaluate(x)
            fx = np.asarray(fx, float)
            residuals = _row_norms(fx[sel])
            step_norms[sel] = steps
            residual_norms[sel] = residuals
            finite = np.isfinite(steps + residuals)
            done = (steps < tol) & (residuals <= residual_tol)
            converged[sel] |= done
            stop = done | ~finite
            if stop.any():
                rows = rows[~stop]
                if rows.size == 0:
                    break

    return BatchNewtonResult(
        x=x,
        converged=converged,
        iterations=iterations,
        singular=singular,
        step_norms=step_norms,
        residual_norms=residual_norms,
    )
