"""Newton–Raphson for scalars, small systems, and many independent systems at once.

Stop when the step ‖x_{n+1} − x_n‖ < ``tol`` (the course's rule) and ‖F(x_{n+1})‖ ≤ ``residual_tol``
(default ``tol``), so that a tiny step far from a root is not taken for convergence.  Steps are linear
solves (:func:`newton`: LU; :func:`newton_batch`: Cramer's rule for n ≤ 3, LU above).  One rule for both
solvers: a misuse (bad setting, seed, or what ``F``/``jac`` return) raises ``InvalidGeometryError``; a
failed run (singular J, NaN, ``max_iter``) ends with ``converged=False`` and a ``message``, and with
``on_failure="raise"`` (:func:`newton`'s default; :func:`newton_batch`'s is "report") raises
``SingularJacobianError`` or ``ConvergenceError``.

>>> result = newton(lambda x: x**2 - 2.0, 1.0, jac=lambda x: 2.0 * x)
>>> round(result.x, 12), result.iterations, result.converged, result.message
(1.414213562373, 5, True, 'converged in 5 iterations')
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .errors import (
    ConvergenceError,
    InvalidArgumentError,
    InvalidGeometryError,
    SingularJacobianError,
    require_choice,
)
from .thresholds import MAX_CONDITION

__all__ = ["NewtonResult", "BatchNewtonResult", "newton", "newton_batch", "finite_difference_jacobian",
           "hadamard_ratio", "ill_conditioned", "is_singular", "linear_solver", "LinearStack",
           "singular_jacobian_text"]

#: The most updates a run may take: the history of one run stays small.
MAX_ITERATIONS = 10_000
#: The most unknowns one Newton run takes: an update is an n×n solve (n³/3 operations, n² numbers).
MAX_UNKNOWNS = 500
ON_FAILURE = ("raise", "report")


def singular_jacobian_text(n: int = 2) -> str:
    """How a Jacobian Newton's step test refuses (:func:`ill_conditioned`) is described in a
    ``SingularJacobianError``: by the bounds it broke, never by round-off digits.
    Its condition number then exceeds MAX_CONDITION^(1/(n − 1)), as ‖row‖ ≤ σ_max.

    >>> singular_jacobian_text(2)
    'ill-conditioned (|det J| ≤ 1e-12 × the product of its row lengths, so condition number > 1e+12)'
    """
    bound = MAX_CONDITION ** (1 / max(n - 1, 1))
    return f"ill-conditioned (|det J| ≤ {1 / MAX_CONDITION:.0e} × the product of its row lengths, so " \
           f"condition number > {bound:.0e})"


@dataclass(frozen=True)
class NewtonResult:
    """What one Newton run did.

    x : the last iterate (a float for a scalar problem, else an array (n,)).
    converged : the step and residual tests both passed.  ill_conditioned : stopped by Newton's step test
    (:func:`ill_conditioned`: J too close to singular to take a step), not the mechanism's singularity rule
    (``Motion.singular``); ``singular`` is its older name.
    iterations : updates x_n → x_{n+1} performed.  message : what happened, in words.
    history : x_0 and every iterate, (iterations + 1, n).  step_norms : ‖x_{n+1} − x_n‖ per
    update.  step_components : |x_{n+1} − x_n| per variable.  residual_norms : ‖F(x_k)‖, k = 0 … iterations.
    """

    x: float | np.ndarray
    converged: bool
    iterations: int
    history: np.ndarray
    step_norms: np.ndarray
    step_components: np.ndarray
    residual_norms: np.ndarray
    message: str = ""
    ill_conditioned: bool = False

    @property
    def singular(self) -> bool:
        """The older name of :attr:`ill_conditioned` (Newton's step test stopped the run)."""
        return self.ill_conditioned


@dataclass(frozen=True)
class BatchNewtonResult:
    """What a batched Newton run did, one entry per system (the fields of :class:`NewtonResult`
    without the history): x (N, n); converged, ill_conditioned, iterations (N,); step_norms and
    residual_norms (N,) of the last update; message, a summary.  ``singular`` is the older name of
    ``ill_conditioned``.
    """

    x: np.ndarray
    converged: np.ndarray
    iterations: np.ndarray
    ill_conditioned: np.ndarray
    step_norms: np.ndarray
    residual_norms: np.ndarray
    message: str = ""

    @property
    def singular(self) -> np.ndarray:
        """The older name of :attr:`ill_conditioned` (Newton's step test stopped these systems)."""
        return self.ill_conditioned


def finite_difference_jacobian(F: Callable, x: np.ndarray, fx: np.ndarray | None = None) -> np.ndarray:
    """Central-difference Jacobian of ``F`` at ``x`` ((n,) or a batch (N, n)); step ε^(1/3)·max(1, |x_j|).
    ``fx`` is accepted for signature symmetry and ignored.

    >>> J = finite_difference_jacobian(lambda v: np.array([v[0] * v[1], v[0]]), np.array([2.0, 3.0]))
    >>> np.round(J, 8).tolist()
    [[3.0, 2.0], [1.0, 0.0]]
    """
    x = np.asarray(x, dtype=float)
    h = np.finfo(float).eps ** (1 / 3) * np.maximum(1.0, np.abs(x))
    columns = []
    for j in range(x.shape[-1]):
        step = np.zeros_like(x)
        step[..., j] = h[..., j]
        difference = np.asarray(F(x + step), float) - np.asarray(F(x - step), float)
        columns.append(difference / (2 * h[..., j : j + 1]))
    return np.stack(columns, axis=-1)


class LinearStack:
    """N matrices J (N, n, n) prepared once for J·x = b and the singularity test: for n ≤ 3 entries laid
    out (n, n, N), det J and, for n = 3, the cofactors (Cramer's rule); LU above.
    ``rows`` (indices or a mask) keeps those matrices only.

    >>> stack = LinearStack(np.array([[[2.0, 0.0], [0.0, 4.0]], [[1.0, 1.0], [2.0, 2.0]]]))
    >>> solvable = ~stack.ill_conditioned
    >>> stack.ill_conditioned.tolist(), stack.take(solvable).solve(np.array([[2.0, 8.0]])).tolist()
    ([False, True], [[1.0, 2.0]])
    """

    __slots__ = ("n", "size", "_J", "_A", "_det", "_cofactors", "_singular")

    def __init__(self, J: np.ndarray, rows=None):
        J = np.asarray(J, dtype=float)
        self.n, self._singular = J.shape[-1], None
        if self.n > 3:
            self._J = J if rows is None else J[rows]
            self._A = self._det = self._cofactors = None
            self.size = len(self._J)
            return
        A = J.transpose(1, 2, 0)
        if rows is not None:
            A = A[:, :, rows] if np.asarray(rows).dtype == bool else np.take(A, rows, axis=2)
        elif not A.flags.c_contiguous:
            A = np.ascontiguousarray(A)
        self._set(A)

    def _set(self, A: np.ndarray) -> None:
        n, self._A, self._J, self.size = A.shape[0], A, None, A.shape[-1]
        self._cofactors = None
        if n == 1:
            self._det = A[0, 0]
        elif n == 2:
            self._det = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
        else:
            (a, b, c), (d, e, f), (g, h, i) = A
            self._cofactors = np.array([[e * i - f * h, f * g - d * i, d * h - e * g],
                                        [c * h - b * i, a * i - c * g, b * g - a * h],
                                        [b * f - c * e, c * d - a * f, a * e - b * d]])
            self._det = a * self._cofactors[0, 0] + b * self._cofactors[0, 1] + c * self._cofactors[0, 2]

    def take(self, rows) -> LinearStack:
        """The same stack restricted to ``rows`` (indices or a mask), nothing computed again."""
        part = LinearStack.__new__(LinearStack)
        part.n, part._singular = self.n, None if self._singular is None else self._singular[rows]
        if self.n > 3:
            part._J, part._A, part._det, part._cofactors = self._J[rows], None, None, None
            part.size = len(part._J)
            return part
        part._A, part._J, part._det = self._A[:, :, rows], None, self._det[rows]
        part._cofactors = None if self._cofactors is None else self._cofactors[:, :, rows]
        part.size = part._A.shape[-1]
        return part

    @property
    def matrices(self) -> np.ndarray:
        """The stack (N, n, n) (a view of the entries for n ≤ 3)."""
        return self._J if self.n > 3 else self._A.transpose(2, 0, 1)

    @property
    def ratio(self) -> np.ndarray:
        """|det J| / Π‖row of J‖ per matrix (see :func:`hadamard_ratio`)."""
        if self.n > 3:
            return _unit_rows_det(self._J)
        A = self._A
        if self.n == 2:
            rows = (A[0, 0] * A[0, 0] + A[0, 1] * A[0, 1]) * (A[1, 0] * A[1, 0] + A[1, 1] * A[1, 1])
        else:
            rows = (A * A).sum(axis=1).prod(axis=0)
        return np.abs(self._det) / np.sqrt(rows)

    @property
    def ill_conditioned(self) -> np.ndarray:
        """True per matrix too ill-conditioned to solve with, or not finite (see :func:`ill_conditioned`);
        computed once."""
        if self._singular is None:
            with np.errstate(all="ignore"):
                regular = self._regular()
                self._singular = np.zeros(self.size, bool) if regular else ~(self.ratio > 1.0 / MAX_CONDITION)
        return self._singular

    @property
    def singular(self) -> np.ndarray:
        """The older name of :attr:`ill_conditioned` (Newton's step test, not the mechanism's rule)."""
        return self.ill_conditioned

    def _regular(self) -> bool:
        """True when one pass proves every matrix regular: each ‖row‖ ≤ √n·max|entry|, so |det J| above
        twice (for rounding) (√n·max|entry|)ⁿ / MAX_CONDITION passes the test (n ≤ 3; NaN fails)."""
        if self.n > 3 or self.size == 0:
            return False
        largest = np.maximum(self._A.max(), -self._A.min())
        return bool(np.abs(self._det).min() > 2.0 * (self.n ** 0.5 * largest) ** self.n / MAX_CONDITION)

    @property
    def finite(self) -> np.ndarray:
        """True per matrix whose entries are all finite."""
        if self.n > 3:
            return np.isfinite(self._J).all(axis=(1, 2))
        return np.isfinite(self._A).all(axis=(0, 1))

    def solve(self, b) -> np.ndarray:
        """x (N, n) with J·x = b for b (N, n), every matrix at once (inf or NaN where J is singular)."""
        b = np.asarray(b, dtype=float)
        if self.n > 3:
            return np.linalg.solve(self._J, b[..., None])[..., 0]
        return self._solve_columns(b.T).T

    def _solve_columns(self, b: np.ndarray) -> np.ndarray:
        """x (n, N) from b (n, N): Cramer's rule, x = adj(J)·b / det J."""
        A, det = self._A, self._det
        if self.n == 1:
            return b / det
        if self.n == 2:
            return np.array([A[1, 1] * b[0] - A[0, 1] * b[1], A[0, 0] * b[1] - A[1, 0] * b[0]]) / det
        return (self._cofactors * b[:, None]).sum(axis=0) / det


def _unit_rows_det(J: np.ndarray) -> np.ndarray:
    """|det J| / Π‖row of J‖ per matrix (N, n, n) as |det| of J with every row made unit (divided by its
    largest entry, then by its length): neither det J nor the product of lengths over- or underflows, however
    many rows or however large or small their entries (a zero row gives 0, a NaN NaN)."""
    with np.errstate(all="ignore"):
        largest = np.abs(J).max(axis=-1, keepdims=True)
        scaled = J / np.where(largest > 0, largest, 1.0)
        length = np.linalg.norm(scaled, axis=-1, keepdims=True)
        return np.abs(np.linalg.det(scaled / np.where(length > 0, length, 1.0)))


def hadamard_ratio(J: np.ndarray) -> np.ndarray:
    """|det J| / Π‖row of J‖ per matrix (N, n, n): 1 for orthogonal rows, 0 when singular, unchanged by
    scaling a row; the measure of Newton's step test (:func:`ill_conditioned`).

    >>> float(hadamard_ratio(np.array([[[2.0, 0.0], [0.0, 3.0]]]))[0])
    1.0
    """
    return LinearStack(J).ratio


def ill_conditioned(J: np.ndarray) -> np.ndarray:
    """Newton's step test, per matrix of a stack (N, n, n): True where J is too ill-conditioned to solve
    J·Δx = −F with (Hadamard ratio ≤ 1/MAX_CONDITION) or not finite.  It knows nothing of a mechanism: a
    mechanism's configuration is singular by the one rule of :mod:`course_lib.mechanism.singular`
    (σ_min of J scaled by its typical sizes), which ``Motion.singular`` and ``Mechanism.is_singular`` give.

    >>> ill_conditioned(np.array([[[1.0, 1.0], [2.0, 2.0]], [[1.0, 0.0], [0.0, 1.0]]])).tolist()
    [True, False]
    """
    return LinearStack(J).ill_conditioned


#: The older name of :func:`ill_conditioned` (Newton's step test, not the mechanism's singularity rule).
is_singular = ill_conditioned


def linear_solver(J: np.ndarray) -> Callable[[np.ndarray], np.ndarray]:
    """b ↦ x with J·x = b for a stack J (N, n, n) and b (N, n), J prepared once (:class:`LinearStack`).

    >>> solve = linear_solver(np.array([[[2.0, 1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 4.0]]]))
    >>> solve(np.array([[3.0, 1.0, 4.0]])).tolist()
    [[1.0, 1.0, 1.0]]
    """
    return LinearStack(J).solve


def _settings(tol, max_iter, residual_tol, on_failure) -> tuple[float, int, float]:
    """The checked settings: tol > 0 finite, 1 ≤ max_iter ≤ MAX_ITERATIONS, residual_tol > 0 (inf allowed)."""
    if (type(tol) is float and 0 < tol < np.inf and residual_tol is None and type(max_iter) is int
            and 1 <= max_iter <= MAX_ITERATIONS and on_failure in ON_FAILURE):
        return tol, max_iter, tol  # the common case, at once
    require_choice("on_failure", on_failure, ON_FAILURE, InvalidArgumentError)

    def number(name, value, allow_inf=False):
        real = isinstance(value, int | float | np.integer | np.floating) and not isinstance(value, bool)
        if not (real and value > 0 and (np.isfinite(value) or (allow_inf and value == np.inf))):
            raise InvalidArgumentError(f"{name} must be a positive number; got {value!r}")
        return float(value)

    tol = number("tol", tol)
    residual_tol = tol if residual_tol is None else number("residual_tol", residual_tol, allow_inf=True)
    integer = isinstance(max_iter, int | np.integer | float | np.floating) and not isinstance(max_iter, bool)
    if not (integer and np.isfinite(max_iter) and int(max_iter) == max_iter and max_iter >= 1):
        raise InvalidArgumentError(f"max_iter must be a positive integer; got {max_iter!r}")
    if max_iter > MAX_ITERATIONS:
        raise InvalidArgumentError(f"max_iter must be at most {MAX_ITERATIONS:,} (Newton converges in a "
                                   f"handful of updates or not at all); got max_iter={max_iter!r}")
    return tol, int(max_iter), residual_tol


def _real(name: str, value, shape: tuple, x) -> np.ndarray:
    """``value`` returned by the callable ``name`` at ``x`` as a float array of ``shape``, else raise."""
    if type(value) is np.ndarray and value.dtype == float and value.shape == shape:
        return value  # the common case, at once
    where = f"at x={np.round(x, 12).tolist()}" if np.size(x) <= 9 else f"at x of shape {np.shape(x)}"
    if value is None or np.iscomplexobj(value):
        what = "None" if value is None else "complex numbers"
        raise InvalidGeometryError(f"{name} returned {what} {where}: it must return real numbers "
                                   "(Newton here works with real numbers only)")
    try:
        raw = np.asarray(value)
        if raw.dtype == object and any(entry is None for entry in raw.ravel()):
            raise TypeError
        array = raw.astype(float)
    except (TypeError, ValueError):
        raise InvalidGeometryError(f"{name} must return real numbers; got {value!r} {where}") from None
    if array.shape != shape and array.size == int(np.prod(shape)) and (len(shape) == 1 or shape == (1, 1)):
        array = array.reshape(shape)
    if array.shape != shape:
        what = "residuals" if name == "F" else "Jacobians" if len(shape) == 3 else "a Jacobian"
        raise InvalidGeometryError(f"{name} must return {what} of shape {shape} for x of shape "
                                   f"{np.shape(x)}; got shape {array.shape} {where}")
    return array


def newton(F: Callable, x0, jac: Callable | None = None, tol: float = 1e-6, max_iter: int = 50,
           residual_tol: float | None = None, on_failure: str = "raise") -> NewtonResult:
    """Solve F(x) = 0 by Newton–Raphson from ``x0``, keeping the whole history.

    ``x0`` a number (``F`` and ``jac`` then take and return numbers) or n unknowns (``F`` gives n
    residuals, ``jac`` the n×n Jacobian; without ``jac``, central differences).  Each update solves
    J(x_n)·Δx = −F(x_n); stopping and failures as in the module's rule.

    >>> F = lambda v: np.array([v[0] ** 2 + v[1] ** 2 - 1.0, v[0] - v[1]])
    >>> result = newton(F, np.array([1.0, 0.5]))
    >>> np.round(result.x, 9).tolist(), result.converged
    ([0.707106781, 0.707106781], True)
    """
    tol, max_iter, residual_tol = _settings(tol, max_iter, residual_tol, on_failure)
    scalar = np.ndim(x0) == 0
    try:
        x = np.atleast_1d(np.asarray(x0, dtype=float)).copy()
    except (TypeError, ValueError):
        x = np.array([np.nan])
    if x.ndim == 1 and x.size > MAX_UNKNOWNS:  # each update solves an n×n system: judged before any work
        raise InvalidArgumentError(f"x0 must hold at most {MAX_UNKNOWNS:,} unknowns (each Newton update "
                                   f"solves an n×n system); got {x.size:,} (shape {x.shape})")
    if x.ndim != 1 or not np.all(np.isfinite(x)):
        raise InvalidGeometryError(f"x0 must be a finite number or 1-D vector; got {x0!r}")
    n = x.size

    def F_vec(v):
        return _real("F", F(v[0] if scalar else v.copy()), (n,), v)

    if jac is None:
        def J_mat(v):
            with np.errstate(all="ignore"):
                return finite_difference_jacobian(F_vec, v)
    else:
        def J_mat(v):
            return _real("jac", jac(v[0] if scalar else v.copy()), (n, n), v)

    history, steps, residuals, failure = [x], [], [], None

    def result(converged: bool, message: str, stopped: bool = False) -> NewtonResult:
        path, step_array = np.array(history), np.array(steps).reshape(-1, n)
        return NewtonResult(
            x=float(path[-1, 0]) if scalar else path[-1].copy(), converged=converged, iterations=len(steps),
            history=path[:, 0] if scalar else path, step_norms=np.sqrt((step_array * step_array).sum(axis=1)),
            step_components=np.abs(step_array[:, 0] if scalar else step_array),
            residual_norms=np.array(residuals), message=message, ill_conditioned=stopped)

    def here():
        return float(x[0]) if scalar else x.tolist()

    with np.errstate(all="ignore"):  # a failure is reported below, not as a numpy warning
        fx = F_vec(x)
        residuals.append(float(np.sqrt(fx @ fx)))
        if not np.isfinite(fx).all():
            failure = f"F returned {fx.tolist()} at x={here()}"
        while failure is None:
            J = J_mat(x)
            if not np.isfinite(J).all():
                failure = f"jac returned {J.tolist()} at x={here()}, after {len(steps)} iterations"
                break
            ratio = float(_unit_rows_det(J[None])[0])  # hadamard_ratio of one J
            if not ratio > 1.0 / MAX_CONDITION:
                message = f"the Jacobian is {singular_jacobian_text(n)} at x={here()}; Newton cannot take " \
                          "a step from here: try another seed"
                if on_failure == "raise":
                    raise SingularJacobianError(message, x=here(), condition_number=float(np.linalg.cond(J)))
                return result(False, message, stopped=True)
            step = np.linalg.solve(J, -fx)
            x = x + step  # a new array: the history keeps every iterate
            fx = F_vec(x)
            history.append(x)
            steps.append(step)
            residual = float(np.sqrt(fx @ fx))
            residuals.append(residual)
            if not (np.isfinite(x).all() and np.isfinite(fx).all()):
                failure = f"Newton diverged: a non-finite value appeared after {len(steps)} iterations"
            elif float(np.sqrt(step @ step)) < tol and residual <= residual_tol:
                return result(True, f"converged in {len(steps)} iterations")
            elif len(steps) == max_iter:
                failure = (f"Newton did not converge in max_iter={max_iter} iterations "
                           f"(last step {np.linalg.norm(step):.3g}, residual {residual:.3g})")
    last = result(False, failure)
    if on_failure == "raise":
        raise ConvergenceError(failure, result=last)
    return last


def _row_norms(a: np.ndarray) -> np.ndarray:
    """‖row‖ of a (N, n), summed in row order whatever the layout (the core's are columns of (n, N))."""
    if a.ndim == 2 and a.T.flags.c_contiguous:
        return np.sqrt(np.einsum("ij,ij->j", a.T, a.T))
    return np.sqrt(np.einsum("ij,ij->i", a, a))


def newton_batch(F: Callable, x0, jac: Callable | bool | np.ndarray | LinearStack | None = None,
                 tol: float = 1e-6, max_iter: int = 50, residual_tol: float | None = None,
                 on_failure: str = "report") -> BatchNewtonResult:
    """Solve N independent systems F(x_i) = 0 at once, one vectorized loop, by the rule of :func:`newton`.

    ``x0`` (N, n); ``F`` maps iterates (N, n) to residuals (N, n), ``jac`` to Jacobians (N, n, n);
    ``jac=True``: ``F`` returns both; ``jac`` an array or :class:`LinearStack`: the constant J of an
    affine F.  Each system stops on its own; ``F`` is called last at the returned ``x``.

    >>> targets = np.array([[2.0], [9.0]])
    >>> result = newton_batch(lambda x: x**2 - targets, np.ones((2, 1)), jac=lambda x: 2 * x[:, :, None])
    >>> np.round(result.x[:, 0], 9).tolist(), result.iterations.tolist(), result.message
    ([1.414213562, 3.0], [5, 6], 'all 2 systems converged')
    >>> both = newton_batch(lambda x: (x**2 - targets, 2 * x[:, :, None]), np.ones((2, 1)), jac=True)
    >>> bool(np.array_equal(both.x, result.x)), both.iterations.tolist()
    (True, [5, 6])

    A linear system takes one step to its solution and a second, of round-off size, to show it:

    >>> J, c = np.array([[[2.0, 1.0], [1.0, 3.0]]]), np.array([[-3.0, -4.0]])
    >>> linear = newton_batch(lambda x: np.einsum("nij,nj->ni", J, x) + c, np.zeros((1, 2)), jac=J)
    >>> np.round(linear.x, 12).tolist(), linear.iterations.tolist()
    ([[1.0, 1.0]], [2])
    """
    tol, max_iter, residual_tol = _settings(tol, max_iter, residual_tol, on_failure)
    try:
        x = np.array(x0, dtype=float)
    except (TypeError, ValueError):
        x = np.array(np.nan)
    if x.ndim != 2 or not (np.isfinite(x.sum()) or np.isfinite(x).all()):  # a finite sum: all finite
        raise InvalidGeometryError(f"x0 must be a finite (N, n) array; got shape {np.shape(x0)}")
    N, n = x.shape
    fixed = None
    if isinstance(jac, np.ndarray | LinearStack):
        stack = isinstance(jac, LinearStack)
        if (jac.size, jac.n) != (N, n) if stack else jac.shape != (N, n, n):
            got = f"a LinearStack of {jac.size} {jac.n}x{jac.n} matrices" if stack else f"shape {jac.shape}"
            raise InvalidGeometryError(f"a constant jac must be a stack of shape {(N, n, n)} for x0 of shape "
                                       f"{(N, n)}; got {got}")
        fixed = jac if stack else LinearStack(_real("jac", jac, (N, n, n), x))

        def evaluate(xs):
            return _real("F", F(xs), (N, n), xs), None
    elif jac is True:
        def evaluate(xs):
            pair = F(xs)
            if not (isinstance(pair, tuple) and len(pair) == 2):
                raise InvalidGeometryError(f"with jac=True, F must return (residuals, Jacobians); "
                                           f"got {pair!r}")
            return _real("F", pair[0], (N, n), xs), lambda: _real("jac", pair[1], (N, n, n), xs)
    else:
        if jac is None or jac is False:
            def jacobian(xs):
                return finite_difference_jacobian(F, xs)
        else:
            jacobian = jac

        def evaluate(xs):
            return _real("F", F(xs), (N, n), xs), lambda: _real("jac", jacobian(xs), (N, n, n), xs)

    converged, stopped = np.zeros(N, dtype=bool), np.zeros(N, dtype=bool)  # stopped: by the step test
    iterations, step_norms = np.zeros(N, dtype=int), np.full(N, np.inf)

    with np.errstate(all="ignore"):  # failed rows may hold NaN; they are masked out
        fx, J = evaluate(x)
        residual_norms = _row_norms(fx)  # then each row's after its last update
        active = np.isfinite(residual_norms)  # the systems still iterating
        count, updates = int(active.sum()), 0
        while count and updates < max_iter:
            # while most rows iterate every row is solved, those iterating updated; else they are picked out
            every, rows = count == N, None if 2 * count >= N else np.flatnonzero(active)
            if fixed is not None:
                stack = fixed if rows is None else fixed.take(rows)
            else:
                stack = LinearStack(J(), rows)
            bad = stack.ill_conditioned if every or rows is not None else stack.ill_conditioned & active
            if bad.any():  # these stop: J singular or not finite
                ended = bad if rows is None else rows[bad]
                stopped[ended], iterations[ended], active[ended] = stack.finite[bad], updates, False
                count, every = int(active.sum()), False
                if count == 0:
                    break
                if rows is not None:
                    rows, stack = rows[~bad], stack.take(~bad)
            step = stack.solve(fx if rows is None else fx[rows])  # −(the step): Cramer's rule is odd in b
            if every:
                x -= step
            elif rows is None:
                np.subtract(x, step, out=x, where=active[:, None])
            else:
                x[rows] -= step
            updates += 1
            fx, J = evaluate(x)
            steps, residuals = _row_norms(step), _row_norms(fx if rows is None else fx[rows])
            done = (steps < tol) & (residuals <= residual_tol)
            stop = done | ~np.isfinite(steps + residuals)
            if every:
                step_norms, residual_norms, converged = steps, residuals, done
                iterations.fill(updates)
            elif rows is None:
                stop &= active
                for kept, new in ((step_norms, steps), (residual_norms, residuals), (converged, done),
                                  (iterations, updates)):
                    np.copyto(kept, new, where=active)
            else:
                step_norms[rows], residual_norms[rows], converged[rows], iterations[rows] = (
                    steps, residuals, done, updates)
            if stop.any():
                active[stop if rows is None else rows[stop]] = False
                count = int(active.sum())

    failed = np.flatnonzero(~converged)
    if failed.size == 0:
        message = f"all {N} systems converged"
    else:
        k = failed[0]
        why = ("its Jacobian is " + singular_jacobian_text(n) if stopped[k] else
               "a non-finite value appeared" if not np.isfinite(residual_norms[k] + step_norms[k]) or
               not np.all(np.isfinite(x[k])) else f"not converged in max_iter={max_iter} iterations")
        message = f"{failed.size} of {N} systems did not converge; the first, row {k}: {why}"
    result = BatchNewtonResult(x=x, converged=converged, iterations=iterations, ill_conditioned=stopped,
                               step_norms=step_norms, residual_norms=residual_norms, message=message)
    if failed.size and on_failure == "raise":
        if stopped[failed[0]]:
            raise SingularJacobianError(message, x=x[failed[0]].tolist())
        raise ConvergenceError(message, result=result)
    return result
