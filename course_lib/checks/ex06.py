"""Checkers of exercise set 06 (the shaper's quick return) and of lesson 12's Try it.

The drawing (:class:`ShaperDrawing`): the crank O2A (r2) turns about O2, d straight above the lever's pivot
O4 = (0, 0); the block at A slides along the lever O4B (l4) at the unknown r4 from O4; the link BC (l5)
drives the ram, whose pin C runs on y = h at x.  Unknowns θ4, r4, θ5, x; input θ2; m, rad.
"""
# ruff: noqa: F403, F405

import math
from collections.abc import Mapping
from dataclasses import astuple, dataclass
from functools import cached_property
from itertools import permutations

import numpy as np

from ..errors import InvalidArgumentError, InvalidGeometryError, require_positive
from .engine import *  # the feedback engine's helpers (engine.__all__)

__all__ = ["ShaperDrawing", "SHAPER", "quick_return_time_ratio", "check_shaper_loops",
           "check_shaper_position", "check_ram_motion", "check_ram_stroke", "check_quick_return_time_ratio"]

#: The symbols of the loops: the input θ2, the unknowns in the order the exercises ask for them, the lengths.
NAMES = ("theta2", "theta4", "r4", "theta5", "x", "r2", "d", "l4", "l5", "h")
UNKNOWNS = NAMES[1:5]
_PROBES = np.radians(np.arange(10.0, 360.0, 45.0))  # crank angles where the loops are evaluated
_NUDGE = np.array([0.05, 0.02, -0.04, 0.03])  # the unknowns off the drawing, to see a row respond
#: Crank angles over one turn, where a task's shaper must assemble and the loops must fix the unknowns.
_TURN = np.linspace(0.0, 2 * np.pi, 256, endpoint=False)
_RANDOM = np.random.default_rng(20240607)  # a fixed seed: the same checks every run
#: Crank angles where every equation must vanish on the drawn shaper: the probes, the turn, random ones.
_CLOSED = np.concatenate([_PROBES, _TURN, _RANDOM.uniform(0.0, 2 * np.pi, 32)])
#: Positions that do not close the loops, where no equation may vanish: random crank angles, each unknown
#: moved off the drawing by 0.02 to 0.2 (rad or m) either way.
_OPEN_THETA2 = _RANDOM.uniform(0.0, 2 * np.pi, 24)
_OPEN_NUDGE = _RANDOM.uniform(0.02, 0.2, (4, 24)) * _RANDOM.choice([-1.0, 1.0], (4, 24))


def quick_return_time_ratio(crank: float, pivot_distance: float) -> float:
    """Time ratio (π + 2β)/(π − 2β) of a slotted-lever quick return, crank r2, pivots d apart, sin β = r2/d.

    >>> quick_return_time_ratio(0.05, 0.10)
    2.0
    """
    if not require_positive("crank", crank) < require_positive("pivot_distance", pivot_distance):
        raise InvalidGeometryError("a quick return needs crank < pivot_distance (else the lever turns "
                                   f"fully); got crank={crank}, pivot_distance={pivot_distance}")
    beta = math.asin(crank / pivot_distance)
    return (math.pi + 2 * beta) / (math.pi - 2 * beta)


