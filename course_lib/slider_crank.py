"""The offset slider-crank in the textbook's Cartesian form (SI units, radians).

The crank (``crank``, θ2) turns about the origin O2; the rod (``rod``, θ3 from the crank pin A to the
slider pin C, lesson 00's name for it) drives C = A + rod·(cos θ3, sin θ3) = (x, offset) along the line
y = ``offset``, with x = crank·cos θ2 ± √(rod² − (offset − crank·sin θ2)²): ``branch="right"`` (θ3 in
(−π/2, π/2)) or ``"left"`` (θ3 in (π/2, 3π/2), the course's power saw, :mod:`course_lib.saw` with
x = r1 cos θ1).  The machine is one declaration (:attr:`OffsetSliderCrank.mechanism`: the loop, the
points O2, A, C and the links crank, rod), which gives the rates and the singularity rule (the core's).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache, cached_property
from types import MappingProxyType

import numpy as np

from .errors import (
    SingularJacobianError,
    failure_policy,
    report_unreachable,
    require_broadcast,
    require_choice,
    require_finite,
    require_positive,
)
from .motion import Motion
from .planar import Unpacks

__all__ = ["OffsetSliderCrank", "SliderCrankMotion", "BRANCHES", "ASSEMBLIES"]

#: Assemblies of the slider-crank: slider pin to the right or to the left of the crank pin.
BRANCHES = ("right", "left")
#: The assemblies by name, as the core's σ (``assembly=``): left (the saw's) is σ = +1.
ASSEMBLIES = {"left": {"x": +1}, "right": {"x": -1}}


@cache
def _declaration():
    """The loop C = A + rod·(cos θ3, sin θ3) on the core: unknowns θ3 and x, input θ2; the points O2, A,
    C and the links crank, rod."""
    import sympy as sp

    from .mechanism import Mechanism

    theta2, theta3, x, crank, rod, offset = sp.symbols("theta2 theta3 x crank rod offset")
    loop = sp.Matrix([crank * sp.cos(theta2) + rod * sp.cos(theta3) - x,
                      crank * sp.sin(theta2) + rod * sp.sin(theta3) - offset])
    points = {"O2": sp.Matrix([0, 0]), "A": sp.Matrix([crank * sp.cos(theta2), crank * sp.sin(theta2)]),
              "C": sp.Matrix([x, offset])}
    return Mechanism([loop], [theta3, x], [theta2], {crank: 0.075, rod: 0.170, offset: 0.045},
                     points=points, links={"crank": ("O2", "A"), "rod": ("A", "C")}, ground=("O2",),
                     sliders=("C",))


@dataclass(frozen=True)
class SliderCrankMotion(Unpacks, Motion):
    """A :class:`~course_lib.mechanism.Motion` of :attr:`OffsetSliderCrank.mechanism` (position θ3, x;
    their rates; input θ2) that also names its values: rod angle θ3 (rad), slider position x (m), ω3
    (rad/s), slider velocity v (m/s), α3 (rad/s²) and slider acceleration a (m/s²), broadcast from the
    inputs.  Unpacks in that order.

    >>> motion = OffsetSliderCrank(0.05, 0.2).solve([0.0, np.pi / 2], omega2=1.0)
    >>> np.array(motion).shape, motion.v.tolist() == motion.velocity["x"].tolist()
    ((6, 2), True)
    """

    _values = ("theta3", "x", "omega3", "v", "alpha3", "a")
    _names = MappingProxyType({"omega3": ("velocity", "theta3"), "v": ("velocity", "x"),
                               "alpha3": ("acceleration", "theta3"), "a": ("acceleration", "x")})


@dataclass(frozen=True)
class OffsetSliderCrank:
    """Crank pivot at the origin, slider pin on the line y = ``offset`` (lengths in metres).

    >>> motion = OffsetSliderCrank(crank=0.075, rod=0.170, offset=0.045).solve(0.0, branch="left")
    >>> round(float(motion.x), 6), round(float(motion.theta3), 6)
    (-0.088936, 2.873694)
    """

    crank: float
    rod: float
    offset: float = 0.0

    def __post_init__(self) -> None:
        object.__setattr__(self, "crank", require_positive("crank", self.crank))
        object.__setattr__(self, "rod", require_positive("rod", self.rod))
        object.__setattr__(self, "offset", float(require_finite("offset", self.offset, unit="metres")))

    @cached_property
    def mechanism(self):
        """The machine as one declaration on :class:`~course_lib.mechanism.Mechanism` with these lengths:
        the loop (unknowns θ3, x; input θ2), the points O2, A, C and the links crank, rod.

        >>> mechanism = OffsetSliderCrank(0.075, 0.170, 0.045).mechanism
        >>> list(mechanism.points), mechanism.links.names
        (['O2', 'A', 'C'], ('crank', 'rod'))
        """
        return _declaration().with_parameters({"crank": self.crank, "rod": self.rod, "offset": self.offset})

    def motion(self, theta2, omega2=0.0, alpha2=0.0, branch: str = "right", *, on_failure: str | None = None):
        """:meth:`solve` under the name the declarations use: its :class:`SliderCrankMotion` is a
        :class:`~course_lib.mechanism.Motion` of :attr:`mechanism`, to draw, animate or explore.

        >>> motion = OffsetSliderCrank(0.05, 0.2).motion([0.0, np.pi / 2], omega2=1.0)
        >>> np.round(motion.velocity["x"], 6).tolist(), motion.singular.tolist()
        ([0.0, -0.05], [False, False])
        """
        return self.solve(theta2, omega2, alpha2, branch=branch, on_failure=on_failure)

    def joints(self, theta2, branch: str = "right") -> np.ndarray:
        """O2, A and C (m), shape (..., 3, 2): the declaration's points at the solved position.

        >>> OffsetSliderCrank(0.05, 0.2).joints(np.pi / 2).round(6).tolist()
        [[0.0, 0.0], [0.0, 0.05], [0.193649, 0.0]]
        """
        points = self.mechanism.joints(self.solve(theta2, branch=branch))
        return np.stack(np.broadcast_arrays(*points.values()), axis=-2)

    def solve(self, theta2, omega2=0.0, alpha2=0.0, branch: str = "right", *, assembly=None,
              on_failure: str | None = None) -> SliderCrankMotion:
        """Position, velocity and acceleration of rod and slider for the crank's θ2 (rad), ω2 (rad/s),
        α2 (rad/s²), vectorized.  ``UnreachableError`` where |offset − crank·sin θ2| > rod,
        ``SingularJacobianError`` where the rod is perpendicular to the line (cos θ3 = 0: the declared
        loop's J singular by the core's rule); ``on_failure="nan"``: NaN there instead.  The assembly:
        ``assembly="left"`` or ``"right"``, or the core's σ (``{"x": +1}`` is left); ``branch=`` is its
        older name.

        >>> motion = OffsetSliderCrank(0.05, 0.2).solve(np.pi / 2, omega2=1.0)
        >>> round(float(motion.v), 6), round(float(motion.omega3), 6)
        (-0.05, 0.0)
        """
        require_choice("branch", branch, BRANCHES)
        branch = self.mechanism.assembly_named(assembly, ASSEMBLIES, branch, "right")
        policy = failure_policy(on_failure)
        theta2, omega2, alpha2 = require_broadcast(theta2=require_finite("theta2", theta2, unit="rad"),
                                                   omega2=require_finite("omega2", omega2, unit="rad/s"),
                                                   alpha2=require_finite("alpha2", alpha2, unit="rad/s²"))
        a2, b3 = self.crank, self.rod
        s2, c2 = np.sin(theta2), np.cos(theta2)
        height = self.offset - a2 * s2  # vertical rise of the rod from A to B
        unreachable = np.abs(height) > b3
        report_unreachable(unreachable, {"theta2": theta2},
                           f"the rod ({b3:g} m) cannot reach the slider line y = {self.offset:g} m", policy)
        reach = np.sqrt(np.where(unreachable, np.nan, np.maximum(b3**2 - height**2, 0.0)))  # horizontal run
        run = reach if branch == "right" else -reach
        x = a2 * c2 + run
        theta3 = np.arctan2(height, run)
        if branch == "left":
            theta3 = np.mod(theta3, 2 * np.pi)  # keep θ3 in (π/2, 3π/2)
        with np.errstate(invalid="ignore"):
            velocity, acceleration, singular = self.mechanism.rates(
                np.stack([theta3, x], axis=-1), theta2[..., None], omega2[..., None], alpha2[..., None],
                trig={"theta2": (c2, s2), "theta3": (run / b3, height / b3)})
        perpendicular = singular & ~unreachable
        if policy == "raise" and np.any(perpendicular):
            first = float(theta2[perpendicular].ravel()[0])
            raise SingularJacobianError(f"the rod is perpendicular to the slider line at theta2={first:.6g} "
                                        "(cos(theta3) = 0): the velocity equations are singular there",
                                        x=first)
        (omega3, v), (alpha3, a) = np.moveaxis(velocity, -1, 0), np.moveaxis(acceleration, -1, 0)
        return self.mechanism._motion({"theta3": theta3, "x": x}, {"theta2": theta2},
                                        {"theta3": omega3, "x": v}, {"theta3": alpha3, "x": a},
                                        converged=~unreachable, singular=perpendicular,
                                        kind=SliderCrankMotion)
