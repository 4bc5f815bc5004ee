"""One core for every planar mechanism: write the vector loops once, get position, velocity, acceleration.

A mechanism is declared by its loop equations F(q, u) = 0 in sympy: unknowns q (angles or lengths),
inputs u and a number for every other symbol.  The core derives once, lambdified with cse: F,
J = ∂F/∂q, F_u = ∂F/∂u, the velocity system J·q̇ = −F_u·u̇, the acceleration system J·q̈ = −(the rest of
d²F/dt²) and the stacked 3n system.  It splits the loops into blocks solved in turn and, where a block
reduces to one quadratic by the course's half-angle route (:func:`~course_lib.symbolic.reduce_loop`),
solves it in closed form, each block's assembly fixed by its root σ = ±1; elsewhere by Newton–Raphson
with continuation.  SI units, radians.

The singularity rule: J is singular where the smallest singular value of J̃ — J with each row and column
divided by its typical size at the declaration's generic point — is below ``SINGULAR`` = 1e-6 (near one
below ``NEAR_SINGULAR`` = 1e-3); there the rates are undefined and asking for them raises.

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
>>> sweep.position["theta3"].shape, bool(sweep.converged.all()), sweep.velocity, sweep.message
((7,), True, None, '')
"""

from __future__ import annotations

import copy
import itertools
from collections.abc import Callable, Mapping, Sequence
from functools import wraps
from types import MappingProxyType

import numpy as np
import sympy as sp

from .errors import (
    FAILURE_POLICIES,
    ConvergenceError,
    InvalidGeometryError,
    SingularJacobianError,
    UnreachableError,
    require_broadcast,
    require_choice,
    require_finite,
)
from .motion import NEAR_SINGULAR, SINGULAR, Deferred, Motion
from .newton import (
    BatchNewtonResult,
    LinearStack,
    NewtonResult,
    newton,
    newton_batch,
    singular_jacobian_text,
)
from .planar import scalar_or_array
from .symbolic import LoopForm, is_angle, rate_name, reduce_loop

__all__ = ["Mechanism", "Motion", "Links", "SINGULAR", "NEAR_SINGULAR"]

LINEAR_STAGES = ("newton", "direct")

#: A continuation step changes no unknown by more than this (radians, or typical lengths).
MAX_CHANGE = 0.1
#: A corrector step moves no unknown by more than this (radians, or typical lengths).
MAX_STEP = 0.5
#: A closed-form or continued position is accepted where |F_i| / (typical size of row i) stays below this.
RESIDUAL = 1e-8

#: The core's own time: a Dummy, so no symbol of a declaration (a parameter named t) can be taken for it.
_TIME = sp.Dummy("t", real=True)
_NOT_SMOOTH = (sp.Abs, sp.sign, sp.Heaviside, sp.Max, sp.Min, sp.Piecewise, sp.floor, sp.ceiling, sp.re,
               sp.im, sp.arg, sp.conjugate, sp.DiracDelta, sp.frac, sp.Mod)


def _symbols(argument: str, values) -> tuple[sp.Symbol, ...]:
    values = tuple(values) if isinstance(values, Sequence) and not isinstance(values, str) else (values,)
    for value in values:
        if not isinstance(value, sp.Symbol):
            raise InvalidGeometryError(f"{argument} must be sympy Symbols; got {value!r} in {argument}")
    names = [value.name for value in values]
    if len(set(names)) != len(names) or not names:
        raise InvalidGeometryError(f"{argument} must be one or more distinct symbols; got {list(values)}")
    return values


def _expression(where: str, value) -> sp.Expr:
    """One loop row (an Eq becomes lhs − rhs), refused by name when not a smooth real expression."""
    if isinstance(value, sp.Equality):
        value = value.lhs - value.rhs
    try:
        expr = sp.sympify(value, strict=True)
    except (sp.SympifyError, TypeError, ValueError):
        raise InvalidGeometryError(f"{where} must be a sympy expression (= 0) or Eq; got {value!r}") from None
    if not isinstance(expr, sp.Expr) or isinstance(expr, sp.MatrixBase):
        raise InvalidGeometryError(f"{where} must be a sympy expression (= 0) or Eq; got {value!r}")
    rough = sorted({type(node).__name__ for node in sp.preorder_traversal(expr)
                    if isinstance(node, _NOT_SMOOTH)})
    if rough:
        raise InvalidGeometryError(f"{where} uses {', '.join(rough)}, which is not smooth: Newton and the "
                                   f"rates need derivatives everywhere, so write the loop without it; "
                                   f"got {expr}")
    if expr.has(sp.I) or expr.has(sp.zoo, sp.nan, sp.oo, -sp.oo):
        raise InvalidGeometryError(f"{where} must be real (no I, no infinity): write the x and y components "
                                   f"as two rows; got {expr}")
    return expr


def _equations(loops) -> tuple[sp.Matrix, list[str], list[list[int]]]:
    """The rows of the loops, the name of each row and the rows of each declared loop."""
    if isinstance(loops, sp.Equality) and isinstance(loops.lhs, sp.MatrixBase):
        loops = [loops]
    if isinstance(loops, str) or not isinstance(loops, Sequence):
        loops = [loops]
    rows, names, groups = [], [], []
    for k, loop in enumerate(loops):
        if isinstance(loop, sp.Equality) and isinstance(loop.lhs, sp.MatrixBase):
            loop = loop.lhs - loop.rhs
        if isinstance(loop, sp.MatrixBase):
            entries = list(loop)
            group = []
            for j, entry in enumerate(entries):
                group.append(len(rows))
                names.append(f"loops[{k}][{j}]")
                rows.append(_expression(names[-1], entry))
            groups.append(group)
            continue
        groups.append([len(rows)])
        names.append(f"loops[{k}]")
        rows.append(_expression(names[-1], loop))
    if not rows:
        raise InvalidGeometryError(f"loops must hold at least one equation; got {loops!r}")
    return sp.Matrix(rows), names, groups


def _number(name: str, value) -> float:
    """A parameter's value: a number or a sympy constant (sp.pi / 6), finite and real."""
    if isinstance(value, sp.Basic):
        if not (isinstance(value, sp.Expr) and value.is_number):
            raise InvalidGeometryError(f"{name} must be a number; got {value!r} (it holds symbols)")
        complex_value = complex(value.evalf(30))
        if complex_value.imag:
            raise InvalidGeometryError(f"{name} must be a real number; got {value!r}")
        value = complex_value.real
    array = require_finite(name, value)
    if array.ndim:
        raise InvalidGeometryError(f"{name} must be one number; got {value!r}")
    return float(array)


def _keyed(argument: str, mapping, symbols, required: bool = True) -> dict[str, object]:
    """A dict keyed by symbols or their names → {name: value}; unknown keys and missing names raise."""
    names = [symbol.name for symbol in symbols]
    if not isinstance(mapping, Mapping):
        raise InvalidGeometryError(f"{argument} must be a dict keyed by {', '.join(names)}; got {mapping!r}")
    out = {}
    for key, value in mapping.items():
        name = key.name if isinstance(key, sp.Symbol) else key
        if not isinstance(name, str) or name not in names:
            raise InvalidGeometryError(f"{argument} has the key {key!r}, which is not one of {names}")
        if name in out:
            raise InvalidGeometryError(f"{argument} gives {name} twice; got keys {list(mapping)}")
        out[name] = value
    missing = [name for name in names if name not in out]
    if required and missing:
        raise InvalidGeometryError(f"{argument} must give a value for {', '.join(missing)}; "
                                   f"got keys {list(mapping)}")
    return out


def _unwrap_to(values: np.ndarray, target: np.ndarray) -> np.ndarray:
    """``values`` shifted by whole turns to within π of ``target`` (NaN stays NaN)."""
    return values - 2 * np.pi * np.round((values - target) / (2 * np.pi))


def _points(points) -> dict[str, sp.Matrix]:
    """Declared points: name (text) → 2×1 Matrix of smooth real expressions, else the named error."""
    if points is None:
        return {}
    if not isinstance(points, Mapping):
        raise InvalidGeometryError(f"points must be a dict name → Matrix([x, y]); got {points!r}")
    out = {}
    for name, xy in points.items():
        if not isinstance(name, str) or not name:
            raise InvalidGeometryError(f"points must be keyed by names (text); got the key {name!r}")
        try:
            matrix = sp.Matrix(xy)
        except (TypeError, ValueError, sp.SympifyError):
            matrix = None
        if matrix is None or matrix.shape != (2, 1):
            raise InvalidGeometryError(f"points[{name!r}] must be a 2x1 Matrix (x, y); got {xy!r}")
        out[name] = sp.Matrix([_expression(f"points[{name!r}][{k}]", e) for k, e in enumerate(matrix)])
    return out


