"""The offset slider-crank in the textbook's Cartesian form (SI units, radians).

The crank (``crank``, θ2) turns about the origin O2; the rod (``rod``, θ3 from the crank pin A to the
slider pin C, lesson 00's name for it) drives C = A + rod·(cos θ3, sin θ3) = (xC, offset) along the line
y = ``offset``, with xC = crank·cos θ2 ± √(rod² − (offset − crank·sin θ2)²): ``assembly="right"`` (C right
of A: cos θ3 > 0) or ``"left"`` (cos θ3 < 0, the course's power saw, :mod:`course_lib.saw` with
xC = r1 cos θ1).  The machine is one declaration (:attr:`OffsetSliderCrank.mechanism`: the loop, the
points O2, A, C and the links crank, rod), solved by the core (its closed form registered as the
block's kernel), which gives the rates and the singularity rule.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache, cached_property
from types import MappingProxyType

import numpy as np

from .errors import (
    failure_policy,
    require_broadcast,
    require_choice,
    require_finite,
    require_positive,
)
from .motion import Motion, recast
from .motion import machine_joints as _machine_joints
from .planar import Unpacks
from .thresholds import LEVEL

__all__ = ["OffsetSliderCrank", "SliderCrankMotion", "BRANCHES", "ASSEMBLIES"]

#: Assemblies of the slider-crank: slider pin to the right or to the left of the crank pin.
BRANCHES = ("right", "left")
#: The assemblies by name, as the core's σ (``assembly=``): left (the saw's) is σ = +1.
ASSEMBLIES = {"left": {"xC": +1}, "right": {"xC": -1}}


def _kernel(parameters, known, sigma):
    """The block θ3, xC in closed form (the kernel registered on the declaration, see
    :meth:`~course_lib.mechanism.Mechanism.with_kernel`): the rod rises h = offset − crank·sin θ2 from A to
    C and runs ∓√(rod² − h²) along the line, σ = +1 (left, the saw's) the minus sign; θ3 = atan2(h, run),
    xC = crank·cos θ2 + run.  NaN where |h| > rod; the level 1 − (h / rod)² (the derived closed form's)."""
    crank, rod, offset = parameters["crank"], parameters["rod"], parameters["offset"]
    theta2 = known["theta2"]
    height = offset - crank * np.sin(theta2)
    level = 1.0 - (height / rod) ** 2
    run = np.sqrt(np.where(level < -LEVEL, np.nan, rod * rod * np.maximum(level, 0.0)))
    run = -sigma * run  # σ = ±1, or one per instant
    return {"theta3": np.arctan2(height, run), "xC": crank * np.cos(theta2) + run}, level


@cache
def _declaration():
    """The loop C = A + rod·(cos θ3, sin θ3) on the core: unknowns θ3 and xC (the slider pin's x, x_C),
    input θ2; the points O2, A, C and the links crank, rod."""
    import sympy as sp

    from .mechanism import Mechanism

    theta2, theta3, xC, crank, rod, offset = sp.symbols("theta2 theta3 xC crank rod offset")
    loop = sp.Matrix([crank * sp.cos(theta2) + rod * sp.cos(theta3) - xC,
                      crank * sp.sin(theta2) + rod * sp.sin(theta3) - offset])
    points = {"O2": sp.Matrix([0, 0]), "A": sp.Matrix([crank * sp.cos(theta2), crank * sp.sin(theta2)]),
              "C": sp.Matrix([xC, offset])}
    return Mechanism([loop], [theta3, xC], [theta2], {crank: 0.075, rod: 0.170, offset: 0.045},
                     points=points, links={"crank": ("O2", "A"), "rod": ("A", "C")}, ground=("O2",),
                     sliders=("C",))


@dataclass(frozen=True)
class SliderCrankMotion(Unpacks, Motion):
    """A :class:`~course_lib.mechanism.Motion` of :attr:`OffsetSliderCrank.mechanism` (position θ3, xC;
    their rates; input θ2) that also names its values: rod angle θ3 (rad), slider position xC (m), ω3
    (rad/s), slider velocity v_xC (m/s), α3 (rad/s²) and slider acceleration a_xC (m/s²), broadcast from
    the inputs.  Unpacks in that order.  ``x``, ``v``, ``a`` are the older names of xC, v_xC, a_xC.

    >>> motion = OffsetSliderCrank(0.05, 0.2).solve([0.0, np.pi / 2], omega2=1.0)
    >>> np.array(motion).shape, motion.v_xC.tolist() == motion.velocity["xC"].tolist()
    ((6, 2), True)
    """

    _values = ("theta3", "xC", "omega3", "v_xC", "alpha3", "a_xC")
    _names = MappingProxyType({"omega3": ("velocity", "theta3"), "v_xC": ("velocity", "xC"),
                               "alpha3": ("acceleration", "theta3"), "a_xC": ("acceleration", "xC"),
                               # older names (glossary: "Older spellings")
                               "x": ("position", "xC"), "v": ("velocity", "xC"), "a": ("acceleration", "xC")})


@dataclass(frozen=True)
class OffsetSliderCrank:
    """Crank pivot at the origin, slider pin on the line y = ``offset`` (lengths in metres).

    >>> motion = OffsetSliderCrank(crank=0.075, rod=0.170, offset=0.045).solve(0.0, branch="left")
    >>> round(float(motion.xC), 6), round(float(motion.theta3), 6)
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
        the loop (unknowns θ3, xC; input θ2), the points O2, A, C and the links crank, rod.

        >>> mechanism = OffsetSliderCrank(0.075, 0.170, 0.045).mechanism
        >>> list(mechanism.points), mechanism.links.names
        (['O2', 'A', 'C'], ('crank', 'rod'))
        """
        return _declaration().with_parameters({"crank": self.crank, "rod": self.rod,
                                               "offset": self.offset}).with_kernel("theta3", _kernel)

    def motion(self, theta2, omega2=0.0, alpha2=0.0, branch: str = "right", *, on_failure: str | None = None):
        """:meth:`solve` under the name the declarations use: its :class:`SliderCrankMotion` is a
        :class:`~course_lib.mechanism.Motion` of :attr:`mechanism`, to draw, animate or explore.

        >>> motion = OffsetSliderCrank(0.05, 0.2).motion([0.0, np.pi / 2], omega2=1.0)
        >>> np.round(motion.velocity["xC"], 6).tolist(), motion.singular.tolist()
        ([0.0, -0.05], [False, False])
        """
        return self.solve(theta2, omega2, alpha2, branch=branch, on_failure=on_failure)

    def joints(self, motion, branch: str = "right"):
        """The points O2, A and C (m) of a solved ``motion``, by name (``self.mechanism.joints(motion)``).
        The older spelling ``joints(theta2, branch)`` solves at θ2 and stacks them, shape (..., 3, 2).

        >>> slider = OffsetSliderCrank(0.05, 0.2)
        >>> slider.joints(slider.solve(np.pi / 2))["C"].round(6).tolist(), slider.joints(np.pi / 2).shape
        ([0.193649, 0.0], (3, 2))
        """
        return _machine_joints(self, motion, lambda: self.mechanism.joints(self.solve(motion, branch=branch)))

    def solve(self, theta2, omega2=0.0, alpha2=0.0, branch: str = "right", *, assembly=None,
              on_failure: str | None = None) -> SliderCrankMotion:
        """Position, velocity and acceleration of rod and slider for the crank's θ2 (rad), ω2 (rad/s),
        α2 (rad/s²), vectorized: the core's solve of :attr:`mechanism` (its block θ3, xC solved by the
        closed form :func:`_kernel`), the same :class:`~course_lib.mechanism.Motion` as
        ``self.mechanism.solve`` with the course's names added.  ``UnreachableError`` where
        |offset − crank·sin θ2| > rod, ``SingularJacobianError`` while moving where the rod is
        perpendicular to the line (cos θ3 = 0: J singular by the core's rule); ``on_failure="nan"``: NaN
        there instead.  At rest (ω2 = α2 = 0) the rates are 0.  The assembly: ``assembly="left"`` or
        ``"right"``, or the core's σ (``{"xC": +1}`` is left); ``branch=`` is its older name.  Angles
        follow the core's rule: the first instant's in [−π, π], each next within a turn of its neighbour.

        >>> motion = OffsetSliderCrank(0.05, 0.2).solve(np.pi / 2, omega2=1.0)
        >>> round(float(motion.v_xC), 6), round(float(motion.omega3), 6)
        (-0.05, 0.0)
        """
        require_choice("branch", branch, BRANCHES)
        branch = self.mechanism.assembly_named(assembly, ASSEMBLIES, branch, "right")
        policy = failure_policy(on_failure)
        theta2, omega2, alpha2 = require_broadcast(theta2=require_finite("theta2", theta2, unit="rad"),
                                                   omega2=require_finite("omega2", omega2, unit="rad/s"),
                                                   alpha2=require_finite("alpha2", alpha2, unit="rad/s²"))
        moving = bool(np.any(omega2) or np.any(alpha2))
        motion = self.mechanism.solve({"theta2": theta2}, {"theta2": omega2} if moving else None,
                                      {"theta2": alpha2} if moving else None, assembly=ASSEMBLIES[branch],
                                      on_failure=policy)
        return recast(motion, SliderCrankMotion, at_rest=not moving)
