"""The power saw of the course: an offset slider-crank solved by Newton–Raphson (SI units, radians).

A crank r2 (angle θ2, driven by the motor) and a rod r3 (angle θ3, crank pin → slider pin) drive the
slider, whose pin moves on the line y = r1y; with r1 = r1·(cos θ1, sin θ1) from the crank pivot to the
slider pin, the loop is r1 = r2 + r3.  The report keeps θ1 in (−π/2, π/2] (eq. 21 uses acot), so with
the slider left of the crank pivot r1 is *negative*: at rest r1 ≈ −0.0997 m, θ1 ≈ −0.4684 rad, and
θ3 = π − asin(…) (eq. 20: the rod points to the left).  Velocity (10)–(12) and acceleration (13)–(15)
equations are linear, with the position Jacobian as matrix; appendix D solves all nine at once.

The saw is one declaration (:attr:`Saw.mechanism`: the loop and the slider line, unknowns r1, θ1, θ3,
input θ2, the points O2 (crank pivot), A (crank pin) and C (slider pin, lesson 00's notation), the
links crank and rod); every residual, Jacobian, Newton route, singularity test (the core's rule) and
drawing below comes from it.  :meth:`Saw.motion` is the core's solve of it, its one block (Newton's,
with no closed form the core can derive) solved by the course's closed form registered as its kernel
(:func:`_kernel`); :func:`analytic` keeps the course's eqs. 20–28 as written.

σ on the saw (the core's −sign(det J_b); here det J_b = −r1·r3·cos θ3): the kernel keeps r1 < 0, the
course's r1 (C reached from O2 against the direction θ1), so σ = +1 is the rod pointing left, C left of
A (cos θ3 < 0, the course's saw: ``assembly="left"``), σ = −1 the rod pointing right (``"right"``), as
the offset slider-crank names them.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, field
from functools import cache, cached_property, lru_cache
from types import MappingProxyType

import numpy as np

from .errors import (
    ConvergenceError,
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
from .newton import NewtonResult
from .planar import Unpacks
from .profile import first_turn_time, motor_profile

__all__ = ["Saw", "COURSE_SAW", "ASSEMBLIES", "UNKNOWNS", "SEED_PRINTED", "SEED_CODE", "position_residual",
           "position_jacobian", "velocity_residual", "velocity_residual_jacobian", "acceleration_residual",
           "acceleration_residual_jacobian", "system_residual", "system_jacobian", "SawMotion", "SawSolution",
           "solve_consecutive", "solve_simultaneous", "analytic", "joint_positions", "SawSweep", "sweep"]

#: Names of the nine unknowns, in the course's order.
UNKNOWNS = ("r1", "theta1", "theta3", "v_r", "omega1", "omega3", "a_r", "alpha1", "alpha3")

#: The seed vector printed in the report (its eq. 16).
SEED_PRINTED = np.array([-0.1, -0.5, 3.0, 0.5, 0.0, -0.5, 0.5, 0.0, -0.5])
#: The seed vector of the report's MATLAB listings (rates with the opposite signs).
SEED_CODE = np.array([-0.1, -0.5, 3.0, -0.5, 0.0, 0.5, -0.5, 0.0, 0.5])

VARIANTS = ("loop", "substituted")
#: The saw's assemblies by name → σ of its block (the side of A that C lies on).
ASSEMBLIES = {"left": {"theta3": +1}, "right": {"theta3": -1}}
LINEAR_STAGES = ("newton", "direct")
METHODS = ("consecutive", "simultaneous", "batched", "analytic")


@dataclass(frozen=True)
class Saw:
    """Lengths of the saw in metres: slider-line offset ``r1y``, crank ``r2``, rod ``r3`` (by default
    the course's 45 mm, 75 mm and 170 mm).

    >>> Saw().r3, Saw(r1y=0.03).r2
    (0.17, 0.075)
    """

    r1y: float = 0.045
    r2: float = 0.075
    r3: float = 0.170

    def __post_init__(self) -> None:
        offset = float(require_finite("r1y", self.r1y, unit="metres"))
        if offset == 0.0:
            raise InvalidGeometryError("r1y must be non-zero: with the slider line through the crank pivot, "
                                       f"r1 = r1y / sin(theta1) is undefined; got {self.r1y!r}")
        object.__setattr__(self, "r1y", offset)
        object.__setattr__(self, "r2", require_positive("r2", self.r2))
        object.__setattr__(self, "r3", require_positive("r3", self.r3))

    @cached_property
    def mechanism(self):
        """The saw as one declaration on :class:`~course_lib.mechanism.Mechanism` with these lengths:
        eqs. (7)–(9) (unknowns r1, θ1, θ3; input θ2), the points O2, A, C and the links crank, rod.

        >>> mechanism = Saw().mechanism
        >>> list(mechanism.points), mechanism.links.names, [s.name for s in mechanism.unknowns]
        (['O2', 'A', 'C'], ('crank', 'rod'), ['r1', 'theta1', 'theta3'])
        """
        return _core(self)

    def motion(self, theta2, omega2=0.0, alpha2=0.0, *, assembly="left", on_failure: str | None = None):
        """A :class:`SawMotion`: the core's solve of :attr:`mechanism` (position r1, θ1, θ3 and their
        rates; input θ2), the same :class:`~course_lib.mechanism.Motion` as ``self.mechanism.solve`` with
        the course's names added, to draw, animate or explore.  The position by the course's closed form
        (eqs. 20–21, registered as the block's kernel), the rates by the core from the declared loop (J·q̇
        = −F_u·ω2 and its derivative; the same as the course's eqs. 22–28).  ``assembly``: ``"left"`` (the
        course's: the rod pointing left, C left of A), ``"right"``, or σ by any unknown (see the module).
        ``UnreachableError`` where the rod cannot reach the slider line, ``SingularJacobianError`` where it
        is perpendicular to it while moving; ``on_failure="nan"``: NaN there.

        >>> motion = Saw().motion([0.0, 1.0], omega2=6.0)
        >>> np.round(motion.position["theta3"], 6).tolist(), np.round(motion.velocity["theta3"], 6).tolist()
        ([2.873694, 3.248327], [2.744974, 1.438397])
        >>> motion.assembly["theta3"].tolist()
        [1, 1]
        """
        sigma = self.mechanism.assembly_sigma(assembly, ASSEMBLIES)
        policy = failure_policy(on_failure)
        theta2, omega2, alpha2 = require_broadcast(theta2=require_finite("theta2", theta2, unit="rad"),
                                                   omega2=require_finite("omega2", omega2, unit="rad/s"),
                                                   alpha2=require_finite("alpha2", alpha2, unit="rad/s²"))
        motion = self.mechanism.solve({"theta2": theta2}, {"theta2": omega2}, {"theta2": alpha2},
                                      assembly=sigma, on_failure=policy)
        return recast(motion, SawMotion)

    def joints(self, motion):
        """The points O2, A and C (m) of a solved ``motion``, by name (``self.mechanism.joints(motion)``).
        The older spelling ``joints(theta2)`` is :func:`joint_positions` of this saw, shape (..., 3, 2).

        >>> saw = Saw()
        >>> np.round(saw.joints(saw.motion(0.0))["C"], 4).tolist(), saw.joints(0.0).shape
        ([-0.0889, 0.045], (3, 2))
        """
        return _machine_joints(self, motion, lambda: self.mechanism.joints(self.motion(motion)))


#: The saw of the course (r1y = 0.045 m, r2 = 0.075 m, r3 = 0.170 m).
COURSE_SAW = Saw()


@cache
def _declaration(variant: str):
    """The saw's loop and slider line on the core (unknowns r1, theta1, theta3; input theta2), as
    (Fx, Fy, Fc) for "loop" or (Fc, Fx, Fy) with r1 = r1y / sin θ1 for "substituted"."""
    import sympy as sp

    from .mechanism import Mechanism

    r1, theta1, theta2, theta3, r1y, r2, r3 = sp.symbols("r1 theta1 theta2 theta3 r1y r2 r3")
    fx = -r1 * sp.cos(theta1) + r2 * sp.cos(theta2) + r3 * sp.cos(theta3)
    fy = r1 * sp.sin(theta1) - r2 * sp.sin(theta2) - r3 * sp.sin(theta3)
    fc = r1 * sp.sin(theta1) - r1y
    loops = [sp.Matrix([fx, fy]), fc]
    A = sp.Matrix([r2 * sp.cos(theta2), r2 * sp.sin(theta2)])
    drawing = {"points": {"O2": sp.Matrix([0, 0]), "A": A,
                          "C": A + sp.Matrix([r3 * sp.cos(theta3), r3 * sp.sin(theta3)])},
               "links": {"crank": ("O2", "A"), "rod": ("A", "C")}, "ground": ("O2",), "sliders": ("C",)}
    if variant == "substituted":
        on_the_line = {r1: r1y / sp.sin(theta1)}
        loops = [fc, fx.subs(on_the_line), fy.subs(on_the_line)]
    return Mechanism(loops, [r1, theta1, theta3], [theta2], {r1y: 0.045, r2: 0.075, r3: 0.170}, **drawing)


@lru_cache(maxsize=64)
def _checked_saw(saw) -> Saw:
    """``saw`` itself when it is a :class:`Saw`, else ``InvalidGeometryError`` naming it."""
    if not isinstance(saw, Saw):
        raise InvalidGeometryError(f"saw must be a Saw(r1y, r2, r3) (e.g. COURSE_SAW); got {saw!r}")
    return saw


def _kernel(parameters, known, sigma):
    """The saw's block (r1, θ1, θ3) in closed form, the kernel registered on its declaration: sin θ3 from
    the slider line (the course's eq. 20: Fy − Fc = 0), cos θ3 = −σ·√(1 − sin²θ3) (σ = +1: the rod
    pointing left), C = A + r3·(cos θ3, sin θ3) and r1 = −|O2C| with θ1 its direction (eq. 21: r1 < 0 as
    the course's); the level 1 − sin²θ3 (0 where the rod is perpendicular to the slider line, where the
    two assemblies meet; < 0 where it cannot reach the line).

    >>> values, level = _kernel({"r1y": 0.045, "r2": 0.075, "r3": 0.17}, {"theta2": np.zeros(1)}, 1)
    >>> [round(float(values[name][0]), 6) for name in ("r1", "theta1", "theta3")]
    [-0.099672, -0.468422, 2.873694]
    """
    r1y, r2, r3 = parameters["r1y"], parameters["r2"], parameters["r3"]
    c2, s2 = np.cos(known["theta2"]), np.sin(known["theta2"])
    s3 = (r1y - r2 * s2) / r3
    level = 1.0 - s3 * s3
    with np.errstate(invalid="ignore"):
        c3 = -sigma * np.sqrt(level)
    x = r2 * c2 + r3 * c3
    length = np.hypot(x, r1y)
    c1, s1 = -x / length, -r1y / length  # r1 = −length along (cos θ1, sin θ1)
    return {"r1": -length, "theta1": np.arctan2(s1, c1), "theta3": np.arctan2(s3, c3),
            ("theta1", "cos"): c1, ("theta1", "sin"): s1, ("theta3", "cos"): c3, ("theta3", "sin"): s3,
            ("theta2", "cos"): c2, ("theta2", "sin"): s2}, level


def _core(saw: Saw, variant: str = "loop"):
    saw = _checked_saw(saw)
    declaration = _declaration(require_choice("variant", variant, VARIANTS))
    lengths = (saw.r1y, saw.r2, saw.r3)
    core = declaration.with_parameters(dict(zip(declaration.parameters, lengths, strict=True)))
    return core.with_kernel("r1", _kernel) if variant == "loop" else core


def _position(saw: Saw, variant: str):
    """The core of the position equations the solvers take: None for the loop's own."""
    return None if require_choice("variant", variant, VARIANTS) == "loop" else _core(saw, variant)


def _last(values, size: int, name: str) -> np.ndarray:
    array = np.asarray(values, dtype=float)
    if array.shape[-1:] != (size,):
        raise InvalidGeometryError(f"{name} must have {size} entries on its last axis; got shape "
                                   f"{array.shape}")
    return array


def _motion(*values) -> list[np.ndarray]:
    """θ2, ω2, α2 (any of them) as arrays (..., 1), the core's inputs."""
    return [np.asarray(value, dtype=float)[..., None] for value in values]


def position_residual(position, theta2, *, saw: Saw = COURSE_SAW, variant: str = "loop") -> np.ndarray:
    """Residuals of the position equations at ``position`` = (r1, θ1, θ3), shape (..., 3): eqs. (7)–(9)
    Fx = −r1 cos θ1 + r2 cos θ2 + r3 cos θ3, Fy = r1 sin θ1 − r2 sin θ2 − r3 sin θ3, Fc = r1 sin θ1 − r1y,
    or for ``variant="substituted"`` (Fc, Fx, Fy) with r1 = r1y / sin θ1 (the Jacobian (17)'s system).

    >>> bool(np.allclose(position_residual([-0.0996724914, -0.4684217805, 2.8736937412], 0.0), 0, atol=1e-10))
    True
    """
    position = _last(position, 3, "position")
    return _core(saw, variant).residual(position, *_motion(theta2))


def position_jacobian(position, *, saw: Saw = COURSE_SAW, variant: str = "loop") -> np.ndarray:
    """∂(position residuals)/∂(r1, θ1, θ3), shape (..., 3, 3), free of θ2.  ``variant="substituted"``
    gives eq. (17): [[sin θ1, r1 cos θ1, 0], [0, r1y (cot²θ1 + 1), −r3 sin θ3], [0, 0, −r3 cos θ3]]; the
    loop's determinant −r1·r3·cos θ3 vanishes only with the rod perpendicular to the slider line.

    >>> bool(abs(np.linalg.det(position_jacobian([-0.1, -0.5, 3.0])) - 0.1 * 0.17 * np.cos(3.0)) < 1e-15)
    True
    """
    position = _last(position, 3, "position")
    return _core(saw, variant).jacobian(position, np.zeros(position.shape[:-1] + (1,)))


def velocity_residual(velocity, position, theta2, omega2, *, saw: Saw = COURSE_SAW) -> np.ndarray:
    """Residuals of the velocity equations (10)–(12) at ``velocity`` = (v_r, ω1, ω3), shape (..., 3):
    d/dt of (7)–(9), J·(v_r, ω1, ω3) + ∂F/∂θ2·ω2.

    >>> velocity_residual([0.0, 0.0, 0.0], [-0.1, -0.5, 3.0], 0.0, 0.0).tolist()
    [0.0, 0.0, 0.0]
    """
    velocity, position = _last(velocity, 3, "velocity"), _last(position, 3, "position")
    theta2, omega2 = _motion(theta2, omega2)
    return _core(saw).velocity_residual(velocity, position, theta2, omega2)


def velocity_residual_jacobian(position, *, saw: Saw = COURSE_SAW) -> np.ndarray:
    """∂(velocity residuals)/∂(v_r, ω1, ω3), eq. (18), shape (..., 3, 3): the Jacobian of
    :func:`velocity_residual`, which is the position Jacobian J.

    >>> at, v = [-0.1, -0.5, 3.0], np.array([0.2, -1.0, 0.5])   # the residuals are linear in v
    >>> change = velocity_residual(v, at, 0.3, 2.0) - velocity_residual(0 * v, at, 0.3, 2.0)
    >>> bool(np.abs(velocity_residual_jacobian(at) @ v - change).max() < 1e-12)
    True
    """
    return position_jacobian(position, saw=saw)


def acceleration_residual(acceleration, velocity, position, theta2, omega2, alpha2, *,
                          saw: Saw = COURSE_SAW) -> np.ndarray:
    """Residuals of the acceleration equations (13)–(15) at ``acceleration`` = (a_r, α1, α3), shape (..., 3).

    >>> acceleration_residual([0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [-0.1, -0.5, 3.0], 0.0, 0.0, 0.0).tolist()
    [0.0, 0.0, 0.0]
    """
    arrays = [_last(a, 3, name) for a, name in ((acceleration, "acceleration"), (velocity, "velocity"),
                                                (position, "position"))]
    return _core(saw).acceleration_residual(*arrays, *_motion(theta2, omega2, alpha2))


def acceleration_residual_jacobian(position, *, saw: Saw = COURSE_SAW) -> np.ndarray:
    """∂(acceleration residuals)/∂(a_r, α1, α3), shape (..., 3, 3): the Jacobian of
    :func:`acceleration_residual`, which is the position Jacobian J (eq. 19 lists its rows in the order
    Fc, Fx, Fy).

    >>> at, v, a = [-0.1, -0.5, 3.0], [0.2, -1.0, 0.5], np.array([1.0, 3.0, -2.0])   # linear in a
    >>> change = (acceleration_residual(a, v, at, 0.3, 2.0, 5.0)
    ...           - acceleration_residual(0 * a, v, at, 0.3, 2.0, 5.0))
    >>> bool(np.abs(acceleration_residual_jacobian(at) @ a - change).max() < 1e-12)
    True
    """
    return position_jacobian(position, saw=saw)


#: The older name of :func:`velocity_residual_jacobian` (``velocity_jacobian`` is the five-bar's V = −A⁻¹B).
velocity_jacobian = velocity_residual_jacobian
#: The older name of :func:`acceleration_residual_jacobian`.
acceleration_jacobian = acceleration_residual_jacobian


def _system(x, theta2, omega2, alpha2, saw, variant):
    position = _position(saw, variant)
    return _core(saw).system(_last(x, 9, "x"), *_motion(theta2, omega2, alpha2), position=position)


def system_residual(x, theta2, omega2, alpha2, *, saw: Saw = COURSE_SAW, variant: str = "loop") -> np.ndarray:
    """The nine residuals (position, velocity, acceleration) at the nine unknowns ``x``, shape (..., 9).

    >>> bool(np.allclose(system_residual(np.zeros(9) + [0.1, 0.5, 0.3, 0, 0, 0, 0, 0, 0], 0, 0, 0)[3:], 0))
    True
    """
    return _system(x, theta2, omega2, alpha2, saw, variant)[0]


def system_jacobian(x, *, saw: Saw = COURSE_SAW, variant: str = "loop") -> np.ndarray:
    """The 9×9 Jacobian of :func:`system_residual` (the course's appendix D), shape (..., 9, 9), free of
    θ2 and its rates: block lower-triangular, each diagonal block of the rates the position Jacobian.

    >>> system_jacobian(SEED_PRINTED).shape, bool(np.all(system_jacobian(SEED_PRINTED)[:3, 3:] == 0))
    ((9, 9), True)
    """
    return _system(x, 0.0, 0.0, 0.0, saw, variant)[1]


def _closed_position(sine, theta2, saw: Saw):
    """r1, θ1, θ3 of the course's assembly from sin θ3 (eqs. 20, 21; NaN where |sin θ3| > 1)."""
    theta3 = np.pi - np.arcsin(sine)  # (20)
    theta1 = np.arctan2(saw.r1y, saw.r2 * np.cos(theta2) + saw.r3 * np.cos(theta3))  # (21): acot(x / r1y)
    theta1 = np.where(theta1 > np.pi / 2, theta1 - np.pi, theta1)  # moved into (−π/2, π/2]
    theta1 = np.where(theta1 <= -np.pi / 2, theta1 + np.pi, theta1)
    return saw.r1y / np.sin(theta1), theta1, theta3


def _check_assembly(theta2, saw: Saw, on_failure: str = "raise") -> np.ndarray:
    """sin θ3 (from Fy − Fc = 0); UnreachableError where the rod cannot reach the slider line,
    SingularJacobianError where the declared loop's J is singular by the core's rule (σ_min(J̃) <
    SINGULAR: the rod perpendicular to the slider line, cos θ3 = 0)."""
    saw = _checked_saw(saw)
    sine = (saw.r1y - saw.r2 * np.sin(theta2)) / saw.r3
    report_unreachable(np.abs(sine) > 1.0, {"theta2": theta2},
                       f"the rod r3 = {saw.r3:g} m cannot reach the slider line y = r1y = {saw.r1y:g} m "
                       "(|r1y - r2 sin(theta2)| > r3)", on_failure)
    reaches = np.abs(sine) <= 1.0
    toggle = reaches
    if np.any(reaches):
        with np.errstate(invalid="ignore"):
            q = np.stack(_closed_position(np.where(reaches, sine, 0.0), theta2, saw), axis=-1)
        toggle = reaches & saw.mechanism.is_singular(q, np.asarray(theta2, dtype=float)[..., None])
    if np.any(toggle):
        first = float(np.broadcast_to(theta2, toggle.shape)[toggle].ravel()[0])
        raise SingularJacobianError(
            f"the Jacobian is singular at theta2={first:.6g}: the rod r3 is perpendicular to the "
            "slider line (cos(theta3) = 0), a limit position where the rates are undefined",
            x=q[toggle][0].tolist())  # the unknowns r1, θ1, θ3 there
    return sine


def _scalar(name: str, value, unit: str) -> float:
    array = require_finite(name, value, unit=unit)
    if array.ndim != 0:
        raise InvalidGeometryError(f"{name} must be a single number for a single Newton solve (use sweep "
                                   f"or analytic for arrays); got shape {array.shape}")
    return float(array)


def _seed(x0) -> np.ndarray:
    seed = SEED_PRINTED if x0 is None else require_finite("x0", x0)
    if seed.shape != (9,):
        raise InvalidGeometryError(f"x0 must hold the nine unknowns {UNKNOWNS}; got shape {seed.shape}")
    return np.array(seed, dtype=float)


def _one_instant(theta2, omega2, alpha2, x0, variant: str, saw: Saw):
    """The checked inputs of a solve at one instant: θ2, ω2, α2 as floats, the nine-value seed and the
    position equations (:func:`_position`)."""
    theta2 = _scalar("theta2", theta2, "rad")
    motion = (theta2, _scalar("omega2", omega2, "rad/s"), _scalar("alpha2", alpha2, "rad/s²"))
    position = _position(saw, variant)
    seed = _seed(x0)
    _check_assembly(theta2, saw)
    return (*motion, seed, position)


def _course_assembly(x, seed, method: str, theta2) -> None:
    """ConvergenceError, naming the seed, where Newton reached the other assembly: the rod pointing
    right (cos θ3 > 0) instead of left towards the slider."""
    theta3 = np.asarray(x)[..., 2]
    other = np.cos(theta3) > 0
    if np.any(other):
        first = np.flatnonzero(np.ravel(other))[0]
        angle = float(np.ravel(theta2)[first]) if np.ndim(theta2) else float(theta2)
        where = f" (instant {first}, theta2={angle:.6g})" if np.ndim(other) else f" at theta2={angle:.6g}"
        raise ConvergenceError(
            f"{method} Newton from the seed x0={np.round(seed, 6).tolist()} reached the other assembly"
            f"{where}: the rod points right (cos(theta3) > 0, theta3 = {np.ravel(theta3)[first]:.6g} rad); "
            "the course's saw has it pointing left to the slider (theta3 near pi): seed theta3 near pi")


@dataclass(frozen=True)
class SawMotion(Unpacks, Motion):
    """A :class:`~course_lib.mechanism.Motion` of :attr:`Saw.mechanism` (position r1, θ1, θ3; their
    rates; input θ2) that also names its nine values as the course does (:data:`UNKNOWNS`: r1, θ1, θ3,
    v_r, ω1, ω3, a_r, α1, α3) and the crank's θ2.  Unpacks as the nine; ``x`` stacks them on the last
    axis.

    >>> motion = Saw().motion([0.0, 1.0], omega2=6.0)
    >>> np.round(motion.theta3, 6).tolist(), motion.x.shape, np.array(motion).shape
    ([2.873694, 3.248327], (2, 9), (9, 2))
    """

    _values = UNKNOWNS
    _names = MappingProxyType({name: (part, unknown) for part, names in (
        ("velocity", UNKNOWNS[3:6]), ("acceleration", UNKNOWNS[6:]))
        for name, unknown in zip(names, UNKNOWNS[:3], strict=True)})

    @property
    def x(self) -> np.ndarray:
        """The nine unknowns as one array (..., 9), columns ordered as :data:`UNKNOWNS`."""
        return np.stack(np.broadcast_arrays(*(np.asarray(value, dtype=float) for value in self)), axis=-1)

    def as_dict(self) -> dict[str, float | np.ndarray]:
        """The nine values by name.

        >>> round(solve_consecutive(0.0).as_dict()["theta3"], 6)
        2.873694
        """
        return {name: getattr(self, name) for name in UNKNOWNS}


@dataclass(frozen=True)
class SawSolution(SawMotion):
    """:class:`SawMotion` at one crank angle from Newton–Raphson, with the Newton ``iterations`` of all
    ``stages`` (name → ``NewtonResult``) and the ``method``."""

    stages: Mapping[str, NewtonResult] = field(default_factory=dict, repr=False)
    method: str = "simultaneous"


def _saw_motion(saw: Saw, values: np.ndarray, theta2, kind: type[SawMotion] = SawMotion, **extra):
    """The nine values (..., 9) at the crank angles ``theta2`` as a ``kind`` of :class:`SawMotion`."""
    columns = [dict(zip(UNKNOWNS[:3], np.moveaxis(values[..., k:k + 3], -1, 0), strict=True))
               for k in (0, 3, 6)]
    return saw.mechanism._motion(columns[0], {"theta2": theta2}, *columns[1:], kind=kind, **extra)


def solve_consecutive(theta2: float, omega2: float = 0.0, alpha2: float = 0.0, x0=None, tol: float = 1e-6,
                      *, saw: Saw = COURSE_SAW, variant: str = "loop", linear_stages: str = "newton",
                      max_iter: int = 50) -> SawSolution:
    """Newton–Raphson stage by stage ("NR consecutivo") at the crank's ``theta2`` (rad), ``omega2`` (rad/s),
    ``alpha2`` (rad/s²) from ``x0`` (default :data:`SEED_PRINTED`); ``linear_stages="direct"``: the linear
    stages in one step.  ``UnreachableError`` or ``SingularJacobianError`` where the saw cannot move.

    >>> solution = solve_consecutive(0.0)
    >>> [solution.stages[s].iterations for s in ("position", "velocity", "acceleration")]
    [4, 2, 2]
    """
    theta2, omega2, alpha2, seed, position = _one_instant(theta2, omega2, alpha2, x0, variant, saw)
    require_choice("linear_stages", linear_stages, LINEAR_STAGES)
    stages = _core(saw).consecutive([theta2], [omega2], [alpha2], seed, tol=tol, max_iter=max_iter,
                                    linear_stages=linear_stages, position=position)
    x = np.concatenate([stage.x for stage in stages.values()])
    _course_assembly(x, seed, "consecutive", theta2)
    return _saw_motion(saw, x, theta2, SawSolution, stages=MappingProxyType(stages), method="consecutive",
                       iterations=sum(stage.iterations for stage in stages.values()))


def solve_simultaneous(theta2: float, omega2: float = 0.0, alpha2: float = 0.0, x0=None, tol: float = 1e-6,
                       *, saw: Saw = COURSE_SAW, variant: str = "loop", max_iter: int = 50) -> SawSolution:
    """Newton–Raphson on all nine equations at once (the course's "NR simultáneo", 9×9 Jacobian of
    appendix D).  Arguments and errors as :func:`solve_consecutive`.

    >>> solution = solve_simultaneous(0.0, x0=SEED_CODE)
    >>> solution.iterations, bool(np.abs(solution.x[3:]).max() < 1e-12)
    (5, True)
    """
    theta2, omega2, alpha2, seed, position = _one_instant(theta2, omega2, alpha2, x0, variant, saw)
    result = _core(saw).simultaneous([theta2], [omega2], [alpha2], seed, tol=tol, max_iter=max_iter,
                                     position=position)
    _course_assembly(result.x, seed, "simultaneous", theta2)
    return _saw_motion(saw, result.x, theta2, SawSolution, stages=MappingProxyType({"simultaneous": result}),
                       method="simultaneous", iterations=result.iterations, newton=result)


@older_failure_keywords
def analytic(theta2, omega2=0.0, alpha2=0.0, *, saw: Saw = COURSE_SAW, on_failure: str | None = None):
    """The nine unknowns in closed form (the course's eqs. 20–28; its eq. 22, labelled r1, is ω3 and its
    eq. 23, labelled ω3, repeats θ1), shape broadcast(θ2, ω2, α2) + (9,); ``on_failure="nan"`` gives NaN
    rows instead of raising ``UnreachableError``.

    >>> np.round(analytic(0.0)[:3], 6).tolist()
    [-0.099672, -0.468422, 2.873694]
    """
    policy = failure_policy(on_failure)
    theta2 = require_finite("theta2", theta2, unit="rad")
    omega2 = require_finite("omega2", omega2, unit="rad/s")
    alpha2 = require_finite("alpha2", alpha2, unit="rad/s²")
    theta2, omega2, alpha2 = np.broadcast_arrays(theta2, omega2, alpha2)
    sine = _check_assembly(theta2, saw, policy)
    bad = np.abs(sine) > 1.0
    sine = np.where(bad, 0.0, sine)
    r2, r3 = saw.r2, saw.r3
    s2, c2 = np.sin(theta2), np.cos(theta2)
    r1, theta1, theta3 = _closed_position(sine, theta2, saw)  # (20), (21)
    s3, c3 = np.sin(theta3), np.cos(theta3)
    c1, tan1 = np.cos(theta1), np.tan(theta1)
    omega3 = -omega2 * r2 * c2 / (r3 * c3)  # (the report's 22)
    v_r = -c1 * (omega2 * r2 * s2 + omega3 * r3 * s3)  # (25)
    omega1 = -v_r * tan1 / r1  # (24)
    alpha3 = (r2 * s2 * omega2**2 + r3 * s3 * omega3**2 - alpha2 * r2 * c2) / (r3 * c3)  # (26)
    a_r = (r1 * omega1**2 - r2 * c1 * c2 * omega2**2 - r3 * c1 * c3 * omega3**2
           - alpha2 * r2 * c1 * s2 - alpha3 * r3 * c1 * s3)  # (28)
    alpha1 = omega1**2 * tan1 - (2 * v_r * omega1 + a_r * tan1) / r1  # (27)
    values = np.stack([r1, theta1, theta3, v_r, omega1, omega3, a_r, alpha1, alpha3], axis=-1)
    return np.where(bad[..., None], np.nan, values)


def joint_positions(theta2, *, saw: Saw = COURSE_SAW) -> np.ndarray:
    """Crank pivot O2, crank pin A and slider pin C (m), shape (..., 3, 2), for drawing: the declaration's
    points (:attr:`Saw.mechanism`) at :meth:`Saw.motion`'s position, in declared order (the older spelling
    of ``saw.mechanism.joints(saw.motion(theta2))``, which gives them by name).

    >>> np.round(joint_positions(0.0), 4).tolist()
    [[0.0, 0.0], [0.075, 0.0], [-0.0889, 0.045]]
    """
    saw = _checked_saw(saw)
    return np.stack(np.broadcast_arrays(*saw.mechanism.joints(saw.motion(theta2)).values()), axis=-2)


@dataclass(frozen=True)
class SawSweep(SawMotion):
    """:class:`SawMotion` at the times ``t`` (s) of the motor profile, with the motor's ``omega2``,
    ``alpha2``, the Newton ``iterations`` per point, ``stage_iterations`` (n, stages) and the ``method``.

    >>> result = sweep(5, method="analytic")
    >>> result.x.shape, result.theta2.shape, list(result.position)
    ((5, 9), (5,), ['r1', 'theta1', 'theta3'])
    """

    t: np.ndarray | None = None
    omega2: np.ndarray | None = None
    alpha2: np.ndarray | None = None
    stage_iterations: np.ndarray | None = None
    method: str = "analytic"


def sweep(n: int = 1000, method: str = "simultaneous", *, tol: float = 1e-6, x0=None, saw: Saw = COURSE_SAW,
          variant: str = "loop", linear_stages: str = "newton", t_end: float | None = None) -> SawSweep:
    """The saw at ``n`` times on [0, ``t_end``] (default 2T ≈ 3.883 s) of the motor profile: ``method``
    "consecutive" or "simultaneous" (point by point, each seeded with the previous solution), "batched"
    (all points at once from ``x0``) or "analytic".

    >>> result = sweep(50, method="consecutive")
    >>> bool(np.allclose(result.x, sweep(50, method="analytic").x, atol=1e-9))
    True
    """
    require_choice("method", method, METHODS)
    require_choice("variant", variant, VARIANTS)
    require_choice("linear_stages", linear_stages, LINEAR_STAGES)
    integer = isinstance(n, int | np.integer | float | np.floating) and not isinstance(n, bool)
    if not (integer and np.isfinite(n) and int(n) == n and n >= 2):
        raise InvalidGeometryError(f"n must be an integer number of points >= 2; got {n!r}")
    n = int(n)
    end = 2 * first_turn_time() if t_end is None else require_positive("t_end", t_end)
    t = np.linspace(0.0, end, n)
    theta2, omega2, alpha2 = motor_profile(t)
    seed = _seed(x0)
    _check_assembly(theta2, saw)
    if method == "analytic":
        values = analytic(theta2, omega2, alpha2, saw=saw)
        stage_iterations = np.zeros((n, 0), dtype=int)
    elif method == "batched":
        stages = _core(saw).consecutive(*_motion(theta2, omega2, alpha2), seed, tol=tol,
                                        linear_stages=linear_stages, position=_position(saw, variant))
        values = np.concatenate([stage.x for stage in stages.values()], axis=1)
        _course_assembly(values, seed, "batched", theta2)
        stage_iterations = np.stack([stage.iterations for stage in stages.values()], axis=1)
    else:
        values = np.empty((n, 9))
        stage_iterations = np.empty((n, 3 if method == "consecutive" else 1), dtype=int)
        solve = solve_consecutive if method == "consecutive" else solve_simultaneous
        options = {"linear_stages": linear_stages} if method == "consecutive" else {}
        for k in range(n):
            solution = solve(theta2[k], omega2[k], alpha2[k], seed, tol, saw=saw, variant=variant, **options)
            values[k] = seed = solution.x
            stage_iterations[k] = [stage.iterations for stage in solution.stages.values()]
    return _saw_motion(saw, values, theta2, SawSweep, iterations=stage_iterations.sum(axis=1), t=t,
                       omega2=omega2, alpha2=alpha2, stage_iterations=stage_iterations, method=method)
