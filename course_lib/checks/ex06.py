"""Checkers of exercise set 06 (the shaper's quick return) and of lesson 12's Try it.

The drawing (:class:`ShaperDrawing`): the crank O2A (r2) turns about O2, d straight above the lever's pivot
O4 = (0, 0); the block at A slides along the lever O4B (l4) at the unknown r4 from O4; the link BC (l5)
drives the ram, whose pin C runs on y = h at x.  Unknowns θ4, r4, θ5, x; input θ2; m, rad.
"""
# ruff: noqa: F403, F405

import math
from collections.abc import Mapping
from dataclasses import astuple, dataclass
from functools import cache, cached_property
from itertools import permutations

import numpy as np

from ..errors import InvalidArgumentError, InvalidGeometryError, require_finite, require_positive
from ..planar import wrap_angle
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


#: The shaper's assemblies by name, as the core's σ (``assembly=``, see :class:`ShaperDrawing`): the block on
#: the lever's ray (r4 > 0, σ = +1 on the lever loop) and C right of B (σ = −1 on the ram loop) as drawn.
_ASSEMBLIES = {"as drawn": {"r4": +1, "x": -1}, "C left of B": {"r4": +1, "x": +1}}


@cache
def _declaration():
    """The shaper on the core: the lever loop O4 → O2 → A = O4 → A and the ram loop O4 → B → C = (x, h);
    unknowns θ4, r4, θ5, x; input θ2; the points O4, O2, A, B, C and the links crank, lever, link."""
    import sympy as sp

    from ..mechanism import Mechanism

    theta2, theta4, r4, theta5, x = sp.symbols(" ".join(NAMES[:5]), real=True)
    r2, d, l4, l5, h = sp.symbols(" ".join(NAMES[5:]), positive=True)

    def R(length, angle):  # the course's link vector
        return sp.Matrix([length * sp.cos(angle), length * sp.sin(angle)])

    O2 = sp.Matrix([0, d])
    A, B, C = O2 + R(r2, theta2), R(l4, theta4), sp.Matrix([x, h])
    lengths = {r2: 0.06, d: 0.15, l4: 0.30, l5: 0.15, h: 0.30}  # the drawing's; each shaper gives its own
    return Mechanism([A - R(r4, theta4), B + R(l5, theta5) - C], [theta4, r4, theta5, x], [theta2], lengths,
                     points={"O4": sp.zeros(2, 1), "O2": O2, "A": A, "B": B, "C": C},
                     links={"crank": ("O2", "A"), "lever": ("O4", "B"), "link": ("B", "C")},
                     ground=("O4", "O2"), sliders=("A", "C"))