class Links(tuple):
    """The declared links: a tuple of (start, end) point-name pairs, as before, that also knows each
    link's name (``names``: the declaration's, or "link 1", "link 2", … for a plain list of pairs).

    >>> links = Links([("O2", "A"), ("A", "B")], names=("crank", "coupler"))
    >>> links == (("O2", "A"), ("A", "B")), links.named()
    (True, {'crank': ('O2', 'A'), 'coupler': ('A', 'B')})
    """

    names: tuple[str, ...]

    def __new__(cls, pairs=(), names=None):
        links = super().__new__(cls, (tuple(pair) for pair in pairs))
        links.names = tuple(names) if names is not None else tuple(f"link {k + 1}" for k in range(len(links)))
        return links

    def named(self) -> dict[str, tuple[str, str]]:
        """Link name → (start, end) point names, in the declared order."""
        return dict(zip(self.names, self, strict=True))


def _links(links, points) -> Links:
    """Declared links: pairs of two different declared point names (a list, or a dict name → pair), else
    the named error."""
    names = None
    if isinstance(links, Mapping):
        if not all(isinstance(name, str) and name for name in links):
            raise InvalidGeometryError(f"links must be named by text; got the names {list(links)}")
        names, links = list(links), list(links.values())
    if isinstance(links, str | bytes) or not isinstance(links, Sequence):
        raise InvalidGeometryError(f"links must be a list of pairs of point names; got {links!r}")
    out = []
    for k, link in enumerate(links):
        if isinstance(link, str) or not isinstance(link, Sequence) or len(link) != 2:
            raise InvalidGeometryError(f"links[{k}] must be a pair of point names; got {link!r}")
        if not all(isinstance(end, str) and end in points for end in link):
            raise InvalidGeometryError(f"links: {tuple(link)} names a point not in points {list(points)}")
        if link[0] == link[1]:
            raise InvalidGeometryError(f"links[{k}] joins {link[0]!r} to itself; got {link!r}")
        out.append((link[0], link[1]))
    return Links(out, names)


def _drawing(points, links: Links, ground, sliders, plates, styles):
    """The declaration's drawing: ``ground`` and ``sliders`` as tuples of declared point names, ``plates``
    (name → three or more point names) and ``styles`` (link name → line properties) as read-only
    mappings, else the named error."""
    found = []
    for argument, names in (("ground", ground), ("sliders", sliders)):
        names = (names,) if isinstance(names, str) else names
        if not isinstance(names, Sequence) or not all(isinstance(n, str) and n in points for n in names):
            raise InvalidGeometryError(f"{argument} must name declared points {list(points)}; got {names!r}")
        found.append(tuple(names))
    plates = {} if plates is None else plates
    if not isinstance(plates, Mapping) or not all(
            isinstance(name, str) and isinstance(corners, Sequence) and not isinstance(corners, str)
            and len(corners) >= 3 and all(c in points for c in corners) for name, corners in plates.items()):
        raise InvalidGeometryError(f"plates must map names to three or more declared points {list(points)}; "
                                   f"got {plates!r}")
    styles = {} if styles is None else styles
    if not isinstance(styles, Mapping) or not set(styles) <= set(links.names) or not all(
            isinstance(style, Mapping) for style in styles.values()):
        raise InvalidGeometryError(f"styles must map link names {list(links.names)} to line properties; "
                                   f"got {styles!r}")
    return (*found, MappingProxyType({name: tuple(corners) for name, corners in plates.items()}),
            MappingProxyType({name: MappingProxyType(dict(style)) for name, style in styles.items()}))


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


def _rows(*arrays) -> tuple[tuple, list[np.ndarray]]:
    """Arrays (..., k) broadcast over their leading axes and flattened to (N, k); and that leading shape."""
    arrays = [np.asarray(a, dtype=float) for a in arrays]
    shape = np.broadcast_shapes(*(a.shape[:-1] for a in arrays))
    return shape, [_broadcast(a, shape + a.shape[-1:]).reshape(-1, a.shape[-1]) for a in arrays]


def _broadcast(array, shape) -> np.ndarray:
    array = np.asarray(array)
    return array if array.shape == shape else np.broadcast_to(array, shape)


