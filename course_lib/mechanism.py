"""One core for every planar mechanism: write the vector loops once, get position, velocity, acceleration.

A mechanism is declared by its loop equations F(q, u) = 0 in sympy: unknowns q (angles or lengths),
inputs u and a number for every other symbol.  The core derives once, lambdified with cse: F,
J = ∂F/∂q, F_u = ∂F/∂u, the velocity system J·q̇ = −F_u·u̇, the acceleration system J·q̈ = −(the rest of
d²F/dt²) and the stacked 3n system.  :meth:`Mechanism.solve` finds the position by Newton–Raphson, then
the rates by linear solves with the same J.  SI units, radians.

>>> import numpy as np, sympy as sp
>>> th2, th3, th4 = sp.symbols("theta2 theta3 theta4")
>>> l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
>>> wiper = Mechanism(
...     loops=[sp.Matrix([l2*sp.cos(th2) + l3*sp.cos(th3) - l4*sp.cos(th4) - l1,
...                       l2*sp.sin(th2) + l3*sp.sin(th3) - l4*sp.sin(th4)])],
...     unknowns=[th3, th4], inputs=[th2],
...     parameters={l1: 0.20, l2: 0.06, l3: 0.18, l4: 0.12})
>>> motion = wiper.solve({th2: np.pi / 2}, rates={th2: 10.0}, guess={th3: 0.4, th4: 1.6})
>>> round(motion.position["theta4"], 6), round(motion.velocity["theta4"], 6), motion.newton.iterations
(1.815502, 4.761066, 5)
>>> sweep = wiper.solve({th2: np.linspace(0, 2 * np.pi, 7)}, guess={th3: 0.4, th4: 1.6})
>>> sweep.position["theta3"].shape, bool(sweep.converged.all()), sweep.velocity
((7,), True, None)
"""

from __future__ import annotations

import copy
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import wraps
from types import MappingProxyType

import numpy as np
import sympy as sp
from sympy.printing.numpy import NumPyPrinter
from sympy.printing.precedence import precedence

from .errors import (
    ConvergenceError,
    InvalidGeometryError,
    SingularJacobianError,
    UnreachableError,
    require_choice,
    require_finite,
)
from .newton import (
    BatchNewtonResult,
    LinearStack,
    NewtonResult,
    is_singular,
    linear_solver,
    newton,
    newton_batch,
    singular_jacobian_text,
)
from .planar import scalar_or_array
from .symbolic import TIME, rate_name

__all__ = ["Mechanism", "Motion"]

ON_FAILURE = ("raise", "nan")
LINEAR_STAGES = ("newton", "direct")

#: Two Newton solutions of one instant closer than this (plus 100·tol) are the same assembly.
SAME_ROOT = 1e-6


@dataclass(frozen=True)
class Motion:
    """What :meth:`Mechanism.solve` found, shaped like the broadcast inputs (Python numbers for scalars).

    position, velocity, acceleration : unknown's name → q, q̇, q̈ (SI); the rates None unless asked.
    converged, singular : masks, True where Newton converged / J is singular (NaN values there).
    iterations : Newton updates per instant.  inputs : input's name → its broadcast values.
    newton : one instant's ``NewtonResult`` with its history; None for a sweep.
    """

    position: Mapping[str, float | np.ndarray]
    velocity: Mapping[str, float | np.ndarray] | None
    acceleration: Mapping[str, float | np.ndarray] | None
    converged: bool | np.ndarray
    singular: bool | np.ndarray
    iterations: int | np.ndarray
    inputs: Mapping[str, float | np.ndarray]
    newton: NewtonResult | None = None


def _symbols(argument: str, values) -> tuple[sp.Symbol, ...]:
    values = tuple(values) if isinstance(values, Sequence) else (values,)
    for value in values:
        if not isinstance(value, sp.Symbol):
            raise InvalidGeometryError(f"{argument} must be sympy Symbols; got {value!r} in {argument}")
    names = [value.name for value in values]
    if len(set(names)) != len(names) or not names:
        raise InvalidGeometryError(f"{argument} must be one or more distinct symbols; got {list(values)}")
    return values


def _equations(loops) -> sp.Matrix:
    rows = []
    for k, loop in enumerate(loops if isinstance(loops, Sequence) else [loops]):
        if isinstance(loop, sp.MatrixBase):
            rows.extend(loop)
            continue
        try:
            rows.append(sp.sympify(loop, strict=True))
        except (sp.SympifyError, TypeError):
            raise InvalidGeometryError(f"loops[{k}] must be a sympy Matrix or expression; got {loop!r}") \
                from None
    return sp.Matrix(rows)


def _numbers(parameters) -> dict[sp.Symbol, float]:
    if not isinstance(parameters, Mapping) or not all(isinstance(k, sp.Symbol) for k in parameters):
        raise InvalidGeometryError(f"parameters must map sympy Symbols to numbers; got {parameters!r}")
    values = {k: require_finite(f"parameters[{k}]", v) for k, v in parameters.items()}
    if any(v.ndim for v in values.values()):
        raise InvalidGeometryError(f"parameters must map each symbol to one number; got {parameters!r}")
    return {k: float(v) for k, v in values.items()}


