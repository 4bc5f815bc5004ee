"""Choosing an assembly by σ (``Mechanism.solve(..., assembly=...)``) instead of by a numeric guess: σ = +1
and −1 are the two roots of the half-angle quadratic the core derives, told apart by σ = −sign(det J_b) —
for the four-bar, open (B left of the line A → O4) is +1 — checked against circle intersections and cross
products computed here.
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


@pytest.mark.parametrize("key", [th4, "theta4", th3, "theta3"])
@pytest.mark.parametrize(("sigma", "branch"), [(+1, "open"), (-1, "crossed")])
def test_sigma_picks_the_branch_the_course_names(sigma, branch, key):
    theta2 = np.radians(np.arange(0.0, 360.0, 15.0))
    motion = WIPER.solve({th2: theta2}, assembly={key: sigma})
    A, B = fourbar_pins(0.20, 0.06, 0.18, 0.12, theta2, branch)
    theta4 = np.arctan2(B[:, 1], B[:, 0] - 0.20)
    assert np.abs(np.angle(np.exp(1j * (motion.position["theta4"] - theta4)))).max() < 1e-12
    assert set(np.ravel(motion.assembly["theta4"])) == set(np.ravel(motion.assembly["theta3"])) == {sigma}
    # the stated meaning: σ = +1 where B lies left of the directed line A → O4
    to_O4, to_B = np.array([0.20, 0.0]) - A, B - A
    assert set(np.sign(to_O4[:, 0] * to_B[:, 1] - to_O4[:, 1] * to_B[:, 0])) == {sigma}


def test_two_keys_of_one_block_must_agree():
    with pytest.raises(InvalidGeometryError, match="two σ for one block"):
        WIPER.solve({th2: 1.0}, assembly={"theta3": 1, "theta4": -1})
    assert WIPER.solve({th2: 1.0}, assembly={"theta3": -1, "theta4": -1}).assembly["theta4"] == -1


@pytest.mark.parametrize("assembly", [{"theta2": 1}, {"theta4": 0}, {"theta4": True}, [1], {"x": -1},
                                      {"theta4": 1j}, {"theta4": "1"}])
def test_a_wrong_assembly_is_refused_by_name(assembly):
    with pytest.raises(InvalidGeometryError, match="assembly"):
        WIPER.solve({th2: 1.0}, assembly=assembly)