class Mechanism:
    """A planar mechanism declared by its loop equations (each expression = 0, or an ``Eq``).

    ``loops``: 2×1 sympy matrices (x and y components of a vector loop), scalar expressions or ``Eq`` s, as
    many equations in all as ``unknowns``; loops may share unknowns.  ``inputs``: the driven variables.
    ``parameters``: a number (or a sympy constant such as ``sp.pi / 6``) for every other symbol, keyed by
    the symbol or its name (:meth:`with_parameters` gives the same declaration with other numbers, sharing
    everything derived).  Optional ``points`` (name → 2×1 matrix of x, y) and ``links`` (pairs of point
    names, or a dict link name → pair: :class:`Links`) describe the drawing, with the ``ground`` pivots
    and ``sliders`` (point names), ``plates`` (name → three or more point names: a rigid plate, shaded)
    and ``styles`` (link name → line properties) that ``draw``, ``animate`` and ``explore`` use.  A
    declaration is checked when made: rows that are not smooth and real, involve no unknown, repeat or
    depend on each other (J of rank < n at a generic point) are refused by name.

    >>> x, th = sp.symbols("x theta")
    >>> follower = Mechanism([sp.Eq(x, sp.cos(th))], unknowns=[x], inputs=[th])
    >>> follower.solve({th: np.pi / 2}, rates={th: 2.0}, guess={x: 0.5}).velocity["x"]
    -2.0
    """

    def __init__(self, loops, unknowns, inputs, parameters: Mapping | None = None, *,
                 points: Mapping | None = None, links: Sequence = (), ground: Sequence[str] = (),
                 sliders: Sequence[str] = (), plates: Mapping[str, Sequence[str]] | None = None,
                 styles: Mapping[str, Mapping] | None = None):
        self.unknowns = _symbols("unknowns", unknowns)
        self.inputs = _symbols("inputs", inputs)
        moving = self.unknowns + self.inputs
        if len({s.name for s in moving}) != len(moving):
            raise InvalidGeometryError(f"unknowns and inputs must not share a symbol; got {moving}")
        equations, self._row_names, self._loops = _equations(loops)
        n = len(self.unknowns)
        if equations.rows != n:
            raise InvalidGeometryError(f"loops give {equations.rows} equations for the {n} unknowns "
                                       f"{list(self.unknowns)}: there must be one equation per unknown")
        points = _points(points)
        # one symbol per name: the unknowns' and inputs' own, else the first met (whatever its assumptions)
        canonical = {s.name: s for s in moving}
        found = equations.free_symbols.union(*(xy.free_symbols for xy in points.values()))
        for symbol in sorted(found, key=lambda s: (s.name, str(sorted(s.assumptions0.items())))):
            canonical.setdefault(symbol.name, symbol)
        swap = {s: canonical[s.name] for s in found if canonical[s.name] is not s}
        self.equations = equations.xreplace(swap)
        self.points = {name: xy.xreplace(swap) for name, xy in points.items()}
        self.links = _links(links, self.points)
        self.ground, self.sliders, self.plates, self.styles = _drawing(
            self.points, self.links, ground, sliders, plates, styles)
        used = self.equations.free_symbols
        for argument, symbols in (("unknowns", self.unknowns), ("inputs", self.inputs)):
            for symbol in symbols:
                if symbol not in used:
                    raise InvalidGeometryError(f"{argument}: {symbol} appears in no loop "
                                               f"(the loops contain {sorted(map(str, used))})")
        self._check_rows()
        everything = used.union(*(xy.free_symbols for xy in self.points.values()))
        given = {} if parameters is None else parameters
        if not isinstance(given, Mapping):
            raise InvalidGeometryError(f"parameters must map sympy Symbols (or their names) to numbers; "
                                       f"got {given!r}")
        by_name, moving_names = {s.name: s for s in everything}, {s.name for s in moving}
        values, clash, unused = {}, set(), set()
        for key, value in given.items():
            name = key.name if isinstance(key, sp.Symbol) else key
            if not isinstance(name, str):
                raise InvalidGeometryError(f"parameters must be keyed by sympy Symbols or their names; "
                                           f"got the key {key!r}")
            if name in moving_names:
                clash.add(name)
            elif name not in by_name:
                unused.add(name)
            else:
                values[by_name[name]] = _number(f"parameters[{name}]", value)
        left_over = {s.name for s in everything - set(moving) - set(values)}
        shown = {str(k): v for k, v in given.items()}
        for bad, what in ((clash, "is an unknown or input and cannot be a parameter"),
                          (left_over, "has no value: give it one in parameters"),
                          (unused, "appears in no loop or point")):
            if bad:
                raise InvalidGeometryError(f"parameters: {', '.join(sorted(bad))} {what}; "
                                           f"got parameters={shown}")
        self.parameters = MappingProxyType(values)
        self._values = tuple(self.parameters.values())
        self._derived, self._numeric = {}, {}
        self._check_rank()

    def _check_rows(self) -> None:
        """Rows that involve no unknown, or repeat another (up to sign), refused by name."""
        unknowns = set(self.unknowns)
        for name, row in zip(self._row_names, self.equations, strict=True):
            if not row.free_symbols & unknowns:
                raise InvalidGeometryError(f"{name} does not involve any unknown: a row that is zero or "
                                           f"constant in {list(self.unknowns)} fixes nothing; got {row}")
        for (i, a), (j, b) in itertools.combinations(enumerate(self.equations), 2):
            if sp.expand(a - b) == 0 or sp.expand(a + b) == 0:
                raise InvalidGeometryError(f"{self._row_names[j]} repeats {self._row_names[i]}: the rows "
                                           f"must be independent; got {b}")

    def _check_rank(self) -> None:
        """J of full rank at a generic point, else the dependent rows named."""
        J = self._generic_jacobians()
        if J is None:
            return
        r, c = self._scales
        scaled = J / r[:, None] / c[None, :]
        u_all, s_all, _ = np.linalg.svd(scaled)
        ratio = s_all[:, -1] / s_all[:, 0]
        if ratio.max() >= 1e-9:
            return
        best = int(np.argmax(ratio))
        rows = [self._row_names[i] for i in np.flatnonzero(np.abs(u_all[best][:, -1]) > 0.1)]
        raise InvalidGeometryError(f"the rows {', '.join(rows)} depend on each other: J = ∂F/∂q has rank "
                                   f"< {len(self.unknowns)} at every configuration, so no input fixes the "
                                   "unknowns; declare independent loops")

    def with_parameters(self, parameters: Mapping) -> Mechanism:
        """The same loops with other numbers for all the parameters (keyed by symbol or name): nothing
        is derived again.

        >>> x, th, a = sp.symbols("x theta a")
        >>> crank = Mechanism([x - a * sp.cos(th)], [x], [th], {a: 1.0})
        >>> crank.with_parameters({"a": 3.0}).residual([0.0], [0.0]).tolist()
        [-3.0]
        """
        if not isinstance(parameters, Mapping):
            raise InvalidGeometryError(f"parameters must map each of {list(self.parameters)} to a number; "
                                       f"got {parameters!r}")
        by_name = {s.name: s for s in self.parameters}
        values = {}
        for key, value in parameters.items():
            name = key.name if isinstance(key, sp.Symbol) else key
            if name not in by_name:
                raise InvalidGeometryError(f"parameters must give a number for each of "
                                           f"{list(self.parameters)} and nothing else; "
                                           f"got {list(parameters)}")
            values[by_name[name]] = _number(f"parameters[{name}]", value)
        if set(values) != set(self.parameters):
            raise InvalidGeometryError(f"parameters must give a number for each of {list(self.parameters)} "
                                       f"and nothing else; got {list(parameters)}")
        other = copy.copy(self)
        other.parameters = MappingProxyType({k: values[k] for k in self.parameters})
        other._values = tuple(other.parameters.values())
        other._numeric = {}
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

    def _in_time(self, expressions: sp.Matrix) -> tuple[sp.Matrix, sp.Matrix]:
        """d/dt and d²/dt² of ``expressions``: unknowns and inputs made functions of the core's own time (a
        Dummy), differentiated, the derivatives named by :attr:`rate_symbols`."""
        functions = {s: sp.Function(s.name, real=True)(_TIME) for s in self.rate_symbols}
        back = {}
        for symbol, function in functions.items():
            first, second = self.rate_symbols[symbol]
            back.update({function.diff(_TIME, 2): second, function.diff(_TIME): first, function: symbol})
        first = expressions.xreplace(functions).diff(_TIME)
        return first.xreplace(back), first.diff(_TIME).xreplace(back)

    @_derived
    def _time_derivatives(self) -> tuple[sp.Matrix, sp.Matrix]:
        """dF/dt and d²F/dt² of the loops."""
        return self._in_time(self.equations)

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
        function = sp.lambdify(arguments, replaced[:len(expressions)], "numpy", cse=cse)
        inputs = {s.name for s in self.inputs}
        where = [(k, j) for k, group in enumerate(groups) for j in range(len(group))]
        angles_of = [((s.name, func), np.cos if func == "cos" else np.sin, symbols.index(s), s.name in inputs)
                     for func, s in trig]

        def evaluate(values, *arrays, known=None, same_point=False, seen=None):
            arrays = [np.asarray(a, dtype=float) for a in arrays]
            columns = [arrays[k][..., j] for k, j in where]
            angles = []
            for key, func, index, is_input in angles_of:
                value = None if known is None else known.get(key)
                if value is None:
                    value = func(columns[index])
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
            out, arguments = np.empty((len(expressions),) + shape), [*columns, *angles]  # floats stay floats
            for block in blocks:
                inputs, part = arguments, out
                if block is not Ellipsis:
                    inputs, part = [a[block] if np.ndim(a) else a for a in arguments], out[:, block]
                for k, value in enumerate(function(*inputs, *values)):
                    part[k] = value
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

    # ------------------------------------------------------------ structure: blocks, angles, closed forms

    @_derived
    def _structure(self) -> dict:
        """The blocks solved in turn (rows, columns), the angle unknowns, and each block's closed form
        (a :class:`~course_lib.symbolic.LoopForm`, or None where Newton solves it)."""
        n = len(self.unknowns)
        column = {s: j for j, s in enumerate(self.unknowns)}
        involves = [{column[s] for s in row.free_symbols if s in column} for row in self.equations]
        angles = {s for s in self.unknowns if all(is_angle(row, s) for row in self.equations if row.has(s))}
        remaining, solved, blocks = list(range(n)), set(), []

        def open_columns(rows):
            return set().union(*(involves[i] for i in rows)) - solved

        while remaining:
            whole = [g for g in self._loops if set(g) <= set(remaining)]
            choices = ([g for g in whole if len(open_columns(g)) == len(g) <= 2]
                       + [[i] for i in remaining if len(open_columns([i])) == 1]
                       + [list(p) for p in itertools.combinations(remaining, 2) if len(open_columns(p)) == 2]
                       + [g for g in whole if len(open_columns(g)) == len(g)])
            rows = choices[0] if choices else list(remaining)
            columns = sorted(open_columns(rows))
            if len(columns) != len(rows):
                rows, columns = list(remaining), sorted(set(range(n)) - solved)
            blocks.append((rows, columns))
            solved |= set(columns)
            remaining = [i for i in remaining if i not in rows]
        forms = []
        for rows, columns in blocks:
            form = None
            if len(columns) <= 2:
                try:
                    form = reduce_loop([self.equations[i] for i in rows], [self.unknowns[j] for j in columns],
                                       angles)
                except (ValueError, TypeError, NotImplementedError, ZeroDivisionError, sp.PolynomialError):
                    form = None
            forms.append(form)
        return {"blocks": blocks, "angles": angles, "forms": forms}

    @property
    def closed_forms(self) -> list[LoopForm | None]:
        """Each block's closed form, derived from the declaration by the half-angle route (None where a
        block does not reduce and Newton solves it); ``quadratic`` holds its (a, b, c).

        >>> th2, th3, th4 = sp.symbols("theta2 theta3 theta4")
        >>> l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
        >>> loop = sp.Matrix([l2*sp.cos(th2) + l3*sp.cos(th3) - l4*sp.cos(th4) - l1,
        ...                   l2*sp.sin(th2) + l3*sp.sin(th3) - l4*sp.sin(th4)])
        >>> form, = Mechanism([loop], [th3, th4], [th2], {l1: 0.2, l2: 0.06, l3: 0.18, l4: 0.12}).closed_forms
        >>> form.unknowns, form.quadratic[1]
        ((theta4, theta3), -4*l2*l4*sin(theta2))
        """
        return list(self._structure["forms"])

    @_derived
    def _closed_fns(self) -> list | None:
        """Per block, the compiled (a, b, c) and second-unknown functions; None unless every block reduces."""
        forms = self._structure["forms"]
        if any(form is None for form in forms):
            return None
        compiled = []
        for form in forms:
            second = None
            if form.second is not None:
                second = self._compile(list(form.second[1:]), self.unknowns, self.inputs)
            linear = form.kind == "length" and form.quadratic[0] == 0
            compiled.append((self._compile(list(form.quadratic), self.unknowns, self.inputs), second, linear))
        return compiled

    # ------------------------------------------------------------ typical sizes and the singularity rule

    def _generic_jacobians(self) -> np.ndarray | None:
        """J at 24 generic configurations (angles in (−π, π], lengths of the parameters' typical size)."""
        if "generic" not in self._numeric:
            sizes = [abs(v) for v in self._values if v != 0.0]
            length = float(np.median(sizes)) if sizes else 1.0
            rng = np.random.default_rng(0)
            angles = self._structure["angles"] | {s for s in self.inputs if all(
                is_angle(row, s) for row in self.equations if row.has(s))}

            def sample(symbols):
                return np.column_stack([rng.uniform(-np.pi, np.pi, 24) if s in angles else
                                        length * rng.uniform(0.5, 2.0, 24) * rng.choice([-1, 1], 24)
                                        for s in symbols])

            q, u = sample(self.unknowns), sample(self.inputs)
            with np.errstate(all="ignore"):
                J = self.jacobian(q, u)
            J = J[np.isfinite(J).all(axis=(1, 2))]
            self._numeric["generic"] = J if len(J) else None
        return self._numeric["generic"]

    @property
    def _scales(self) -> tuple[np.ndarray, np.ndarray]:
        """Typical size of each row and column of J at the generic configurations (rows first)."""
        if "scales" not in self._numeric:
            J, n = self._generic_jacobians(), len(self.unknowns)
            if J is None:
                rows = columns = np.ones(n)
            else:
                units = self._column_units(J)
                J = J / units
                rows = np.sqrt((J * J).mean(axis=(0, 2)))
                rows = np.where(rows > 0, rows, 1.0)
                scaled = J / rows[:, None]
                columns = np.sqrt((scaled * scaled).mean(axis=(0, 1)))
                columns = np.where(columns > 0, columns, 1.0) * units
            self._numeric["scales"] = (rows, columns)
        return self._numeric["scales"]

    def _column_units(self, J: np.ndarray) -> np.ndarray:
        """A unit for each column of J: 1 for an angle, one typical length ℓ for every length — the ℓ of
        the least-squares fit log|J_ij| ≈ log d_i + log ℓ·[j a length] over the nonzero typical sizes.  A
        change of units multiplies row i of J by some d_i and the lengths' columns by 1/k: ℓ moves by k, so
        J divided by these units changes by whole rows only, which the row sizes take.  With angles alone
        or lengths alone every unit is 1 (then a change of units is such rows already)."""
        lengths = [j for j, s in enumerate(self.unknowns) if s not in self._structure["angles"]]
        units = np.ones(len(self.unknowns))
        if not lengths or len(lengths) == len(units):
            return units
        size = np.sqrt((J * J).mean(axis=0))
        i, j = np.nonzero(size > 0)
        fit = np.zeros((len(i), len(units) + 1))
        fit[np.arange(len(i)), i] = 1.0
        fit[:, -1] = np.isin(j, lengths)
        solution = np.linalg.lstsq(fit, np.log(size[i, j]), rcond=None)[0]
        units[lengths] = np.exp(solution[-1])
        return units

    def smallest_singular_value(self, q, u) -> np.ndarray:
        """σ_min(J̃) at positions ``q`` (..., n) and inputs ``u`` (..., m): J̃ is J with each row and column
        divided by its typical size at the declaration's generic point, so the test ignores units and a
        row vanishing as a whole counts.  J is singular where it is below ``SINGULAR``.

        >>> x, y, s = sp.symbols("x y s")
        >>> trammel = Mechanism([x**2 + y**2 - 1, x - s], [x, y], [s])
        >>> values = trammel.smallest_singular_value([[0.6, 0.8], [1.0, 0.0]], [[0.6], [1.0]])
        >>> [round(float(v), 3) for v in values]
        [0.798, 0.0]
        """
        q, u = self._checked(q=q, u=u)
        return self._smallest(self.jacobian(q, u))

    def is_singular(self, q, u) -> np.ndarray:
        """The one singularity rule: True where σ_min(J̃) < ``SINGULAR`` (see
        :meth:`smallest_singular_value`), or where J is not finite; ``q`` (..., n), ``u`` (..., m).

        >>> x, y, s = sp.symbols("x y s")
        >>> Mechanism([x**2 + y**2 - 1, x - s], [x, y], [s]).is_singular([[0.6, 0.8], [1.0, 0.0]],
        ...                                                               [[0.6], [1.0]]).tolist()
        [False, True]
        """
        return ~(self.smallest_singular_value(q, u) >= SINGULAR)

    def motion_of(self, position: Mapping, inputs: Mapping, velocity: Mapping | None = None,
                  acceleration: Mapping | None = None, *, converged=None, singular=None, near_singular=None,
                  message: str = "", assembly: Mapping | None = None, iterations=0,
                  newton: NewtonResult | None = None, kind: type[Motion] = Motion, **extra) -> Motion:
        """A :class:`Motion` of this mechanism from values found another way (a machine's own closed form):
        ``position`` and the rates keyed by the unknowns' names, ``inputs`` by the inputs', broadcast
        together.  ``converged`` defaults to "every unknown finite"; ``singular`` and ``near_singular`` to
        the core's rule where converged; ``iterations`` (default 0) and ``newton`` say how it was found.
        ``kind``: a machine's own :class:`Motion` (its result type, with its names for the values and its
        ``extra`` fields).

        >>> th, x = sp.symbols("theta x")
        >>> follower = Mechanism([x - sp.cos(th)], [x], [th])
        >>> motion = follower.motion_of({"x": [1.0, 0.0]}, {"theta": [0.0, np.pi / 2]})
        >>> motion.converged.tolist(), motion.singular.tolist(), motion.iterations.tolist()
        ([True, True], [False, False], [0, 0])
        """
        unknowns, inputs_named = [s.name for s in self.unknowns], [s.name for s in self.inputs]
        for argument, given, names in (("position", position, unknowns), ("inputs", inputs, inputs_named),
                                       ("velocity", velocity, unknowns),
                                       ("acceleration", acceleration, unknowns)):
            if given is not None and (not isinstance(given, Mapping) or sorted(given) != sorted(names)):
                raise InvalidGeometryError(f"{argument} must map each of {names} to its values; got {given!r}"
                                           [:400])
        named = {f"position[{k}]": position[k] for k in unknowns} | {f"inputs[{k}]": inputs[k]
                                                                      for k in inputs_named}
        for rates_name, rates in (("velocity", velocity), ("acceleration", acceleration)):
            if rates is not None:
                named |= {f"{rates_name}[{k}]": rates[k] for k in unknowns}
        arrays = dict(zip(named, require_broadcast(**{k: require_finite(k, v, allow_nan=True)
                                                         for k, v in named.items()}), strict=True))

        def part(prefix, names, given):
            return None if given is None else {k: arrays[f"{prefix}[{k}]"] for k in names}

        return self._motion(
            part("position", unknowns, position), part("inputs", inputs_named, inputs),
            part("velocity", unknowns, velocity), part("acceleration", unknowns, acceleration),
            converged=converged, singular=singular, near_singular=near_singular, message=message,
            assembly=assembly, iterations=iterations, newton=newton, kind=kind, **extra)

    def _motion(self, position, inputs, velocity=None, acceleration=None, *, converged=None, singular=None,
                near_singular=None, message="", assembly=None, iterations=0, newton=None, kind=Motion,
                **extra) -> Motion:
        """:meth:`motion_of` of values already checked (a machine's own, keyed by the declared names):
        broadcast, shaped, and the singularity masks not given left to the core's rule, computed when
        first read."""
        values = [*position.values(), *inputs.values(), *(velocity or {}).values(),
                  *(acceleration or {}).values()]
        shape = np.broadcast_shapes(*(np.shape(v) for v in values))

        def shaped(value):
            return scalar_or_array(_broadcast(value, shape))

        def by_name(values):
            return None if values is None else MappingProxyType({k: shaped(v) for k, v in values.items()})

        if converged is None:
            converged = np.logical_and.reduce([np.isfinite(v) for v in position.values()])
        converged = shaped(np.asarray(converged, bool))
        found = {}

        def smallest():  # the core's σ_min(J̃), once, for whichever mask is read first
            if not found:
                found["smallest"] = self._smallest_where(position, inputs, shape)
            return found["smallest"]

        if singular is None:
            singular = Deferred(lambda: shaped(np.asarray(converged) & ~(smallest() >= SINGULAR)))
        else:
            singular = shaped(np.asarray(singular, bool))
        if near_singular is None:
            near_singular = Deferred(lambda: shaped(np.asarray(converged) & ~(smallest() >= NEAR_SINGULAR)))
        else:
            near_singular = shaped(np.asarray(near_singular, bool))
        return kind(position=by_name(position), velocity=by_name(velocity),
                    acceleration=by_name(acceleration),
                    converged=converged, singular=singular, iterations=shaped(np.asarray(iterations)),
                    newton=newton, inputs=by_name(inputs), near_singular=near_singular, message=message,
                    assembly=None if assembly is None else MappingProxyType(dict(assembly)), **extra)

    def _smallest_where(self, position, inputs, shape) -> np.ndarray:
        """σ_min(J̃) (shape ``shape``) at the declared values by name (unknowns not finite taken as 0)."""
        q = np.stack([np.broadcast_to(position[s.name], shape) for s in self.unknowns], axis=-1)
        u = np.stack([np.broadcast_to(inputs[s.name], shape) for s in self.inputs], axis=-1)
        q, u = q.reshape(-1, len(self.unknowns)), u.reshape(-1, len(self.inputs))
        with np.errstate(all="ignore"):
            return self._smallest(self._J(np.where(np.isfinite(q), q, 0.0), u)).reshape(shape)

    def _smallest(self, J: np.ndarray) -> np.ndarray:
        """σ_min(J̃) of a stack J (..., n, n): exact for n ≤ 2, else exact where a bound cannot settle it."""
        rows, columns = self._scales
        n = J.shape[-1]
        # entries first (n, n, ...): contiguous for the compiled terms' J, so each operation runs in one pass
        A = np.moveaxis(J, (-2, -1), (0, 1)) / rows[:, None].reshape((n, 1) + (1,) * (J.ndim - 2))
        A /= columns.reshape((1, n) + (1,) * (J.ndim - 2))
        with np.errstate(all="ignore"):
            if n == 1:
                return np.abs(A[0, 0])
            frobenius = (A * A).sum(axis=(0, 1))
            if n == 2:
                det = A[0, 0] * A[1, 1] - A[0, 1] * A[1, 0]
                largest = np.sqrt((frobenius + np.sqrt(np.maximum(frobenius**2 - 4 * det**2, 0.0))) / 2)
                return np.where(largest > 0, np.abs(det) / largest, 0.0)
            det = np.ones(A.shape[2:])
            for block_rows, block_columns in self._structure["blocks"]:
                block = A[np.ix_(block_rows, block_columns)]
                if len(block_rows) == 1:
                    det = det * block[0, 0]
                elif len(block_rows) == 2:
                    det = det * (block[0, 0] * block[1, 1] - block[0, 1] * block[1, 0])
                else:
                    det = det * np.linalg.det(np.moveaxis(block, (0, 1), (-2, -1)))
            smallest = np.array(np.abs(det) / np.sqrt(frobenius) ** (n - 1))  # a lower bound (an array)
            unsure = ~(smallest >= NEAR_SINGULAR) & np.isfinite(frobenius)
            if unsure.any():
                stacked = np.moveaxis(A, (0, 1), (-2, -1))
                smallest[unsure] = np.linalg.svd(stacked[unsure], compute_uv=False)[..., -1]
            return smallest

    # ------------------------------------------------------------ numbers (arrays ordered as declared)

    def _checked(self, **arrays) -> list[np.ndarray]:
        """Each named array as floats (finite, or NaN: not assembled) whose last axis holds the declared
        count (q…: the unknowns, u…: the inputs, x: 3n), broadcast together on the leading axes; else the
        named error."""
        n, m = len(self.unknowns), len(self.inputs)
        out, leading = [], {}
        for name, value in arrays.items():
            size, order = ((3 * n, "q, q̇, q̈") if name in ("x", "seed") else
                           (n, [s.name for s in self.unknowns]) if name.startswith("q") else
                           (m, [s.name for s in self.inputs]))
            array = require_finite(name, value, allow_nan=True)
            if array.ndim == 0 or array.shape[-1] != size:
                raise InvalidGeometryError(f"{name} must have {size} entries on its last axis (ordered as "
                                           f"{order}); got {value!r} of shape {array.shape}")
            out.append(array)
            leading[name] = array.shape[:-1]
        try:
            np.broadcast_shapes(*leading.values())
        except ValueError:
            shapes = ", ".join(f"{name} of shape {np.shape(v)}" for name, v in arrays.items())
            raise InvalidGeometryError(f"the arrays must broadcast on their leading axes; "
                                       f"got {shapes}") from None
        return out

    def newton_function(self, u) -> Callable[[np.ndarray], tuple[np.ndarray, np.ndarray]]:
        """q ↦ (F(q, u), J(q, u)) at the fixed inputs ``u`` (N, m), for ``newton_batch(..., jac=True)``:
        F and J from one evaluation, sharing the cos and sin of q, those of ``u`` computed once for
        every call.

        >>> th, x = sp.symbols("theta x")
        >>> F = Mechanism([x**2 - th], [x], [th]).newton_function(np.array([[4.0], [9.0]]))
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

    def _check_position(self, position) -> None:
        def names(symbols):
            return [s.name for s in symbols]

        if position is not None and not (isinstance(position, Mechanism)
                                         and names(position.unknowns) == names(self.unknowns)
                                         and names(position.inputs) == names(self.inputs)):
            raise InvalidGeometryError(f"position must be a Mechanism with the unknowns "
                                       f"{list(self.unknowns)} and inputs {list(self.inputs)}; "
                                       f"got {position!r}")

    def _block_stacks(self, J: np.ndarray) -> list:
        """Per block of a stack J (N, n, n): its rows, columns, the columns solved before it, its diagonal
        block prepared for solving (:class:`LinearStack`) and the coupling to the earlier columns."""
        blocks = self._structure["blocks"]
        if len(blocks) == 1:
            return [(None, None, [], LinearStack(J), None)]
        entries = J.transpose(1, 2, 0)  # (n, n, N): contiguous for the compiled terms' J
        stacks, done = [], []
        for rows, columns in blocks:
            block = np.ascontiguousarray(entries[np.ix_(rows, columns)]).transpose(2, 0, 1)
            coupling = J[:, rows][:, :, done] if done else None
            stacks.append((rows, columns, done, LinearStack(block), coupling))
            done = done + list(columns)
        return stacks

    def _solve_blocks(self, J: np.ndarray, b: np.ndarray, stacks: list | None = None) -> np.ndarray:
        """x (N, n) with J·x = b for a stack J (N, n, n), block by block (forward substitution);
        ``stacks``: :meth:`_block_stacks` of J, when already prepared."""
        stacks = self._block_stacks(J) if stacks is None else stacks
        if len(stacks) == 1:
            return stacks[0][3].solve(b)
        x = np.empty(b.shape)
        for rows, columns, done, stack, coupling in stacks:
            rhs = b[:, rows]
            if done:
                rhs = rhs - np.einsum("nij,nj->ni", coupling, x[:, done])
            x[:, columns] = stack.solve(rhs)
        return x

    def rates(self, q, u, u_rate, u_acceleration=None, *, trig: Mapping | None = None, singular=None):
        """q̇, q̈ (None without ``u_acceleration``) and the singular mask at known positions, by J·q̇ =
        −F_u·u̇, J·q̈ = −(the rest of d²F/dt²); NaN where singular (σ_min(J̃) < SINGULAR, see
        :meth:`smallest_singular_value`).  ``q`` (..., n), the others (..., m); ``trig``: {name: (cos, sin)}
        already computed; ``singular``: the caller's own mask.

        >>> th, x = sp.symbols("theta x")
        >>> [a.tolist() for a in Mechanism([x**2 - th], [x], [th]).rates([2.0], [4.0], [1.0], [0.0])]
        [[0.25], [-0.03125], False]
        """
        names = dict(q=q, u=u, u_rate=u_rate)
        if u_acceleration is not None:
            names["u_acceleration"] = u_acceleration
        arrays = self._checked(**names)
        shape, arrays = _rows(*arrays)
        q, u, u_rate = arrays[:3]
        if trig is not None and not isinstance(trig, Mapping):
            raise InvalidGeometryError(f"trig must map names to (cos, sin) pairs; got {trig!r}")
        known = {(name, func): _broadcast(value, shape).ravel() for name, pair in (trig or {}).items()
                 for func, value in zip(("cos", "sin"), pair, strict=True)}
        J, F_u = self._rate_terms(q, u, known, same_point=True)
        if singular is None:
            singular = ~(self._smallest(J) >= SINGULAR)
        else:
            singular = _broadcast(np.asarray(singular, dtype=bool), shape).ravel()
        any_singular = singular.any()
        if any_singular:
            J = np.where(singular[:, None, None], np.eye(len(self.unknowns)), J)
        stacks = self._block_stacks(J)
        q_rate = self._solve_blocks(J, sum(F_u[:, :, j] * -u_rate[:, j, None]
                                           for j in range(u_rate.shape[1])), stacks)
        q_acc = None
        if u_acceleration is not None:
            q_acc = self._solve_blocks(J, self._rhs(q, q_rate, u, u_rate, arrays[3], known), stacks)
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
        u, u_rate, u_acc, seed = self._route_arguments(u, u_rate, u_acceleration, seed, position)
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
        u, u_rate, u_acc, seed = self._route_arguments(u, u_rate, u_acceleration, seed, position)
        start = np.broadcast_to(seed, (len(u), seed.size)) if u.ndim == 2 else seed
        return self._run("simultaneous", u, lambda x: self.system(x, u, u_rate, u_acc, position), start, tol,
                         max_iter)

    def _route_arguments(self, u, u_rate, u_acceleration, seed, position):
        """The checked arguments of the course's two routes: u, u̇, ü (m,) or (N, m) alike, seed (3n,)."""
        u, u_rate, u_acc, seed = self._checked(u=u, u_rate=u_rate, u_acceleration=u_acceleration, seed=seed)
        self._check_position(position)
        if u.ndim > 2 or seed.ndim != 1 or not (u.shape == u_rate.shape == u_acc.shape):
            raise InvalidGeometryError(f"u, u_rate and u_acceleration must share one shape, (m,) or (N, m), "
                                       f"and seed must be one vector of 3n values; got shapes {u.shape}, "
                                       f"{u_rate.shape}, {u_acc.shape} and {seed.shape}")
        return u, u_rate, u_acc, seed

    # ------------------------------------------------------------ solving a motion

    def _F(self, q, u, known=None, same_point=False) -> np.ndarray:
        terms = self._residual_fn(self._values, q, u, known=known, same_point=same_point)
        return _vector(terms, 0, len(self.unknowns))

    def _J(self, q, u, known=None) -> np.ndarray:
        n = len(self.unknowns)
        return _matrix(self._jacobian_fn(self._values, q, u, known=known), 0, n, n)

    def solve(self, inputs: Mapping, rates: Mapping | None = None, accelerations: Mapping | None = None,
              guess: Mapping | None = None, *, assembly: Mapping | None = None, tol: float = 1e-10,
              max_iter: int = 50, on_failure: str = "raise") -> Motion:
        """Position, and velocity and acceleration if asked, at each value of the inputs.

        ``inputs``, ``rates``, ``accelerations`` map inputs (symbol or name) to numbers or arrays,
        broadcast together (missing rates are 0).  ``guess`` picks the assembly: Newton runs from it at the
        first instant (its history in ``Motion.newton`` for one instant).  Where every block reduces to a
        closed form (:attr:`closed_forms`) each block keeps the root σ nearest that solution (σ = +1 without
        a guess, or the σ that ``assembly`` gives by the block's first unknown, as ``Motion.assembly``
        names them), and Newton only cross-checks; elsewhere each instant continues from its neighbour's
        solution (tangent predictor, steps subdivided and Newton's steps limited, so no instant lands on
        another assembly).  A sweep of one input is followed from its first instant outward, in increasing
        and in decreasing order of the input (the order the values come in does not matter); several inputs
        in the order given.  Angles stay within a turn of their neighbours.  Raises, unless
        ``on_failure="nan"``: ``SingularJacobianError`` (rates asked where J is singular, or a singular
        seed), ``ConvergenceError`` (no root from the guess), ``UnreachableError`` (no assembly).

        >>> th, x = sp.symbols("theta x")
        >>> motion = Mechanism([x**2 - th], [x], [th]).solve({th: [4.0, 1.0]}, {th: 1.0}, guess={x: 2.0})
        >>> motion.position["x"].tolist(), motion.velocity["x"].tolist(), motion.acceleration["x"].tolist()
        ([2.0, 1.0], [0.25, 0.5], [-0.03125, -0.25])
        """
        require_choice("on_failure", on_failure, FAILURE_POLICIES)
        u_given = _keyed("inputs", inputs, self.inputs)
        rate_given = _keyed("rates", {} if rates is None else rates, self.inputs, required=False)
        acc_given = _keyed("accelerations", {} if accelerations is None else accelerations, self.inputs,
                           required=False)
        closed = self._closed_fns is not None
        chosen = self._assembly(assembly, closed)
        seed = None
        if guess is not None or not closed:
            q_given = _keyed("guess", {} if guess is None else guess, self.unknowns)
            for name, value in q_given.items():
                if np.ndim(value) != 0 and np.size(value) != 1 or isinstance(value, str | bytes):
                    raise InvalidGeometryError(f"guess must give one number per unknown; got guess[{name}]="
                                               f"{value!r}")
            seed = np.array([float(require_finite(f"guess[{k}]", v).ravel()[0]) for k, v in q_given.items()])
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
        paths, notes, result, assembly = self._paths(u), [], None, None
        known, at_q = {}, None  # the cos and sin of the inputs, computed once; of q, where q is final
        stuck = np.zeros(len(u), bool)
        with np.errstate(all="ignore"):
            if seed is not None:
                result = newton(lambda q: self._F(q, u[0]), seed, jac=lambda q: self._J(q, u[0]),
                                tol=tol, max_iter=max_iter, on_failure="report")
            if closed:
                target = None if result is None else result.x if result.converged else seed
                if result is not None and not result.converged:
                    notes.append(f"Newton from the guess did not converge at {self._where(u, 0)} "
                                 f"({result.message}); the closed form gave the assembly nearest the guess")
                q, iterations, sigma, at_q = self._closed(u, paths, target, tol, max_iter, notes, chosen,
                                                          known)
                if shape == () and result is not None:
                    iterations[0] = result.iterations
                assembly = {name: scalar_or_array(values.reshape(shape)) for name, values in sigma.items()}
            elif shape == ():
                where = self._where(u, 0)
                if on_failure == "raise" and result.singular:
                    raise SingularJacobianError(f"at {where}: {result.message}", result.x.tolist())
                if on_failure == "raise" and not result.converged:
                    raise ConvergenceError(f"at {where}, from the guess: {result.message}", result=result)
                q = result.x[None, :].copy() if result.converged else np.full((1, len(seed)), np.nan)
                iterations, stuck[0] = np.array([result.iterations]), result.singular
            else:
                start = result.x if result.converged else None
                if start is None:
                    start, fixed, _ = self._correct(seed, u[0], tol, max_iter)
                    if not fixed:
                        start = None
                    if start is None and on_failure == "raise":
                        where = self._where(u, 0)
                        if result.singular:
                            raise SingularJacobianError(f"at {where}, the first instant: {result.message}",
                                                        result.x.tolist())
                        raise ConvergenceError(f"at {where}, the first instant, from the guess: "
                                               f"{result.message}", result=result)
                q, iterations = self._march(u, paths, start, tol, max_iter, notes)
            converged = np.isfinite(q).all(axis=1)
            safe = q if converged.all() else np.where(converged[:, None], q, 0.0)
            want_rates = rates is not None or accelerations is not None
            at_q = at_q if at_q is not None and safe is q else dict(known)
            J, F_u = (self._rate_terms(safe, u, at_q, same_point=True) if want_rates
                      else (self._J(safe, u, at_q), None))
            smallest = self._smallest(J)
            singular = converged & ~(smallest >= SINGULAR) | stuck
            near = converged & ~(smallest >= NEAR_SINGULAR)
            if want_rates:
                q_rate, q_acc, _ = self._rates(safe, u, u_rate, u_acc, singular | ~converged, (J, F_u), at_q)
        self._notes(notes, converged, singular, near, u)
        if on_failure == "raise":
            self._report(~converged, singular & want_rates, u, closed)
        velocity = acceleration = None
        if want_rates:
            velocity, acceleration = self._by_name(q_rate, shape), self._by_name(q_acc, shape)

        def shaped(values):
            return scalar_or_array(values.reshape(shape))

        inputs_used = {s.name: scalar_or_array(a) for s, a in zip(self.inputs, arrays[:m], strict=True)}
        return Motion(position=self._by_name(q, shape), velocity=velocity, acceleration=acceleration,
                      converged=shaped(converged), singular=shaped(singular), iterations=shaped(iterations),
                      inputs=MappingProxyType(inputs_used), newton=result if shape == () else None,
                      near_singular=shaped(near), message="; ".join(notes),
                      assembly=None if assembly is None else MappingProxyType(assembly))

    def _rates(self, q, u, u_rate, u_acc, singular, terms, known=None
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """q̇ and q̈ (N, n) at solved positions from (J, F_u) there, NaN where ``singular`` (``known``: the
        cos and sin already computed at q and u, see _compile)."""
        J, F_u = terms
        if singular.any():
            J = np.where(singular[:, None, None], np.eye(len(self.unknowns)), J)
        stacks = self._block_stacks(J)
        q_rate = self._solve_blocks(J, np.einsum("nij,nj->ni", F_u, -u_rate), stacks)
        q_acc = self._solve_blocks(J, self._rhs(q, q_rate, u, u_rate, u_acc, known), stacks)
        q_rate[singular], q_acc[singular] = np.nan, np.nan
        return q_rate, q_acc, singular

    @staticmethod
    def _paths(u: np.ndarray) -> list[np.ndarray]:
        """The orders a sweep follows, each from instant 0: one input outward from it in increasing and in
        decreasing order of the input; several inputs in the order given."""
        N, m = u.shape
        if N == 1:
            return [np.array([0])]
        if m > 1:
            return [np.arange(N)]
        order = np.argsort(u[:, 0], kind="stable")
        at = int(np.flatnonzero(order == 0)[0])
        return [p for p in (order[at:], order[:at + 1][::-1]) if len(p) > 1]

    def _distance(self, a: np.ndarray, b: np.ndarray, columns=None) -> np.ndarray:
        """max over unknowns of |a − b| in typical units (angles compared modulo a turn)."""
        columns = range(len(self.unknowns)) if columns is None else columns
        angles = self._structure["angles"]
        scale = self._scales[1]
        gaps = []
        for j in columns:
            gap = a[..., j] - b[..., j]
            if self.unknowns[j] in angles:
                gap = _unwrap_to(gap, 0.0)
            gaps.append(np.abs(gap) * scale[j])
        return np.max(gaps, axis=0)

    # ------------------------------------------------------------ the closed-form route

    @staticmethod
    def _roots(a, b, c, kind):
        """The roots σ = +1 and −1 of a·v² + b·v + c = 0 (v = tan(θ/2) → θ for an angle), each from the
        better-conditioned of (−b + σ√Δ)/(2a) and 2c/(−b − σ√Δ), NaN where Δ < 0 beyond rounding; and Δ over
        its scale: (root +1, root −1, Δ / scale)."""
        discriminant = b * b - 4 * a * c
        # for an angle, (a, b, c) = (C − A, 2B, C + A) of A cos θ + B sin θ + C:
        # Δ ≤ b² + (a − c)² = 4(A² + B²)
        scale = b * b + ((a - c) ** 2 if kind == "angle" else np.abs(4 * a * c))
        bad = ~(discriminant >= -1e-12 * scale)
        root = np.sqrt(np.maximum(discriminant, 0.0))
        two_a, two_c = 2 * a, 2 * c
        size_a, size_c = np.abs(two_a), np.abs(two_c)
        out = []
        for y1, x2 in ((-b + root, -b - root), (-b - root, -b + root)):
            first = np.abs(y1) + size_a >= size_c + np.abs(x2)
            y, x = np.where(first, y1, two_c), np.where(first, two_a, x2)
            wrong = bad | ((np.abs(y) + np.abs(x)) == 0)
            value = 2 * np.arctan2(y, x) if kind == "angle" else y / x
            out.append(np.where(wrong, np.nan, value))
        return out[0], out[1], np.where(scale > 0, discriminant / scale, 0.0)

    def _assembly(self, assembly: Mapping | None, closed: bool) -> dict[str, int]:
        """``solve``'s ``assembly``: σ = ±1 by the name (or symbol) of a block's first unknown."""
        if assembly is None:
            return {}
        firsts = [form.unknowns[0].name for form in self._structure["forms"] if form is not None and closed]
        if not isinstance(assembly, Mapping) or not closed:
            raise InvalidGeometryError(f"assembly must map the first unknown of each closed-form block "
                                       f"({firsts or 'none here: give a guess instead'}) to σ = +1 or −1; "
                                       f"got assembly={assembly!r}")
        chosen = {}
        for key, value in assembly.items():
            name = getattr(key, "name", key)
            if name not in firsts or isinstance(value, bool) or value not in (1, -1):
                raise InvalidGeometryError(f"assembly must map one of {firsts} to σ = +1 or −1; got "
                                           f"assembly={dict(assembly)!r}")
            chosen[name] = int(value)
        return chosen

    def _closed(self, u, paths, target, tol, max_iter, notes, chosen=None, known=None
                ) -> tuple[np.ndarray, np.ndarray, dict, dict | None]:
        """Positions (N, n) from the closed forms, each block's σ picked at the first instant from
        ``target`` (the Newton solution, or the guess) and kept along the paths except where the two
        assemblies meet (a change point, reported in ``notes``); then cross-checked by the residual.
        ``known``: the inputs' cos and sin (see _compile), shared; also returned: those of the positions
        too, where every position is found and none was corrected (else None)."""
        known = {} if known is None else known
        N, n = len(u), len(self.unknowns)
        q, sigmas = np.full((N, n), np.nan), {}
        structure = self._structure
        for form, (coefficients, second, linear) in zip(structure["forms"], self._closed_fns, strict=True):
            first = self.unknowns.index(form.unknowns[0])
            a, b, c = coefficients(self._values, q, u, known=known)
            if linear:
                q[:, first] = -c / b
            else:
                plus, minus, level = self._roots(a, b, c, form.kind)
                name = form.unknowns[0].name
                picked = (chosen or {}).get(name) or self._pick(plus, minus, paths, target, first)
                sigma = np.full(N, picked)
                self._follow(sigma, plus, minus, level, paths, u, first, notes)
                q[:, first] = np.where(sigma > 0, plus, minus)
                sigmas[form.unknowns[0].name] = sigma
            if form.second is not None:
                other = self.unknowns.index(form.unknowns[1])
                values = second(self._values, q, u, known=known)
                q[:, other] = np.arctan2(values[1], values[0]) if form.second[0] == "angle" else values[0]
        self._continuous(q, paths, target)
        iterations = np.zeros(N, int)
        rows = self._scales[0]
        finite = np.isfinite(q).all(axis=1)
        everywhere = bool(finite.all())
        at_q = dict(known)
        at = q if everywhere else np.where(finite[:, None], q, 0.0)
        residual = np.abs(self._F(at, u, at_q, same_point=True)) / rows
        doubt = np.flatnonzero(finite & ~(residual.max(axis=1) <= RESIDUAL))
        for k in doubt:  # the cross-check: Newton from the closed form, kept only on the same assembly
            polished, fixed, count = self._correct(q[k], u[k], tol, max_iter)
            iterations[k] = count
            q[k] = polished if fixed and self._distance(polished, q[k]) <= MAX_CHANGE else np.nan
        return q, iterations, sigmas, at_q if everywhere and not len(doubt) else None

    def _pick(self, plus, minus, paths, target, first) -> int:
        """σ at the first instant (along the paths) where the two roots differ: the one nearer ``target``."""
        if target is None:
            return 1
        for k in itertools.chain(*paths):
            both = np.array([plus[k], minus[k]])
            if np.isfinite(both).all() and self._distance(both[:1, None], both[1:, None], [0]) > 1e-7:
                size = self._scales[1][first]
                gaps = np.abs(both - target[first])
                if self.unknowns[first] in self._structure["angles"]:
                    gaps = np.abs(_unwrap_to(both - target[first], 0.0))
                return 1 if gaps[0] * size <= gaps[1] * size else -1
        return 1

    def _follow(self, sigma, plus, minus, level, paths, u, first, notes) -> None:
        """Swap σ where the two assemblies meet between instants (a change point): there the other root
        continues the motion smoothly (a secant from the two instants before predicts it)."""
        name, is_angle_ = self.unknowns[first].name, self.unknowns[first] in self._structure["angles"]
        for path in paths:
            for _ in range(64):
                if len(path) < 3:
                    break
                chosen = np.where(sigma[path] > 0, plus[path], minus[path])
                other = np.where(sigma[path] > 0, minus[path], plus[path])
                steps = np.linalg.norm(np.diff(u[path], axis=0), axis=1)
                ratio = np.where(steps[:-1] > 0, steps[1:] / np.where(steps[:-1] > 0, steps[:-1], 1.0), 0.0)
                back = chosen[1:-1] - chosen[:-2]
                if is_angle_:
                    back = _unwrap_to(back, 0.0)
                predicted = chosen[1:-1] + back * ratio

                def gap(values, predicted=predicted):
                    d = values - predicted
                    return np.abs(_unwrap_to(d, 0.0) if is_angle_ else d)

                same, swapped = gap(chosen[2:]), gap(other[2:])
                low = np.minimum(level[path][1:-1], level[path][2:])
                suspect = (swapped < 0.25 * same) & (same * self._scales[1][first] > 1e-6) & (low < 0.1)
                if not suspect.any():
                    break
                k = int(np.argmax(suspect)) + 2
                sigma[path[k:]] *= -1
                notes.append(f"the two assemblies of {name} meet (a change point) between "
                             f"{self._where(u, path[k - 1])} and {self._where(u, path[k])}: the motion "
                             "continues on the smooth one (σ swapped there)")

    def _continuous(self, q, paths, target) -> None:
        """Angles unwrapped along each path, the first instant's within π of ``target`` (if any)."""
        columns = [j for j, s in enumerate(self.unknowns)
                   if s in self._structure["angles"] and np.isfinite(q[0, j])]
        if not columns:
            return
        if target is not None:
            q[0, columns] = _unwrap_to(q[0, columns], target[columns])
        for path in paths:
            ordered = len(path) > 1 and path[0] == 0 and path[-1] == len(path) - 1 \
                and bool((np.diff(path) == 1).all())
            rows = slice(0, len(path)) if ordered else path
            values = q[rows][:, columns]
            finite = np.isfinite(values).all(axis=1)
            if not finite[0] or finite.sum() < 2:
                continue
            if not finite.all():
                rows, values = path[finite], values[finite]
            # each step within π: whole turns taken off, counted along the path
            turns = np.cumsum(np.round(np.diff(values, axis=0) / (2 * np.pi)), axis=0)
            moved = (turns != 0).any(axis=0)
            for k in np.flatnonzero(moved):
                kept = values[1:, k] - 2 * np.pi * turns[:, k]
                if isinstance(rows, slice):
                    q[1:len(path), columns[k]] = kept
                else:
                    q[rows[1:], columns[k]] = kept

    # ------------------------------------------------------------ Newton with continuation

    def _correct(self, q, u, tol, max_iter) -> tuple[np.ndarray, bool, int]:
        """Newton from ``q`` at one instant, steps by the least-squares solve of the scaled J (the smallest
        singular values dropped: no huge step near a singularity) and no larger than MAX_STEP."""
        rows, columns = self._scales
        q, step = np.array(q, dtype=float), np.inf
        for k in range(max_iter + 1):
            F, J = self._newton_terms(q, u)
            if not (np.isfinite(F).all() and np.isfinite(J).all()):
                return q, False, k
            if step < tol and np.sqrt(F @ F) <= tol:
                return q, True, k
            if k == max_iter:
                break
            U, S, Vt = np.linalg.svd(J / rows[:, None] / columns[None, :])
            if not S[0] > 0:
                return q, False, k
            keep = S > 1e-10 * S[0]
            change = Vt[keep].T @ ((U[:, keep].T @ (-F / rows)) / S[keep])
            largest = np.abs(change).max()
            if largest > MAX_STEP:
                change *= MAX_STEP / largest
            delta = change / columns
            q, step = q + delta, float(np.sqrt(delta @ delta))
        # at a toggle or limit the root is double: F falls to round-off while the steps only halve, so
        # the step test cannot pass there; a vanishing residual where J is singular is the root itself
        F, J = self._newton_terms(q, u)
        if np.sqrt(F @ F) <= tol and not self._smallest(J) >= SINGULAR:
            return q, True, max_iter
        return q, False, max_iter

    def _advance(self, q, u_from, u_to, tol, max_iter) -> tuple[np.ndarray | None, int]:
        """The solution at ``u_to`` continued from ``q`` at ``u_from``: tangent predictor, Newton corrector,
        the step halved until the corrector lands near the prediction (no other assembly)."""
        step_u = u_to - u_from
        if not step_u.any():
            return q.copy(), 0
        columns = self._scales[1]
        angles = [j for j, s in enumerate(self.unknowns) if s in self._structure["angles"]]
        done, h, count = 0.0, 1.0, 0
        while done < 1.0:
            h = min(h, 1.0 - done)
            if h < 1e-13:
                return None, count
            here = u_from + done * step_u
            J, F_u = self._rate_terms(q, here)
            singular = not self._smallest(J) >= SINGULAR
            prediction = q
            if not singular:
                tangent = np.linalg.solve(J, -(F_u @ step_u))
                prediction = q + h * tangent
                change = float(np.max(np.abs(h * tangent) * columns))
                if change > MAX_CHANGE:
                    h *= 0.9 * MAX_CHANGE / change
                    continue
            else:
                change = MAX_CHANGE
            found, fixed, used = self._correct(prediction, u_from + (done + h) * step_u, tol, max_iter)
            count += used
            if fixed:
                found[angles] = _unwrap_to(found[angles], prediction[angles])
                if float(np.max(np.abs(found - prediction) * columns)) <= max(0.5 * change, 1e-6):
                    q, done, h = found, done + h, min(2 * h, 1.0)
                    continue
            h *= 0.5
        return q, count

    def _march(self, u, paths, start, tol, max_iter, notes) -> tuple[np.ndarray, np.ndarray]:
        """Positions along the paths from ``start`` at instant 0 (None: nothing found there)."""
        N, n = len(u), len(self.unknowns)
        q, iterations = np.full((N, n), np.nan), np.zeros(N, int)
        if start is None:
            return q, iterations
        q[0] = start
        rows, columns = self._scales

        def orientation(k):
            det = np.linalg.det(self._J(q[k], u[k]) / rows[:, None] / columns[None, :])
            return 0.0 if not abs(det) > SINGULAR else np.sign(det)

        for path in paths:
            last, sign = path[0], orientation(path[0])
            for k in path[1:]:
                found, iterations[k] = self._advance(q[last], u[last], u[k], tol, max_iter)
                if found is None:
                    continue
                q[k] = found
                now = orientation(k)
                if sign and now and now != sign:
                    notes.append(f"the assemblies meet (a change point) between {self._where(u, last)} and "
                                 f"{self._where(u, k)}: the motion continues on the smooth one")
                last, sign = k, now or sign
        return q, iterations

    # ------------------------------------------------------------ reporting

    def _where(self, u, index) -> str:
        row = np.atleast_2d(u)[index]
        return ", ".join(f"{s.name}={float(value)!r}" for s, value in zip(self.inputs, row, strict=True))

    def _notes(self, notes, converged, singular, near, u) -> None:
        """The singular and near-singular instants and the limits met, added to ``notes`` in words."""
        for mask, what in ((singular, f"J is singular (σ_min(J̃) < {SINGULAR:.0e}: a toggle, limit or change "
                                      "point; the rates are undefined)"),
                           (near & ~singular, f"near a singular configuration (σ_min(J̃) < "
                                               f"{NEAR_SINGULAR:.0e}: the rates are large and sensitive)"),
                           (~converged, "no assembly (beyond a limit position, or not reached)")):
            if mask.any():
                first = int(np.flatnonzero(mask)[0])
                notes.append(f"{what} at {self._where(u, first)} ({int(mask.sum())} of {mask.size} instants)")

    def _report(self, bad, singular, u, closed) -> None:
        """Raise the named error of the first bad instant (see :meth:`solve`)."""
        if not (bad.any() or singular.any()):
            return
        first = int(np.flatnonzero(bad | singular)[0])
        where = self._where(u, first)
        count = f"({int((bad | singular).sum())} of {bad.size} instants, first at index {first})"
        if singular[first]:
            raise SingularJacobianError(f"J is singular at {where} {count}: the mechanism is at a toggle, "
                                        f"limit or change point (σ_min(J̃) < {SINGULAR:.0e}), where the rates "
                                        "are undefined; ask for positions only, or move the input off it")
        if closed:
            raise UnreachableError(f"the loops cannot be closed at {where} {count}: the closed form has no "
                                   "real root there (B² − 4AC < 0), so no assembly exists", mask=bad)
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

    @_derived
    def _point_rate_fn(self):
        """(q, q̇, q̈, u, u̇, ü) → each point's velocity and acceleration, its declaration differentiated."""
        terms = []
        for point in self.points.values():
            terms += [entry for derivative in self._in_time(point) for entry in derivative]
        q, u = self.unknowns, self.inputs
        return self._compile(terms, q, self._rates_of(q, 1), self._rates_of(q, 2), u, self._rates_of(u, 1),
                             self._rates_of(u, 2))

    def point_motion(self, motion: Motion, rates: Mapping | None = None, accelerations: Mapping | None = None
                     ) -> dict[str, tuple[np.ndarray, np.ndarray, np.ndarray]]:
        """Position, velocity and acceleration (each (..., 2), SI) of every declared point along ``motion``
        (solved with ``rates``, and ``accelerations`` if any: pass the same input rates here; missing ones
        are 0), from the point's declaration differentiated in time — ω k̂ × r and α k̂ × r − ω² r, Coriolis
        terms included, without writing any of them by hand.

        >>> th, x = sp.symbols("theta x")
        >>> A = sp.Matrix([sp.cos(th), sp.sin(th)])
        >>> crank = Mechanism([x - sp.cos(th)], [x], [th], points={"O": sp.zeros(2, 1), "A": A},
        ...                   links=[("O", "A")])
        >>> turning = crank.solve({th: 0.0}, rates={th: 2.0}, guess={x: 1.0})
        >>> [v.round(12).tolist() for v in crank.point_motion(turning, rates={th: 2.0})["A"]]
        [[1.0, 0.0], [0.0, 2.0], [-4.0, 0.0]]
        """
        positions = self.joints(motion)
        if motion.velocity is None:
            raise InvalidGeometryError("point_motion needs the unknowns' rates: solve with rates={input: "
                                       "rate} (and accelerations=... if any); got a motion of positions only")
        zero = {name: 0.0 for name in motion.position}
        arrays = [np.stack(np.broadcast_arrays(*(values[s.name] for s in self.unknowns)), axis=-1)
                  for values in (motion.position, motion.velocity, motion.acceleration or zero)]
        given = [_keyed(argument, {} if mapping is None else mapping, self.inputs, required=False)
                 for argument, mapping in (("rates", rates), ("accelerations", accelerations))]
        inputs = [np.stack(np.broadcast_arrays(*(motion.inputs[s.name] for s in self.inputs)), axis=-1)]
        ones = np.ones_like(inputs[0][..., 0])
        for argument, values in zip(("rates", "accelerations"), given, strict=True):
            inputs.append(np.stack([require_finite(f"{argument}[{s.name}]", values.get(s.name, 0.0)) * ones
                                    for s in self.inputs], axis=-1))
        terms = self._point_rate_fn(self._values, *arrays, *inputs)
        return {name: (positions[name], _vector(terms, 4 * k, 2), _vector(terms, 4 * k + 2, 2))
                for k, name in enumerate(self.points)}

    def joints(self, motion: Motion) -> dict[str, np.ndarray]:
        """Coordinates (m) of the declared ``points`` along a motion: name → array (..., 2).

        >>> th, x = sp.symbols("theta x")
        >>> A = sp.Matrix([sp.cos(th), sp.sin(th)])
        >>> crank = Mechanism([x - sp.cos(th)], [x], [th], points={"O": sp.zeros(2, 1), "A": A},
        ...                   links=[("O", "A")])
        >>> crank.joints(crank.solve({th: [0.0, np.pi / 2]}, guess={x: 1.0}))["A"].round(12).tolist()
        [[1.0, 0.0], [0.0, 1.0]]
        """
        if not self.points:
            raise InvalidGeometryError("joints needs points: declare points={name: Matrix([x, y])}; "
                                       "got points={}")
        names = [s.name for s in self.unknowns], [s.name for s in self.inputs]
        # a Motion of these loops, or of the same loops solved the other way round (a five-bar's inverse)
        values = {**motion.inputs, **motion.position} if isinstance(motion, Motion) else {}
        if sorted(values) != sorted(names[0] + names[1]):
            raise InvalidGeometryError(f"motion must be a Motion of this mechanism (unknowns {names[0]}, "
                                       f"inputs {names[1]}); got {motion!r}"[:400])
        q = np.stack(np.broadcast_arrays(*(values[s.name] for s in self.unknowns)), axis=-1)
        u = np.stack(np.broadcast_arrays(*(values[s.name] for s in self.inputs)), axis=-1)
        xy = self._point_fn(self._values, q, u)
        return {name: _vector(xy, 2 * k, 2) for k, name in enumerate(self.points)}
