"""The four-bar linkage: l1 = ground O2O4, l2 = crank O2A (input θ2), l3 = coupler AB (θ3), l4 = rocker
O4B (θ4), O2 = (0, 0), O4 = (l1, 0).  The loop R2 + R3 − R4 − R1 = 0 is solved by the tangent half-angle
substitution (Norton, *Design of Machinery*, §4.5); the machine is one declaration
(:attr:`FourBar.mechanism`: the loop, the points O2, A, B, O4 and the links ground, crank, coupler,
rocker), which gives the rates, the singularity rule (the core's ``SINGULAR``), the joints and a
:class:`~course_lib.mechanism.Motion` (:meth:`FourBar.motion`) to draw, animate or explore.  Branches:
``"open"`` (B left of the line A → O4, Norton's minus sign) and ``"crossed"``.  SI units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cache, cached_property
from types import MappingProxyType

import numpy as np

from .errors import (
    failure_policy,
    older_failure_keywords,
    require_broadcast,
    require_choice,
    require_finite,
    require_positive,
)
from .motion import Deferred, Motion, recast
from .motion import machine_joints as _machine_joints
from .planar import Unpacks, scalar_or_array, wrap_angle
from .thresholds import COINCIDENT, LEVEL

__all__ = ["ASSEMBLIES", "BRANCHES", "FourBar", "FourBarSolution", "GrashofResult", "InputRange",
           "CouplerPointMotion"]

#: The two assembly circuits, named as in Norton's *Design of Machinery*.
BRANCHES = ("open", "crossed")
#: The assemblies by name, as the core's σ (``assembly=``): open has B left of the line A → O4 (σ = +1).
ASSEMBLIES = {"open": {"theta4": +1}, "crossed": {"theta4": -1}}
#: A toggle angle within √COINCIDENT (rad) of π or 0 is a full turn's change point, not a limit: there the
#: lengths that decide it (1 ∓ cos θ2 ≈ θ²/2) differ by rounding.
TOGGLE_TOL = COINCIDENT ** 0.5


def _finite(name: str, value, unit: str):
    """A finite Python float as it is (checked at no cost), else :func:`require_finite`."""
    if type(value) is float and math.isfinite(value):
        return value
    return require_finite(name, value, unit)


@cache
def _unit_lengths(*lengths: float) -> tuple[float, ...]:
    """The lengths divided by the longest: the same angles and rates, no overflow or underflow."""
    longest = max(lengths)
    return tuple(length / longest for length in lengths)


def _kernel(parameters, known, sigma):
    """The block θ3, θ4 in closed form (the kernel registered on the declaration, see
    :meth:`~course_lib.mechanism.Mechanism.with_kernel`): Norton's half-angle quadratic A t² + B t + C = 0
    in t = tan(θ4/2) times 2·l2·l4, with the lengths divided by the longest (no overflow); σ = +1 (open)
    is Norton's minus sign.  θ3, θ4 in (−π, π], NaN where the loop cannot close or where A lies on O4
    with coupler = rocker (B anywhere on a circle: the level 0 there, the position not determined); the
    level B² − 4AC over B² + (A − C)²."""
    l1, l2, l3, l4 = _unit_lengths(*(parameters[name] for name in ("l1", "l2", "l3", "l4")))
    theta2 = known["theta2"]
    if np.ndim(theta2) == 0:  # one instant: a sweep of one
        values, level = _kernel(parameters, {**known, "theta2": np.reshape(theta2, 1)}, sigma)
        return {key: value[0] for key, value in values.items()}, level[0]
    k3 = l2**2 - l3**2 + l4**2 + l1**2
    cos2, sin2 = np.cos(theta2), np.sin(theta2)
    # each line the same operations in the same order as the formulas in the comments (the same bits),
    # written in place: a long sweep's temporaries are the time, not the arithmetic
    A = np.multiply(2 * l2 * l4, cos2)  # A = 2·l2·l4·cos θ2 − 2·l1·l4 − 2·l1·l2·cos θ2 + k3
    A -= 2 * l1 * l4
    work = np.multiply(2 * l1 * l2, cos2)
    A -= work
    A += k3
    B = np.multiply(-4 * l2 * l4, sin2)  # B = −4·l2·l4·sin θ2
    C = np.multiply(2 * (l1 * l2 + l2 * l4), cos2)  # C = 2·l1·l4 − 2·(l1·l2 + l2·l4)·cos θ2 + k3
    np.subtract(2 * l1 * l4, C, out=C)
    C += k3
    squared = B * B
    np.multiply(4 * A, C, out=work)
    discriminant = np.subtract(squared, work)  # B² − 4AC
    scale = np.subtract(A, C)  # (A − C)² + B² = 16 l4² |AO4|²
    scale *= scale
    scale += squared
    np.multiply(-LEVEL, scale, out=work)
    lost = discriminant < work  # below −LEVEL·scale the loop cannot close; above, rounding
    anywhere = None
    if abs(l3 - l4) < COINCIDENT:  # A on O4 with coupler = rocker: B anywhere on a circle
        anywhere = np.hypot(l1 - l2, 2 * np.sqrt(l1 * l2) * np.sin(theta2 / 2)) < COINCIDENT
        lost |= anywhere
    root = np.maximum(discriminant, 0.0)
    np.copyto(root, np.nan, where=lost)
    np.sqrt(root, out=root)
    # t = y/x with (y, x) = (−B ± √Δ, 2A) or, the same root, (2C, −B ∓ √Δ): take the larger pair
    root *= -sigma  # Norton's minus sign for the open assembly (σ = ±1, or one per instant)
    np.negative(B, out=B)  # −B from here on
    y1, x1, y2, x2 = np.add(B, root), np.multiply(2, A), np.multiply(2, C), np.subtract(B, root, out=root)
    first = np.empty(np.shape(A), bool)  # |y1| + |x1| ≥ |y2| + |x2|
    np.abs(y1, out=work)
    np.add(work, np.abs(x1, out=B), out=work)
    np.abs(y2, out=B)
    np.add(B, np.abs(x2, out=squared), out=B)
    np.greater_equal(work, B, out=first)
    y, x = np.where(first, y1, y2), np.where(first, x1, x2)
    del y1, x1, y2, x2
    norm = np.multiply(x, x)  # θ4 = 2·atan2(y, x), by the double-angle formulas: cos θ4 = (x² − y²)/norm,
    np.multiply(y, y, out=work)  # sin θ4 = 2xy/norm with norm = x² + y²
    cos4 = np.subtract(norm, work)
    norm += work
    cos4 /= norm
    sin4 = np.multiply(2, x, out=x)
    sin4 *= y
    sin4 /= norm
    coupler_x = np.multiply(l4, cos4, out=y)  # R3 = B − A, of length l3: (l4·cos θ4 + l1 − l2·cos θ2,
    coupler_x += l1  # l4·sin θ4 − l2·sin θ2)
    coupler_x -= np.multiply(l2, cos2, out=work)
    coupler_y = np.multiply(l4, sin4, out=norm)
    coupler_y -= np.multiply(l2, sin2, out=work)
    # the level B² − 4AC over B² + (A − C)²; scale 0: A = C, B = 0, the constant equation A = 0 (every θ4,
    # or none)
    if (scale > 0).all():
        level = np.divide(discriminant, scale, out=discriminant)
    else:
        level = np.where(scale > 0, discriminant / np.where(scale > 0, scale, 1.0),
                         np.where(A == 0, 0.0, -1.0))
    if anywhere is not None:
        level = np.where(anywhere, 0.0, level)
    theta3, theta4 = np.arctan2(coupler_y, coupler_x), np.arctan2(sin4, cos4)
    coupler_x /= l3
    coupler_y /= l3
    return {"theta3": theta3, "theta4": theta4, ("theta3", "cos"): coupler_x, ("theta3", "sin"): coupler_y,
            ("theta4", "cos"): cos4, ("theta4", "sin"): sin4, ("theta2", "cos"): cos2, ("theta2", "sin"): sin2
            }, level


def _declaration(coupler: bool = False):
    """The loop R2 + R3 − R4 − R1 = 0 on the core: unknowns θ3, θ4, input θ2, parameters l1 … l4; with
    ``coupler``, also the coupler point P = A + p·(cos(θ3 + δ), sin(θ3 + δ)) and the plate A, B, P."""
    import sympy as sp

    from .mechanism import Mechanism

    theta2, theta3, theta4 = sp.symbols("theta2 theta3 theta4")
    l1, l2, l3, l4 = sp.symbols("l1:5")
    A, B = sp.Matrix([l2 * sp.cos(theta2), l2 * sp.sin(theta2)]), sp.Matrix([l1 + l4 * sp.cos(theta4),
                                                                               l4 * sp.sin(theta4)])
    loop = A + sp.Matrix([l3 * sp.cos(theta3), l3 * sp.sin(theta3)]) - B
    points = {"O2": sp.Matrix([0, 0]), "A": A, "B": B, "O4": sp.Matrix([l1, 0])}
    links = {"crank": ("O2", "A"), "coupler": ("A", "B"), "rocker": ("B", "O4"), "ground": ("O4", "O2")}
    parameters, plates = {l1: 0.20, l2: 0.06, l3: 0.18, l4: 0.12}, {}
    if coupler:
        p, delta = sp.symbols("p delta")
        points["P"] = A + p * sp.Matrix([sp.cos(theta3 + delta), sp.sin(theta3 + delta)])
        parameters |= {p: 0.09, delta: 0.0}
        plates = {"coupler": ("A", "B", "P")}
    return Mechanism([loop], [theta3, theta4], [theta2], parameters, points=points, links=links,
                     ground=("O2", "O4"), plates=plates)


@dataclass(frozen=True)
class FourBarSolution(Unpacks, Motion):
    """A :class:`~course_lib.mechanism.Motion` of :attr:`FourBar.mechanism` (position θ3, θ4; velocity;
    acceleration; input θ2) that also names its values as the course does: θ3, θ4 (rad; the first
    instant's in [−π, π], each next within a turn of its neighbour), ω3, ω4 (rad/s), α3, α4 (rad/s²) of
    coupler and rocker.  ``unreachable`` True where the loop cannot close (``converged`` False there),
    ``singular`` where J is singular by the core's rule or the position is not determined (NaN rates while
    moving, with ``on_failure="nan"``), ``near_singular`` by the core's rule.  Unpacks as the six values;
    ``np.array`` gives (6, ...).

    >>> solution = FourBar(0.06, 0.18, 0.12, 0.20).solve([0.0, 1.0], omega2=10.0)
    >>> np.array(solution).shape, bool(np.all(solution.omega4 == solution.velocity["theta4"]))
    ((6, 2), True)
    """

    unreachable: bool | np.ndarray = False
    branch: str = "open"
    _values = ("theta3", "theta4", "omega3", "omega4", "alpha3", "alpha4")
    _names = MappingProxyType({"omega3": ("velocity", "theta3"), "omega4": ("velocity", "theta4"),
                               "alpha3": ("acceleration", "theta3"), "alpha4": ("acceleration", "theta4")})

    @property
    def reachable(self) -> bool | np.ndarray:
        """True where the loop closes (``~unreachable``).

        >>> FourBar(0.15, 0.10, 0.12, 0.20).solve([0.0, 2.0], on_failure="nan").reachable.tolist()
        [True, False]
        """
        return scalar_or_array(~np.asarray(self.unreachable))

    @property
    def mask(self) -> bool | np.ndarray:
        """The older name of ``unreachable`` (the same array)."""
        return self.unreachable


@dataclass(frozen=True)
class GrashofResult:
    """Grashof class (``name``, Norton's), s + l and p + q (m), the ``shortest`` and ``longest`` link
    ("ground", "crank", "coupler", "rocker"; the first on a tie) and ``is_grashof`` (s + l ≤ p + q).

    >>> result = FourBar(0.06, 0.18, 0.12, 0.20).grashof()
    >>> result.name, result.shortest, round(result.s_plus_l, 12), round(result.p_plus_q, 12)
    ('Grashof crank-rocker', 'crank', 0.26, 0.3)
    """

    name: str
    s_plus_l: float
    p_plus_q: float
    shortest: str
    longest: str
    is_grashof: bool


@dataclass(frozen=True)
class InputRange:
    """The crank angles θ2 at which the loop closes: ``full_rotation``, closed ``intervals`` (rad, ((0, 2π),)
    for a full turn, () if it never assembles) and the ``toggle_angles`` at their ends.

    >>> r = FourBar(crank=0.12, coupler=0.06, rocker=0.18, ground=0.20).input_range()
    >>> r.full_rotation, len(r.intervals)
    (False, 2)
    """

    full_rotation: bool
    intervals: tuple[tuple[float, float], ...]
    toggle_angles: tuple[float, ...]


@dataclass(frozen=True)
class CouplerPointMotion(Unpacks):
    """Position, velocity and acceleration of a coupler point, each (..., 2), in m, m/s, m/s².

    >>> motion = FourBar(0.06, 0.18, 0.12, 0.20).coupler_point(0.0, p=0.09, delta=0.0)
    >>> motion.position.shape, motion.velocity.tolist()
    ((2,), [0.0, 0.0])
    """

    position: np.ndarray
    velocity: np.ndarray
    acceleration: np.ndarray
    _values = ("position", "velocity", "acceleration")


@dataclass(frozen=True)
class FourBar:
    """A four-bar linkage: crank l2, coupler l3, rocker l4, ground l1 (m, each > 0 and finite).

    >>> linkage = FourBar(crank=0.06, coupler=0.18, rocker=0.12, ground=0.20)
    >>> linkage.l1, linkage.l2, linkage.l3, linkage.l4
    (0.2, 0.06, 0.18, 0.12)
    """

    crank: float
    coupler: float
    rocker: float
    ground: float

    def __post_init__(self) -> None:
        for name in ("crank", "coupler", "rocker", "ground"):
            object.__setattr__(self, name, require_positive(name, getattr(self, name)))

    l1 = property(lambda self: self.ground, doc="Ground length l1 (m) = |O2O4|.")
    l2 = property(lambda self: self.crank, doc="Crank length l2 (m) = |O2A|.")
    l3 = property(lambda self: self.coupler, doc="Coupler length l3 (m) = |AB|.")
    l4 = property(lambda self: self.rocker, doc="Rocker length l4 (m) = |O4B|.")

    @cached_property
    def mechanism(self):
        """The machine as one declaration on :class:`~course_lib.mechanism.Mechanism` with these lengths:
        the loop (unknowns θ3, θ4, input θ2), the points O2, A, B, O4 and the links crank, coupler,
        rocker, ground.

        >>> loop = FourBar(0.06, 0.18, 0.12, 0.20).mechanism
        >>> round(loop.solve({"theta2": 0.7}, guess={"theta3": 0.4, "theta4": 1.6}).position["theta4"], 6)
        1.516178
        >>> list(loop.points), loop.links.names
        (['O2', 'A', 'B', 'O4'], ('crank', 'coupler', 'rocker', 'ground'))
        """
        return _declaration().with_parameters({"l1": self.l1, "l2": self.l2, "l3": self.l3,
                                               "l4": self.l4}).with_kernel("theta4", _kernel)

    def loop_residual(self, theta2, theta3, theta4) -> np.ndarray:
        """R2 + R3 − R4 − R1 as (x, y) components, shape (..., 2); zero when the loop closes.

        >>> np.round(FourBar(0.06, 0.18, 0.12, 0.20).loop_residual(0.0, 0.0, np.pi / 2), 12).tolist()
        [0.04, -0.12]
        """
        q = np.stack(require_broadcast(**{name: require_finite(name, value, "rad") for name, value in
                                          (("theta3", theta3), ("theta4", theta4), ("theta2", theta2))}), -1)
        return self.mechanism.residual(q[..., :2], q[..., 2:])

    def loop_jacobian(self, theta3, theta4) -> np.ndarray:
        """J = ∂(loop)/∂(θ3, θ4) = [[−l3 sin θ3, l4 sin θ4], [l3 cos θ3, −l4 cos θ4]], shape (..., 2, 2);
        det J = l3·l4·sin(θ3 − θ4) is zero at a toggle.

        >>> np.round(FourBar(1.0, 2.0, 3.0, 4.0).loop_jacobian(np.pi / 2, 0.0), 12).tolist()
        [[-2.0, 0.0], [0.0, -3.0]]
        """
        q = np.stack(require_broadcast(theta3=require_finite("theta3", theta3, "rad"),
                                       theta4=require_finite("theta4", theta4, "rad")), -1)
        return self.mechanism.jacobian(q, np.zeros(q.shape[:-1] + (1,)))

    @older_failure_keywords
    def solve(self, theta2, omega2=0.0, alpha2=0.0, branch: str = "open", *, assembly=None,
              on_failure: str | None = None) -> FourBarSolution:
        """θ3, θ4, ω3, ω4, α3, α4 for crank angle θ2 (rad), speed ω2 (rad/s), acceleration α2 (rad/s²),
        broadcast: the core's solve of :attr:`mechanism` (whose block θ3, θ4 is solved by the course's
        closed form, :func:`_kernel`), the same :class:`~course_lib.mechanism.Motion` as
        ``self.mechanism.solve`` with the course's names added.  ``UnreachableError`` where the loop cannot
        close, ``SingularJacobianError`` at a toggle while moving (the core's rule: σ_min(J̃) < SINGULAR);
        ``on_failure="nan"``: NaN there.  At rest (ω2 = α2 = 0) the rates are 0.  The assembly:
        ``assembly="open"`` or ``"crossed"``, or the core's σ by either unknown (``{"theta4": +1}`` is
        open: B left of A → O4); ``branch=`` is its older name.  Angles follow the core's rule: the first
        instant's in [−π, π], each next within a turn of its neighbour.

        >>> crossed = FourBar(0.06, 0.18, 0.12, 0.20).solve(np.pi / 2, assembly="crossed")
        >>> round(crossed.theta3, 6), round(crossed.theta4, 6), crossed.assembly["theta4"]
        (-0.901761, -2.398416, -1)
        """
        require_choice("branch", branch, BRANCHES)
        branch = self.mechanism.assembly_named(assembly, ASSEMBLIES, branch, "open")
        policy = failure_policy(on_failure)
        theta2 = _finite("theta2", theta2, "rad")
        omega2 = _finite("omega2", omega2, "rad/s")
        alpha2 = _finite("alpha2", alpha2, "rad/s^2")
        require_broadcast(theta2=theta2, omega2=omega2, alpha2=alpha2)
        moving = bool(np.any(omega2) or np.any(alpha2))
        motion = self.mechanism.solve({"theta2": theta2}, {"theta2": omega2} if moving else None,
                                      {"theta2": alpha2} if moving else None, assembly=ASSEMBLIES[branch],
                                      on_failure=policy)
        # unreachable: not found, and not because the position is not determined (counted singular)
        unreachable = Deferred(lambda: scalar_or_array(~np.asarray(motion.converged)
                                                       & ~np.asarray(motion.singular)))
        return recast(motion, FourBarSolution, at_rest=not moving, unreachable=unreachable, branch=branch)

    def motion(self, theta2, omega2=0.0, alpha2=0.0, branch: str = "open", *, assembly=None,
               on_failure: str | None = None):
        """:meth:`solve` under the name the declarations use: its :class:`FourBarSolution` is a
        :class:`~course_lib.mechanism.Motion` of :attr:`mechanism`, to draw, animate or explore like any
        declaration's.

        >>> motion = FourBar(0.06, 0.18, 0.12, 0.20).motion([0.0, 0.7], omega2=10.0)
        >>> np.round(motion.position["theta4"], 6).tolist(), motion.converged.tolist()
        ([1.618433, 1.516178], [True, True])
        """
        return self.solve(theta2, omega2, alpha2, branch=branch, assembly=assembly, on_failure=on_failure)

    @older_failure_keywords
    def joints(self, motion, branch: str = "open", *, on_failure: str | None = None):
        """The points O2, A, B, O4 (m) of a solved ``motion``, by name (``self.mechanism.joints(motion)``).
        The older spelling ``joints(theta2, branch)`` solves at θ2 and stacks them, shape (..., 4, 2).

        >>> bar = FourBar(1.0, 1.0, 1.0, 1.0)
        >>> {name: point.round(12).tolist() for name, point in bar.joints(bar.solve(np.pi / 2)).items()}
        {'O2': [0.0, 0.0], 'A': [0.0, 1.0], 'B': [1.0, 1.0], 'O4': [1.0, 0.0]}
        """
        return _machine_joints(self, motion, lambda: self.mechanism.joints(
            self.solve(motion, branch=branch, on_failure=failure_policy(on_failure))))

    @older_failure_keywords
    def transmission_angle(self, theta2, branch: str = "open", acute: bool = True,
                           *, assembly=None, on_failure: str | None = None):
        """Transmission angle μ (rad): the joint angle at B, |θ4 − θ3| folded into [0, π], with ``acute``
        (Norton's design value) into [0, π/2]; good force transmission wants μ ≥ 40° or so
        (``thresholds.TRANSMISSION_MIN_DEG``).  ``assembly=`` as in :meth:`solve`.

        >>> round(float(np.degrees(FourBar(0.06, 0.18, 0.12, 0.20).transmission_angle(np.pi / 2))), 4)
        85.752
        """
        policy = failure_policy(on_failure)
        solution = self.solve(theta2, branch=branch, assembly=assembly, on_failure=policy)
        turn = np.asarray(solution.theta4) - np.asarray(solution.theta3)
        joint_angle = np.abs(wrap_angle(turn, nan_ok=True))
        mu = np.minimum(joint_angle, np.pi - joint_angle) if acute else joint_angle
        return scalar_or_array(mu)

    def with_coupler_point(self, p: float, delta: float):
        """:attr:`mechanism` with the coupler point P = A + p·(cos(θ3 + δ), sin(θ3 + δ)) (p in m, δ in rad)
        and the coupler plate A, B, P: the same loop, so a solution draws with P on it
        (``draw(wiper.with_coupler_point(p, delta), wiper.solve(theta2))``).

        >>> plate = FourBar(1.0, 1.0, 1.0, 1.0).with_coupler_point(p=0.5, delta=0.0)
        >>> plate.plates["coupler"], plate.joints(FourBar(1.0, 1.0, 1.0, 1.0).solve(np.pi / 2))["P"].tolist()
        (('A', 'B', 'P'), [0.5, 1.0])
        """
        p = require_positive("p", p, allow_zero=True)
        delta = float(require_finite("delta", delta, "rad"))
        return _declaration(coupler=True).with_parameters(
            {"l1": self.l1, "l2": self.l2, "l3": self.l3, "l4": self.l4, "p": p, "delta": delta})

    @older_failure_keywords
    def coupler_point(self, theta2, p: float, delta: float, omega2=0.0, alpha2=0.0, branch: str = "open",
                      *, assembly=None, on_failure: str | None = None) -> CouplerPointMotion:
        """Motion of the coupler point P of :meth:`with_coupler_point`: its declaration differentiated by the
        core (:meth:`~course_lib.mechanism.Mechanism.point_motion`), which is the course's V_P = ω2 k̂×R2
        + ω3 k̂×r and A_P = α2 k̂×R2 − ω2² R2 + α3 k̂×r − ω3² r with r = P − A.  ``assembly=`` as in
        :meth:`solve`.

        >>> motion = FourBar(1.0, 1.0, 1.0, 1.0).coupler_point(np.pi / 2, p=0.5, delta=0.0, omega2=1.0)
        >>> motion.position.round(12).tolist(), motion.velocity.round(12).tolist()
        ([0.5, 1.0], [-1.0, 0.0])
        """
        plate = self.with_coupler_point(p, delta)
        policy = failure_policy(on_failure)
        solution = self.solve(theta2, omega2, alpha2, branch=branch, assembly=assembly, on_failure=policy)
        position, velocity, acceleration = plate.point_motion(
            solution, rates={"theta2": omega2}, accelerations={"theta2": alpha2})["P"]
        return CouplerPointMotion(position=position, velocity=velocity, acceleration=acceleration)

    def grashof(self) -> GrashofResult:
        """Grashof class: s + l < p + q is Grashof (shortest link ground: double-crank, coupler:
        double-rocker, else crank-rocker), s + l = p + q change-point, else non-Grashof triple-rocker.

        >>> FourBar(crank=0.12, coupler=0.18, rocker=0.20, ground=0.06).grashof().name
        'Grashof double-crank'
        """
        lengths = {"ground": self.l1, "crank": self.l2, "coupler": self.l3, "rocker": self.l4}
        ordered = sorted(lengths, key=lengths.get)  # stable: ties keep the order above
        shortest, longest = ordered[0], ordered[-1]
        s_plus_l = lengths[shortest] + lengths[longest]
        p_plus_q = lengths[ordered[1]] + lengths[ordered[2]]
        if np.isclose(s_plus_l, p_plus_q, rtol=LEVEL, atol=0.0):
            name = "change-point"
        elif s_plus_l > p_plus_q:
            name = "non-Grashof triple-rocker"
        else:
            name = {"ground": "Grashof double-crank", "coupler": "Grashof double-rocker"}.get(
                shortest, "Grashof crank-rocker")
        return GrashofResult(name, s_plus_l, p_plus_q, shortest, longest, name != "non-Grashof triple-rocker")

    def input_range(self) -> InputRange:
        """The crank angles θ2 (rad) at which the loop closes: |AO4| between |l3 − l4| and l3 + l4, each
        bound that binds a toggle angle (coupler and rocker folded or extended).

        >>> r = FourBar(crank=0.15, coupler=0.10, rocker=0.12, ground=0.20).input_range()
        >>> r.full_rotation, [round(a, 6) for a in r.toggle_angles]
        (False, [-1.333578, 1.333578])
        """
        l1, l2, l3, l4 = _unit_lengths(self.l1, self.l2, self.l3, self.l4)

        def toggle(reach):  # θ2 in [0, π] where |AO4| = reach, or None when |AO4| never equals it
            # 1 ∓ cos θ2 as products of differences, accurate even where θ2 is near 0 or π
            below, above = (reach - l1 + l2) * (reach + l1 - l2), (l1 + l2 - reach) * (l1 + l2 + reach)
            if below < 0 or above < 0:
                return None
            return float(2 * np.arctan2(np.sqrt(below), np.sqrt(above)))

        extended, folded = toggle(l3 + l4), toggle(abs(l3 - l4))  # need θ2 ≤ extended, θ2 ≥ folded
        if l3 + l4 < abs(l1 - l2) or abs(l3 - l4) > l1 + l2 or (None not in (extended, folded)
                                                                  and extended < folded):
            return InputRange(full_rotation=False, intervals=(), toggle_angles=())
        theta_max = np.pi if extended is None else extended  # binds when < π
        theta_min = 0.0 if folded is None else folded  # binds when > 0
        # a toggle within rounding of π or 0 (a change point) does not stop a full turn
        upper, lower = theta_max < np.pi - TOGGLE_TOL, theta_min > TOGGLE_TOL
        if not upper and not lower:
            return InputRange(full_rotation=True, intervals=((0.0, 2 * np.pi),), toggle_angles=())
        if upper and lower:
            intervals = ((-theta_max, -theta_min), (theta_min, theta_max))
        else:
            intervals = ((-theta_max, theta_max),) if upper else ((theta_min, 2 * np.pi - theta_min),)
        return InputRange(False, intervals, sum(intervals, ()))
