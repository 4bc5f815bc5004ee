"""sympy helpers for deriving kinematics the way the course does: angles are functions of time θ(t), and
differentiating a loop equation with dθ/dt → ω, d²θ/dt² → α gives the velocity and acceleration
equations; the tangent half-angle substitution turns a trigonometric equation into a polynomial one.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import sympy as sp

__all__ = ["TIME", "time_symbols", "rate_name", "d_dt", "static", "half_angle", "jacobian", "lambdify"]

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