def _keyed(argument: str, mapping, symbols, required: bool = True) -> dict[str, object]:
    """A dict keyed by symbols or their names → {name: value}; unknown keys and missing names raise."""
    names = [symbol.name for symbol in symbols]
    if not isinstance(mapping, Mapping):
        raise InvalidGeometryError(f"{argument} must be a dict keyed by {', '.join(names)}; got {mapping!r}")
    out = {}
    for key, value in mapping.items():
        name = key.name if isinstance(key, sp.Symbol) else key
        if name not in names:
            raise InvalidGeometryError(f"{argument} has the key {key!r}, which is not one of {names}")
        out[name] = value
    missing = [name for name in names if name not in out]
    if required and missing:
        raise InvalidGeometryError(f"{argument} must give a value for {', '.join(missing)}; "
                                   f"got keys {list(mapping)}")
    return out


def _derived(build):
    """A property computed once per declaration, shared by its :meth:`~Mechanism.with_parameters` copies."""

    @wraps(build)
    def getter(self):
        if build.__name__ not in self._derived:
            self._derived[build.__name__] = build(self)
        return self._derived[build.__name__]

    return property(getter)


def _vector(terms, start: int, size: int) -> np.ndarray:
    """Rows start … start + size of compiled terms (k, ...) as a vector (..., size) (a view)."""
    return terms[start:start + size].transpose(*range(1, terms.ndim), 0)


def _matrix(terms, start: int, rows: int, columns: int) -> np.ndarray:
    """Rows of compiled terms (k, ...) as matrices (..., rows, columns), row by row (a view)."""
    block = terms[start:start + rows * columns].reshape((rows, columns) + terms.shape[1:])
    return block.transpose(*range(2, block.ndim), 0, 1)


_BLOCK = 65_536  # points per block of a long sweep's evaluation


def _one_instant(function, values, arrays, where, angles_of, known, same_point, seen) -> np.ndarray | None:
    """A compiled function's terms (k,) at one instant in Python numbers (0-d arrays cost a microsecond per
    operation), the array path's bits; None where Python refuses a value (the array path gives inf/NaN)."""
    columns = [float(arrays[k][j]) for k, j in where]
    angles = _angles(angles_of, known, same_point, seen, lambda func, index: float(func(columns[index])))
    try:
        with np.errstate(all="raise"):
            return np.array(function(*columns, *angles, *values), dtype=float)
    except (ArithmeticError, ValueError, TypeError):
        return None


def _angles(angles_of, known, same_point, seen, make) -> list:
    """The cos and sin a compiled function takes: from ``known``, else ``make(func, index)`` (kept in
    ``known`` if an input's, or with ``same_point``); each given to ``seen``."""
    angles = []
    for key, func, index, is_input in angles_of:
        value = None if known is None else known.get(key)
        if value is None:
            value = make(func, index)
            if known is not None and (is_input or same_point):
                known[key] = value
        angles.append(value)
        if seen is not None:
            seen[key] = value
    return angles


class _Printer(NumPyPrinter):
    """numpy's printer, with x**2 written x*x: what numpy computes for an array's square, where a
    Python number's x**2 calls pow, which differs from x*x in the last bit for about 1 x in 1,000."""

    def _print_Pow(self, expr, rational=False):
        if expr.exp == 2:
            base = self.parenthesize(expr.base, precedence(expr), strict=True)
            return f"({base}*{base})"
        return super()._print_Pow(expr, rational=rational)


def _rows(*arrays) -> tuple[tuple, list[np.ndarray]]:
    """Arrays (..., k) broadcast over their leading axes and flattened to (N, k); and that leading shape."""
    arrays = [np.asarray(a, dtype=float) for a in arrays]
    shape = np.broadcast_shapes(*(a.shape[:-1] for a in arrays))
    return shape, [_broadcast(a, shape + a.shape[-1:]).reshape(-1, a.shape[-1]) for a in arrays]


def _broadcast(array, shape) -> np.ndarray:
    array = np.asarray(array)
    return array if array.shape == shape else np.broadcast_to(array, shape)


