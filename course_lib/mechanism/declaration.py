"""The declaration: loops, unknowns, inputs, parameters and the drawing's named points, links, ground,
sliders, plates and styles, checked when made; its time derivatives in symbols.

One room of :class:`~course_lib.mechanism.Mechanism`, which is all of them together.
"""

from __future__ import annotations

import copy
import itertools
from collections.abc import Mapping, Sequence
from functools import wraps
from types import MappingProxyType
from typing import TYPE_CHECKING

import numpy as np
import sympy as sp
from sympy.core.function import AppliedUndef

from ..errors import (
    InvalidGeometryError,
    known_keywords,
    require_finite,
)
from ..planar import scalar_or_array
from ..symbolic import rate_name

if TYPE_CHECKING:
    from . import Mechanism

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
    unknown = sorted({str(node.func) if isinstance(node, AppliedUndef) else type(node).__name__
                      for node in sp.preorder_traversal(expr)
                      if isinstance(node, AppliedUndef | sp.Integral | sp.Derivative | sp.Subs | sp.Sum
                                    | sp.Product | sp.Limit)})
    if unknown:  # nothing numpy can evaluate: an undefined function, an unevaluated integral or derivative
        raise InvalidGeometryError(f"{where} uses {', '.join(unknown)}, which has no numeric value: write "
                                   f"the loop with known functions (sin, cos, sqrt, …); got {expr}"[:400])
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


def _plain(name: str, value):
    """An input, rate or guess as numpy can read it: sympy numbers (sp.pi / 3), alone or in a list, become
    floats (see :func:`_number`); anything else is left for ``require_finite`` to judge."""
    if isinstance(value, sp.Basic):
        return _number(name, value)
    if isinstance(value, list | tuple):
        flat = np.array(value, dtype=object)
        if flat.dtype == object and any(isinstance(v, sp.Basic) for v in flat.ravel()):
            return np.array([_number(name, v) for v in flat.ravel()], dtype=float).reshape(flat.shape)
    return value


def _keyed(argument: str, mapping, symbols, required: bool = True) -> dict[str, object]:
    """A dict keyed by symbols or their names → {name: value} in the declared order of ``symbols`` (whatever
    order the keys came in); unknown keys and missing names raise."""
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
    return {name: out[name] for name in names if name in out}


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


def _broadcast(array, shape) -> np.ndarray:
    array = np.asarray(array)
    return array if array.shape == shape else np.broadcast_to(array, shape)


class Declaration:
    """What was declared, checked when made: the loops' rows, unknowns, inputs, parameters and drawing."""

    @known_keywords
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
        inner = sorted(s.name for s in found | set(moving) if s.name.startswith("_"))
        if inner:
            raise InvalidGeometryError(f"symbols named with a leading underscore are the core's own (its "
                                       f"compiled cos and sin): rename {', '.join(inner)}")
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
            elif name in by_name and by_name[name] in values:
                twice = [f"{k!r}: {v!r}" for k, v in given.items() if getattr(k, "name", k) == name]
                raise InvalidGeometryError(f"parameters gives {name} twice (as a symbol and by its name): "
                                           f"{', '.join(twice)}; give it once")
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
        """The same loops with other numbers for some or all of the parameters (keyed by symbol or name;
        the others keep theirs): nothing is derived again.

        >>> x, th, a, b = sp.symbols("x theta a b")
        >>> crank = Mechanism([x - a * sp.cos(th) - b], [x], [th], {a: 1.0, b: 0.5})
        >>> crank.with_parameters({"a": 3.0}).residual([0.0], [0.0]).tolist()
        [-3.5]
        """
        if not isinstance(parameters, Mapping):
            raise InvalidGeometryError(f"parameters must map some of {list(self.parameters)} to numbers; "
                                       f"got {parameters!r}")
        by_name = {s.name: s for s in self.parameters}
        values, given = dict(self.parameters), set()
        for key, value in parameters.items():
            name = key.name if isinstance(key, sp.Symbol) else key
            if name not in by_name:
                raise InvalidGeometryError(f"parameters must give numbers for some of "
                                           f"{list(self.parameters)} and nothing else; "
                                           f"got {list(parameters)}")
            if name in given:  # as a symbol and by name: which one was meant is not known
                raise InvalidGeometryError(f"parameters gives {name} twice (as a symbol and by its name); "
                                           f"give it once; got {parameters!r}"[:400])
            given.add(name)
            values[by_name[name]] = _number(f"parameters[{name}]", value)
        other = copy.copy(self)
        other.parameters = MappingProxyType({k: values[k] for k in self.parameters})
        other._values = tuple(other.parameters.values())
        other._numeric = {}
        return other

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

    def _flat(self, position: Mapping, inputs: Mapping, shape) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Values by name (each broadcast to ``shape``) as flat q (N, n) — not finite taken as 0 — and u
        (N, m), with the mask of the instants whose every unknown is finite."""
        q = np.stack([np.broadcast_to(position[s.name], shape) for s in self.unknowns], axis=-1)
        u = np.stack([np.broadcast_to(inputs[s.name], shape) for s in self.inputs], axis=-1)
        q, u = q.reshape(-1, len(self.unknowns)), u.reshape(-1, len(self.inputs))
        found = np.isfinite(q).all(axis=1)
        return (q if found.all() else np.where(np.isfinite(q), q, 0.0)), u, found

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

    def _check_position(self, position) -> None:
        def names(symbols):
            return [s.name for s in symbols]

        if position is not None and not (isinstance(position, Declaration)
                                         and names(position.unknowns) == names(self.unknowns)
                                         and names(position.inputs) == names(self.inputs)):
            raise InvalidGeometryError(f"position must be a Mechanism with the unknowns "
                                       f"{list(self.unknowns)} and inputs {list(self.inputs)}; "
                                       f"got {position!r}")

    def _where(self, u, index) -> str:
        row = np.atleast_2d(u)[index]
        if self._units is not None:  # a twin's inputs (see .scaling): said in the declaration's units
            row = row * self._units.u
        return ", ".join(f"{s.name}={float(value)!r}" for s, value in zip(self.inputs, row, strict=True))

    def _by_name(self, values: np.ndarray, shape) -> Mapping[str, float | np.ndarray]:
        return MappingProxyType({s.name: scalar_or_array(values[:, k].reshape(shape))
                                 for k, s in enumerate(self.unknowns)})
