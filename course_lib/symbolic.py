"""sympy helpers for deriving kinematics the way the course does: angles are functions of time θ(t), and
differentiating a loop equation with dθ/dt → ω, d²θ/dt² → α gives the velocity and acceleration
equations; the tangent half-angle substitution turns a trigonometric equation into a polynomial one.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import sympy as sp

from .errors import InvalidGeometryError

__all__ = ["TIME", "time_symbols", "rate_name", "d_dt", "static", "half_angle", "jacobian", "lambdify",
           "LoopForm", "is_angle", "reduce_loop"]

#: The time symbol used by every time-dependent symbol of the course.
TIME = sp.Symbol("t", real=True)


def time_symbols(*names: str) -> tuple[sp.Function, ...]:
    """θ(t)-style functions of time, one per name.

    >>> time_symbols("theta3", "theta4")
    (theta3(t), theta4(t))
    """
    return tuple(sp.Function(name, real=True)(TIME) for name in names)


def rate_name(name: str, order: int) -> str:
    """The name of a first or second time derivative: theta2 → omega2, alpha2; else r1 → v_r1, a_r1.

    >>> rate_name("theta3", 1), rate_name("r1", 2)
    ('omega3', 'a_r1')
    """
    if name.startswith("theta"):
        return ("omega" if order == 1 else "alpha") + name[len("theta") :]
    return ("v_" if order == 1 else "a_") + name


def d_dt(expr: sp.Expr, order: int = 1) -> sp.Expr:
    """Time derivative of ``expr`` with the rates as plain symbols (:func:`rate_name`: θ' → ω, θ'' → α,
    r1' → v_r1, r1'' → a_r1); take a second derivative with ``order=2``, not ``d_dt`` twice.

    >>> theta, = time_symbols("theta2")
    >>> static(d_dt(sp.sin(theta), 2))
    alpha2*cos(theta2) - omega2**2*sin(theta2)
    """
    if isinstance(order, bool) or not isinstance(order, int) or order < 1:
        raise InvalidGeometryError(f"order must be a whole number >= 1 (1: velocity, 2: acceleration); "
                                   f"got {order!r}")
    derivative = sp.diff(expr, TIME, order)
    return derivative.xreplace({d: sp.Symbol(rate_name(d.expr.func.__name__, d.derivative_count), real=True)
                                for d in derivative.atoms(sp.Derivative)})


def static(expr):
    """Every θ(t)-style function of time replaced by a plain symbol of the same name (to display or lambdify).

    >>> theta, = time_symbols("theta4")
    >>> static(sp.cos(theta) + 1)
    cos(theta4) + 1
    """
    expr = sp.sympify(expr)
    functions = {f for f in expr.atoms(sp.Function) if f.args == (TIME,)}
    return expr.xreplace({f: sp.Symbol(f.func.__name__, real=True) for f in functions})


def half_angle(expr: sp.Expr, angle: sp.Expr, tangent: sp.Symbol) -> sp.Expr:
    """Substitute cos θ = (1 − u²)/(1 + u²), sin θ = 2u/(1 + u²) with u = tan(θ/2).

    >>> u, th = sp.symbols("u theta")
    >>> sp.simplify(half_angle(sp.sin(th)**2 + sp.cos(th)**2, th, u))
    1
    """
    below = 1 + tangent**2
    return expr.subs({sp.cos(angle): (1 - tangent**2) / below, sp.sin(angle): 2 * tangent / below})


def jacobian(expressions: Sequence[sp.Expr], variables: Sequence[sp.Expr]) -> sp.Matrix:
    """∂Fᵢ/∂xⱼ as a sympy Matrix (variables may be θ(t) functions or symbols).

    >>> x, y = sp.symbols("x y")
    >>> jacobian([x * y, x + y], [x, y]).tolist()
    [[y, x], [1, 1]]
    """
    return sp.Matrix(expressions).jacobian(sp.Matrix(variables))


def lambdify(variables: Sequence[sp.Expr], expr) -> Callable:
    """sympy.lambdify to numpy, accepting θ(t) functions as arguments.

    >>> x = sp.Symbol("x")
    >>> float(lambdify([x], sp.sin(x) ** 2)(0.5)) == __import__("math").sin(0.5) ** 2
    True
    """
    dummies = [sp.Dummy() for _ in variables]
    expr = sp.sympify(expr).xreplace(dict(zip(variables, dummies, strict=True)))
    return sp.lambdify(dummies, expr, modules="numpy")


@dataclass(frozen=True)
class LoopForm:
    """A loop reduced by the course's half-angle route to one quadratic a·v² + b·v + c = 0.

    unknowns : the block's unknowns, the first one found from the quadratic (v = tan(first/2) for an
    angle, v = first for a length).  kind : "angle" or "length", the first unknown's.  quadratic : (a, b, c)
    in the known symbols (a is 0 where the form is linear: one root).  second : the other unknown from the
    first, ``("angle", cos, sin)`` or ``("length", value)`` in the first unknown's cos/sin (an angle) or
    the first unknown itself (a length); None for a one-unknown block.  route : how the quadratic was
    reached, in words.
    """

    unknowns: tuple
    kind: str
    quadratic: tuple
    second: tuple | None
    route: str


def _trig_symbols(expr, angles):
    """``expr`` (an expression or a Matrix) with cos and sin of each angle (sums expanded) as plain
    symbols, sin² reduced by sin² = 1 − cos²: (expression, {angle: (c, s)}), or None where an angle
    survives otherwise."""
    pairs = {a: (sp.Dummy(f"c_{a}"), sp.Dummy(f"s_{a}")) for a in angles}
    generators = [s for pair in pairs.values() for s in reversed(pair)]
    identities = [s**2 + c**2 - 1 for c, s in pairs.values()]

    def one(entry):
        entry = sp.expand(sp.expand_trig(sp.expand(entry)))
        entry = entry.xreplace({f(a): pair[k] for a, pair in pairs.items()
                                for k, f in enumerate((sp.cos, sp.sin))})
        if entry.free_symbols & set(angles):
            return None
        if identities and entry.has(*generators):
            entry = sp.reduced(entry, identities, *generators, order="lex")[1]
        return sp.expand(entry)

    if isinstance(expr, sp.MatrixBase):
        entries = [one(e) for e in expr]
        return None if any(e is None for e in entries) else (sp.Matrix(entries), pairs)
    entry = one(expr)
    return None if entry is None else (entry, pairs)


def _tidy(expr):
    """sin² → 1 − cos² for every angle, expanded: the known angles' identity applied too."""
    def reduce(e):
        return e.is_Pow and isinstance(e.base, sp.sin) and e.exp.is_Integer and e.exp >= 2

    expr = sp.expand(expr)
    while expr.has(sp.sin) and any(reduce(e) for e in expr.atoms(sp.Pow)):
        expr = sp.expand(expr.replace(reduce, lambda e: (1 - sp.cos(e.base.args[0]) ** 2)
                                      * sp.sin(e.base.args[0]) ** (e.exp - 2)))
    return expr


