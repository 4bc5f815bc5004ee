"""Mechanism.point_motion: every declared point's velocity and acceleration, from its declaration
differentiated in time, checked against central differences of the point's own path (an independent route)."""

import numpy as np
import pytest
import sympy as sp

from course_lib.errors import InvalidGeometryError
from course_lib.fourbar import FourBar
from course_lib.mechanism import Mechanism

th2, th4, r4 = sp.symbols("theta2 theta4 r4", real=True)
r2, d = sp.symbols("r2 d", positive=True)
LEVER = sp.Matrix([r2 * sp.cos(th2) - r4 * sp.cos(th4), d + r2 * sp.sin(th2) - r4 * sp.sin(th4)])
QUICK_RETURN = Mechanism([LEVER], [th4, r4], [th2], {r2: 0.05, d: 0.10},
                         points={"O4": sp.zeros(2, 1), "O2": sp.Matrix([0, d]),
                                 "A": r4 * sp.Matrix([sp.cos(th4), sp.sin(th4)]),
                                 "B": 0.3 * sp.Matrix([sp.cos(th4), sp.sin(th4)])},
                         links=[("O2", "A"), ("O4", "B")])


def path(mechanism, theta2, omega2, alpha2, guess, t):
    """The points at θ2(t) = θ2 + ω2 t + α2 t²/2."""
    motion = mechanism.solve({"theta2": theta2 + omega2 * t + alpha2 * t**2 / 2}, guess=guess)
    return mechanism.joints(motion)


@pytest.mark.parametrize(("mechanism", "guess"), [(FourBar(0.06, 0.18, 0.12, 0.20).mechanism, None),
                                                  (QUICK_RETURN, {"theta4": 1.0, "r4": 0.1})])
@pytest.mark.parametrize(("theta2", "omega2", "alpha2"),
                         [(0.3, 10.0, 0.0), (2.0, -4.0, 25.0), (4.5, 7.0, -12.0)])
def test_point_rates_are_the_derivatives_of_the_points_paths(mechanism, guess, theta2, omega2, alpha2):
    h = 1e-4
    ahead, here, behind = (path(mechanism, theta2, omega2, alpha2, guess, t) for t in (h, 0.0, -h))
    motion = mechanism.solve({"theta2": theta2}, rates={"theta2": omega2}, accelerations={"theta2": alpha2},
                             guess=guess)
    points = mechanism.point_motion(motion, rates={"theta2": omega2}, accelerations={"theta2": alpha2})
    for name, (position, velocity, acceleration) in points.items():
        assert np.abs(position - here[name]).max() < 1e-15
        assert np.abs(velocity - (ahead[name] - behind[name]) / (2 * h)).max() < 1e-6
        assert np.abs(acceleration - (ahead[name] - 2 * here[name] + behind[name]) / h**2).max() < 1e-3


def test_a_motion_without_rates_is_refused_by_name():
    wiper = FourBar(0.06, 0.18, 0.12, 0.20).mechanism
    with pytest.raises(InvalidGeometryError, match="rates"):
        wiper.point_motion(wiper.solve({"theta2": 1.0}))
