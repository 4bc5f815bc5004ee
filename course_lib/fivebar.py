"""The five-bar parallel robot of the course: forward and inverse kinematics, velocities,
singularities and workspace.  The constraints are the course's EcL2, EcL3: |P3 − P2|² − l2² = 0 and
|P3 − P4|² − l3² = 0 (see :class:`FiveBar`); SI units, angles from +x counter-clockwise.  The machine is
one declaration (:attr:`FiveBar.mechanism`: EcL2, EcL3 with the motors' θ1, θ4 as inputs, the points
P1 … P5 and the links l1 … l5); the inverse kinematics' rates come from the same loops with inputs and
unknowns swapped, and both singularities are the core's rule (σ_min(J̃) < ``SINGULAR``).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache, cached_property, partial
from typing import Any

import numpy as np

from .errors import (
    InvalidArgumentError,
    InvalidGeometryError,
    SingularJacobianError,
    failure_policy,
    older_failure_keywords,
    report_unreachable,
    require_broadcast,
    require_choice,
    require_finite,
    require_positive,
)
from .motion import Motion, recast
from .motion import machine_joints as _machine_joints
from .newton import linear_solver
from .planar import Unpacks, scalar_or_array
from .thresholds import COINCIDENT, LEVEL, RESIDUAL

__all__ = ["FORWARD_ASSEMBLIES", "FiveBar", "ForwardResult", "InverseResult", "SingularityMeasures",
           "WorkspaceMap", "WORKING_MODES"]

#: The four working modes (σ1, σ2) of the inverse kinematics, in the course's order.
WORKING_MODES = ((1, 1), (-1, 1), (1, -1), (-1, -1))
#: The lengths (m) the five-bar accepts: fourth powers of them stay far from under- and overflow.
LENGTH_RANGE = (1e-60, 1e60)


@dataclass(frozen=True)
class ForwardResult(Unpacks, Motion):
    """A :class:`~course_lib.mechanism.Motion` of :attr:`FiveBar.mechanism` (position X3, Y3; inputs θ1,
    θ4) that also names its values: the end effector P3 = (x3, y3) (m), NaN where the robot cannot be
    assembled (``reachable`` False, the older name of ``converged``); ``singular`` and ``near_singular``
    by the core's rule (a parallel singularity: l2 and l3 aligned); ``mode`` the assembly σ.  Unpacks as
    (x3, y3).

    >>> x3, y3 = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08).forward(np.pi / 2, np.pi / 2)
    >>> round(x3, 6), round(y3, 6)
    (0.0, 0.244568)
    """

    mode: int = 1
    _values = ("x3", "y3")

    reachable = property(lambda self: self.converged, doc="True where assembled (``converged``).")


@dataclass(frozen=True)
class InverseResult(Unpacks, Motion):
    """A :class:`~course_lib.mechanism.Motion` of the five-bar's loops solved the other way round
    (position θ1, θ4; inputs X3, Y3) that also names its values: the crank angles (θ1, θ4) (rad) in
    (−π, π], NaN where out of reach (``reachable`` False, the older name of ``converged``);
    ``singular`` and ``near_singular`` by the core's rule (a serial singularity: a leg stretched or
    folded); ``modes`` the working mode (σ1, σ2).  Draws like a forward one: ``draw(robot, result)``.
    Unpacks as (θ1, θ4).

    >>> result = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08).inverse(0.0, np.sqrt(0.25**2 - 0.04**2) - 1e-9)
    >>> bool(result.reachable), bool(result.singular), bool(result.near_singular)
    (True, False, True)
    """

    modes: tuple[int, int] = (1, 1)
    _values = ("theta1", "theta4")

    reachable = property(lambda self: self.converged, doc="True where in reach (``converged``).")


@dataclass(frozen=True)
class SingularityMeasures(Unpacks):
    """Sines, zero at a singularity: ``serial_leg1`` cross(P2 − P1, P3 − P2)/(l1·l2), ``serial_leg4`` the
    same for l4, l3, ``parallel`` cross(P3 − P2, P3 − P4)/(l2·l3) (the distal links aligned)."""

    serial_leg1: Any
    serial_leg4: Any
    parallel: Any
    _values = ("serial_leg1", "serial_leg4", "parallel")


@dataclass(frozen=True)
class WorkspaceMap:
    """Inverse kinematics of working mode ``modes`` over the grid of end-effector positions ``x3``, ``y3``
    (X3, Y3 in m, shape (ny, nx)), NaN where not ``reachable``; ``x``, ``y`` are the grid's older names."""

    x3: np.ndarray
    y3: np.ndarray
    reachable: np.ndarray
    theta1: np.ndarray
    theta4: np.ndarray
    serial_leg1: np.ndarray
    serial_leg4: np.ndarray
    parallel: np.ndarray
    modes: tuple[int, int]

    @property
    def x(self) -> np.ndarray:
        """The older name of :attr:`x3`."""
        return self.x3

    @property
    def y(self) -> np.ndarray:
        """The older name of :attr:`y3`."""
        return self.y3