def _common(quadratic):
    """(a, b, c) tidied and divided by their greatest common factor."""
    a, b, c = (_tidy(e) for e in quadratic)
    common = sp.gcd_list([e for e in (a, b, c) if e != 0])
    if common != 0 and common.free_symbols:
        a, b, c = (sp.expand(sp.cancel(e / common)) for e in (a, b, c))
    return a, b, c


def _affine(expr, symbols):
    """(coefficients of ``symbols``, rest) when ``expr`` is affine in them, else None."""
    if not symbols:
        return [], expr
    poly = sp.Poly(expr, *symbols)
    if poly.total_degree() > 1:
        return None
    coefficients = [poly.coeff_monomial(s) for s in symbols]
    return coefficients, sp.expand(expr - sum(c * s for c, s in zip(coefficients, symbols, strict=True)))


def _angle_quadratic(E, c, s):
    """A c + B s + C = 0 (affine in c = cos θ, s = sin θ) → (C − A) t² + 2B t + (C + A), t = tan(θ/2)."""
    found = _affine(E, [c, s])
    if found is None:
        return None
    (A, B), C = found
    if A == 0 and B == 0:
        return None
    return sp.expand(C - A), sp.expand(2 * B), sp.expand(C + A)


def _length_quadratic(E, v):
    if not E.has(v):
        return None
    poly = sp.Poly(E, v)
    if poly.degree() > 2:
        return None
    a, b, c = (poly.coeff_monomial(v**k) for k in (2, 1, 0))
    return sp.expand(a), sp.expand(b), sp.expand(c)


