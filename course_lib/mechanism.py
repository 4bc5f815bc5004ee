"""One core for every planar mechanism: write the vector loops once, get position, velocity, acceleration.

A mechanism is declared by its loop equations F(q, u) = 0 in sympy: the unknowns q (angles, or
lengths such as a slider's travel), the inputs u (the driven joints) and a number for every other
symbol.  From that the core derives, once and when first needed, lambdified with common
subexpressions: F, J = ∂F/∂q and F_u = ∂F/∂u; the velocity system J·q̇ = −F_u·u̇ and the
acceleration system J·q̈ = −(the rest of d²F/dt²), by differentiating the loops in time; and the
stacked 3n system in (q, q̇, q̈).  :meth:`Mechanism.solve` finds the position by Newton–Raphson
(:mod:`course_lib.newton`), then the rates by linear solves with the same J.  SI units, radians.

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

from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from functools import cached_property
from types import MappingProxyType

import numpy as np
import sympy as sp

from .errors import (
    ConvergenceError,
    InvalidGeometryError,
    SingularJacobianError,
    UnreachableError,
    require_choice,
    require_finite,
)
from .newton import NewtonResult, is_singular, linear_solver, newton, newton_batch
from .planar import scalar_or_array
from .symbolic import TIME, rate_name

__all__ = ["Mechanism", "Motion"]

ON_FAILURE = ("raise", "nan")

#: Two Newton solutions of one instant closer than this (plus 100·tol) are the same assembly.
SAME_ROOT = 1e-6


@dataclass(frozen=True)
class Motion:
    """What :meth:`Mechanism.solve` found, shaped like the (broadcast) inputs.

    Attributes
    ----------
    position, velocity, acceleration : unknown's name → q, q̇, q̈ (m or rad, per s, per s²);
        ``velocity`` and ``acceleration`` are None unless ``rates`` or ``accelerations`` was given.
    converged : True where Newton converged (position and rates are NaN elsewhere).
    singular : True where J is singular at the solution or stopped Newton (rates are NaN there).
    iterations : Newton updates that produced each instant's position.
    inputs : input's name → its values, broadcast to the common shape.
    newton : for a single instant, the ``NewtonResult`` with its history; None for a sweep.

    Masks are True where their name holds; scalar inputs give Python numbers.
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


