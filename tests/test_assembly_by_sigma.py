"""Choosing an assembly by σ (``Mechanism.solve(..., assembly=...)``) instead of by a numeric guess: σ = +1
and −1 are the two roots of the half-angle quadratic the core derives, checked against circle intersections.
"""

import numpy as np
import pytest
import sympy as sp
from geometry import fourbar_pins

from course_lib.errors import InvalidGeometryError
from course_lib.mechanism import Mechanism

th2, th3, th4 = sp.symbols("theta2 theta3 theta4", real=True)
l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
LOOP = sp.Matrix([l2 * sp.cos(th2) + l3 * sp.cos(th3) - l4 * sp.cos(th4) - l1,
                  l2 * sp.sin(th2) + l3 * sp.sin(th3) - l4 * sp.sin(th4)])
WIPER = Mechanism([LOOP], [th3, th4], [th2], {l1: 0.20, l2: 0.06, l3: 0.18, l4: 0.12})


@pytest.mark.parametrize(("sigma", "branch"), [(+1, "crossed"), (-1, "open")])
def test_sigma_picks_the_branch_the_course_names(sigma, branch):
    theta2 = np.radians(np.arange(0.0, 360.0, 15.0))
    motion = WIPER.solve({th2: theta2}, assembly={th4: sigma})
    _, B = fourbar_pins(0.20, 0.06, 0.18, 0.12, theta2, branch)
    theta4 = np.arctan2(B[:, 1], B[:, 0] - 0.20)
    assert np.abs(np.angle(np.exp(1j * (motion.position["theta4"] - theta4)))).max() < 1e-12
    assert set(np.ravel(motion.assembly["theta4"])) == {sigma}


@pytest.mark.parametrize("assembly", [{"theta3": 1}, {"theta4": 0}, {"theta4": True}, [1], {"x": -1}])
def test_a_wrong_assembly_is_refused_by_name(assembly):
    with pytest.raises(InvalidGeometryError, match="assembly"):
        WIPER.solve({th2: 1.0}, assembly=assembly)
