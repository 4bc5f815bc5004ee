"""The compiled functions: F, J, F_u, the acceleration right-hand side and the 3n system, derived once from
the declaration and lambdified with cse (cos and sin of the unknowns and inputs computed once per call).

One room of :class:`~course_lib.mechanism.Mechanism`, which is all of them together.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING

import numpy as np
import sympy as sp
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.precedence import PRECEDENCE

from ..errors import (
    InvalidGeometryError,
)
from .declaration import _broadcast, _derived

if TYPE_CHECKING:
    from . import Mechanism


def _vector(terms, start: int, size: int) -> np.ndarray:
    """Rows start … start + size of compiled terms (k, ...) as a vector (..., size) (a view)."""
    return terms[start:start + size].transpose(*range(1, terms.ndim), 0)


def _matrix(terms, start: int, rows: int, columns: int) -> np.ndarray:
    """Rows of compiled terms (k, ...) as matrices (..., rows, columns), row by row (a view)."""
    block = terms[start:start + rows * columns].reshape((rows, columns) + terms.shape[1:])
    return block.transpose(*range(2, block.ndim), 0, 1)


_BLOCK = 65_536  # points per block of a long sweep's evaluation


def _finite_rows(*arrays: np.ndarray) -> np.ndarray:
    """True where every entry of the row (last axis) of every array is finite: column by column, ten times
    faster than ``np.isfinite(a).all(axis=-1)`` on the few columns a loop has."""
    ok = None
    for array in arrays:
        for j in range(array.shape[-1]):
            column = np.isfinite(array[..., j])
            ok = column if ok is None else np.logical_and(ok, column, out=ok)
    return ok


def _rows(*arrays) -> tuple[tuple, list[np.ndarray]]:
    """Arrays (..., k) broadcast over their leading axes and flattened to (N, k); and that leading shape."""
    arrays = [np.asarray(a, dtype=float) for a in arrays]
    shape = np.broadcast_shapes(*(a.shape[:-1] for a in arrays))
    return shape, [_broadcast(a, shape + a.shape[-1:]).reshape(-1, a.shape[-1]) for a in arrays]


def _recalled(memo: dict, key, func, column: np.ndarray) -> np.ndarray:
    """func(column) (a cos or sin), taken from ``memo`` where it holds the value for an argument with the
    same bits as ``column`` (the same operation on the same bits: the same bits out), else computed and
    kept there with a copy of its argument."""
    if column.dtype != np.float64:
        return func(column)
    bits = column.view(np.int64)
    kept = memo.get(key)
    if (kept is not None and kept[0].shape == bits.shape
            and (not bits.size or kept[0].flat[0] == bits.flat[0])  # most other arguments differ there
            and np.array_equal(kept[0], bits)):
        return kept[1]
    value = func(column)
    memo[key] = (bits.copy(), value)
    return value


def _sums_expanded(expression: sp.Expr, symbols) -> sp.Expr:
    """cos and sin of a sum that holds unknowns or inputs (θ3 + δ) written with those of its terms
    (cos θ3 cos δ − sin θ3 sin δ): the cos and sin of θ3 are computed once per call anyway, and those of
    the parameters are numbers.

    >>> th, d = sp.symbols("theta delta")
    >>> _sums_expanded(sp.cos(th + d), [th])
    -sin(delta)*sin(theta) + cos(delta)*cos(theta)
    """
    def is_sum(f):
        return (isinstance(f, (sp.cos, sp.sin)) and f.args[0].is_Add
                and any(s in f.args[0].free_symbols for s in symbols))

    return expression.replace(is_sum, lambda f: sp.expand_trig(f))


class _ReciprocalPrinter(NumPyPrinter):
    """numpy code with a negative whole power written as a reciprocal of a product, 1/(x*x) for x**-2:
    numpy's general power is some fifty times slower than a multiplication."""

    def _print_Pow(self, expr, rational=False):
        exponent = expr.exp
        if exponent.is_Integer and -4 <= exponent < 0:
            base = self.parenthesize(expr.base, PRECEDENCE["Mul"])
            return "1/(" + "*".join([base] * -int(exponent)) + ")"
        return super()._print_Pow(expr, rational=rational)