@cache
def _declaration():
    """The five-bar on the core: EcL2 and EcL3, unknowns X3, Y3 (the end effector), inputs θ1, θ4 (the
    motors), the points P1 … P5 and the links l1 … l5."""
    import sympy as sp

    from .mechanism import Mechanism

    x3, y3, theta1, theta4 = sp.symbols("x3 y3 theta1 theta4")
    l1, l2, l3, l4, l5 = lengths = sp.symbols("l1:6")
    P1, P5 = sp.Matrix([l5 / 2, 0]), sp.Matrix([-l5 / 2, 0])
    P2 = sp.Matrix([l1 * sp.cos(theta1) + l5 / 2, l1 * sp.sin(theta1)])
    P4 = sp.Matrix([l4 * sp.cos(theta4) - l5 / 2, l4 * sp.sin(theta4)])
    P3 = sp.Matrix([x3, y3])
    loops = [(x3 - l1 * sp.cos(theta1) - l5 / 2) ** 2 + (y3 - l1 * sp.sin(theta1)) ** 2 - l2**2,
             (x3 - l4 * sp.cos(theta4) + l5 / 2) ** 2 + (y3 - l4 * sp.sin(theta4)) ** 2 - l3**2]
    parameters = dict(zip(lengths, (0.10, 0.15, 0.15, 0.10, 0.08), strict=True))
    points = {"P1": P1, "P2": P2, "P3": P3, "P4": P4, "P5": P5}
    links = {"l1": ("P1", "P2"), "l2": ("P2", "P3"), "l3": ("P3", "P4"), "l4": ("P4", "P5"),
             "l5": ("P5", "P1")}
    return Mechanism(loops, [x3, y3], [theta1, theta4], parameters, points=points, links=links,
                     ground=("P1", "P5"))


def _lengths(parameters) -> tuple[float, ...]:
    return tuple(parameters[name] for name in ("l1", "l2", "l3", "l4", "l5"))


def _forward_kernel(parameters, known, sigma):
    """The block X3, Y3 in closed form (the kernel registered on the declaration, see
    :meth:`~course_lib.mechanism.Mechanism.with_kernel`): P3 where the circles of radius l3 about P4 and l2
    about P2 meet, P3 = P4 + [(d² + l3² − l2²)·e + σ·√Δ·n] / (2d²) with e = P2 − P4, d = |e|, n = e turned
    +90° and Δ = 4d²l3² − (d² + l3² − l2²)²; σ = +1 (arms up) left of the line P4 → P2.  NaN where the
    distal links cannot meet (Δ < 0 beyond rounding) or P2 = P4 (d = 0); the level Δ over
    4d²l3² + (d² + l3² − l2²)²."""
    l1, l2, l3, l4, l5 = _lengths(parameters)
    theta1, theta4 = known["theta1"], known["theta4"]
    cos1, sin1, cos4, sin4 = np.cos(theta1), np.sin(theta1), np.cos(theta4), np.sin(theta4)
    ex = l1 * cos1 + l5 / 2 - (l4 * cos4 - l5 / 2)
    ey = l1 * sin1 - l4 * sin4
    d2 = ex * ex + ey * ey
    along = d2 + l3 * l3 - l2 * l2
    reach, squared = 4 * d2 * l3 * l3, along * along
    discriminant, scale = reach - squared, reach + squared
    across = sigma * np.sqrt(np.where((discriminant < -LEVEL * scale) | (d2 == 0), np.nan,
                                      np.maximum(discriminant, 0.0)))
    with np.errstate(divide="ignore", invalid="ignore"):
        x3 = l4 * cos4 - l5 / 2 + (along * ex - across * ey) / (2 * d2)
        y3 = l4 * sin4 + (along * ey + across * ex) / (2 * d2)
        level = np.where(scale > 0, discriminant / np.where(scale > 0, scale, 1.0), 0.0)
    return {"x3": x3, "y3": y3, ("theta1", "cos"): cos1, ("theta1", "sin"): sin1, ("theta4", "cos"): cos4,
            ("theta4", "sin"): sin4}, level


def _leg_kernel(leg: int, parameters, known, sigma):
    """The block θ1 (``leg`` 1, EcL2) or θ4 (``leg`` 4, EcL3) of the inverse in closed form (the kernel
    registered on the loops solved the other way round): the course's half-angle root with its working
    mode −σ (the core's σ = +1 where the leg turns counter-clockwise at its elbow); NaN where the leg cannot
    reach P3 or where its crank angle is undetermined (P3 on its base pivot, l1 = l2 or l4 = l3); the
    level b² − 4ac over b² + (a − c)²."""
    theta, level = _half_angle_root(*_leg_coefficients(_lengths(parameters), leg, known["x3"], known["y3"]),
                                    -sigma)
    return {f"theta{leg}": theta}, level