class Mechanism:
    """A planar mechanism declared by its loop equations (each expression = 0).

    ``loops``: 2×1 sympy matrices (x and y components of a vector loop) or scalar expressions,
    as many equations in all as ``unknowns``; loops may share unknowns.  ``inputs``: the driven
    variables.  ``parameters``: a number for every other symbol.  Optional ``points`` (name →
    2×1 matrix of x, y) and ``links`` (pairs of point names) describe the drawing.

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
        parameters = {} if parameters is None else parameters
        if not isinstance(parameters, Mapping) or not all(isinstance(k, sp.Symbol) for k in parameters):
            raise InvalidGeometryError(f"parameters must map sympy Symbols to numbers; got {parameters!r}")
        values = {k: require_finite(f"parameters[{k}]", v) for k, v in parameters.items()}
        if any(v.ndim for v in values.values()):
            raise InvalidGeometryError(f"parameters must map each symbol to one number; got {parameters!r}")
        self.parameters = MappingProxyType({k: float(v) for k, v in values.items()})
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

    # ------------------------------------------------------------ derived once, symbolically

    @cached_property
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

    @cached_property
    def _time_derivatives(self) -> tuple[sp.Matrix, sp.Matrix]:
        """dF/dt and d²F/dt²: every unknown and input made a function of time, the loops
        differentiated, then the derivatives named by :attr:`rate_symbols`."""
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
        """d²F/dt² (= 0): J·q̈ + F_u·ü plus the terms in products of rates (see :attr:`velocity_equations`)."""
        return self._time_derivatives[1]

    def _rates_of(self, symbols, order: int) -> list[sp.Symbol]:
        return [self.rate_symbols[s][order - 1] for s in symbols]

    def _compile(self, expressions, *groups) -> Callable[..., np.ndarray]:
        """Numeric f(*arrays), array k of shape (..., len(groups[k])) → (..., len(expressions))."""
        values = {symbol: sp.Float(value) for symbol, value in self.parameters.items()}
        expressions = [sp.sympify(e).xreplace(values) for e in expressions]
        function = sp.lambdify([s for group in groups for s in group], expressions, "numpy", cse=True)

        def evaluate(*arrays):
            arrays = [np.asarray(a, dtype=float) for a in arrays]
            out = np.empty(np.broadcast_shapes(*(a.shape[:-1] for a in arrays)) + (len(expressions),))
            columns = [a[..., k] for a in arrays for k in range(a.shape[-1])]
            for k, value in enumerate(function(*columns)):
                out[..., k] = value
            return out

        return evaluate

    @cached_property
    def _residual_and_jacobian(self) -> Callable[..., np.ndarray]:
        """(q, u) → F and J entries side by side, sharing their subexpressions."""
        F = self.equations
        return self._compile([*F, *F.jacobian(self.unknowns)], self.unknowns, self.inputs)

    @cached_property
    def _input_jacobian(self) -> Callable[..., np.ndarray]:
        return self._compile(self.equations.jacobian(self.inputs), self.unknowns, self.inputs)

    @cached_property
    def _acceleration_rhs(self) -> Callable[..., np.ndarray]:
        """(q, q̇, u, u̇, ü) → −(d²F/dt² with q̈ = 0), the right-hand side of J·q̈ = …"""
        q, u = self.unknowns, self.inputs
        zero = {s: 0 for s in self._rates_of(q, 2)}
        rest = -self.acceleration_equations.xreplace(zero)
        return self._compile(rest, q, self._rates_of(q, 1), u, self._rates_of(u, 1), self._rates_of(u, 2))

    @cached_property
    def _system_terms(self) -> Callable[..., np.ndarray]:
        q, u = self.unknowns, self.inputs
        x = [*q, *self._rates_of(q, 1), *self._rates_of(q, 2)]
        G = sp.Matrix([*self.equations, *self.velocity_equations, *self.acceleration_equations])
        return self._compile([*G, *G.jacobian(x)], x, u, self._rates_of(u, 1), self._rates_of(u, 2))

    # ------------------------------------------------------------ numbers (arrays ordered as declared)

    def _newton_terms(self, q, u) -> tuple[np.ndarray, np.ndarray]:
        """F (..., n) and J (..., n, n) from one evaluation."""
        n = len(self.unknowns)
        terms = self._residual_and_jacobian(q, u)
        return terms[..., :n], terms[..., n:].reshape(terms.shape[:-1] + (n, n))

    def residual(self, q, u) -> np.ndarray:
        """F(q, u), shape (..., n): ``q`` (..., n) ordered as ``unknowns``, ``u`` (..., m) as ``inputs``.

        >>> th, x = sp.symbols("theta x")
        >>> follower, q, u = Mechanism([x - sp.cos(th)], [x], [th]), [1.5], [np.pi / 2]
        >>> [f(q, u).tolist() for f in (follower.residual, follower.jacobian, follower.input_jacobian)]
        [[1.5], [[1.0]], [[1.0]]]
        """
        return self._newton_terms(q, u)[0]

    def jacobian(self, q, u) -> np.ndarray:
        """J = ∂F/∂q, shape (..., n, n) (see :meth:`residual`)."""
        return self._newton_terms(q, u)[1]

    def input_jacobian(self, q, u) -> np.ndarray:
        """F_u = ∂F/∂u, shape (..., n, m) (see :meth:`residual`)."""
        terms = self._input_jacobian(q, u)
        return terms.reshape(terms.shape[:-1] + (len(self.unknowns), len(self.inputs)))

    def system(self, x, u, u_rate, u_acceleration) -> tuple[np.ndarray, np.ndarray]:
        """The 3n simultaneous system: residuals of position, velocity and acceleration equations
        at x = (q, q̇, q̈), shape (..., 3n), and their Jacobian in x, shape (..., 3n, 3n).

        >>> th, x = sp.symbols("theta x")
        >>> G, JG = Mechanism([x - sp.cos(th)], [x], [th]).system([1.0, 0.0, 0.0], [0.0], [2.0], [0.0])
        >>> G.tolist(), JG.tolist()
        ([0.0, 0.0, 4.0], [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]])
        """
        size = 3 * len(self.unknowns)
        terms = self._system_terms(x, u, u_rate, u_acceleration)
        return terms[..., :size], terms[..., size:].reshape(terms.shape[:-1] + (size, size))

    # ------------------------------------------------------------ solving

    def _continuation(self, u: np.ndarray, seed: np.ndarray, tol: float, max_iter: int):
        """Positions at the rows of ``u`` in order, each on the assembly that Newton from the previous
        row's solution reaches (the first row's from ``seed``), found with few batched Newton runs.

        One batch solves every remaining row from the same seed.  Row k + 1's solution is accepted
        when one Newton step from row k's solution lands ten times closer to it than it started, or
        else when a full Newton run from row k's solution (what continuation does) reaches it.  At the
        first row that fails both, that run's value is continuation's; the rows after it are solved
        again from there."""
        N, n = u.shape[0], len(self.unknowns)
        q = np.full((N, n), np.nan)
        converged, stuck, iterations = np.zeros(N, bool), np.zeros(N, bool), np.zeros(N, int)

        def batch(rows, seeds):
            u_rows = u[rows]
            return newton_batch(lambda x: self._newton_terms(x, u_rows), seeds, jac=True, tol=tol,
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

        ``inputs`` maps each input (symbol or name) to a number or array; ``rates`` and
        ``accelerations`` map inputs to u̇, ü (missing entries are 0); all broadcast together.
        ``guess`` maps every unknown to a number: the seed of Newton at the first instant; each
        later instant (in C order) continues from the previous solution, so a sweep follows one
        assembly.  One instant (every input a number) is solved by :func:`~course_lib.newton.newton`
        and keeps its history in ``Motion.newton``; arrays by batched runs of
        :func:`~course_lib.newton.newton_batch` that give what continuation gives.  ``tol`` and
        ``max_iter`` are Newton's.  Velocity and acceleration come from J·q̇ = −F_u·u̇ and
        J·q̈ = −(the rest of d²F/dt²), solved with the J of the position.

        Raises (unless ``on_failure="nan"``, which gives NaN and the masks instead):
        ``SingularJacobianError`` where J is singular during Newton, or at a solution where rates are
        asked; ``ConvergenceError`` where Newton fails from the guess; ``UnreachableError`` where it
        fails from the previous instant's solution (the assembly cannot follow the input there).

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
        shape, m, n = arrays[0].shape, len(self.inputs), len(self.unknowns)
        u, u_rate, u_acc = (np.stack(arrays[k * m:(k + 1) * m], axis=-1).reshape(-1, m) for k in range(3))
        with np.errstate(all="ignore"):
            if shape == ():
                q, converged, stuck, iterations, result = self._one_instant(u[0], seed, tol, max_iter,
                                                                            on_failure)
            else:
                result = None
                q, converged, stuck, iterations = self._continuation(u, seed, tol, max_iter)
            J = self._newton_terms(q, u)[1]
            singular = stuck | (converged & is_singular(J))
        want_rates = rates is not None or accelerations is not None
        if on_failure == "raise":
            self._report(~converged | (singular & want_rates), singular, u)
        q[~converged] = np.nan
        velocity = acceleration = None
        if want_rates:
            good = converged & ~singular
            solve = linear_solver(np.where(good[:, None, None], J, np.eye(n)))
            q_rate = solve(-np.einsum("nij,nj->ni", self.input_jacobian(q, u), u_rate))
            q_rate[~good] = np.nan
            with np.errstate(invalid="ignore"):
                rest = self._acceleration_rhs(q, q_rate, u, u_rate, u_acc)
            q_acc = solve(np.where(good[:, None], rest, 0.0))
            q_acc[~good] = np.nan
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
        try:
            result = newton(lambda q: self.residual(q, u), seed, jac=lambda q: self.jacobian(q, u),
                            tol=tol, max_iter=max_iter)
        except SingularJacobianError as err:
            if on_failure == "raise":
                raise SingularJacobianError(f"at {where}: {err}", err.x, err.condition_number) from err
            return np.full((1, seed.size), np.nan), np.array([False]), np.array([True]), np.array([0]), None
        except ConvergenceError as err:
            if on_failure == "raise":
                raise ConvergenceError(f"at {where}, from the guess: {err}", result=err.result) from err
            result = err.result
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

    @cached_property
    def _point_terms(self) -> Callable[..., np.ndarray]:
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
        xy = self._point_terms(q, u)
        return {name: xy[..., 2 * k:2 * k + 2] for k, name in enumerate(self.points)}