class Compiled:
    """The declaration's functions, derived once and compiled: F, J, F_u, the rates' right-hand sides."""

    def _compile(self, expressions, *groups, keep: int | None = None,
                 reciprocals: bool = False) -> Callable[..., np.ndarray]:
        """f(values, *arrays, known=None, same_point=False, seen=None, into=None): array k (...,
        len(groups[k])) → (len(expressions), ...); with ``keep``, the first ``keep`` only, with the bits of
        the whole; ``reciprocals``: x**(−k) computed as 1/(x·…·x), not by numpy's slow general power;
        ``into``: one array (...) per expression to write it in (the caller's rows, no copy after), returned;
        ``memo``: a dict keeping each cos and sin computed with its argument's bits, so a later call whose
        argument has the same bits takes it from there (see :func:`_recalled`).

        cos and sin of unknowns and inputs are arguments, computed once per call or taken from ``known``
        ({(name, "cos"): array}, where inputs' are kept, and unknowns' with ``same_point``); ``seen``
        receives every one used."""
        symbols = [s for group in groups for s in group]
        expressions = [_sums_expanded(sp.sympify(e), symbols) for e in expressions]

        def angles(among):
            return sorted({(f.func.__name__, f.args[0]) for e in among for f in e.atoms(sp.cos, sp.sin)
                           if f.args[0] in symbols}, key=str)

        trig, cse = angles(expressions), True
        # named symbols, not Dummies: a Dummy's number orders the printed sums, so the bits would vary
        placeholders = {getattr(sp, func)(s): sp.Symbol(f"_{func}_{s.name}") for func, s in trig}
        replaced = [e.xreplace(placeholders) for e in expressions]
        if keep is not None:
            trig, expressions = angles(expressions[:keep]), expressions[:keep]

            def cse(_):
                replacements, reduced = sp.cse(replaced, list=False)
                reduced, used = list(reduced)[:keep], []
                needed = set().union(*(e.free_symbols for e in reduced))
                for symbol, value in reversed(replacements):
                    if symbol in needed:
                        used.append((symbol, value))
                        needed |= value.free_symbols
                return used[::-1], reduced

        arguments = [*symbols, *(placeholders[getattr(sp, func)(s)] for func, s in trig), *self.parameters]
        function = sp.lambdify(arguments, replaced[:len(expressions)], "numpy", cse=cse,
                               printer=_ReciprocalPrinter if reciprocals else None)
        inputs = {s.name for s in self.inputs}
        where = [(k, j) for k, group in enumerate(groups) for j in range(len(group))]
        angles_of = [((s.name, func), np.cos if func == "cos" else np.sin, symbols.index(s), s.name in inputs)
                     for func, s in trig]

        def evaluate(values, *arrays, known=None, same_point=False, seen=None, into=None, memo=None):
            arrays = [np.asarray(a, dtype=float) for a in arrays]
            columns = [arrays[k][..., j] for k, j in where]
            angles = []
            for key, func, index, is_input in angles_of:
                value = None if known is None else known.get(key)
                if value is None:
                    column = columns[index]
                    value = func(column) if memo is None else _recalled(memo, key, func, column)
                    if known is not None and (is_input or same_point):
                        known[key] = value
                angles.append(value)
                if seen is not None:
                    seen[key] = value
            shapes = {a.shape[:-1] for a in arrays}
            shape = shapes.pop() if len(shapes) == 1 else np.broadcast_shapes(*shapes)
            if shapes or len(shape) != 1 or shape[0] <= 2 * _BLOCK:
                blocks = [Ellipsis]  # one block: the whole
            else:  # a long sweep in blocks: the temporaries stay in the cache and are reused
                blocks = [slice(start, start + _BLOCK) for start in range(0, shape[0], _BLOCK)]
            out = np.empty((len(expressions),) + shape) if into is None else into
            arguments = [*columns, *angles]  # floats stay floats
            for block in blocks:
                inputs, part = arguments, out
                if block is not Ellipsis:
                    inputs = [a[block] if np.ndim(a) else a for a in arguments]
                    part = out[:, block] if into is None else [row[block] for row in into]
                for k, value in enumerate(function(*inputs, *values)):
                    if into is None:
                        part[k] = value
                    else:
                        part[k][...] = value
            return out

        evaluate.function = function  # the lambdified code, for reading
        # the columns of each group the expressions read (a symbol, or the cos or sin of one)
        free = set().union(*(e.free_symbols for e in expressions))
        evaluate.reads = [[j for j, s in enumerate(group) if s in free] for group in groups]
        return evaluate

    @_derived
    def _newton_fn(self):
        """(q, u) → F and J side by side, sharing their subexpressions."""
        F = self.equations
        return self._compile([*F, *F.jacobian(self.unknowns)], self.unknowns, self.inputs)

    @_derived
    def _residual_fn(self):
        """(q, u) → F alone, the bits of :attr:`_newton_fn`'s."""
        F = self.equations
        return self._compile([*F, *F.jacobian(self.unknowns)], self.unknowns, self.inputs, keep=F.rows)

    @_derived
    def _jacobian_fn(self):
        """(q, u) → J alone, the bits of :attr:`_rate_fn`'s."""
        F, n = self.equations, len(self.unknowns)
        terms = [*F.jacobian(self.unknowns), *F.jacobian(self.inputs)]
        return self._compile(terms, self.unknowns, self.inputs, keep=n * n)

    @_derived
    def _rate_fn(self):
        """(q, u) → J and F_u side by side."""
        F = self.equations
        terms = [*F.jacobian(self.unknowns), *F.jacobian(self.inputs)]
        return self._compile(terms, self.unknowns, self.inputs)

    @_derived
    def _acceleration_fn(self):
        """(q, q̇, u, u̇, ü) → −(d²F/dt² with q̈ = 0), the right-hand side of J·q̈ = …"""
        q, u = self.unknowns, self.inputs
        rest = -self.acceleration_equations.xreplace({s: 0 for s in self._rates_of(q, 2)})
        return self._compile(rest, q, self._rates_of(q, 1), u, self._rates_of(u, 1), self._rates_of(u, 2))

    @_derived
    def _fused_rate_fn(self):
        """(q, u, u̇, ü) → J, q̇ and q̈ side by side, q̇ and q̈ by Cramer's rule block by block (the blocks
        solved in turn, each block's right-hand side with the earlier blocks' rates in it), sharing their
        subexpressions: one pass over the values where every block has one or two unknowns (None
        elsewhere, where the rates take :meth:`Rates._rates`'s linear solves)."""
        blocks = self._structure["blocks"]
        if any(len(columns) > 2 for _, columns in blocks):
            return None
        q, u = self.unknowns, self.inputs
        q_rate, u_rate, u_acc = self._rates_of(q, 1), self._rates_of(u, 1), self._rates_of(u, 2)
        J, F_u = self.equations.jacobian(q), self.equations.jacobian(u)
        rest = -self.acceleration_equations.xreplace({s: 0 for s in self._rates_of(q, 2)})
        velocity = -(F_u * sp.Matrix(u_rate))

        def cramer(rhs):  # the unknowns' values from J·x = rhs, block by block, earlier blocks substituted
            x = [None] * len(q)
            for rows, columns in blocks:
                b = [rhs[r] - sum((J[r, c] * x[c] for c in range(len(q)) if x[c] is not None), sp.S.Zero)
                     for r in rows]
                block = J.extract(rows, columns)
                if len(columns) == 1:
                    x[columns[0]] = b[0] / block[0, 0]
                    continue
                det = block[0, 0] * block[1, 1] - block[0, 1] * block[1, 0]
                x[columns[0]] = (block[1, 1] * b[0] - block[0, 1] * b[1]) / det
                x[columns[1]] = (block[0, 0] * b[1] - block[1, 0] * b[0]) / det
            return x

        rates = cramer(velocity)
        accelerations = cramer(rest.xreplace(dict(zip(q_rate, rates, strict=True))))
        return self._compile([*J, *rates, *accelerations], q, u, u_rate, u_acc, reciprocals=True)

    @_derived
    def _system_fn(self):
        q, u = self.unknowns, self.inputs
        x = [*q, *self._rates_of(q, 1), *self._rates_of(q, 2)]
        G = sp.Matrix([*self.equations, *self.velocity_equations, *self.acceleration_equations])
        return self._compile([*G, *G.jacobian(x)], x, u, self._rates_of(u, 1), self._rates_of(u, 2))

    def _newton_terms(self, q, u, known=None, seen=None) -> tuple[np.ndarray, np.ndarray]:
        """F (..., n) and J (..., n, n) from one evaluation (``known``, ``seen``: see _compile)."""
        n = len(self.unknowns)
        terms = self._newton_fn(self._values, q, u, known=known, seen=seen)
        return _vector(terms, 0, n), _matrix(terms, n, n, n)

    def _rate_terms(self, q, u, known=None, same_point=False) -> tuple[np.ndarray, np.ndarray]:
        """J (..., n, n) and F_u (..., n, m) from one evaluation (``known``, ``same_point``: see _compile)."""
        n, m = len(self.unknowns), len(self.inputs)
        terms = self._rate_fn(self._values, q, u, known=known, same_point=same_point)
        return _matrix(terms, 0, n, n), _matrix(terms, n * n, n, m)

    def _rhs(self, q, q_rate, u, u_rate, u_acceleration, known=None) -> np.ndarray:
        """−(d²F/dt² with q̈ = 0), shape (..., n): the right-hand side of J·q̈ = …"""
        terms = self._acceleration_fn(self._values, q, q_rate, u, u_rate, u_acceleration, known=known)
        return _vector(terms, 0, len(self.unknowns))

    def _F(self, q, u, known=None, same_point=False, memo=None) -> np.ndarray:
        terms = self._residual_fn(self._values, q, u, known=known, same_point=same_point, memo=memo)
        return _vector(terms, 0, len(self.unknowns))

    def _J(self, q, u, known=None) -> np.ndarray:
        n = len(self.unknowns)
        return _matrix(self._jacobian_fn(self._values, q, u, known=known), 0, n, n)

    def newton_function(self, u) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
        """q ↦ (F(q, u), J(q, u)) at the fixed inputs ``u`` (N, m), for ``newton_batch(..., jac=True)``:
        F and J from one evaluation, sharing the cos and sin of q, those of ``u`` computed once for
        every call.

        >>> th, x = sp.symbols("theta x")
        >>> F = Mechanism([x**2 - th], [x], [th]).newton_function(np.array([[4.0], [9.0]]))
        >>> from course_lib.newton import newton_batch
        >>> newton_batch(F, np.ones((2, 1)), jac=True).x[:, 0].tolist()
        [2.0, 3.0]
        """
        (u,) = self._checked(u=u)
        if u.ndim != 2:
            raise InvalidGeometryError(f"u must be an (N, {len(self.inputs)}) array of inputs; "
                                       f"got shape {u.shape}")
        known = {}
        return lambda q: self._newton_terms(q, u, known)

    def residual(self, q, u) -> np.ndarray:
        """F(q, u), shape (..., n): ``q`` (..., n) ordered as ``unknowns``, ``u`` (..., m) as ``inputs``.

        >>> th, x = sp.symbols("theta x")
        >>> follower, q, u = Mechanism([x - sp.cos(th)], [x], [th]), [1.5], [np.pi / 2]
        >>> [f(q, u).tolist() for f in (follower.residual, follower.jacobian, follower.input_jacobian)]
        [[1.5], [[1.0]], [[1.0]]]
        """
        q, u = self._checked(q=q, u=u)
        return _vector(self._residual_fn(self._values, q, u), 0, len(self.unknowns))

    def jacobian(self, q, u) -> np.ndarray:
        """J = ∂F/∂q, shape (..., n, n) (see :meth:`residual`)."""
        q, u = self._checked(q=q, u=u)
        n = len(self.unknowns)
        return _matrix(self._jacobian_fn(self._values, q, u), 0, n, n)

    def input_jacobian(self, q, u) -> np.ndarray:
        """F_u = ∂F/∂u, shape (..., n, m) (see :meth:`residual`)."""
        q, u = self._checked(q=q, u=u)
        return self._rate_terms(q, u)[1]

    def velocity_residual(self, q_rate, q, u, u_rate) -> np.ndarray:
        """dF/dt = J·q̇ + F_u·u̇ at the rates ``q_rate`` (..., n), ``u_rate`` (..., m).

        >>> th, x = sp.symbols("theta x")
        >>> follower = Mechanism([x - sp.cos(th)], [x], [th])
        >>> follower.velocity_residual([0.0], [0.0], [np.pi / 2], [2.0]).tolist()
        [2.0]
        """
        q_rate, q, u, u_rate = self._checked(q_rate=q_rate, q=q, u=u, u_rate=u_rate)
        J, F_u = self._rate_terms(q, u)
        return np.einsum("...ij,...j->...i", J, q_rate) + np.einsum("...ij,...j->...i", F_u, u_rate)

    def acceleration_residual(self, q_acceleration, q_rate, q, u, u_rate, u_acceleration) -> np.ndarray:
        """d²F/dt² = J·q̈ − (right-hand side of the acceleration system), shape (..., n).

        >>> th, x = sp.symbols("theta x")
        >>> follower = Mechanism([x - sp.cos(th)], [x], [th])
        >>> follower.acceleration_residual([0.0], [0.0], [0.0], [0.0], [2.0], [0.0]).tolist()
        [4.0]
        """
        q_acc, q_rate, q, u, u_rate, u_acc = self._checked(
            q_acceleration=q_acceleration, q_rate=q_rate, q=q, u=u, u_rate=u_rate,
            u_acceleration=u_acceleration)
        J = self.jacobian(q, u)
        rest = self._rhs(q, q_rate, u, u_rate, u_acc)
        return np.einsum("...ij,...j->...i", J, q_acc) - rest

    def system(self, x, u, u_rate, u_acceleration, position: Mechanism | None = None):
        """The 3n simultaneous system: residuals of position, velocity and acceleration equations
        at x = (q, q̇, q̈), shape (..., 3n), and their Jacobian in x, shape (..., 3n, 3n).  With
        ``position`` (an equivalent declaration, see :meth:`consecutive`) its loops give the first n rows.

        >>> th, x = sp.symbols("theta x")
        >>> G, JG = Mechanism([x - sp.cos(th)], [x], [th]).system([1.0, 0.0, 0.0], [0.0], [2.0], [0.0])
        >>> G.tolist(), JG.tolist()
        ([0.0, 0.0, 4.0], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
        """
        x, u, u_rate, u_acceleration = self._checked(x=x, u=u, u_rate=u_rate, u_acceleration=u_acceleration)
        self._check_position(position)
        n = len(self.unknowns)
        terms = self._system_fn(self._values, x, u, u_rate, u_acceleration)
        G, JG = _vector(terms, 0, 3 * n), _matrix(terms, 3 * n, 3 * n, 3 * n)
        if position is not None:
            G[..., :n], JG[..., :n, :n] = position._newton_terms(x[..., :n], u)
        return G, JG