def _leg_coefficients(lengths, leg: int, X, Y) -> tuple:
    """The course's half-angle coefficients (a, b, c) of ``leg`` 1 (a1, b1, c1) or 4 (a2, b2, c2) at
    (X, Y)."""
    l1, l2, l3, l4, l5 = lengths
    crank, distal, side = (l1, l2, -1) if leg == 1 else (l4, l3, +1)  # the motor at x = −side·l5/2
    common = X * X + Y * Y + l5**2 / 4
    # the course's terms in the course's order: a1 = 0 where it is exactly 0 (lesson 09)
    return (crank**2 - distal**2 + side * crank * l5 + 2 * crank * X + side * l5 * X + common,
            -4 * crank * Y + 0 * X,
            crank**2 - distal**2 - side * crank * l5 - 2 * crank * X + side * l5 * X + common)


def _inverse_coefficients(lengths, X, Y) -> dict[str, Any]:
    """The course's half-angle coefficients a1, b1, c1 (leg 1) and a2, b2, c2 (leg 4) at (X, Y)."""
    (a1, b1, c1), (a2, b2, c2) = (_leg_coefficients(lengths, leg, X, Y) for leg in (1, 4))
    return {"a1": a1, "b1": b1, "c1": c1, "a2": a2, "b2": b2, "c2": c2}


@cache
def _declarations() -> dict:
    """The declaration (``"forward"``: unknowns X3, Y3) and its loops with inputs and unknowns swapped
    (``"inverse"``: unknowns θ1, θ4), each with the course's closed forms registered as its kernels."""
    from .mechanism import Mechanism

    forward = _declaration()
    inverse = Mechanism(list(forward.equations), list(forward.inputs), list(forward.unknowns),
                        dict(forward.parameters), points=dict(forward.points),
                        links=dict(zip(forward.links.names, forward.links, strict=True)),
                        ground=forward.ground)
    return {"forward": forward.with_kernel("x3", _forward_kernel),
            "inverse": inverse.with_kernel("theta1", partial(_leg_kernel, 1)).with_kernel(
                "theta4", partial(_leg_kernel, 4))}


def _stacked(*values) -> np.ndarray:
    """Values broadcast together and stacked on a new last axis."""
    return np.stack(np.broadcast_arrays(*(np.asarray(v, dtype=float) for v in values)), axis=-1)


def _configuration(theta1, theta4, x3, y3) -> list[np.ndarray]:
    """θ1, θ4 (rad), x3, y3 (m) as float arrays broadcast together, or the named error."""
    return require_broadcast(theta1=require_finite("theta1", theta1, "rad"),
                             theta4=require_finite("theta4", theta4, "rad"),
                             x3=require_finite("x3", x3, "m"), y3=require_finite("y3", y3, "m"))


#: The forward assemblies by name, as the core's σ (``assembly=``): arms up has P3 left of the line P4 → P2.
FORWARD_ASSEMBLIES = {"arms up": {"x3": +1}, "arms down": {"x3": -1}}


def _working_mode(modes) -> tuple[int, int]:
    """(σ1, σ2) from ``modes``, or ``InvalidGeometryError`` naming the bad one."""
    if not (isinstance(modes, tuple | list) and len(modes) == 2):
        raise InvalidGeometryError(f"modes must be a pair (sigma1, sigma2) of ±1; got {modes!r}")
    return tuple(int(require_choice(f"sigma{k + 1} (modes[{k}])", modes[k], (1, -1))) for k in (0, 1))


def _half_angle_root(a, b, c, sigma):
    """θ = 2·atan((−b + σ√Δ)/2a) (within two turns) by the larger pair of it and 2c/(−b − σ√Δ) (no small
    divisor), NaN where there is no root (Δ = b² − 4ac below −LEVEL·(b² + (a − c)²), the core's rounding
    rule) or every θ is one (a = b = c = 0 to rounding); and the level Δ / (b² + (a − c)²) (0 where every θ
    is one)."""
    b_squared = b * b
    discriminant, scale = b_squared - 4 * a * c, b_squared + (a - c) ** 2
    root = sigma * np.sqrt(np.clip(discriminant, 0.0, None))
    numerator_1, denominator_1 = -b + root, 2 * a
    numerator_2, denominator_2 = 2 * c, -b - root
    size_1 = np.maximum(np.abs(numerator_1), np.abs(denominator_1))
    size_2 = np.maximum(np.abs(numerator_2), np.abs(denominator_2))
    use_first = size_1 >= size_2
    theta = 2 * np.arctan2(np.where(use_first, numerator_1, numerator_2),
                           np.where(use_first, denominator_1, denominator_2))  # the core: into [−π, π]
    undetermined = np.maximum(size_1, size_2) <= COINCIDENT * (np.abs(a) + np.abs(b) + np.abs(c) + 1e-300)
    level = np.where(scale > 0, discriminant / np.where(scale > 0, scale, 1.0), np.where(c != 0, -1.0, 0.0))
    level = np.where(undetermined, 0.0, level)
    lost = ~(level >= -LEVEL) | undetermined
    return np.where(lost, np.nan, theta), level


