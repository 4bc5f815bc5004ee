"""Scale: a declaration whose loops are homogeneous in its lengths, declared at any size (1e-90 … 1e90 m),
solved with its lengths in units of a power of two near their typical size.

A declaration's *lengths* are the symbols (parameters, unknowns and inputs) that appear inside no function
(not in cos, sin, …); its *angles* are the others.  Its loops are homogeneous when every row is, of some
degree d_i: F_i(λ·lengths, angles) = λ^d_i · F_i(lengths, angles) for every λ > 0 (d_i = 1 for a vector
loop, 2 for a squared distance), and every declared point of degree 1.  Multiplying every length by λ then
multiplies the linkage as a whole: the same angles, every length λ times, the rates of the lengths λ times.

Such a declaration whose parameters' typical length (the median of the nonzero ones) lies outside
[1 / ``UNIT_RANGE``, ``UNIT_RANGE``] is solved as its *twin*: the same loops (everything derived shared,
see :meth:`~course_lib.mechanism.Mechanism.with_parameters`) with every length parameter divided by 2^k,
2^k the power of two nearest that typical length, so the twin's typical length is about 1; the inputs
that are lengths go in divided by 2^k, the lengths found (and their rates) come out multiplied by 2^k.
A power of two is exact in floating point, so nothing is rounded on the way in or out.  There the closed
forms' coefficients (lengths to the fourth power) neither overflow nor underflow, and Newton's ``tol``
(an absolute bound on a step and a residual) applies to the lengths in units of 2^k, as it does to a
linkage of ordinary size.  The rules that are relative (the singularity rule on J̃, the level of a
quadratic, the residual over a row's typical size) give the same verdicts at every scale.

The homogeneity is checked by sympy once per declaration (shared by its ``with_parameters`` copies), and
only when some parameter leaves the range: a declaration of ordinary size never pays for it and is solved
as before, bit for bit.  A declaration that is not homogeneous (a number written in a loop, a ratio
multiplying a length) is solved as declared.

>>> th2, th3, th4 = sp.symbols("theta2 theta3 theta4")
>>> l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
>>> loop = sp.Matrix([l2*sp.cos(th2) + l3*sp.cos(th3) - l4*sp.cos(th4) - l1,
...                   l2*sp.sin(th2) + l3*sp.sin(th3) - l4*sp.sin(th4)])
>>> lengths = {l1: 0.20, l2: 0.06, l3: 0.18, l4: 0.12}
>>> wiper, huge = (Mechanism([loop], [th3, th4], [th2], {k: v * size for k, v in lengths.items()})
...                for size in (1.0, 1e90))
>>> at_1, at_1e90 = (m.solve({th2: 1.0}, rates={th2: 10.0}) for m in (wiper, huge))
>>> [abs(at_1e90.velocity[k] - at_1.velocity[k]) < 1e-12 for k in ("theta3", "theta4")]
[True, True]
>>> wiper._twin() is None, huge._twin()._units.length == 2.0 ** 296
(True, True)

One room of :class:`~course_lib.mechanism.Mechanism`, which is all of them together.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING, NamedTuple

import numpy as np
import sympy as sp

from ..newton import NewtonResult
from ..thresholds import UNIT_RANGE
from .declaration import _derived

if TYPE_CHECKING:
    from . import Mechanism

__all__ = ["Scaling", "Units"]


class Units(NamedTuple):
    """A twin's units: ``length`` = 2^k (m per twin unit), and per unknown (``q``), per input (``u``) and per
    loop row (``rows``) the factor from the twin's values to the declaration's: 2^k for a length, 1 for an
    angle, (2^k)^d_i for row i of degree d_i."""

    length: float
    q: np.ndarray
    u: np.ndarray
    rows: np.ndarray


def _degree(expr: sp.Expr, lengths: list[sp.Symbol], scale: sp.Symbol):
    """The degree d with expr(λ·lengths) = λ^d · expr(lengths) (λ > 0), as a sympy Rational; None where
    ``expr`` is not homogeneous in ``lengths`` (or sympy cannot tell); ``sp.oo`` for 0 (any degree)."""
    if expr == 0:
        return sp.oo
    used = [s for s in lengths if expr.has(s)]
    if not used:
        return sp.S.Zero
    try:  # a polynomial, or a ratio of two, in the lengths (coefficients: anything in the angles)
        orders = []
        for part in sp.fraction(sp.together(expr)):
            poly = sp.Poly(part, *used)
            if not poly.is_homogeneous:
                return None
            orders.append(poly.homogeneous_order())
        return sp.Integer(orders[0] - orders[1])
    except (sp.PolynomialError, sp.GeneratorsNeeded, sp.CoercionFailed, TypeError, ValueError):
        pass
    try:  # anything else (a square root of a sum of squares): the ratio of the scaled to the declared
        ratio = sp.simplify(expr.xreplace({s: scale * s for s in used}) / expr)
    except (TypeError, ValueError, ZeroDivisionError, NotImplementedError):
        return None
    if ratio == 1:
        return sp.S.Zero
    if ratio == scale:
        return sp.S.One
    if ratio.is_Pow and ratio.base == scale and ratio.exp.is_Rational:
        return ratio.exp
    return None


def _norms(rows: np.ndarray) -> np.ndarray:
    """‖row‖ of each row of ``rows`` (K, n), computed on the rows divided by their largest entry (no
    overflow or underflow at lengths of 1e±90 to the fourth power)."""
    peak = np.abs(rows).max(axis=1, initial=0.0)
    safe = np.where((peak > 0) & np.isfinite(peak), peak, 1.0)
    return np.where(np.isfinite(peak), safe * np.sqrt(((rows / safe[:, None]) ** 2).sum(axis=1)), np.inf)


class Scaling:
    """The twin of a homogeneous declaration declared far from unit size, and the values it finds in the
    declaration's own units."""

    #: A twin's :class:`Units` (None: a declaration solved as declared).
    _units: Units | None = None

    @_derived
    def _homogeneous(self) -> tuple[frozenset, tuple] | None:
        """(the length symbols, each loop row's degree) where the loops and points are homogeneous in the
        lengths (see the module's text); else None."""
        expressions = [*self.equations, *(c for xy in self.points.values() for c in xy)]
        symbols = set().union(*(e.free_symbols for e in expressions))
        inside = set().union(*(f.free_symbols for e in expressions for f in e.atoms(sp.Function)))
        lengths = sorted(symbols - inside, key=lambda s: s.name)
        if not lengths:
            return None
        scale = sp.Dummy("lambda", positive=True)
        degrees = [_degree(row, lengths, scale) for row in self.equations]
        if any(d is None or d == sp.oo for d in degrees):
            return None
        if any(_degree(c, lengths, scale) not in (sp.S.One, sp.oo)
               for xy in self.points.values() for c in xy):
            return None
        return frozenset(lengths), tuple(degrees)

    def _twin(self) -> Mechanism | None:
        """The twin this declaration is solved as (see the module's text), or None: found once per
        declaration and registered kernels (``with_kernel`` copies share the numbers' cache)."""
        for kernels, twin in self._numeric.get("twins", ()):
            if kernels is self._kernels:
                return twin
        twin = self._scaled() if self._units is None else None
        self._numeric.setdefault("twins", []).append((self._kernels, twin))
        return twin

    def _scaled(self) -> Mechanism | None:
        """A new twin, or None where the parameters' lengths are of ordinary size or the loops are not
        homogeneous."""
        if all(not v or 1 / UNIT_RANGE <= abs(v) <= UNIT_RANGE for v in self._values):
            return None  # every parameter of ordinary size: no sympy at all
        homogeneous = self._homogeneous
        if homogeneous is None:
            return None
        lengths, degrees = homogeneous
        sizes = [abs(v) for s, v in self.parameters.items() if s in lengths and v]
        if not sizes:
            return None
        typical = float(np.median(sizes))
        if 1 / UNIT_RANGE <= typical <= UNIT_RANGE:
            return None
        exponent = int(np.clip(np.round(np.log2(typical)), -1021, 1023))
        unit = float(np.ldexp(1.0, exponent))
        twin = self.with_parameters({s: v / unit for s, v in self.parameters.items() if s in lengths})
        twin._units = Units(unit, np.array([unit if s in lengths else 1.0 for s in self.unknowns]),
                            np.array([unit if s in lengths else 1.0 for s in self.inputs]),
                            np.array([unit ** float(d) for d in degrees]))
        return twin

    def _in_twin(self, q: np.ndarray, u: np.ndarray) -> tuple[Mechanism, np.ndarray, np.ndarray]:
        """(the declaration values ``q`` (..., n) and ``u`` (..., m) are evaluated on, q, u in its units):
        the twin where there is one, else this declaration itself."""
        twin = self._twin()
        if twin is None:
            return self, q, u
        return twin, q / twin._units.q, u / twin._units.u

    def _shown(self, result: NewtonResult | None, u: np.ndarray | None = None) -> NewtonResult | None:
        """A twin's Newton run of one instant (at the inputs ``u`` (m,), in the twin's units) in the
        declaration's units: its iterates, steps, residual norms and the numbers its message gives; any
        other run as it is."""
        units = self._units
        if units is None or result is None:
            return result
        history = np.asarray(result.history, float)
        steps = np.asarray(result.step_components, float).reshape(-1, history.shape[1]) * units.q
        norms, residuals, message = _norms(steps), np.asarray(result.residual_norms, float), result.message
        if u is not None:  # ‖F‖ of each iterate in the declaration's units: each row times (2^k)^d_i
            with np.errstate(all="ignore"):
                F = self._F(history, np.broadcast_to(u, (len(history), len(u))))
            shown = F * units.rows
            residuals = _norms(shown)[:len(residuals)]
            message = message.replace(f"F returned {F[-1].tolist()}", f"F returned {shown[-1].tolist()}")
        message = message.replace(f"x={history[-1].tolist()}", f"x={(history[-1] * units.q).tolist()}")
        if len(norms) and len(residuals):
            message = re.sub(r"\(last step [^,]*, residual [^)]*\)",
                             f"(last step {norms[-1]:.3g}, residual {residuals[-1]:.3g})", message)
        return NewtonResult(x=result.x * units.q, converged=result.converged, iterations=result.iterations,
                            history=history * units.q, step_norms=norms, step_components=steps,
                            residual_norms=residuals, message=message, ill_conditioned=result.ill_conditioned)