@dataclass(frozen=True)
class ShaperDrawing:
    """The shaper of exercise 06 as drawn, solved by geometry: ``crank`` r2, ``pivot_distance`` d, ``lever``
    l4, ``link`` l5, ``ram_height`` h, in m.

    >>> [round(float(value), 6) for value in ShaperDrawing().configuration(np.pi / 2)]
    [1.570796, 0.21, 0.0, 0.15]
    >>> round(ShaperDrawing().time_ratio(), 6), round(ShaperDrawing().stroke(), 6)
    (1.709953, 0.24)
    """

    crank: float = 0.06
    pivot_distance: float = 0.15
    lever: float = 0.30
    link: float = 0.15
    ram_height: float = 0.30

    def __post_init__(self) -> None:
        quick_return_time_ratio(self.crank, self.pivot_distance)  # checks crank and pivot_distance
        for name in ("lever", "link"):
            require_positive(name, getattr(self, name))
        if not abs(self.ram_height - self.lever) < self.link:
            raise InvalidGeometryError(f"the link cannot reach the ram line from the lever's top; got "
                                       f"lever={self.lever}, link={self.link}, ram_height={self.ram_height}")

    def configuration(self, theta2, assembly: int = +1) -> tuple[np.ndarray, ...]:
        """(θ4, r4, θ5, x) at crank angle(s) ``theta2``; C right of B for ``assembly=+1`` (as drawn)."""
        theta2 = np.asarray(theta2, float)
        A = np.stack([self.crank * np.cos(theta2), self.pivot_distance + self.crank * np.sin(theta2)])
        theta4, r4 = np.arctan2(A[1], A[0]), np.hypot(A[0], A[1])
        rise = (self.ram_height - self.lever * np.sin(theta4)) / self.link
        theta5 = np.arcsin(rise) if assembly > 0 else np.pi - np.arcsin(rise)
        return theta4, r4, theta5, self.lever * np.cos(theta4) + self.link * np.cos(theta5)

    @cached_property
    def _derivatives(self):
        """θ2 ↦ (q, dq/dθ2, d²q/dθ2²) for q = θ4, r4, θ5, x: the closed form differentiated in sympy."""
        import sympy as sp

        th2 = sp.Symbol("theta2", real=True)
        r2, d, l4, l5, h = map(sp.Float, astuple(self))
        Ax, Ay = r2 * sp.cos(th2), d + r2 * sp.sin(th2)
        r4 = sp.sqrt(Ax**2 + Ay**2)
        sin5 = (h - l4 * Ay / r4) / l5
        closed = [sp.atan2(Ay, Ax), r4, sp.asin(sin5), l4 * Ax / r4 + l5 * sp.sqrt(1 - sin5**2)]
        return sp.lambdify(th2, [[q, q.diff(th2), q.diff(th2, 2)] for q in closed], modules="numpy", cse=True)

    def rates(self, theta2, omega2: float, alpha2: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
        """Velocities q′ω2 and accelerations q″ω2² + q′α2 of (θ4, r4, θ5, x), each shape (4, ...)."""
        rows = np.array(self._derivatives(np.asarray(theta2, float)), dtype=float)
        return rows[:, 1] * omega2, rows[:, 2] * omega2**2 + rows[:, 1] * alpha2

    def limit_angles(self) -> tuple[float, float]:
        """Crank angles where the lever stops (O4A ⟂ O2A, sin θ2 = −r2/d)."""
        beta = math.asin(self.crank / self.pivot_distance)
        return -beta, math.pi + beta

    def time_ratio(self) -> float:
        """Crank angle of the slow stroke over that of the fast one (:func:`quick_return_time_ratio`)."""
        return quick_return_time_ratio(self.crank, self.pivot_distance)

    def stroke(self) -> float:
        """The ram's travel between the two lever stops, m."""
        first, second = (self.configuration(angle)[3] for angle in self.limit_angles())
        return float(abs(first - second))


#: The shaper drawn in exercise 06.
SHAPER = ShaperDrawing()


def _assembles(shaper: ShaperDrawing, theta2: float, *rates: float) -> None:
    """The shaper assembles at ``theta2`` (C on the ram's line, either side of B), with the ``rates``
    (ω2, α2) there when they are given."""
    task_possible(lambda: [shaper.configuration(theta2, side) for side in (1, -1)]
                  + (list(shaper.rates(theta2, *rates)) if rates else []),
                  f"the shaper {shaper!r} cannot be assembled at theta2={theta2:.6g} (the link BC cannot "
                  "reach the ram's line there)")


def _moves(shaper: ShaperDrawing, theta2: float, omega2: float, alpha2: float) -> None:
    """The shaper assembles at ``theta2``, with its rates at ``omega2``, ``alpha2``."""
    _assembles(shaper, theta2, omega2, alpha2)


def _turns(shaper: ShaperDrawing) -> None:
    """The shaper assembles at every crank angle of a turn."""
    task_possible(lambda: [shaper.configuration(angles) for angles in (_TURN, _PROBES,
                                                                       np.array(shaper.limit_angles()))],
                  f"the shaper {shaper!r} cannot turn a full revolution (the link BC cannot reach the ram's "
                  "line at some crank angle theta2)")


def _loop_rows(answer):
    """The answer's scalar equations as sympy expressions in plain real symbols; else the feedback."""
    import sympy as sp
    if isinstance(getattr(answer, "equations", None), sp.MatrixBase):
        answer = list(answer.equations)  # a Mechanism
    if isinstance(answer, str | bytes):
        return wrong("build the loops with sympy (symbols and sp.Matrix), not as text.")
    if isinstance(answer, Mapping | set | frozenset):
        return wrong(f"give the loops as a list [loop1, loop2] of 2×1 sympy matrices; got a "
                     f"{type(answer).__name__}.")
    def difference(item):  # an equation lhs = rhs (of components or of matrices) is read as lhs − rhs
        return item.lhs - item.rhs if isinstance(item, sp.Equality) else item

    items = [difference(item) for item in (answer if isinstance(answer, list | tuple) else [answer])]
    rows = [difference(row) for item in items
            for row in (item if isinstance(item, sp.MatrixBase | list | tuple) else [item])]
    expressions = []
    for k, row in enumerate(rows, start=1):
        if isinstance(row, int | float | sp.Number) and not isinstance(row, bool):
            return wrong(f"equation {k} is a number: it does not change when the shaper moves (it holds none "
                         "of θ2, θ4, r4, θ5, x).")
        if isinstance(row, sp.Basic) and row.has(sp.Derivative):
            return wrong(f"equation {k} holds a derivative: the loop equations are about positions only "
                         "(the core differentiates them for you).")
        if row is sp.true or row is sp.false:
            return wrong(f"equation {k} is {row}, not an equation: sympy decided the Eq before you could "
                         "use it. Write each component as an expression equal to zero.")
        expressions.append(expression := plain(row, NAMES))
        if isinstance(expression, Feedback):
            return wrong(f"equation {k}: " + expression.message.removeprefix("Not yet: "))
    return expressions


def _vanishes(values: np.ndarray, scale: np.ndarray) -> np.ndarray:
    """Per row: zero at every probe, compared with what the row gives off the configuration."""
    finite = np.isfinite(values).all(axis=1)
    return finite & (np.abs(values).max(axis=1) <= 1e-9 * np.maximum(scale, 1e-300)) & (scale > 0)


#: The vectors of the two loops, by the symbols whose sign turns each one round (a sign slip on it).
_VECTORS = {"the crank vector (O2 → A)": ("r2",), "the block's vector along the lever (O4 → A)": ("r4",),
            "the lever vector (O4 → B)": ("l4",), "the link vector (B → C)": ("l5",),
            "the frame vector (O4 → O2)": ("d",), "the ram's vector (O4 → C)": ("x", "h")}


def _loop_hint(row, ks: list[int], turned: str, moves: bool) -> str:
    """What looks wrong with equations ``ks`` (1-based; ``row``: the first of them; ``turned``: the vector a
    sign slip turned, or "")."""
    import sympy as sp
    names = {s.name for s in row.free_symbols}
    theta2, theta4, theta5 = sp.symbols(("theta2", "theta4", "theta5"), real=True)
    y_component = row.has(sp.sin(theta4)) and not row.has(sp.cos(theta4))
    block = not names & {"theta5", "x", "l5", "h"}  # the loop through the block
    return next(hint for holds, hint in [
        (not moves, "{where} does not change when the shaper moves: it holds none of θ2, θ4, r4, θ5, x."),
        (turned, "a sign slip: {where} would hold if {turned} pointed the other way (in every component). "
                 "Walk both routes from the same start to the same end point; each vector's sign is its "
                 "direction."),
        (block and "l4" in names, "{where} uses l4 in the loop through the block: from O4 the lever reaches "
                                  "the block A after r4 (the unknown length), not after its full length l4."),
        (block and "r4" not in names, "{where} has no r4: the block's distance along the lever is an unknown "
                                      "of the loop O4 → O2 → A."),
        (block and "d" not in names and y_component and row.has(sp.sin(theta2)),
         "{where} leaves out the frame: O2 sits a distance d straight above O4, so the walk O4 → O2 → A "
         "starts with (0, d)."),
        (not block and "r4" in names and "l4" not in names,
         "{where} uses r4 for O4 → B: B is the end of the lever, at l4 from O4; r4 is where the block is."),
        (not block and "h" not in names and y_component and row.has(sp.sin(theta5)),
         "{where} has no h: the ram's pin C runs on the line y = h, so O4 → C is (x, h)."),
        (True, "{where} is not satisfied by the drawn shaper. Check each vector's sign (both routes from the "
               "same start to the same end point), its length and its angle."),
    ] if holds).format(where=("equation {}" if len(ks) == 1 else "equations {}").format(
        " and ".join(map(str, ks))) + " (counting the components in your order)", turned=turned)


def _golden(f, low: np.ndarray, high: np.ndarray, iterations: int = 48) -> np.ndarray:
    """Where ``f`` (vectorized) is smallest in each bracket [low, high]: golden-section search."""
    ratio = (np.sqrt(5.0) - 1) / 2
    a, b = low.astype(float), high.astype(float)
    c, d = b - ratio * (b - a), a + ratio * (b - a)
    fc, fd = f(c), f(d)
    for _ in range(iterations):
        left = fc <= fd  # the smallest value lies in [a, d]
        a, b = np.where(left, a, c), np.where(left, d, b)
        new = np.where(left, b - ratio * (b - a), a + ratio * (b - a))
        f_new = f(new)
        c, d, fc, fd = (np.where(left, new, d), np.where(left, c, new), np.where(left, f_new, fd),
                        np.where(left, fc, f_new))
    return np.where(fc <= fd, c, d)


def _where(ks) -> str:
    """"equation 2" or "equations 1 and 3", counted from 1 in the student's order."""
    ks = [str(int(k) + 1) for k in ks]
    return "equation " + ks[0] if len(ks) == 1 else f"equations {', '.join(ks[:-1])} and {ks[-1]}"


@reads(_loop_rows, task={"shaper": ShaperDrawing}, possible=_turns)
def check_shaper_loops(rows, shaper: ShaperDrawing = SHAPER) -> Feedback:
    """Exercise 06, task 1: the two vector loops, four expressions "= 0" (two 2×1 matrices or a ``Mechanism``)
    that fix θ4, r4, θ5, x (sign, scale, order free).  Every equation is checked against the loops, with the
    drawing's lengths: it must vanish on the drawn shaper at every crank angle tried (eight probes, a grid
    of the turn, random ones) and at no position off the drawing tried (random ones), and together they
    must fix the unknowns all round the turn (no factor such as cos θ2 that vanishes at some crank angle).

    >>> import sympy as sp
    >>> th2, th4, r4, th5, x, r2, d, l4, l5, h = sp.symbols("theta2 theta4 r4 theta5 x r2 d l4 l5 h")
    >>> lever = [r2 * sp.cos(th2) - r4 * sp.cos(th4), d + r2 * sp.sin(th2) - r4 * sp.sin(th4)]
    >>> ram = [l4 * sp.cos(th4) + l5 * sp.cos(th5) - x, l4 * sp.sin(th4) + l5 * sp.sin(th5) - h]
    >>> check_shaper_loops([*lever, *ram]).ok, check_shaper_loops([lever[0] * sp.cos(th2), lever[1], *ram]).ok
    (True, False)
    """
    import sympy as sp
    if len(rows) != 4:
        only = " — only one loop?" if len(rows) == 2 else ""
        return wrong("two vector loops give four scalar equations (the x and y components of each); "
                     f"you gave {len(rows)}{only}")
    q = np.array(shaper.configuration(_CLOSED))
    probes = q[:, :_PROBES.size]  # _CLOSED starts with the probes

    def evaluate(theta2, q, turned=()):  # residuals (rows, probes), the drawing's lengths substituted
        values = [theta2, *q, *astuple(shaper)]
        values = [-v if name in turned else v for name, v in zip(NAMES, values, strict=True)]
        return np.array([np.broadcast_to(np.asarray(v, dtype=complex), np.shape(theta2))
                         for v in function(*values)])

    def jacobian(theta2, q):  # J (angle, row, unknown) by central differences, rows in units of their size
        J = np.stack([(evaluate(theta2, q + step) - evaluate(theta2, q - step)).real / 2e-6
                      for step in 1e-6 * np.eye(4)[:, :, None]], axis=2).swapaxes(0, 1)
        return J / scale[None, :, None]

    try:
        function = sp.lambdify(sp.symbols(NAMES, real=True), rows, modules="numpy")
        at_drawing = evaluate(_CLOSED, q)
    except Exception as error:  # an undefined function f(θ), a matrix inside a row, …
        return wrong(f"your equations could not be evaluated with numbers ({type(error).__name__}): use only "
                     "the task's symbols, numbers and sympy functions such as sp.cos and sp.sin.")
    scale = np.abs(evaluate(_PROBES, probes + _NUDGE[:, None])).max(axis=1)
    holds = _vanishes(at_drawing, scale)
    if not holds.all():
        # a sign slip: turning one vector round (in every component it appears in) closes failing rows and
        # opens none; the vector that closes the most is the one that flipped
        fixes = {vector: _vanishes(evaluate(_CLOSED, q, symbols), scale)
                 for vector, symbols in _VECTORS.items()}
        slips = sorted(((int((fixed & ~holds).sum()), vector) for vector, fixed in fixes.items()
                        if (fixed >= holds).all() and (fixed & ~holds).any()), reverse=True)
        if slips:
            ks = np.flatnonzero(fixes[slips[0][1]] & ~holds)
            return wrong(_loop_hint(rows[ks[0]], [k + 1 for k in ks], slips[0][1], True))
        k = int(np.argmin(holds))
        if turned := " or ".join(vector for vector, fixed in fixes.items() if fixed[k]):  # in one component
            return wrong(f"a sign slip in equation {k + 1} alone (counting the components in your order): "
                         f"it would hold if {turned} had the other sign there. A vector keeps its sign in "
                         "both of its components: walk both routes from the same start to the same end "
                         "point.")
        return wrong(_loop_hint(rows[k], [k + 1], "", bool(scale[k] > 0)))
    # scaling a row changes nothing, a squared row (zero gradient) counts as zero
    singular_values = np.linalg.svd(jacobian(_PROBES, probes), compute_uv=False)
    if not (np.isfinite(singular_values).all()
            and (singular_values[:, -1] > 1e-6 * singular_values[:, 0]).all()):
        return wrong("each equation holds for the drawn shaper, but together they do not fix θ4, r4, θ5 "
                     "and x: one repeats (or combines) others, or is squared. Give the x and y components "
                     "of two different loops.")
    off = evaluate(_OPEN_THETA2, np.array(shaper.configuration(_OPEN_THETA2)) + _OPEN_NUDGE)
    if (zero := (np.isfinite(off) & (np.abs(off) <= 1e-9 * scale[:, None])).any(axis=1)).any():
        return wrong(f"{_where(np.flatnonzero(zero))} (counting the components in your order) also "
                     f"vanish{'es' if zero.sum() == 1 else ''} at a position that does not close the loops. "
                     "A component of a loop is zero only where the loop closes: write it as it is, without "
                     "Max, Min, Piecewise or a factor that can be zero.")

    def weakest(theta2):  # σ_min and σ_max of J along the drawn motion (0 where J is not finite), and J
        J = jacobian(theta2, np.array(shaper.configuration(theta2)))
        finite = np.isfinite(J).all(axis=(1, 2))
        values = np.linalg.svd(np.where(finite[:, None, None], J, 0.0), compute_uv=False)
        return np.where(finite, values[:, -1], 0.0), values[:, 0], J

    # all round the turn: the smallest singular value at each local minimum on the grid, refined
    low, high, _ = weakest(_TURN)
    size = np.median(high)
    minima = np.flatnonzero((low <= np.roll(low, 1)) & (low <= np.roll(low, -1)))
    minima = minima[np.argsort(low[minima])][:8]
    step = _TURN[1] - _TURN[0]
    at = _golden(lambda theta2: weakest(theta2)[0], _TURN[minima] - step, _TURN[minima] + step)
    low, _, J = weakest(at)
    if (bad := np.flatnonzero(~(low > 1e-6 * size))).size:
        k = bad[np.argmin(low[bad])]
        angle = float(at[k])
        if (undefined := np.flatnonzero(~np.isfinite(J[k]).all(axis=1))).size:
            return wrong(f"{_where(undefined)} (counting the components in your order) cannot be evaluated "
                         f"near θ2 ≈ {angle:.3f} rad (not a number there: a square root or a logarithm of "
                         "something negative, or a division by zero?). Write each component of each loop as "
                         "it is.")
        dead = np.flatnonzero(~(np.linalg.norm(J[k], axis=1) > 1e-6 * size))
        if dead.size:
            one = dead.size == 1
            return wrong(f"{_where(dead)} (counting the components in your order) hold{'s' if one else ''} "
                         f"for the drawn shaper, but at θ2 ≈ {angle:.3f} rad "
                         f"{'it holds' if one else 'they hold'} for any θ4, r4, θ5 and x nearby: "
                         "a factor that is zero at that crank angle (such as cos θ2, θ2 − 1 or cos θ4) "
                         "multiplies it. Write each component of each loop as it is.")
        return wrong(f"each equation holds for the drawn shaper, but at θ2 ≈ {angle:.3f} rad together they "
                     "no longer fix θ4, r4, θ5 and x (there they combine one another). Give the x and y "
                     "components of the two loops as they are.")
    return right("Correct: four scalar equations that the drawn shaper satisfies at every crank angle "
                 "tried, and that fix θ4, r4, θ5 and x.")


def _by_name(names: tuple[str, ...], what: str):
    """A parser: the numbers ``names`` in order, or keyed by name or symbol (a ``Motion``: its position)."""
    read = fields(f"{what} as {len(names)} numbers ({', '.join(names)}) or a dict keyed by those names",
                  *(number(name) for name in names), keys=names)

    def parse(answer):
        if isinstance(getattr(answer, "position", None), Mapping):
            answer = answer.position
        if isinstance(answer, Mapping):
            answer = {getattr(key, "name", key): value for key, value in answer.items()}
        values = read(answer)
        return values if isinstance(values, Feedback) else np.array(values)

    return parse


#: Which entries of (θ4, r4, θ5, x) are angles (compared modulo 2π).
_ANGLES = (True, False, True, False)


@reads(_by_name(UNKNOWNS, "the position"), task={"theta2": "rad", "shaper": ShaperDrawing},
       possible=_assembles)
def check_shaper_position(answer, theta2: float, shaper: ShaperDrawing = SHAPER) -> Feedback:
    """Exercise 06, task 2: the position (θ4, r4, θ5, x) in rad and m, to 4 decimals, at crank angle
    ``theta2`` (rad), or a dict of it.

    >>> print(check_shaper_position({"theta4": 1.0}, 1.0))
    ✘ Not yet: the dict needs the keys theta4, r4, theta5, x.
    """
    reference = theta4, r4, theta5, x = tuple(map(float, shaper.configuration(theta2)))

    def agrees(values, candidate) -> bool:
        return DECIMALS.agrees(values, candidate, _ANGLES)

    return diagnose(answer, DECIMALS, [
        (reference, "Correct: the shaper as drawn, C to the right of B."),
        (tuple(map(float, shaper.configuration(theta2, assembly=-1))),
         "θ4 and r4 are right, but θ5 and x belong to the other assembly, with C to the left of B. "
         "The drawing has C to the right: seed Newton with θ5 near 0."),
        ((theta4 + np.pi, -r4, None, None),
         "θ4 + π with r4 < 0 closes the loop through the block, but the lever's top B = l4(cos θ4, sin θ4) "
         "then points the other way and the ram's loop opens: keep r4 > 0 (the block between O4 and B)."),
        (lambda v: Precision(2, decimals=True).agrees(np.radians(v) * [1, 0, 1, 0] + v * [0, 1, 0, 1],
                                                      reference, _ANGLES) and not agrees(v, reference),
         "your angles look like degrees; the library works in radians."),
        (lambda v: agrees(v / [1, 1000, 1, 1000], reference),
         "r4 and x look like millimetres; give lengths in metres."),
        (tuple(map(float, shaper.configuration(np.degrees(theta2)))),
         "that is the shaper at θ2 given in degrees but read as radians: convert the crank angle with "
         "np.radians before solving."),
        (lambda v: any(agrees(v[[*order]], reference) for order in permutations(range(4))),
         "the right numbers in the wrong order: give (θ4, r4, θ5, x), or pass motion.position."),
        ((theta4, r4, None, None), "θ4 and r4 are right; θ5 and x are not: check the loop O4 → B → C and its "
                                   "seed."),
    ], "θ4 and r4 are not right: check the loop O4 → O2 → A (signs, d, r4) and that θ2 is in radians.",
        angles=_ANGLES)


@reads(_by_name(("v_x", "a_x"), "the ram's velocity and acceleration"),
       task={"theta2": "rad", "omega2": "rad/s", "alpha2": "rad/s²", "shaper": ShaperDrawing},
       possible=_moves)
def check_ram_motion(answer, theta2: float, omega2: float, alpha2: float = 0.0,
                     shaper: ShaperDrawing = SHAPER) -> Feedback:
    """Exercise 06, task 3: the ram's (ẋ, ẍ) in m/s, m/s², to 4 significant figures (or a dict ``v_x``,
    ``a_x``) at the crank's state.

    >>> velocity, acceleration = SHAPER.rates(1.0, 8.0)
    >>> print(check_ram_motion((velocity[1], acceleration[1]), 1.0, 8.0))
    ✘ Not yet: those are the block's rates along the lever (v_r4, a_r4); the task asks for the ram, x.
    """
    velocity, acceleration = shaper.rates(theta2, omega2, alpha2)
    ram = (velocity[3], acceleration[3])
    return diagnose(answer, FIGURES, [
        (ram, "Correct: the ram's velocity and acceleration, both from the same Jacobian J."),
        ((velocity[1], acceleration[1]), "those are the block's rates along the lever (v_r4, a_r4); the task "
                                         "asks for the ram, x."),
        ((velocity[0], acceleration[0]), "those are the lever's rates (ω4, α4); the task asks for the ram's, "
                                         "v_x and a_x."),
        (lambda v: FIGURES.agrees(np.asarray(v) / 1000, ram), "those look like mm/s and mm/s²; give m/s and "
                                                              "m/s²."),
        (np.array(shaper.rates(theta2, -omega2, -alpha2))[:, 3],
         "the ram moves the other way: the crank turns counter-clockwise, so ω2 is positive."),
        (np.array(shaper.rates(np.degrees(theta2), omega2, alpha2))[:, 3],
         "that is the ram at θ2 given in degrees but read as radians: convert with np.radians."),
        ((velocity[3], None), "the velocity is right; the acceleration is not. Even at constant ω2 the ram "
                              "accelerates: solve with rates and accelerations given "
                              "(accelerations={θ2: α2})."),
    ], "the ram's velocity is not right: give rates={θ2: ω2} to solve and read the x entry; check θ2 "
       "(radians) and the assembly (C right of B).")


#: Stroke and time ratio: to 3 significant figures (they are read off a sweep).
_THREE = Precision(3)


@reads(number("the time ratio"), task={"reference": "positive", "correct": str})
def _time_ratio(ratio: float, reference: float, correct: str) -> Feedback:
    """A time ratio against ``reference``, to 3 significant figures: ✔ ``correct``, or the usual slips."""
    slow = 2 * np.pi * reference / (1 + reference)  # the slow stroke's crank angle
    return diagnose(ratio, _THREE, [
        (reference, correct),
        (1 / reference, "that is the fast stroke over the slow one; the time ratio is slow over fast (> 1)."),
        ([slow, 2 * np.pi - slow, np.degrees(slow), 360 - np.degrees(slow)], "that is a crank angle; the "
         "time ratio divides the crank angle of the slow stroke by that of the fast one."),
        (lambda v: abs(v / reference - 1) < 0.05,
         "close, but not to 3 significant figures: find the crank angles where ω4 changes sign more "
         "precisely (interpolate between samples, or use the condition that O4A ⟂ O2A there)."),
    ], "not the time ratio: the lever stops where ω4 = 0 (O4A ⟂ O2A); divide the crank angle turned between "
       "the two stops one way by the angle turned back.")


def check_quick_return_time_ratio(answer, crank: float, pivot_distance: float) -> Feedback:
    """Lesson 12, Try it: the time ratio (slow / fast stroke, to 3 significant figures) of a slotted-lever
    quick return;
    a crank or pivot distance that cannot make one raises ``InvalidArgumentError`` (an
    ``InvalidGeometryError``), whatever the answer.

    >>> check_quick_return_time_ratio(2.0, 0.05, 0.10).ok, check_quick_return_time_ratio(0.5, 0.05, 0.10).ok
    (True, False)
    """
    crank, pivot_distance = (task_argument(name, value, "positive m") for name, value in
                             (("crank", crank), ("pivot_distance", pivot_distance)))
    if not crank < pivot_distance:
        raise InvalidArgumentError("a quick return needs crank < pivot_distance (else the lever turns "
                                   f"fully); got crank={crank!r}, pivot_distance={pivot_distance!r}: no "
                                   "reference answer exists for this task")
    return _time_ratio(answer, quick_return_time_ratio(crank, pivot_distance), "Correct: the crank turns "
                       "π + 2β for the slow stroke and π − 2β for the fast one, sin β = r2/d.")


@reads(vector(2, "(stroke, time_ratio)"), task={"shaper": ShaperDrawing}, possible=_turns)
def check_ram_stroke(answer, shaper: ShaperDrawing = SHAPER) -> Feedback:
    """Exercise 06, task 4: (stroke in m, time ratio), each to 3 significant figures.

    >>> check_ram_stroke((SHAPER.stroke(), SHAPER.time_ratio())).ok
    True
    """
    stroke, ratio = answer
    reference = shaper.stroke()
    return diagnose(stroke, _THREE, [
        (reference, _time_ratio(ratio, shaper.time_ratio(), "Correct: the ram stops when the lever does, so "
                                "its stroke and its time ratio are the lever's.")),
        (1000 * reference, "the stroke looks like millimetres; give metres."),
        (reference / 2, "that is half the stroke (the amplitude); the stroke is the full travel, "
                        "max x − min x."),
        (lambda value: value <= 0, "the stroke is a distance: positive, max x − min x."),
    ], "the stroke is not right: sweep a full revolution on the drawn assembly and take max x − min x.")