@dataclass(frozen=True)
class FiveBar:
    """Crank l1 turns about P1 = (+l5/2, 0) (θ1), crank l4 about P5 = (−l5/2, 0) (θ4), distal links l2
    (P2–P3) and l3 (P4–P3) meet at the end effector P3 = (X3, Y3); metres, l1…l4 > 0, l5 ≥ 0.

    >>> FiveBar(0.10, 0.15, 0.15, 0.10, 0.08).l5
    0.08
    """

    l1: float
    l2: float
    l3: float
    l4: float
    l5: float

    def __post_init__(self) -> None:
        for name in ("l1", "l2", "l3", "l4", "l5"):
            length = require_positive(name, getattr(self, name), allow_zero=name == "l5")
            if not (length == 0 or LENGTH_RANGE[0] <= length <= LENGTH_RANGE[1]):
                raise InvalidGeometryError(f"{name} must lie between {LENGTH_RANGE[0]:.0e} m and "
                                           f"{LENGTH_RANGE[1]:.0e} m; got {length!r}")
            object.__setattr__(self, name, length)

    def _cranks(self, theta1, theta4):
        """P2 and P4 (each (x, y) arrays broadcast together)."""
        half = self.l5 / 2
        p2x, p2y = self.l1 * np.cos(theta1) + half, self.l1 * np.sin(theta1)
        p4x, p4y = self.l4 * np.cos(theta4) - half, self.l4 * np.sin(theta4)
        return np.broadcast_arrays(p2x, p2y, p4x, p4y)

    @cached_property
    def mechanism(self):
        """The machine as one declaration on :class:`~course_lib.mechanism.Mechanism` with these lengths:
        EcL2, EcL3 (unknowns X3, Y3; inputs θ1, θ4), the points P1 … P5 and the links l1 … l5.

        >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08).mechanism
        >>> list(robot.points), robot.links.names, [s.name for s in robot.inputs]
        (['P1', 'P2', 'P3', 'P4', 'P5'], ('l1', 'l2', 'l3', 'l4', 'l5'), ['theta1', 'theta4'])
        """
        return self._cores["forward"]

    def motion(self, theta1, theta4, mode: int = 1, omega1=0.0, omega4=0.0, alpha1=0.0, alpha4=0.0, *,
               on_failure: str | None = None):
        """:meth:`forward` with the rates: position X3, Y3 with the velocity and acceleration of the end
        effector from the crank rates (by the declared loops), as its :class:`ForwardResult`, a
        :class:`~course_lib.mechanism.Motion` of :attr:`mechanism`; NaN rates at a parallel singularity
        (the core's rule).

        >>> motion = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08).motion(1.0, 2.0, omega1=1.0)
        >>> round(motion.position["y3"], 6), bool(motion.converged), bool(motion.singular)
        (0.209003, True, False)
        """
        rates = [require_finite(name, value, unit) for name, value, unit in (
            ("omega1", omega1, "rad/s"), ("omega4", omega4, "rad/s"), ("alpha1", alpha1, "rad/s^2"),
            ("alpha4", alpha4, "rad/s^2"))]
        return self._forward(theta1, theta4, mode, None, on_failure, rates)

    def joints(self, motion, theta4=None, x3=None, y3=None):
        """The points P1 … P5 (m) of a solved ``motion`` (``forward``'s or ``inverse``'s), by name
        (``self.mechanism.joints(motion)``).  The older spelling ``joints(theta1, theta4, x3, y3)`` takes a
        configuration (no solving) and stacks them, shape (..., 5, 2).

        >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
        >>> np.round(robot.joints(robot.inverse(0.0, 0.2))["P2"], 3).tolist()
        [-0.043, 0.056]
        >>> np.round(robot.joints(0.0, np.pi, 0.0, 0.1), 3).tolist()
        [[0.04, 0.0], [0.14, 0.0], [0.0, 0.1], [-0.14, 0.0], [-0.04, 0.0]]
        """
        return _machine_joints(self, motion, lambda: self.mechanism.joints(
            self._configuration(motion, theta4, x3, y3)))

    def _configuration(self, theta1, theta4, x3, y3) -> ForwardResult:
        """A checked configuration (no solving) as a :class:`ForwardResult`, to draw or take joints of:
        ``converged`` where it closes the loops (any other is drawn as given, P3 off its distal links)."""
        theta1, theta4, x3, y3 = _configuration(theta1, theta4, x3, y3)
        return self.mechanism.motion_of({"x3": x3, "y3": y3}, {"theta1": theta1, "theta4": theta4},
                                        singular=False, near_singular=False, kind=ForwardResult)

    def constraints(self, theta1, theta4, x3, y3) -> np.ndarray:
        """EcL2, EcL3: |P3 − P2|² − l2² and |P3 − P4|² − l3² (m²), shape (..., 2); zero when assembled.

        >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
        >>> bool(np.abs(robot.constraints(0.5, 2.5, *robot.forward(0.5, 2.5))).max() < 1e-15)
        True
        """
        return self._constraints(*_configuration(theta1, theta4, x3, y3))

    def _constraints(self, theta1, theta4, x3, y3) -> np.ndarray:
        p = _stacked(x3, y3, theta1, theta4)
        return self._cores["forward"].residual(p[..., :2], p[..., 2:])

    def forward_coefficients(self, theta1, theta4) -> dict[str, np.ndarray]:
        """The course's forward coefficients (X3 = g·Y3 + f in EcL3) ``f``, ``g``, ``a`` = 1 + g², ``b``,
        ``c`` and ``D`` = l5 + l1 cos θ1 − l4 cos θ4 (f, g, b, c: ±inf/NaN where D = 0).

        >>> k = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08).forward_coefficients(np.pi / 2, np.pi / 2)
        >>> round(float(k["f"]), 12), round(float(k["g"]), 12), round(float(k["D"]), 12)
        (0.0, 0.0, 0.08)
        """
        theta1, theta4 = require_broadcast(theta1=require_finite("theta1", theta1, "rad"),
                                           theta4=require_finite("theta4", theta4, "rad"))
        l1, l2, l3, l4, l5 = self.l1, self.l2, self.l3, self.l4, self.l5
        c1, s1, c4, s4 = np.cos(theta1), np.sin(theta1), np.cos(theta4), np.sin(theta4)
        D = l5 + l1 * c1 - l4 * c4
        with np.errstate(divide="ignore", invalid="ignore"):
            f = (l1**2 - l2**2 + l3**2 - l4**2 + l1 * l5 * c1 + l4 * l5 * c4) / (2 * D)
            g = (-2 * l1 * s1 + 2 * l4 * s4) / (2 * D)
            a = 1 + g**2
            b = 2 * f * g + g * l5 - 2 * g * l4 * c4 - 2 * l4 * s4
            c = f**2 - l3**2 + l4**2 + f * l5 + l5**2 / 4 - l4 * (2 * f + l5) * c4
        return {"f": f, "g": g, "a": a, "b": b, "c": c, "D": D}

    @older_failure_keywords
    def forward(self, theta1, theta4, mode: int = 1, *, assembly=None, on_failure: str | None = None
                ) -> ForwardResult:
        """End effector P3 = (X3, Y3) (m) for crank angles θ1, θ4 (rad); ``mode`` the course's σ: +1 "arms
        up" (larger Y3), −1 "arms down".  ``assembly=`` chooses by the core's σ instead (``{"x3": +1}`` or
        ``"arms up"``: P3 left of the line P4 → P2, the course's +1 while P2 is right of P4 and its −1 where
        P2 is left of P4).  The core's solve of :attr:`mechanism` (its block X3, Y3 solved by the course's
        closed form, :func:`_forward_kernel`), with the course's σ read as the core's at each instant.

        >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
        >>> bool(robot.forward(1.0, 2.0, +1).y3 > robot.forward(1.0, 2.0, -1).y3)
        True
        """
        return self._forward(theta1, theta4, mode, assembly, on_failure)

    def _forward(self, theta1, theta4, mode, assembly, on_failure, rates=None) -> ForwardResult:
        """``forward``, and with ``rates`` (ω1, ω4, α1, α4) ``motion``: one solve of :attr:`mechanism`."""
        sigma = int(require_choice("mode", mode, (1, -1)))
        if assembly is not None and mode != 1:  # mode (the course's larger-Y3 σ) is no name of the core's σ
            raise InvalidArgumentError(f"mode and assembly both choose the assembly: give one; got "
                                       f"mode={mode!r}, assembly={assembly!r}")
        side = None if assembly is None else FORWARD_ASSEMBLIES[self.mechanism.assembly_named(
            assembly, FORWARD_ASSEMBLIES, "arms up", "arms up")]["x3"]
        policy = failure_policy(on_failure)
        theta1, theta4 = require_broadcast(theta1=require_finite("theta1", theta1, "rad"),
                                           theta4=require_finite("theta4", theta4, "rad"))
        D = self.l1 * np.cos(theta1) - self.l4 * np.cos(theta4) + self.l5  # P2x − P4x
        right = np.where(D >= 0, 1, -1)  # P2 right of P4 (tie: D → 0⁺): the course's σ is the core's
        chosen = side if side is not None else scalar_or_array(sigma * right)
        inputs = {"theta1": theta1, "theta4": theta4}
        speeds, accelerations = (None, None) if rates is None else (
            dict(zip(inputs, rates[k:k + 2], strict=True)) for k in (0, 2))
        motion = self.mechanism.solve(inputs, speeds, accelerations, assembly={"x3": chosen},
                                      on_failure="nan")
        if policy == "raise" and not np.all(motion.converged):
            free = ~np.asarray(motion.converged) & np.asarray(motion.singular)
            report_unreachable(~np.asarray(motion.converged) & ~free, inputs,
                               "the distal links l2, l3 cannot meet", policy)
            report_unreachable(free, inputs, "P2 and P4 coincide with l2 = l3, so the end effector is "
                                             "undetermined", policy)
        if policy == "raise" and rates is not None and np.any(motion.singular):
            raise SingularJacobianError("parallel (type-2) singularity: the distal links l2, l3 are aligned; "
                                        "the end-effector velocity is undefined there",
                                        condition_number=np.inf)
        return recast(motion, ForwardResult, mode=sigma if side is None else scalar_or_array(side * right))

    def inverse_coefficients(self, x3, y3) -> dict[str, np.ndarray]:
        """The course's half-angle coefficients: a1·v1² + b1·v1 + c1 = 0 with v1 = tan(θ1/2), and a2, b2,
        c2 likewise for v4 = tan(θ4/2), for the end effector (x3, y3) (m) (v: the half-angle tangent, as
        :class:`~course_lib.symbolic.LoopForm` names it).

        >>> k = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08).inverse_coefficients(0.0, 0.2)
        >>> [round(float(k[name]), 6) for name in ("a1", "b1", "c1")]
        [0.0211, -0.08, 0.0371]
        """
        X, Y = require_broadcast(x3=require_finite("x3", x3, "m"), y3=require_finite("y3", y3, "m"))
        return self._inverse_coefficients(X, Y)

    def _inverse_coefficients(self, X, Y) -> dict[str, Any]:
        """``inverse_coefficients`` of checked arrays or numbers."""
        return _inverse_coefficients((self.l1, self.l2, self.l3, self.l4, self.l5), X, Y)

    @older_failure_keywords
    def inverse(self, x3, y3, modes: tuple[int, int] = (1, 1), *, assembly=None,
                on_failure: str | None = None) -> InverseResult:
        """Crank angles θ1, θ4 (rad, in (−π, π]) that put the end effector at (x3, y3) (m); ``modes`` =
        (σ1, σ2), the signs in θ = 2·atan((−b + σ√(b² − 4ac))/2a): the four working modes.  ``assembly=``
        chooses by the core's σ of each leg instead (``{"theta1": s1, "theta4": s4}``, +1 where the leg
        turns counter-clockwise at its elbow: ``modes`` = (−s1, −s4); a leg not named keeps its mode).

        >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
        >>> [round(v, 12) for v in robot.forward(*robot.inverse(0.0, 0.2, modes=(+1, -1)), mode=+1)]
        [0.0, 0.2]
        """
        sigmas = _working_mode(modes)
        if assembly is not None:
            legs = self._cores["inverse"].assembly_sigma(assembly)
            sigmas = (-legs.get("theta1", -sigmas[0]), -legs.get("theta4", -sigmas[1]))
        policy = failure_policy(on_failure)
        X, Y = require_broadcast(x3=require_finite("x3", x3, "m"), y3=require_finite("y3", y3, "m"))
        motion = self._cores["inverse"].solve({"x3": X, "y3": Y},
                                              assembly={"theta1": -sigmas[0], "theta4": -sigmas[1]},
                                              on_failure="nan")
        if policy == "raise" and not np.all(motion.converged):
            self._report_inverse(motion, X, Y)
        return recast(motion, InverseResult, modes=sigmas)

    def _report_inverse(self, motion, X, Y) -> None:
        """The named ``UnreachableError`` of the first instant the inverse did not solve: the leg that cannot
        reach P3 (|P3 − pivot| outside [|l1 − l2|, l1 + l2]), or the crank angle undetermined."""
        inputs = {"x3": X, "y3": Y}
        lost = ~np.asarray(motion.converged)
        for pivot, crank, distal, what in ((self.l5 / 2, self.l1, self.l2, "leg 1 (l1, l2)"),
                                           (-self.l5 / 2, self.l4, self.l3, "leg 4 (l4, l3)")):
            with np.errstate(all="ignore"):
                reach = np.hypot(X - pivot, Y)
                far = lost & ~((reach <= crank + distal) & (reach >= abs(crank - distal)))
            report_unreachable(far, inputs, f"{what} cannot reach the point")
        report_unreachable(lost, inputs, "a crank angle is undetermined (P3 on a base pivot)")

    @cached_property
    def _cores(self) -> dict:
        """The declaration with these lengths ("forward") and its loops with inputs and unknowns swapped
        ("inverse")."""
        lengths = {"l1": self.l1, "l2": self.l2, "l3": self.l3, "l4": self.l4, "l5": self.l5}
        return {kind: core.with_parameters(lengths) for kind, core in _declarations().items()}

    def _terms(self, theta1, theta4, x3, y3):
        """A = ∂(EcL2, EcL3)/∂(X3, Y3) and B = ∂(EcL2, EcL3)/∂(θ1, θ4), each (..., 2, 2), from the core."""
        p = _stacked(x3, y3, theta1, theta4)
        return self._cores["forward"]._rate_terms(p[..., :2], p[..., 2:])

    def jacobian_end_effector(self, theta1, theta4, x3, y3) -> np.ndarray:
        """A = ∂(EcL2, EcL3)/∂(X3, Y3) = 2·[[X3 − P2x, Y3 − P2y], [X3 − P4x, Y3 − P4y]] (m), shape
        (..., 2, 2); det A = 0 is the parallel (type-2) singularity.

        >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
        >>> np.round(robot.jacobian_end_effector(0.0, np.pi, 0.0, 0.1), 3).tolist()
        [[-0.28, 0.2], [0.28, 0.2]]
        """
        return self._terms(*_configuration(theta1, theta4, x3, y3))[0]

    def jacobian_cranks(self, theta1, theta4, x3, y3) -> np.ndarray:
        """B = ∂(EcL2, EcL3)/∂(θ1, θ4) (m²/rad), shape (..., 2, 2), diagonal; a zero on the diagonal is a
        serial (type-1) singularity.

        >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
        >>> (np.round(robot.jacobian_cranks(0.0, np.pi, 0.0, 0.1), 3) + 0.0).tolist()
        [[-0.02, 0.0], [0.0, 0.02]]
        """
        return self._terms(*_configuration(theta1, theta4, x3, y3))[1]

    def singularity_measures(self, theta1, theta4, x3, y3) -> SingularityMeasures:
        """The three normalized singularity measures (see ``SingularityMeasures``).

        >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
        >>> m = robot.singularity_measures(*robot.inverse(0.0, 0.2, modes=(-1, +1)), 0.0, 0.2)
        >>> round(m.serial_leg1, 4), round(m.serial_leg4, 4), round(m.parallel, 4)
        (0.9529, -0.9529, -0.9793)
        """
        leg1, leg4, parallel = self._measures(*_configuration(theta1, theta4, x3, y3))
        return SingularityMeasures(scalar_or_array(leg1), scalar_or_array(leg4), scalar_or_array(parallel))

    def _measures(self, theta1, theta4, x3, y3):
        """The three singularity measures without the input checks: NaN in, NaN out."""
        half = self.l5 / 2
        p2x, p2y, p4x, p4y = self._cranks(theta1, theta4)
        x_2, y_2, x_4, y_4 = x3 - p2x, y3 - p2y, x3 - p4x, y3 - p4y
        leg1 = ((p2x - half) * y_2 - p2y * x_2) / (self.l1 * self.l2)
        leg4 = ((p4x + half) * y_4 - p4y * x_4) / (self.l4 * self.l3)
        return leg1, leg4, (x_2 * y_4 - y_2 * x_4) / (self.l2 * self.l3)

    def _singular(self, kind, policy, theta1, theta4, x3, y3):
        """The mask of a "parallel" or "serial" singularity, by the core's rule (σ_min(J̃) < SINGULAR of
        ∂(EcL2, EcL3)/∂(X3, Y3), or of ∂(EcL2, EcL3)/∂(θ1, θ4)); raises there, or for an unassembled one."""
        residual = np.abs(self._constraints(theta1, theta4, x3, y3))
        scale = max(self.l1, self.l2, self.l3, self.l4, self.l5) ** 2
        if not np.all(residual <= RESIDUAL * scale):
            raise InvalidGeometryError(f"the configuration is not assembled: constraint residual "
                                       f"{residual.max():.3g} m² (x3, y3 must be the end effector for "
                                       "theta1, theta4, e.g. from forward)")
        leg1, leg4, parallel = self._measures(theta1, theta4, x3, y3)
        if kind == "parallel":
            p = _stacked(x3, y3, theta1, theta4)
            singular = self._cores["forward"].is_singular(p[..., :2], p[..., 2:])
            parallel = np.broadcast_to(parallel, singular.shape)
            sine = parallel[singular].ravel()[0] if singular.any() else 0
            message = ("parallel (type-2) singularity: the distal links l2, l3 are aligned (sin of their "
                       f"angle {sine:.2g}); the end-effector velocity is undefined there")
        else:
            p = _stacked(theta1, theta4, x3, y3)
            singular = self._cores["inverse"].is_singular(p[..., :2], p[..., 2:])
            leg1, leg4 = np.broadcast_arrays(np.abs(leg1), np.abs(leg4))
            which = "leg 1 (l1, l2)" if np.any(singular & (leg1 <= leg4)) else "leg 4 (l4, l3)"
            message = f"serial (type-1) singularity: {which} is stretched or folded; the crank rates are " \
                      "undefined there"
        if policy == "raise" and singular.any():
            raise SingularJacobianError(message, condition_number=np.inf)
        return singular

    @older_failure_keywords
    def velocity_jacobian(self, theta1, theta4, x3, y3, *, on_failure: str | None = None) -> np.ndarray:
        """The velocity Jacobian V = −A⁻¹·B (m/rad), shape (..., 2, 2): (Ẋ3, Ẏ3) = V·(ω1, ω4) (A, B: the
        loop's Jacobians in the end effector and in the cranks; V is not the loop Jacobian J).
        ``SingularJacobianError`` at a parallel singularity (``on_failure="nan"``, NaN), as the two rate
        functions at theirs.

        >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
        >>> np.round(robot.velocity_jacobian(*robot.inverse(0.0, 0.2, modes=(-1, +1)), 0.0, 0.2), 4).tolist()
        [[-0.0754, -0.0754], [0.0614, -0.0614]]
        """
        theta1, theta4, x3, y3 = _configuration(theta1, theta4, x3, y3)
        policy = failure_policy(on_failure)
        singular = self._singular("parallel", policy, theta1, theta4, x3, y3)
        A, B = self._terms(theta1, theta4, x3, y3)
        shape, B = A.shape[:-2], B.reshape(-1, 2, 2)
        solve = linear_solver(np.where(singular.reshape(-1, 1, 1), np.eye(2), A.reshape(-1, 2, 2)))
        J = np.stack([solve(-B[:, :, j]) for j in range(2)], axis=-1).reshape(shape + (2, 2))
        return np.where(singular[..., None, None], np.nan, J)

    @older_failure_keywords
    def end_effector_velocity(self, theta1, theta4, x3, y3, omega1, omega4, *, on_failure: str | None = None):
        """(Ẋ3, Ẏ3) (m/s), shape (..., 2), from the crank rates ω1, ω4 (rad/s): A·ṗ = −B·ω.

        >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
        >>> theta1, theta4 = robot.inverse(0.0, 0.2, modes=(-1, +1))
        >>> (np.round(robot.end_effector_velocity(theta1, theta4, 0.0, 0.2, 1.0, -1.0), 4) + 0.0).tolist()
        [0.0, 0.1229]
        """
        theta1, theta4, x3, y3 = _configuration(theta1, theta4, x3, y3)
        omega = [require_finite("omega1", omega1, "rad/s"), require_finite("omega4", omega4, "rad/s")]
        policy = failure_policy(on_failure)
        singular = self._singular("parallel", policy, theta1, theta4, x3, y3)
        p = _stacked(x3, y3, theta1, theta4, *omega)
        return self._cores["forward"].unknown_rates(p[..., :2], p[..., 2:4], p[..., 4:], singular=singular)[0]

    @older_failure_keywords
    def crank_rates(self, theta1, theta4, x3, y3, vx, vy, *, on_failure: str | None = None):
        """(ω1, ω4) (rad/s), shape (..., 2), for the end-effector velocity (vx, vy) (m/s): B·ω = −A·ṗ.

        >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
        >>> np.round(robot.crank_rates(*robot.inverse(0.0, 0.2, (-1, 1)), 0.0, 0.2, 0.0, 0.1), 4).tolist()
        [0.8137, -0.8137]
        """
        theta1, theta4, x3, y3 = _configuration(theta1, theta4, x3, y3)
        velocity = [require_finite(name, value, "m/s") for name, value in (("vx", vx), ("vy", vy))]
        policy = failure_policy(on_failure)
        singular = self._singular("serial", policy, theta1, theta4, x3, y3)
        p = _stacked(theta1, theta4, x3, y3, *velocity)
        return self._cores["inverse"].unknown_rates(p[..., :2], p[..., 2:4], p[..., 4:], singular=singular)[0]

    def workspace(self, x, y, modes: tuple[int, int] = (1, 1)) -> WorkspaceMap:
        """:class:`WorkspaceMap` of working mode ``modes`` over the grid of the 1-D vectors ``x``, ``y`` (m)
        of end-effector positions X3, Y3.

        >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
        >>> w = robot.workspace(np.linspace(-0.3, 0.3, 61), np.linspace(-0.3, 0.3, 61))
        >>> w.reachable.shape, bool(w.reachable[30, 30]), bool(w.reachable[0, 0]), float(w.y3[40, 30])
        ((61, 61), False, False, 0.1)
        """
        x, y = require_finite("x", x, "m"), require_finite("y", y, "m")
        if x.ndim != 1 or y.ndim != 1:
            raise InvalidGeometryError(f"x and y must be 1-D grid vectors; got shapes {x.shape}, {y.shape}")
        X, Y = np.meshgrid(x, y)
        result = self.inverse(X, Y, modes, on_failure="nan")
        theta1, theta4 = np.asarray(result.theta1), np.asarray(result.theta4)
        with np.errstate(invalid="ignore"):
            measures = self._measures(theta1, theta4, X, Y)
        return WorkspaceMap(X, Y, np.asarray(result.converged), theta1, theta4, *measures, tuple(modes))

    def draw(self, theta1: float, theta4: float, x3: float, y3: float, ax=None, title: str | None = None,
             **options):
        """Draw one configuration, its joints P1 … P5 labelled 1 … 5; returns the axes.  The older spelling
        of ``course_lib.plotting.draw(robot, result)`` (a :class:`ForwardResult` or :class:`InverseResult`
        draws directly), which takes the same ``options``.

        >>> import matplotlib; matplotlib.use("Agg")
        >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
        >>> ax = robot.draw(1.2, 1.9, *robot.forward(1.2, 1.9), title="arms up")
        >>> [line.get_gid() for line in ax.lines][:5]
        ['l1', 'l2', 'l3', 'l4', 'l5']
        """
        from .plotting import draw

        motion = self._configuration(theta1, theta4, x3, y3)
        if np.shape(motion.x3) != ():
            raise InvalidGeometryError(f"draw takes one configuration (scalars); got shape "
                                       f"{np.shape(motion.x3)}")
        options.setdefault("labels", {f"P{k}": str(k) for k in range(1, 6)})
        return draw(self, motion, ax, title=title, **options)