def is_angle(expr, symbol) -> bool:
    """True when ``symbol`` appears in ``expr`` only as an angle: inside cos and sin, with a whole
    coefficient (so ``expr`` repeats every turn of it).

    >>> th, r = sp.symbols("theta r")
    >>> is_angle(r * sp.cos(th + 1), th), is_angle(r * sp.cos(th), r)
    (True, False)
    """
    def inside(node) -> bool:
        if node == symbol:
            return False
        if isinstance(node, sp.cos | sp.sin) and node.has(symbol):
            argument = sp.expand(node.args[0])
            slope = argument.diff(symbol)
            return slope.is_Integer and not (argument - slope * symbol).has(symbol)
        return all(inside(arg) for arg in node.args)

    return sp.sympify(expr).has(symbol) and inside(sp.sympify(expr))


def reduce_loop(rows, unknowns, angles) -> LoopForm | None:
    """The course's half-angle route for one or two loop rows in as many ``unknowns`` (the others known):
    eliminate one unknown, reach one quadratic in t = tan(θ/2) (an angle) or in a length; None where the
    rows are not of a classical kind.  ``angles``: the unknowns that are angles (see :func:`is_angle`).

    Kinds: one row in one angle (A cos θ + B sin θ + C = 0) or one length (a polynomial of degree ≤ 2);
    two angles (the second eliminated by |its vector|² = its length², the four-bar's route); an angle and a
    length (the length eliminated by the cross product with its direction); two lengths (linear, or two
    circles: their difference is linear, then one quadratic, the five-bar's route).

    >>> th2, th3, th4, l1, l2, l3, l4 = sp.symbols("theta2 theta3 theta4 l1 l2 l3 l4")
    >>> loop = [l2*sp.cos(th2) + l3*sp.cos(th3) - l4*sp.cos(th4) - l1,
    ...         l2*sp.sin(th2) + l3*sp.sin(th3) - l4*sp.sin(th4)]
    >>> form = reduce_loop(loop, [th3, th4], [th3, th4])
    >>> form.unknowns, form.kind, form.route
    ((theta4, theta3), 'angle', 'two angles: theta3 eliminated by |its vector|² = its length²')
    """
    rows = [sp.expand(sp.sympify(r)) for r in rows]
    unknowns = list(unknowns)
    if len(rows) != len(unknowns) or len(rows) not in (1, 2):
        return None
    if len(rows) == 1:
        (v,) = unknowns
        if v in angles:
            split = _trig_symbols(rows[0], [v])
            quadratic = split and _angle_quadratic(split[0], *split[1][v])
        else:
            quadratic = _length_quadratic(rows[0], v) if not rows[0].has(sp.cos(v), sp.sin(v)) else None
        if quadratic is None:
            return None
        kind = "angle" if v in angles else "length"
        return LoopForm((v,), kind, _common(quadratic), None, f"one row in the {kind} {v}")
    for keep, drop in ((unknowns[1], unknowns[0]), (unknowns[0], unknowns[1])):
        form = _two_unknowns(rows, keep, drop, angles)
        if form is not None:
            return form
    return None