class Mechanism:
    """A planar mechanism declared by its loop equations (each expression = 0).

    ``loops``: 2×1 sympy matrices (x and y components of a vector loop) or scalar expressions,
    as many equations in all as ``unknowns``; loops may share unknowns.  ``inputs``: the driven
    variables.  ``parameters``: a number for every other symbol (:meth:`with_parameters` gives
    the same declaration with other numbers, sharing everything derived).  Optional ``points``
    (name → 2×1 matrix of x, y) and ``links`` (pairs of point names) describe the drawing.

    >>> x, th = sp.symbols("x theta")
    >>> follower = Mechanism([x - sp.cos(th)], unknowns=[x], inputs=[th])
    >>> follower.solve({th: np.pi / 2}, rates={th: 2.0}, guess={x: 0.5}).velocity["x"]
    -2.0
    """

    def __init__(self, loops, unknowns, inputs, parameters: Mapping | None = None, *,
                 points: Mapping | None = None, links: Sequence = ()):
        self.unknowns = _symbols("unknowns", unknowns)
        self.inputs = _symbols("inputs", inputs)
        self.equations = _equations(loops)
        moving = self.unknowns + self.inputs
        if len({s.name for s in moving}) != len(moving):
            raise InvalidGeometryError(f"unknowns and inputs must not share a symbol; got {moving}")
        n = len(self.unknowns)
        if self.equations.rows != n:
            raise InvalidGeometryError(f"loops give {self.equations.rows} equations for the {n} unknowns "
                                       f"{list(self.unknowns)}: there must be one equation per unknown")
        self.parameters = MappingProxyType(_numbers({} if parameters is None else parameters))
        self.points = {str(name): sp.Matrix(xy) for name, xy in (points or {}).items()}
        self.links = tuple((str(a), str(b)) for a, b in links)
        used = self.equations.free_symbols
        for argument, symbols in (("unknowns", self.unknowns), ("inputs", self.inputs)):
            for symbol in symbols:
                if symbol not in used:
                    raise InvalidGeometryError(f"{argument}: {symbol} appears in no loop "
                                               f"(the loops contain {sorted(map(str, used))})")
        for name, xy in self.points.items():
            if xy.shape != (2, 1):
                raise InvalidGeometryError(f"points[{name!r}] must be a 2x1 Matrix (x, y); got {xy!r}")
            used = used | xy.free_symbols
        for link in self.links:
            if not set(link) <= set(self.points):
                raise InvalidGeometryError(f"links: {link} names a point not in points {list(self.points)}")
        clash = set(self.parameters) & set(moving)
        left_over = used - set(moving) - set(self.parameters)
        unused = set(self.parameters) - used
        for bad, what in ((clash, "is an unknown or input and cannot be a parameter"),
                          (left_over, "has no value: give it one in parameters"),
                          (unused, "appears in no loop or point")):
            if bad:
                names = ", ".join(sorted(map(str, bad)))
                raise InvalidGeometryError(f"parameters: {names} {what}; got parameters="
                                           f"{ {str(k): v for k, v in self.parameters.items()} }")
        self._values = tuple(self.parameters.values())
        self._derived = {}

    def with_parameters(self, parameters: Mapping) -> Mechanism:
        """The same loops with other numbers for all the parameters (keyed by symbol or name): nothing
        is derived again.

        >>> x, th, a = sp.symbols("x theta a")
        >>> crank = Mechanism([x - a * sp.cos(th)], [x], [th], {a: 1.0})
        >>> crank.with_parameters({a: 3.0}).residual([0.0], [0.0]).tolist()
        [-3.0]
        """
        if isinstance(parameters, Mapping):
            by_name = {s.name: s for s in self.parameters}
            parameters = {by_name.get(k, k): v for k, v in parameters.items()}
        values = _numbers(parameters)
        if set(values) != set(self.parameters):
            raise InvalidGeometryError(f"parameters must give a number for each of {list(self.parameters)} "
                                       f"and nothing else; got {list(values)}")
        other = copy.copy(self)
        other.parameters = MappingProxyType({k: values[k] for k in self.parameters})
        other._values = tuple(other.parameters.values())
        return other

    # ------------------------------------------------------------ derived once, symbolically

    @_derived
    def rate_symbols(self) -> dict[sp.Symbol, tuple[sp.Symbol, sp.Symbol]]:
        """First and second time derivative of each unknown and input as symbols (θ → ω, α; x → v_x, a_x).

        >>> th, x = sp.symbols("theta2 x")
        >>> Mechanism([x - sp.cos(th)], [x], [th]).rate_symbols
        {x: (v_x, a_x), theta2: (omega2, alpha2)}
        """
        taken = {s.name for s in self.equations.free_symbols | set(self.parameters)}
        rates = {}
        for symbol in self.unknowns + self.inputs:
            pair = tuple(sp.Symbol(rate_name(symbol.name, order), real=True) for order in (1, 2))
            if {p.name for p in pair} & taken:
                raise InvalidGeometryError(f"the rates of {symbol} would be named {pair}, a name already "
                                           "used in the loops or parameters: rename that symbol")
            rates[symbol] = pair
        return rates

    @_derived
    def _time_derivatives(self) -> tuple[sp.Matrix, sp.Matrix]:
        """dF/dt and d²F/dt²: unknowns and inputs made functions of time, the loops differentiated,
        the derivatives named by :attr:`rate_symbols`."""
        functions = {s: sp.Function(s.name, real=True)(TIME) for s in self.rate_symbols}
        back = {}
        for symbol, function in functions.items():
            first, second = self.rate_symbols[symbol]
            back.update({function.diff(TIME, 2): second, function.diff(TIME): first, function: symbol})
        first = self.equations.xreplace(functions).diff(TIME)
        return first.xreplace(back), first.diff(TIME).xreplace(back)

    @property
    def velocity_equations(self) -> sp.Matrix:
        """dF/dt = J·q̇ + F_u·u̇ (= 0), in the symbols of :attr:`rate_symbols`.

        >>> th, x = sp.symbols("theta2 x")
        >>> follower = Mechanism([x - sp.cos(th)], [x], [th])
        >>> follower.velocity_equations, follower.acceleration_equations
        (Matrix([[omega2*sin(theta2) + v_x]]), Matrix([[a_x + alpha2*sin(theta2) + omega2**2*cos(theta2)]]))
        """
        return self._time_derivatives[0]

    @property
    def acceleration_equations(self) -> sp.Matrix:
        """d²F/dt² (= 0): J·q̈ + F_u·ü plus the terms in products of rates."""
        return self._time_derivatives[1]

    def _rates_of(self, symbols, order: int) -> list[sp.Symbol]:
        return [self.rate_symbols[s][order - 1] for s in symbols]

    def _compile(self, expressions, *groups, keep: int | None = None) -> Callable[..., np.ndarray]:
        """f(values, *arrays, known=None, same_point=False, seen=None): array k (..., len(groups[k])) →
        (len(expressions), ...); with ``keep``, the first ``keep`` only, with the bits of the whole.

        cos and sin of unknowns and inputs are arguments, computed once per call or taken from ``known``
        ({(name, "cos"): array}, where inputs' are kept, and unknowns' with ``same_point``); ``seen``
        receives every one used."""
        symbols = [s for group in groups for s in group]
        expressions = [sp.sympify(e) for e in expressions]

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
        function = sp.lambdify(arguments, replaced[:len(expressions)], "numpy", cse=cse, printer=_Printer)
        inputs = {s.name for s in self.inputs}
        where = [(k, j) for k, group in enumerate(groups) for j in range(len(group))]
        angles_of = [((s.name, func), np.cos if func == "cos" else np.sin, symbols.index(s), s.name in inputs)
                     for func, s in trig]

        def evaluate(values, *arrays, known=None, same_point=False, seen=None):
            arrays = [np.asarray(a, dtype=float) for a in arrays]
            if all(a.ndim == 1 for a in arrays):
                terms = _one_instant(function, values, arrays, where, angles_of, known, same_point, seen)
                if terms is not None:
                    return terms
            columns = [arrays[k][..., j] for k, j in where]
            shapes = {a.shape[:-1] for a in arrays}
            shape = shapes.pop() if len(shapes) == 1 else np.broadcast_shapes(*shapes)
            if shapes or len(shape) != 1 or shape[0] <= 2 * _BLOCK:
                blocks = [Ellipsis]  # one block: the whole
            else:  # a long sweep in blocks: the temporaries stay in the cache and are reused
                blocks = [slice(start, start + _BLOCK) for start in range(0, shape[0], _BLOCK)]
            missing = []  # (func, column, array to fill): filled block by block below

            def make(func, index):
                missing.append((func, columns[index], np.empty(columns[index].shape)))
                return missing[-1][2]

            angles = _angles(angles_of, known, same_point, seen, make)
            out, arguments = np.empty((len(expressions),) + shape), [*columns, *angles]  # floats stay floats
            for block in blocks:
                for func, column, value in missing:
                    func(column[block], out=value[block])
                inputs = arguments
                if block is not Ellipsis:
                    inputs = [a[block] if np.ndim(a) else a for a in arguments]
                for k, value in enumerate(function(*inputs, *values)):
                    out[k, block] = value
            return out

        evaluate.function = function  # the lambdified code, for reading
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
    def _system_fn(self):
        q, u = self.unknowns, self.inputs
        x = [*q, *self._rates_of(q, 1), *self._rates_of(q, 2)]
        G = sp.Matrix([*self.equations, *self.velocity_equations, *self.acceleration_equations])
        return self._compile([*G, *G.jacobian(x)], x, u, self._rates_of(u, 1), self._rates_of(u, 2))

    # ------------------------------------------------------------ numbers (arrays ordered as declared)

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

    def newton_function(self, u) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
        """q ↦ (F(q, u), J(q, u)) at the fixed inputs ``u`` (N, m), for ``newton_batch(..., jac=True)``:
        F and J from one evaluation, sharing the cos and sin of q, those of ``u`` computed once for
        every call.

        >>> th, x = sp.symbols("theta x")
        >>> F = Mechanism([x**2 - th], [x], [th]).newton_function(np.array([[4.0], [9.0]]))
        >>> newton_batch(F, np.ones((2, 1)), jac=True).x[:, 0].tolist()
        [2.0, 3.0]
        """
        u, known = np.asarray(u, dtype=float), {}
        return lambda q: self._newton_terms(q, u, known)

    def residual(self, q, u) -> np.ndarray:
        """F(q, u), shape (..., n): ``q`` (..., n) ordered as ``unknowns``, ``u`` (..., m) as ``inputs``.

        >>> th, x = sp.symbols("theta x")
        >>> follower, q, u = Mechanism([x - sp.cos(th)], [x], [th]), [1.5], [np.pi / 2]
        >>> [f(q, u).tolist() for f in (follower.residual, follower.jacobian, follower.input_jacobian)]
        [[1.5], [[1.0]], [[1.0]]]
        """
        return _vector(self._residual_fn(self._values, q, u), 0, len(self.unknowns))

    def jacobian(self, q, u) -> np.ndarray:
        """J = ∂F/∂q, shape (..., n, n) (see :meth:`residual`)."""
        n = len(self.unknowns)
        return _matrix(self._jacobian_fn(self._values, q, u), 0, n, n)

    def input_jacobian(self, q, u) -> np.ndarray:
        """F_u = ∂F/∂u, shape (..., n, m) (see :meth:`residual`)."""
        return self._rate_terms(q, u)[1]

    def velocity_residual(self, q_rate, q, u, u_rate) -> np.ndarray:
        """dF/dt = J·q̇ + F_u·u̇ at the rates ``q_rate`` (..., n), ``u_rate`` (..., m).

        >>> th, x = sp.symbols("theta x")
        >>> follower = Mechanism([x - sp.cos(th)], [x], [th])
        >>> follower.velocity_residual([0.0], [0.0], [np.pi / 2], [2.0]).tolist()
        [2.0]
        """
        J, F_u = self._rate_terms(q, u)
        return np.einsum("...ij,...j->...i", J, q_rate) + np.einsum("...ij,...j->...i", F_u, u_rate)

    def acceleration_residual(self, q_acceleration, q_rate, q, u, u_rate, u_acceleration) -> np.ndarray:
        """d²F/dt² = J·q̈ − (right-hand side of the acceleration system), shape (..., n).

        >>> th, x = sp.symbols("theta x")
        >>> follower = Mechanism([x - sp.cos(th)], [x], [th])
        >>> follower.acceleration_residual([0.0], [0.0], [0.0], [0.0], [2.0], [0.0]).tolist()
        [4.0]
        """
        J = self.jacobian(q, u)
        rest = self._rhs(q, q_rate, u, u_rate, u_acceleration)
        return np.einsum("...ij,...j->...i", J, q_acceleration) - rest

    def system(self, x, u, u_rate, u_acceleration, position: Mechanism | None = None):
        """The 3n simultaneous system: residuals of position, velocity and acceleration equations
        at x = (q, q̇, q̈), shape (..., 3n), and their Jacobian in x, shape (..., 3n, 3n).  With
        ``position`` (an equivalent declaration, see :meth:`consecutive`) its loops give the first n rows.

        >>> th, x = sp.symbols("theta x")
        >>> G, JG = Mechanism([x - sp.cos(th)], [x], [th]).system([1.0, 0.0, 0.0], [0.0], [2.0], [0.0])
        >>> G.tolist(), JG.tolist()
        ([0.0, 0.0, 4.0], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
        """
        n = len(self.unknowns)
        terms = self._system_fn(self._values, x, u, u_rate, u_acceleration)
        G, JG = _vector(terms, 0, 3 * n), _matrix(terms, 3 * n, 3 * n, 3 * n)
        if position is not None:
            G[..., :n], JG[..., :n, :n] = position._newton_terms(np.asarray(x, float)[..., :n], u)
        return G, JG

    def rates(self, q, u, u_rate, u_acceleration=None, *, trig: Mapping | None = None, singular=None):
        """q̇, q̈ (None without ``u_acceleration``) and the singular mask at known positions, by J·q̇ =
        −F_u·u̇, J·q̈ = −(the rest of d²F/dt²); NaN where singular.  ``q`` (..., n), the others (..., m);
        ``trig``: {name: (cos, sin)} already computed; ``singular``: the caller's own mask.

        >>> th, x = sp.symbols("theta x")
        >>> [a.tolist() for a in Mechanism([x**2 - th], [x], [th]).rates([2.0], [4.0], [1.0], [0.0])]
        [[0.25], [-0.03125], False]
        """
        arrays = [q, u, u_rate] + ([] if u_acceleration is None else [u_acceleration])
        shape, arrays = _rows(*arrays)
        q, u, u_rate = arrays[:3]
        known = {(name, func): _broadcast(value, shape).ravel() for name, pair in (trig or {}).items()
                 for func, value in zip(("cos", "sin"), pair, strict=True)}
        J, F_u = self._rate_terms(q, u, known, same_point=True)
        stack = LinearStack(J)
        singular = stack.singular if singular is None else _broadcast(singular, shape).ravel()
        any_singular = singular.any()
        if any_singular:
            stack = LinearStack(np.where(singular[:, None, None], np.eye(len(self.unknowns)), J))
        solve = stack.solve
        q_rate = solve(sum(F_u[:, :, j] * -u_rate[:, j, None] for j in range(u_rate.shape[1])))
        q_acc = None
        if u_acceleration is not None:
            q_acc = solve(self._rhs(q, q_rate, u, u_rate, arrays[3], known))
            if any_singular:
                q_acc[singular] = np.nan
            q_acc = q_acc.reshape(shape + q_acc.shape[-1:])
        if any_singular:
            q_rate[singular] = np.nan
        return q_rate.reshape(shape + q_rate.shape[-1:]), q_acc, singular.reshape(shape)

    # ------------------------------------------------------------ the course's two Newton routes

    def _run(self, stage, u, terms, start, tol, max_iter, direct=False, jacobian=None):
        """One Newton stage from ``start`` (k,) or (N, k); ``terms(x)`` gives (F, J), or F alone for a
        linear stage of constant ``jacobian`` (``direct``: one linear solve).  Failures raise, named."""
        batch = start.ndim == 2
        if direct:
            F0 = terms(start)
            stack = jacobian if batch else LinearStack(jacobian[None])
            stuck = stack.singular
            if batch and stuck.any():
                stack = LinearStack(np.where(stuck[:, None, None], np.eye(start.shape[-1]), stack.matrices))
            x = start + stack.solve(-(F0 if batch else F0[None])).reshape(start.shape)
            residual = np.linalg.norm(terms(x), axis=-1)
            if batch:
                result = BatchNewtonResult(x, residual <= tol, np.ones(len(x), int), stuck,
                                           np.linalg.norm(x - start, axis=-1), residual, "one linear solve")
            else:
                step = x - start
                result = NewtonResult(x, bool(residual <= tol), 1, np.array([start, x]),
                                      np.array([np.linalg.norm(step)]), np.abs(step)[None, :],
                                      np.array([np.linalg.norm(F0), residual]), "one linear solve",
                                      bool(stuck[0]))
        elif jacobian is not None and batch:
            result = newton_batch(terms, start, jac=jacobian, tol=tol, max_iter=max_iter)
        elif jacobian is not None:
            result = newton(terms, start, jac=lambda v: jacobian, tol=tol, max_iter=max_iter,
                            on_failure="report")
        elif batch:
            result = newton_batch(terms, start, jac=True, tol=tol, max_iter=max_iter)
        else:
            result = newton(lambda v: terms(v)[0], start, jac=lambda v: terms(v)[1], tol=tol,
                            max_iter=max_iter, on_failure="report")
        if np.all(result.converged) and not np.any(result.singular):
            return result
        failed = np.flatnonzero(~np.atleast_1d(result.converged) | np.atleast_1d(result.singular))
        first = failed[0]
        where = self._where(u, first)
        if batch:
            what = "the Jacobian became singular" if result.singular[first] else "Newton did not converge"
            message = (f"{stage} stage at {where}: {what} ({failed.size} of {len(start)} points, first at "
                       f"index {first})")
        else:
            message = f"{stage} stage at {where}: " + (
                f"the Jacobian is {singular_jacobian_text(start.size)}" if direct else result.message)
        if np.atleast_1d(result.singular)[first]:
            raise SingularJacobianError(message, x=result.x[first].tolist() if batch else result.x.tolist())
        raise ConvergenceError(message, result=result)

    def consecutive(self, u, u_rate, u_acceleration, seed, *, tol: float = 1e-6, max_iter: int = 50,
                    linear_stages: str = "newton", position: Mechanism | None = None) -> dict:
        """The course's consecutive Newton: position, then velocity, then acceleration, each stage run
        from its third of ``seed`` (q, q̇, q̈: 3n values); returns {stage: result}.

        ``u``, ``u_rate``, ``u_acceleration``: (m,) for one instant (``NewtonResult`` s with history) or
        (N, m) (:func:`newton_batch`).  ``linear_stages="direct"`` solves the linear rate stages in one
        step; ``position``: an equivalent declaration (e.g. a constraint substituted) for stage one.

        >>> th, x = sp.symbols("theta x")
        >>> stages = Mechanism([x**2 - th], [x], [th]).consecutive([4.0], [1.0], [0.0], [1.0, 0.0, 0.0])
        >>> [(stage, round(float(r.x[0]), 6), r.iterations) for stage, r in stages.items()]
        [('position', 2.0, 5), ('velocity', 0.25, 2), ('acceleration', -0.03125, 2)]
        """
        require_choice("linear_stages", linear_stages, LINEAR_STAGES)
        u, u_rate, u_acc, seed = (np.asarray(a, dtype=float) for a in (u, u_rate, u_acceleration, seed))
        n, batch = len(self.unknowns), u.ndim == 2
        start = np.broadcast_to(seed, (len(u), seed.size)) if batch else seed
        form, known, seen = position or self, {}, {}
        position = self._run("position", u, lambda v: form._newton_terms(v, u, known, seen), start[..., :n],
                             tol, max_iter)
        # newton_batch evaluates F last at the x it returns: the cos and sin seen there are those of q
        q, at_q = position.x, {**known, **seen} if batch else dict(known)
        J, F_u = self._rate_terms(q, u, at_q, same_point=True)
        jacobian = LinearStack(J) if batch else J  # both linear stages: one J, prepared once

        def linear(stage, constant, guess):
            def residual(v):
                return np.einsum("...ij,...j->...i", J, v) + constant

            return self._run(stage, u, residual, guess, tol, max_iter, direct=linear_stages == "direct",
                             jacobian=jacobian)

        velocity = linear("velocity", np.einsum("...ij,...j->...i", F_u, u_rate), start[..., n:2 * n])
        rest = self._rhs(q, velocity.x, u, u_rate, u_acc, at_q)
        acceleration = linear("acceleration", -rest, start[..., 2 * n:])
        return {"position": position, "velocity": velocity, "acceleration": acceleration}

    def simultaneous(self, u, u_rate, u_acceleration, seed, *, tol: float = 1e-6, max_iter: int = 50,
                     position: Mechanism | None = None):
        """The course's simultaneous Newton on the 3n system (:meth:`system`); arguments as in consecutive.

        >>> th, x = sp.symbols("theta x")
        >>> result = Mechanism([x**2 - th], [x], [th]).simultaneous([4.0], [1.0], [0.0], [1.0, 0.0, 0.0])
        >>> np.round(result.x, 6).tolist(), result.iterations
        ([2.0, 0.25, -0.03125], 5)
        """
        u, u_rate, u_acc, seed = (np.asarray(a, dtype=float) for a in (u, u_rate, u_acceleration, seed))
        start = np.broadcast_to(seed, (len(u), seed.size)) if u.ndim == 2 else seed
        return self._run("simultaneous", u, lambda x: self.system(x, u, u_rate, u_acc, position), start, tol,
                         max_iter)

    # ------------------------------------------------------------ solving a motion

    def _continuation(self, u: np.ndarray, seed: np.ndarray, tol: float, max_iter: int):
        """Positions at the rows of ``u``, each where Newton from the previous row's solution goes (the
        first from ``seed``), in few batched runs: all rows from one seed, a row accepted when one step
        from its predecessor lands 10× closer, or a run from it agrees; from the first that fails, again."""
        N, n = u.shape[0], len(self.unknowns)
        q = np.full((N, n), np.nan)
        converged, stuck, iterations = np.zeros(N, bool), np.zeros(N, bool), np.zeros(N, int)

        def batch(rows, seeds):
            u_rows, known = u[rows], {}
            return newton_batch(lambda x: self._newton_terms(x, u_rows, known), seeds, jac=True, tol=tol,
                                max_iter=max_iter)

        def keep(rows, result, take):
            q[rows], converged[rows] = result.x[take], result.converged[take]
            stuck[rows], iterations[rows] = result.singular[take], result.iterations[take]

        def distance(a, b):
            return np.abs(a - b).max(axis=-1)

        start, anchor, agree = 0, seed, SAME_ROOT + 100 * tol
        while start < N:
            rows = np.arange(start, N)
            first = batch(rows, np.tile(anchor, (rows.size, 1)))
            # rows that fail from the anchor before its first success, and that success
            k = int(np.argmax(first.converged)) if first.converged.any() else rows.size - 1
            keep(rows, first, slice(None))
            if k + 1 >= rows.size or not first.converged[k]:
                break
            rows, previous, x = rows[k + 1:], first.x[k:-1], first.x[k + 1:]
            F, J = self._newton_terms(previous, u[rows])
            stepped = previous + linear_solver(J)(-F)
            start_gap = distance(previous, x)
            closer = (start_gap <= agree) | (distance(stepped, x) <= 0.1 * start_gap)
            same = first.converged[k + 1:] & closer
            doubt = np.flatnonzero(~same)
            if doubt.size:
                check = batch(rows[doubt], previous[doubt])
                same[doubt] = check.converged & first.converged[k + 1:][doubt] & (
                    distance(check.x, x[doubt]) <= agree)
            if same.all():
                break
            f = int(np.argmin(same))
            where = int(np.searchsorted(doubt, f))
            keep(rows[f:f + 1], check, slice(where, where + 1))  # continuation's value there
            q[rows[f + 1:]], converged[rows[f + 1:]] = np.nan, False
            start = rows[f] + 1
            anchor = q[rows[f]] if converged[rows[f]] else q[rows[f] - 1]
        return q, converged, stuck, iterations

    def solve(self, inputs: Mapping, rates: Mapping | None = None, accelerations: Mapping | None = None,
              guess: Mapping | None = None, *, tol: float = 1e-10, max_iter: int = 50,
              on_failure: str = "raise") -> Motion:
        """Position, and velocity and acceleration if asked, at each value of the inputs.

        ``inputs``, ``rates``, ``accelerations`` map inputs (symbol or name) to numbers or arrays,
        broadcast together (missing rates are 0).  ``guess`` seeds Newton at the first instant; each
        later one (C order) continues from the previous solution.  One instant keeps its history in
        ``Motion.newton``.  Raises, unless ``on_failure="nan"``: ``SingularJacobianError`` (J singular),
        ``ConvergenceError`` (no root from the guess), ``UnreachableError`` (lost while continuing).

        >>> th, x = sp.symbols("theta x")
        >>> motion = Mechanism([x**2 - th], [x], [th]).solve({th: [1.0, 4.0]}, {th: 1.0}, guess={x: 2.0})
        >>> motion.position["x"].tolist(), motion.velocity["x"].tolist(), motion.acceleration["x"].tolist()
        ([1.0, 2.0], [0.5, 0.25], [-0.25, -0.03125])
        """
        require_choice("on_failure", on_failure, ON_FAILURE)
        u_given = _keyed("inputs", inputs, self.inputs)
        rate_given = _keyed("rates", rates or {}, self.inputs, required=False)
        acc_given = _keyed("accelerations", accelerations or {}, self.inputs, required=False)
        q_given = _keyed("guess", guess or {}, self.unknowns)
        seed = np.array([float(require_finite(f"guess[{k}]", v)) if np.ndim(v) == 0 else np.nan
                         for k, v in q_given.items()])
        if np.isnan(seed).any():
            raise InvalidGeometryError(f"guess must give one number per unknown; got {q_given!r}")
        named = {}
        for argument, given in (("inputs", u_given), ("rates", rate_given), ("accelerations", acc_given)):
            for name in (s.name for s in self.inputs):
                named[f"{argument}[{name}]"] = require_finite(f"{argument}[{name}]", given.get(name, 0.0))
        try:
            arrays = np.broadcast_arrays(*named.values())
        except ValueError:
            shapes = {k: np.shape(v) for k, v in named.items()}
            raise InvalidGeometryError(f"inputs, rates and accelerations must broadcast to one shape; "
                                       f"got shapes {shapes}") from None
        shape, m = arrays[0].shape, len(self.inputs)
        u, u_rate, u_acc = (np.stack(arrays[k * m:(k + 1) * m], axis=-1).reshape(-1, m) for k in range(3))
        with np.errstate(all="ignore"):
            if shape == ():
                q, converged, stuck, iterations, result = self._one_instant(u[0], seed, tol, max_iter,
                                                                            on_failure)
            else:
                result = None
                q, converged, stuck, iterations = self._continuation(u, seed, tol, max_iter)
            want_rates = rates is not None or accelerations is not None
            if want_rates:
                q_rate, q_acc, singular = self.rates(q, u, u_rate, u_acc)
            else:
                singular = is_singular(self.jacobian(q, u))
            singular = stuck | (converged & singular)
        if on_failure == "raise":
            self._report(~converged | (singular & want_rates), singular, u)
        q[~converged] = np.nan
        velocity = acceleration = None
        if want_rates:
            q_rate[singular | ~converged], q_acc[singular | ~converged] = np.nan, np.nan
            velocity, acceleration = self._by_name(q_rate, shape), self._by_name(q_acc, shape)

        def shaped(values):
            return scalar_or_array(values.reshape(shape))

        inputs_used = {s.name: scalar_or_array(a) for s, a in zip(self.inputs, arrays[:m], strict=True)}
        return Motion(position=self._by_name(q, shape), velocity=velocity, acceleration=acceleration,
                      converged=shaped(converged), singular=shaped(singular), iterations=shaped(iterations),
                      inputs=MappingProxyType(inputs_used), newton=result)

    def _one_instant(self, u, seed, tol, max_iter, on_failure):
        """Newton with its history at one instant; failures re-raised naming the inputs."""
        where = self._where(u, 0)
        result = newton(lambda q: self.residual(q, u), seed, jac=lambda q: self.jacobian(q, u),
                        tol=tol, max_iter=max_iter, on_failure="report")
        if on_failure == "raise" and result.singular:
            raise SingularJacobianError(f"at {where}: {result.message}", result.x.tolist())
        if on_failure == "raise" and not result.converged:
            raise ConvergenceError(f"at {where}, from the guess: {result.message}", result=result)
        if result.singular:
            return np.full((1, seed.size), np.nan), np.array([False]), np.array([True]), np.array([0]), None
        return (result.x[None, :].copy(), np.array([result.converged]), np.array([False]),
                np.array([result.iterations]), result)

    def _where(self, u, index) -> str:
        row = np.atleast_2d(u)[index]
        return ", ".join(f"{s.name}={value:.6g}" for s, value in zip(self.inputs, row, strict=True))

    def _report(self, bad, singular, u) -> None:
        """Raise the named error of the first bad instant (see :meth:`solve`)."""
        if not bad.any():
            return
        first = int(np.flatnonzero(bad)[0])
        where = self._where(u, first)
        count = f"({int(bad.sum())} of {bad.size} instants, first at index {first})"
        if singular[first]:
            raise SingularJacobianError(f"the Jacobian is singular at {where} {count}: the mechanism is at a "
                                        "toggle or limit position, where the rates are undefined")
        if first == 0:
            raise ConvergenceError(f"Newton did not converge at {where} from the guess {count}: "
                                   "no assembly near the guess, or none at all")
        raise UnreachableError(f"the loops cannot be closed at {where} {count}, continuing from the previous "
                               "instant: the mechanism cannot follow the input there", mask=bad)

    def _by_name(self, values: np.ndarray, shape) -> Mapping[str, float | np.ndarray]:
        return MappingProxyType({s.name: scalar_or_array(values[:, k].reshape(shape))
                                 for k, s in enumerate(self.unknowns)})

    # ------------------------------------------------------------ drawing

    @_derived
    def _point_fn(self):
        return self._compile([c for xy in self.points.values() for c in xy], self.unknowns, self.inputs)

    def joints(self, motion: Motion) -> dict[str, np.ndarray]:
        """Coordinates (m) of the declared ``points`` along a motion: name → array (..., 2).

        >>> th, x = sp.symbols("theta x")
        >>> A = sp.Matrix([sp.cos(th), sp.sin(th)])
        >>> crank = Mechanism([x - sp.cos(th)], [x], [th], points={"A": A}, links=[("A", "A")])
        >>> crank.joints(crank.solve({th: [0.0, np.pi / 2]}, guess={x: 1.0}))["A"].round(12).tolist()
        [[1.0, 0.0], [0.0, 1.0]]
        """
        if not self.points:
            raise InvalidGeometryError("joints needs points: declare points={name: Matrix([x, y])}; "
                                       "got points={}")
        q = np.stack(np.broadcast_arrays(*(motion.position[s.name] for s in self.unknowns)), axis=-1)
        u = np.stack(np.broadcast_arrays(*(motion.inputs[s.name] for s in self.inputs)), axis=-1)
        xy = self._point_fn(self._values, q, u)
        return {name: _vector(xy, 2 * k, 2) for k, name in enumerate(self.points)}