@dataclass(frozen=True)
class ShaperDrawing:
    """The shaper of exercise 06 as drawn: ``crank`` r2, ``pivot_distance`` d, ``lever`` l4, ``link`` l5,
    ``ram_height`` h, in m; lesson 12's quick-return with the ram, declared on the core
    (:attr:`mechanism`) and solved by it (:meth:`solve`, a :class:`~course_lib.motion.Motion`).

    >>> motion = ShaperDrawing().solve(np.pi / 2)
    >>> [round(float(motion.position[name]), 6) for name in ("theta4", "r4", "theta5", "x")]
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
        require_finite("ram_height", self.ram_height, unit="metres")
        if not abs(self.ram_height - self.lever) < self.link:
            raise InvalidGeometryError(f"the link cannot reach the ram line from the lever's top; got "
                                       f"lever={self.lever}, link={self.link}, ram_height={self.ram_height}")

    @cached_property
    def mechanism(self):
        """The shaper as one declaration on :class:`~course_lib.mechanism.Mechanism` with these lengths: the
        lever loop (0, d) + r2(cos θ2, sin θ2) − r4(cos θ4, sin θ4) = 0 and the ram loop l4(cos θ4, sin θ4) +
        l5(cos θ5, sin θ5) − (x, h) = 0 (unknowns θ4, r4, θ5, x; input θ2), the points O4, O2, A, B, C and
        the links crank, lever, link.

        >>> mechanism = ShaperDrawing().mechanism
        >>> list(mechanism.points), mechanism.links.names
        (['O4', 'O2', 'A', 'B', 'C'], ('crank', 'lever', 'link'))
        """
        return _declaration().with_parameters(dict(zip(NAMES[5:], astuple(self), strict=True)))

    def solve(self, theta2, omega2=0.0, alpha2=0.0, *, assembly="as drawn", on_failure: str = "raise"):
        """Position, velocity and acceleration of θ4, r4, θ5, x at the crank's θ2 (rad), ω2 (rad/s), α2
        (rad/s²), vectorized: the core's solve of :attr:`mechanism`, a :class:`~course_lib.motion.Motion`.

        The assembly, as the core's σ = −sign(det J_b) of each loop: on the lever loop det J_b = −r4, so
        σ = +1 puts the block on the ray O4 → B (r4 > 0); on the ram loop det J_b = l5 cos θ5, so σ = −1
        puts C right of B (cos θ5 > 0) and σ = +1 left of it.  ``assembly="as drawn"`` (r4 > 0, C right of
        B) or ``"C left of B"``, or σ by any unknown of a loop (the lever loop's is +1 unless given).

        >>> motion = ShaperDrawing().solve(np.pi / 2, omega2=1.0)
        >>> round(float(motion.velocity["x"]), 6), motion.assembly["x"]
        (-0.085714, -1)
        """
        theta2, omega2, alpha2 = (require_finite(name, value, unit=unit) for name, value, unit in (
            ("theta2", theta2, "rad"), ("omega2", omega2, "rad/s"), ("alpha2", alpha2, "rad/s²")))
        mechanism = self.mechanism
        sigma = {"r4": +1, **mechanism.assembly_sigma(assembly, _ASSEMBLIES)}
        return mechanism.solve({"theta2": theta2}, {"theta2": omega2}, {"theta2": alpha2}, assembly=sigma,
                               on_failure=on_failure)

    def limit_angles(self) -> tuple[float, float]:
        """Crank angles where the lever stops (O4A ⟂ O2A, sin θ2 = −r2/d)."""
        beta = math.asin(self.crank / self.pivot_distance)
        return -beta, math.pi + beta

    def time_ratio(self) -> float:
        """Crank angle of the slow stroke over that of the fast one (:func:`quick_return_time_ratio`)."""
        return quick_return_time_ratio(self.crank, self.pivot_distance)

    def stroke(self) -> float:
        """The ram's travel between the two lever stops, m: x at the two :meth:`limit_angles` (the core's)."""
        first, second = self.solve(np.array(self.limit_angles())).position["x"]
        return float(abs(first - second))


#: The shaper drawn in exercise 06.
SHAPER = ShaperDrawing()


def _position(shaper: ShaperDrawing, theta2, assembly="as drawn") -> np.ndarray:
    """(θ4, r4, θ5, x) of ``shaper`` at crank angle(s) ``theta2`` on ``assembly``, shape (4, ...)."""
    position = shaper.solve(theta2, assembly=assembly).position
    return np.array([position[name] for name in UNKNOWNS], dtype=float)


def _rates(shaper: ShaperDrawing, theta2, omega2, alpha2=0.0) -> tuple[np.ndarray, np.ndarray]:
    """Velocities and accelerations of (θ4, r4, θ5, x), each shape (4, ...), as drawn."""
    motion = shaper.solve(theta2, omega2, alpha2)
    return tuple(np.array([part[name] for name in UNKNOWNS], dtype=float)
                 for part in (motion.velocity, motion.acceleration))


def _assembles(shaper: ShaperDrawing, theta2: float, *rates: float) -> None:
    """The shaper assembles at ``theta2`` (C on the ram's line, either side of B), with the ``rates``
    (ω2, α2) there when they are given."""
    task_possible(lambda: [_position(shaper, theta2, side) for side in _ASSEMBLIES]
                  + (list(_rates(shaper, theta2, *rates)) if rates else []),
                  f"the shaper {shaper!r} cannot be assembled at theta2={theta2:.6g} (the link BC cannot "
                  "reach the ram's line there)")


def _moves(shaper: ShaperDrawing, theta2: float, omega2: float, alpha2: float) -> None:
    """The shaper assembles at ``theta2``, with its rates at ``omega2``, ``alpha2``."""
    _assembles(shaper, theta2, omega2, alpha2)


def _turns(shaper: ShaperDrawing) -> None:
    """The shaper assembles at every crank angle of a turn."""
    task_possible(lambda: [_position(shaper, angles) for angles in (_TURN, _PROBES,
                                                                   np.array(shaper.limit_angles()))],
                  f"the shaper {shaper!r} cannot turn a full revolution (the link BC cannot reach the ram's "
                  "line at some crank angle theta2)")


def _is_motion(answer) -> bool:
    """Whether ``answer`` is a solve's :class:`~course_lib.motion.Motion` (or reads like one)."""
    return all(isinstance(getattr(answer, part, None), Mapping) for part in ("position", "inputs"))


def _is_declaration(answer) -> bool:
    """Whether ``answer`` is a :class:`~course_lib.mechanism.Mechanism` (a declaration)."""
    module = getattr(type(answer), "__module__", None)
    return (isinstance(module, str) and module.startswith("course_lib.mechanism")
            and hasattr(answer, "unknowns"))


def _crank_angle(motion) -> float | None:
    """The crank angle θ2 a one-instant ``motion`` was solved at; None when it has none (or several)."""
    values = np.asarray(motion.inputs.get("theta2", np.nan), dtype=float)
    return float(values) if values.ndim == 0 and np.isfinite(values) else None


def _loop_rows(answer):
    """The answer's scalar equations as sympy expressions in plain real symbols; else the feedback."""
    import sympy as sp
    if _is_motion(answer):
        return wrong("that is a Motion, what a solve returns: this task asks for the loops themselves, "
                     "loops = [lever_loop, ram_loop], two 2×1 sympy matrices.")
    if isinstance(getattr(answer, "equations", None), sp.MatrixBase):
        return wrong("that is a Mechanism, a declaration: this task asks for the loops themselves, loops = "
                     "[lever_loop, ram_loop], two 2×1 sympy matrices; Task 2 declares the Mechanism from "
                     "them.")
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
    return expressions, answer


def _applied(answer) -> bool:
    """Whether ``answer`` (loops: matrices, lists, equations of them) holds a function such as θ2(t)."""
    import sympy as sp
    from sympy.core.function import AppliedUndef

    if isinstance(answer, sp.Equality):
        return _applied(answer.lhs) or _applied(answer.rhs)
    if isinstance(answer, sp.MatrixBase | list | tuple):
        return any(map(_applied, answer))
    return isinstance(answer, sp.Basic) and bool(answer.atoms(AppliedUndef))


def _undeclared(rows, answer, shaper: ShaperDrawing) -> str | None:
    """Why Task 2's ``Mechanism(loops, unknowns=[θ4, r4, θ5, x], inputs=[θ2], parameters={r2: …, h: …})``
    would refuse loops that are right (``rows``: as read; ``answer``: as given), or None when it takes them
    (the check declares them so, the core's own reading)."""
    import sympy as sp

    from ..mechanism import Mechanism

    found = {s.name for row in rows for s in row.free_symbols}
    if missing := [name for name in NAMES[5:] if name not in found]:
        return (f"your loops hold no {', '.join(missing)}: numbers stand where the drawing's lengths go. "
                "Write the lengths as the symbols r2, d, l4, l5, h of the cell above; Task 2 gives their "
                "values as parameters.")
    theta2, *unknowns = sp.symbols(" ".join(NAMES[:5]), real=True)
    lengths = dict(zip(sp.symbols(" ".join(NAMES[5:]), positive=True), astuple(shaper), strict=True))
    try:
        Mechanism(answer, unknowns, [theta2], lengths)
    except Exception as error:
        if _applied(answer):
            return ("your loops are written in functions of time such as θ2(t): write them in the symbols of "
                    "the cell above (th2, th4, r4, th5, x). Task 2 declares them with Mechanism(loops, …), "
                    "which takes symbols and differentiates them in time itself.")
        if isinstance(answer, list | tuple) and any(isinstance(item, list | tuple) for item in answer):
            return ("give each loop as a sympy 2×1 matrix, sp.Matrix([x component, y component]), not as a "
                    "list inside the list: Task 2's Mechanism(loops, …) reads each entry of loops as one "
                    "loop (a matrix) or one equation, and refuses a list there.")
        return (f"each equation is right, but Task 2 declares your loops with Mechanism(loops, …) and the "
                f"core refuses them as given: {error}"[:600])
    return None


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
def check_shaper_loops(read, shaper: ShaperDrawing = SHAPER) -> Feedback:
    """Exercise 06, task 1: the two vector loops, four expressions "= 0" (two 2×1 matrices, or the four rows
    in a list; Eq accepted) that fix θ4, r4, θ5, x (sign, scale, order free).  Every equation is checked
    against the loops, with the drawing's lengths: it must vanish on the drawn shaper at every crank angle
    tried (eight probes, a grid of the turn, random ones) and at no position off the drawing tried (random
    ones), and together they must fix the unknowns all round the turn (no factor such as cos θ2 that
    vanishes at some crank angle).  Right loops are then declared as Task 2 declares them
    (``Mechanism(loops, …)`` with the lengths as symbols): a form the core refuses (a list inside the list,
    functions of time, numbers for the lengths, a ``Mechanism`` already) is named, not ✔.

    >>> import sympy as sp
    >>> th2, th4, r4, th5, x, r2, d, l4, l5, h = sp.symbols("theta2 theta4 r4 theta5 x r2 d l4 l5 h")
    >>> lever = [r2 * sp.cos(th2) - r4 * sp.cos(th4), d + r2 * sp.sin(th2) - r4 * sp.sin(th4)]
    >>> ram = [l4 * sp.cos(th4) + l5 * sp.cos(th5) - x, l4 * sp.sin(th4) + l5 * sp.sin(th5) - h]
    >>> check_shaper_loops([*lever, *ram]).ok, check_shaper_loops([lever[0] * sp.cos(th2), lever[1], *ram]).ok
    (True, False)
    """
    import sympy as sp
    rows, answer = read
    if len(rows) != 4:
        only = " — only one loop?" if len(rows) == 2 else ""
        return wrong("two vector loops give four scalar equations (the x and y components of each); "
                     f"you gave {len(rows)}{only}")
    q = _position(shaper, _CLOSED)
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
        # the angles read in degrees (a factor π/180 on each angle): the rows vanish at the angles in degrees
        in_degrees = np.degrees(q) * np.array([[1], [np.pi / 180], [1], [np.pi / 180]])
        if _vanishes(evaluate(np.degrees(_CLOSED), in_degrees), scale).all():
            return wrong("your loops read the angles in degrees (a factor π/180 on θ): θ2, θ4 and θ5 are in "
                         "radians here, as sp.sin and sp.cos take them; drop the conversion.")
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
    off = evaluate(_OPEN_THETA2, _position(shaper, _OPEN_THETA2) + _OPEN_NUDGE)
    if (zero := (np.isfinite(off) & (np.abs(off) <= 1e-9 * scale[:, None])).any(axis=1)).any():
        return wrong(f"{_where(np.flatnonzero(zero))} (counting the components in your order) also "
                     f"vanish{'es' if zero.sum() == 1 else ''} at a position that does not close the loops. "
                     "A component of a loop is zero only where the loop closes: write it as it is, without "
                     "Max, Min, Piecewise or a factor that can be zero.")

    def weakest(theta2):  # σ_min and σ_max of J along the drawn motion (0 where J is not finite), and J
        J = jacobian(theta2, _position(shaper, theta2))
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
    if problem := _undeclared(rows, answer, shaper):
        return wrong(problem)
    return right("Correct: four scalar equations that the drawn shaper satisfies at every crank angle "
                 "tried, and that fix θ4, r4, θ5 and x.")


def _by_name(names: tuple[str, ...], what: str):
    """A parser: the numbers ``names`` in order, or keyed by name or symbol (a ``Motion``: its position)."""
    read = fields(f"{what} as {len(names)} numbers ({', '.join(names)}) or a dict keyed by those names",
                  *(number(name) for name in names), keys=names)

    def parse(answer):
        if _is_motion(answer):
            answer = answer.position
        if isinstance(answer, Mapping):
            answer = {getattr(key, "name", key): value for key, value in answer.items()}
        values = read(answer)
        return values if isinstance(values, Feedback) else np.array(values)

    return parse


def _names(symbols) -> list[str]:
    return [getattr(symbol, "name", str(symbol)) for symbol in symbols]


_read_position = _by_name(UNKNOWNS, "the position")


def _read_declared(answer):
    """Task 2's answer (shaper, guess, position) as (declaration, guess, the position's four numbers, the
    crank angle of a Motion given as the position or None); else the feedback."""
    if not (isinstance(answer, tuple | list) and len(answer) == 3) or _is_motion(answer):
        return wrong("this task grades your declaration: give (shaper, guess, position), your Mechanism, the "
                     "guess you solved it from and the position — the check cell of Task 2 passes them so.")
    declaration, guess, position = answer
    if declaration is None:
        return wrong("declare the shaper as a Mechanism and store it as shaper: this task grades your "
                     "declaration, solved here from your guess at θ2 and at other crank angles, not only the "
                     "four numbers.")
    if not _is_declaration(declaration):
        return wrong("shaper should be your declaration, Mechanism(loops, unknowns=…, inputs=…, "
                     f"parameters=…); got a {type(declaration).__name__}.")
    unknowns, inputs = _names(declaration.unknowns), _names(declaration.inputs)
    if sorted(unknowns) != sorted(UNKNOWNS):
        return wrong(f"your shaper's unknowns are {', '.join(unknowns)}: declare θ4, r4, θ5, x (the symbols "
                     "th4, r4, th5, x of Task 1's cell), the names Tasks 3 and 4 read its motion by.")
    if inputs != ["theta2"]:
        return wrong(f"your shaper's inputs are {', '.join(inputs)}: the crank angle θ2 (th2) is the one "
                     "input.")
    if guess is None:
        return wrong("store the guess you solved from as guess, a dict {th4: …, r4: …, th5: …, x: …} read "
                     "off the drawing: the check (and Tasks 3 and 4) solve your shaper from it.")
    if not isinstance(guess, Mapping):
        return wrong(f"guess should be a dict {{th4: …, r4: …, th5: …, x: …}}; got a {type(guess).__name__}.")
    values = _read_position(position)
    if isinstance(values, Feedback):
        return values
    return declaration, guess, values, _crank_angle(position) if _is_motion(position) else None


#: Which entries of (θ4, r4, θ5, x) are angles (compared modulo 2π).
_ANGLES = (True, False, True, False)
#: Crank angles where Task 2's declaration is solved afresh from the student's guess: a turn from θ2 = 0,
#: as Task 4 sweeps it, and angles off that grid.
_FRESH = np.radians(np.concatenate([np.arange(0.0, 360.0, 15.0), [7.0, 101.0, 203.0, 311.0]]))


def _same(values: np.ndarray, reference: np.ndarray) -> np.ndarray:
    """Per instant (the last axis): (θ4, r4, θ5, x) found by a solve equal to ``reference`` (to 1e-7 rad and
    1e-9 m, well above a converged solve's error), angles modulo 2π."""
    gaps = np.abs(values - reference)
    gaps[[0, 2]] = np.abs(np.angle(np.exp(1j * (values[[0, 2]] - reference[[0, 2]]))))
    return np.all(gaps <= np.array([1e-7, 1e-9, 1e-7, 1e-9]).reshape((4,) + (1,) * (gaps.ndim - 1)), axis=0)


def _declared(declaration, guess, theta2: float, shaper: ShaperDrawing) -> Feedback | None:
    """What is wrong with a student's declaration of the shaper, solved from their guess at ``theta2`` and at
    fresh crank angles, against ``shaper`` as drawn; None when it is the drawn shaper at all of them."""
    given = {getattr(symbol, "name", str(symbol)): value for symbol, value in declaration.parameters.items()}
    drawing = dict(zip(NAMES[5:], astuple(shaper), strict=True))
    if set(drawing) <= set(given):  # the drawing's names: its numbers, in metres
        if all(abs(given[name] - 1000 * value) <= 1e-9 * 1000 * value for name, value in drawing.items()):
            return wrong("your parameters look like millimetres (1000 times the drawing's): give the lengths "
                         "in metres, as the drawing's table does.")
        if off := [name for name, value in drawing.items() if not abs(given[name] - value) <= 1e-9 * value]:
            return wrong(f"your parameter{'s' if len(off) > 1 else ''} {', '.join(off)} "
                         f"{'are' if len(off) > 1 else 'is'} not the drawing's: give r2, d, l4, l5, h as its "
                         "table does, in metres.")

    def solved(angles):
        position = declaration.solve({"theta2": angles}, guess=guess).position
        return np.array([position[name] for name in UNKNOWNS], dtype=float)

    try:
        mine = solved(theta2)
    except Exception as error:  # the core's named error on the student's declaration or guess
        return wrong(f"your shaper could not be solved from your guess at θ2 = {theta2:.4f} rad "
                     f"({type(error).__name__}: {error})"[:600])
    if _same(mine, _position(shaper, theta2, "C left of B")):
        return wrong("your shaper, solved from your guess, is the other assembly: C left of B. The drawing "
                     "has C to the right of B: seed θ5 near 0 in guess.")
    if not _same(mine, _position(shaper, theta2)):
        return wrong(f"your shaper, solved from your guess at θ2 = {theta2:.4f} rad, is not the drawn "
                     "shaper: check its parameters (the drawing's r2, d, l4, l5, h in metres) and that its "
                     "loops are Task 1's.")
    try:
        mine = solved(_FRESH)
    except Exception as error:
        return wrong(f"your shaper is right at θ2 = {theta2:.4f} rad, but could not be solved from your "
                     f"guess over a turn ({type(error).__name__}: {error})"[:600])
    agree = _same(mine, _position(shaper, _FRESH))
    if not agree.all():
        angle = float(_FRESH[np.argmin(agree)])
        left = _same(mine, _position(shaper, _FRESH, "C left of B"))[np.argmin(agree)]
        return wrong(f"your shaper is right at θ2 = {theta2:.4f} rad, but solved from your guess over a turn "
                     f"(as Task 4 sweeps it) it is not the drawn shaper at θ2 = {angle:.4f} rad"
                     + (": C is left of B there. Seed θ5 near 0 in guess, so C stays right of B."
                        if left else ": check its parameters and loops."))
    return None


def _one_sign_flipped(reference, names: tuple[str, ...]) -> list[tuple[tuple, str]]:
    """Rules: the answer is ``reference`` with exactly one entry of the other sign, named."""
    return [(tuple(-value if j == k else value for j, value in enumerate(reference)),
             f"{names[k]} has the wrong sign; the other entries are right.")
            for k in range(len(reference)) if reference[k] != 0]


@reads(_read_declared, task={"theta2": "rad", "shaper": ShaperDrawing}, possible=_assembles)
def check_shaper_position(answer, theta2: float, shaper: ShaperDrawing = SHAPER) -> Feedback:
    """Exercise 06, task 2: the declaration, its guess and the position it gives, ``(shaper, guess,
    position)``.  The declaration (a ``Mechanism`` with unknowns θ4, r4, θ5, x and input θ2, any order) is
    solved here from the guess at ``theta2`` (rad) and at fresh crank angles over a turn, and must be the
    drawn shaper at all of them (C right of B); the position — ``motion.position``, the ``Motion``, a dict
    or the four numbers (θ4, r4, θ5, x) in rad and m to 4 decimals — must be it at ``theta2``.  Right numbers
    without a declaration that gives them are not ✔.

    >>> print(check_shaper_position((None, None, (1.1, 0.2, 0.1, 0.2)), 1.0))
    ✘ Not yet: declare the shaper as a Mechanism and store it as shaper: this task grades your declaration, \
solved here from your guess at θ2 and at other crank angles, not only the four numbers.
    """
    declaration, guess, values, solved_at = answer
    if (problem := _declared(declaration, guess, theta2, shaper)) is not None:
        return problem
    if solved_at is not None and not abs(np.angle(np.exp(1j * (solved_at - theta2)))) < 1e-9:
        return wrong(f"your Motion was solved at θ2 = {solved_at:.4f} rad; the task asks for the position at "
                     f"θ2 = {theta2:.4f} rad.")
    reference = theta4, r4, theta5, x = tuple(map(float, _position(shaper, theta2)))

    def agrees(values, candidate) -> bool:
        return DECIMALS.agrees(values, candidate, _ANGLES)

    return diagnose(values, DECIMALS, [
        (reference, "Correct: your declaration gives the shaper as drawn, C to the right of B."),
        (tuple(map(float, _position(shaper, theta2, "C left of B"))),
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
        (tuple(map(float, _position(shaper, np.degrees(theta2)))),
         "that is the shaper at θ2 given in degrees but read as radians: convert the crank angle with "
         "np.radians before solving."),
        (lambda v: any(agrees(v[[*order]], reference) for order in permutations(range(4))),
         "the right numbers in the wrong order: give (θ4, r4, θ5, x), or pass motion.position."),
        *_one_sign_flipped(reference, ("θ4", "r4", "θ5", "x")),
        ((theta4, r4, None, None), "θ4 and r4 are right; θ5 and x are not: check the loop O4 → B → C and its "
                                   "seed."),
    ], "θ4 and r4 are not right: check the loop O4 → O2 → A (signs, d, r4) and that θ2 is in radians.",
        angles=_ANGLES)


def _read_ram(answer):
    """Task 3's answer: (v_x, a_x), a dict of them, or the Motion solved with rates; as (the two numbers, the
    crank angle of a Motion or None); else the feedback."""
    if _is_declaration(answer):
        return wrong("that is your declaration: solve it with rates and accelerations and give "
                     "ram = (v_x, a_x), or the Motion the solve returns.")
    at = None
    if _is_motion(answer):
        if answer.velocity is None or answer.acceleration is None:
            return wrong("your Motion holds no rates: solve with rates={th2: omega2} and accelerations="
                         "{th2: 0.0} (solved without them it holds the position only).")
        if "x" not in answer.velocity:
            return wrong(f"your Motion has no unknown x (it has {', '.join(answer.velocity)}): solve your "
                         "shaper of Task 2, whose unknown x is the ram.")
        at = _crank_angle(answer)
        answer = (answer.velocity["x"], answer.acceleration["x"])
    values = _by_name(("v_x", "a_x"), "the ram's velocity and acceleration")(answer)
    return values if isinstance(values, Feedback) else (values, at)


@reads(_read_ram, task={"theta2": "rad", "omega2": "rad/s", "alpha2": "rad/s²", "shaper": ShaperDrawing},
       possible=_moves)
def check_ram_motion(answer, theta2: float, omega2: float, alpha2: float = 0.0,
                     shaper: ShaperDrawing = SHAPER) -> Feedback:
    """Exercise 06, task 3: the ram's (ẋ, ẍ) in m/s, m/s², to 4 significant figures (or a dict ``v_x``,
    ``a_x``, or the ``Motion`` solved with rates and accelerations) at the crank's state.

    >>> motion = SHAPER.solve(1.0, 8.0)
    >>> print(check_ram_motion((motion.velocity["r4"], motion.acceleration["r4"]), 1.0, 8.0))
    ✘ Not yet: those are the block's rates along the lever (v_r4, a_r4); the task asks for the ram, x.
    """
    values, solved_at = answer
    if solved_at is not None and not abs(np.angle(np.exp(1j * (solved_at - theta2)))) < 1e-9:
        return wrong(f"your Motion was solved at θ2 = {solved_at:.4f} rad; the task asks for the ram at "
                     f"θ2 = {theta2:.4f} rad.")
    velocity, acceleration = _rates(shaper, theta2, omega2, alpha2)
    ram = (velocity[3], acceleration[3])

    def ram_of(*state):
        return tuple(part[3] for part in _rates(shaper, *state))

    return diagnose(values, FIGURES, [
        (ram, "Correct: the ram's velocity and acceleration, both from the same Jacobian J."),
        ((velocity[1], acceleration[1]), "those are the block's rates along the lever (v_r4, a_r4); the task "
                                         "asks for the ram, x."),
        ((velocity[0], acceleration[0]), "those are the lever's rates (ω4, α4); the task asks for the ram's, "
                                         "v_x and a_x."),
        (lambda v: FIGURES.agrees(np.asarray(v) / 1000, ram), "those look like mm/s and mm/s²; give m/s and "
                                                              "m/s²."),
        (lambda v: any(FIGURES.agrees(np.asarray(v)[::-1], ram, digits=digits) for digits in (4, 3, 2)),
         "the right numbers in the wrong order: ram = (v_x, a_x), the velocity first."),
        (ram_of(theta2, -omega2, -alpha2),
         "the ram moves the other way: the crank turns counter-clockwise, so ω2 is positive."),
        (ram_of(np.degrees(theta2), omega2, alpha2),
         "that is the ram at θ2 given in degrees but read as radians: convert with np.radians."),
        ((velocity[3], -acceleration[3]),
         "the velocity is right, but the acceleration has the wrong sign: a_x is the x entry of the solve's "
         "acceleration as it is (ẍ, positive along +x)."),
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
        (lambda v: v <= 0, "a time ratio divides two crank angles the crank turns, both positive: it is "
                           "positive (and > 1, slow over fast)."),
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
    if _is_motion(answer):
        return wrong("that is a Motion, what a solve returns: give the time ratio, one number you compute "
                     "from the crank angles where its ω4 changes sign.")
    return _time_ratio(answer, quick_return_time_ratio(crank, pivot_distance), "Correct: the crank turns "
                       "π + 2β for the slow stroke and π − 2β for the fast one, sin β = r2/d.")


#: The way the ram moves on a stroke, as a student may write it.
_DIRECTIONS = {"left": "left", "-x": "left", "−x": "left", "right": "right", "+x": "right", "x": "right"}


def _direction(text) -> str | None:
    """"left" or "right" from what a student wrote ("Left", "to the left", "-x"); None otherwise."""
    if not isinstance(text, str):
        return None
    words = " ".join(text.strip().lower().replace("_", " ").split())
    for prefix in ("to the ", "towards the ", "the ", "to "):
        words = words.removeprefix(prefix)
    return _DIRECTIONS.get(words.replace(" ", ""))


def _read_stroke(answer):
    """Task 4's answer ((stroke, time ratio), stops, cutting) — or ((stroke, time ratio), cutting), the stops
    left out — as (the two numbers, the two stops or None, "left" or "right"); else the feedback."""
    asked = ("((stroke, time_ratio), stops, cutting): the numbers, the two crank angles where the ram stops "
             "and the way it moves on the cutting stroke — the check cell of Task 4 passes "
             "(stroke_and_ratio, stops, cutting)")
    if _is_motion(answer) or _is_declaration(answer):
        return wrong("give the numbers read off your sweep, ((stroke, time_ratio), stops, cutting), not the "
                     f"{'Motion' if _is_motion(answer) else 'declaration'} itself.")
    if not (isinstance(answer, tuple | list) and len(answer) in (2, 3)) or all(
            isinstance(entry, int | float | np.number) and not isinstance(entry, bool | np.bool_)
            for entry in answer):
        return wrong(f"give {asked}.")
    numbers, *stops, cutting = answer
    if _is_motion(numbers):
        return wrong("stroke_and_ratio should be the numbers read off your sweep, (stroke, time_ratio), not "
                     "the Motion: the stroke is max x − min x, the time ratio slow over fast.")
    numbers = vector(2, "stroke_and_ratio = (stroke, time_ratio)")(numbers)
    if isinstance(numbers, Feedback):
        return numbers
    if len(answer) == 3:
        if stops[0] is None:
            return wrong("stops is still None: give the two crank angles (rad) where the ram stops, "
                         "stops = (θ2 at one stop, θ2 at the other).")
        if _is_motion(stops[0]):
            return wrong("stops should be two crank angles (rad), read off your sweep where ω4 changes sign, "
                         "not the Motion.")
        stops = vector(2, "stops = (θ2 at one stop, θ2 at the other)")(stops[0])
        if isinstance(stops, Feedback):
            return stops
    if cutting is None:
        return wrong('cutting is still None: answer the last question too, "left" or "right" (the way the '
                     'ram moves on the cutting stroke).')
    direction = _direction(cutting)
    if direction is None:
        return wrong(f'cutting should be "left" or "right" (a string): the way the ram moves on the cutting '
                     f"stroke; got {cutting!r}"[:200] + ".")
    return numbers, (stops if len(answer) == 3 else None), direction


#: The crank angles of the stops: to 3 decimals (rad; interpolated between samples of a sweep).
_STOPS = Precision(3, decimals=True)


def _stops_verdict(stops: np.ndarray, shaper: ShaperDrawing) -> Feedback:
    """The two crank angles (rad, either order, modulo 2π) where the lever, and so the ram, stops."""
    reference = np.array(shaper.limit_angles())
    beta = -reference[0]

    def either(value, candidate):  # the pair in either order
        return any(_STOPS.agrees(value[order], candidate, angles=True) for order in ([0, 1], [1, 0]))

    return diagnose(stops, either, [
        (reference, "the stops are right."),
        (lambda v: either(np.radians(v), reference) and not either(v, reference),
         "the stops are in degrees; give them in radians (np.radians converts)."),
        (np.array([beta, np.pi - beta]), "those are the crank angles where sin θ2 = +r2/d; the lever stops "
                                         "where O4A ⟂ O2A, below O2: sin θ2 = −r2/d."),
        (lambda v: all(min(abs(wrap_angle(value - reference))) < 0.05 for value in v)
         and len({round(float(wrap_angle(value)), 6) for value in v}) == 2,
         "close, but not to 3 decimals: interpolate between the two samples where ω4 changes sign (lesson "
         "12, section 4), or use the condition O4A ⟂ O2A there; the nearest sample is not enough."),
        (lambda v: sum(min(abs(wrap_angle(value - reference))) < 5e-4 for value in v) == 1,
         "one stop is right, the other is not: the lever stops twice a turn, once at each end of its swing "
         "(ω4 changes sign twice)."),
    ], "those are not the crank angles where the ram stops: it stops when the lever does, where ω4 changes "
       "sign (O4A ⟂ O2A); give both, in radians.")


def _cutting(shaper: ShaperDrawing) -> str:
    """The way the ram moves on the slow (cutting) stroke, the crank turning counter-clockwise: the sign of
    its velocity halfway between the lever's stops the long way round (θ2 = π/2)."""
    return "left" if shaper.solve(np.mean(shaper.limit_angles()), 1.0).velocity["x"] < 0 else "right"


@reads(_read_stroke, task={"shaper": ShaperDrawing}, possible=_turns)
def check_ram_stroke(answer, shaper: ShaperDrawing = SHAPER) -> Feedback:
    """Exercise 06, task 4: ((stroke in m, time ratio), stops, cutting): the stroke and the time ratio each
    to 3 significant figures and the two crank angles where the ram stops (rad, to 3 decimals, either order)
    (compute), and the way the ram moves on the cutting stroke, "left" or "right" (interpret);
    ((stroke, time ratio), cutting) leaves the stops out.

    >>> check_ram_stroke(((SHAPER.stroke(), SHAPER.time_ratio()), SHAPER.limit_angles(), "left")).ok
    True
    >>> check_ram_stroke(((SHAPER.stroke(), SHAPER.time_ratio()), (3.5, 5.9), "left")).ok
    False
    """
    (stroke, ratio), stops, cutting = answer
    reference = shaper.stroke()
    swapped = (ratio, stroke), (reference, shaper.time_ratio())
    if any(_THREE.agrees(*swapped, digits=digits) for digits in (3, 2)):
        return wrong("the right numbers in the wrong order: stroke_and_ratio = (stroke, time_ratio), the "
                     "stroke first.")
    verdict = diagnose(stroke, _THREE, [
        (reference, _time_ratio(ratio, shaper.time_ratio(), "the stroke and the time ratio are right.")),
        (1000 * reference, "the stroke looks like millimetres; give metres."),
        (reference / 2, "that is half the stroke (the amplitude); the stroke is the full travel, "
                        "max x − min x."),
        (lambda value: value <= 0, "the stroke is a distance: positive, max x − min x."),
    ], "the stroke is not right: sweep a full revolution on the drawn assembly and take max x − min x.")
    if not verdict.ok:
        return verdict
    if stops is not None and not (stopped := _stops_verdict(stops, shaper)).ok:
        return wrong("the stroke and the time ratio are right; " + stopped.message.removeprefix("Not yet: "))
    if cutting != _cutting(shaper):
        return wrong("the stroke and the time ratio are right; cutting is not. The shaper cuts on its slow "
                     "stroke, while the crank turns the long way round between the two stops: which way does "
                     "the ram move then? (The sign of v_x at a crank angle on that stroke tells.)")
    where = " (at your two stops)" if stops is not None else ""
    return right(f"Correct: the ram stops when the lever does{where}, so its stroke and its time ratio are "
                 f"the lever's; it cuts moving {cutting}, on the slow stroke.")