def _two_unknowns(rows, keep, drop, angles) -> LoopForm | None:
    """One elimination of ``drop``, keeping ``keep`` (see :func:`reduce_loop`)."""
    in_angles = [u for u in (keep, drop) if u in angles]
    split = _trig_symbols(sp.Matrix(rows), in_angles) if in_angles else (sp.Matrix(rows), {})
    if split is None:
        return None
    F, pairs = split
    if keep in angles and drop in angles:        # two angles
        ck, sk = pairs[keep]
        cd, sd = pairs[drop]
        parts = [_affine(row, [ck, sk, cd, sd]) for row in F]
        if any(p is None for p in parts):
            return None
        M_keep = sp.Matrix([[p[0][0], p[0][1]] for p in parts])
        M_drop = sp.Matrix([[p[0][2], p[0][3]] for p in parts])
        P = sp.Matrix([p[1] for p in parts])
        gram = sp.expand(M_drop.T * M_drop)
        length2 = gram[0, 0]
        if length2 == 0 or sp.expand(gram - length2 * sp.eye(2)) != sp.zeros(2, 2):
            return None
        rest = P + M_keep * sp.Matrix([ck, sk])
        E = sp.reduced(sp.expand(rest.dot(rest) - length2), [sk**2 + ck**2 - 1], sk, ck, order="lex")[1]
        quadratic = _angle_quadratic(sp.expand(E), ck, sk)
        if quadratic is None:
            return None
        back = -(M_drop.T * rest) / length2
        back = back.xreplace({ck: sp.cos(keep), sk: sp.sin(keep)})
        return LoopForm((keep, drop), "angle", _common(quadratic), ("angle", _tidy(back[0]), _tidy(back[1])),
                        f"two angles: {drop} eliminated by |its vector|² = its length²")
    if keep in angles and drop not in angles:    # an angle and a length
        ck, sk = pairs[keep]
        if any(sp.Poly(row, drop).degree() > 1 for row in F):
            return None
        F1 = sp.Matrix([sp.expand(row.coeff(drop, 1)) for row in F])
        F0 = sp.expand(F - F1 * drop)
        if F1 == sp.zeros(2, 1) or any(_affine(e, [ck, sk]) is None for e in (*F0, *F1)):
            return None
        cross = sp.expand(F0[0] * F1[1] - F0[1] * F1[0])
        E = sp.reduced(cross, [sk**2 + ck**2 - 1], sk, ck, order="lex")[1]
        quadratic = _angle_quadratic(sp.expand(E), ck, sk)
        if quadratic is None:
            return None
        back = sp.expand(-F0.dot(F1)) / sp.expand(F1.dot(F1))
        back = back.xreplace({ck: sp.cos(keep), sk: sp.sin(keep)})
        return LoopForm((keep, drop), "angle", _common(quadratic), ("length", sp.cancel(_tidy(back))),
                        f"an angle and a length: {drop} eliminated by the cross product with its direction")
    if keep in angles or drop in angles:
        return None
    # two lengths: linear, or quadratic parts in proportion (circles: their difference is linear)
    polys = [sp.Poly(row, keep, drop) for row in F]
    if any(p.total_degree() > 2 or p.total_degree() < 1 for p in polys):
        return None
    monomials = [keep**2, keep * drop, drop**2]
    squares = [sp.Matrix([p.coeff_monomial(m) for m in monomials]) for p in polys]
    if squares[1] == sp.zeros(3, 1) and squares[0] != sp.zeros(3, 1):
        F = sp.Matrix([F[1], F[0]])
        squares = squares[::-1]
    if squares[1] == sp.zeros(3, 1):
        linear, other = F[1], F[0]
    else:
        index = next(k for k in range(3) if squares[1][k] != 0)
        ratio = sp.cancel(squares[0][index] / squares[1][index])
        if sp.expand(squares[0] - ratio * squares[1]) != sp.zeros(3, 1):
            return None
        linear, other = sp.expand(F[0] - ratio * F[1]), F[1]
    a_drop, a_keep = sp.expand(linear).coeff(drop, 1), sp.expand(linear).coeff(keep, 1)
    if sp.expand(linear - a_drop * drop - a_keep * keep).has(keep, drop) or a_drop == 0:
        return None
    value = sp.expand(-(linear - a_drop * drop)) / a_drop          # drop = g·keep + f
    E = sp.numer(sp.together(sp.expand(other.subs(drop, value))))
    quadratic = _length_quadratic(sp.expand(E), keep)
    if quadratic is None:
        return None
    value = _tidy(sp.numer(sp.together(value))) / _tidy(sp.denom(sp.together(value)))
    return LoopForm((keep, drop), "length", _common(quadratic), ("length", value),
                    f"two lengths: {drop} from a linear combination of the rows, then one quadratic")
