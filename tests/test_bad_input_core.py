"""The core answers a bad input by name, never silently or with a raw traceback: a parameter given twice,
a masked array, a bad tol or max_iter, a symbol that collides with the core's own names, a motion_of of
values that do not close the loops, and values looked up by a name or Symbol that is not there."""

import numpy as np
import pytest
import sympy as sp

from course_lib.errors import InvalidArgumentError, InvalidGeometryError
from course_lib.fourbar import FourBar
from course_lib.mechanism import Mechanism

th2, th3, th4 = sp.symbols("theta2 theta3 theta4")
l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
LOOP = sp.Matrix([l2 * sp.cos(th2) + l3 * sp.cos(th3) - l4 * sp.cos(th4) - l1,
                  l2 * sp.sin(th2) + l3 * sp.sin(th3) - l4 * sp.sin(th4)])
NUMBERS = {l1: 0.20, l2: 0.06, l3: 0.18, l4: 0.12}
WIPER = Mechanism([LOOP], [th3, th4], [th2], NUMBERS)
COS = sp.Symbol("_cos_theta2")

CASES = {
    "a parameter twice": (lambda: Mechanism([LOOP], [th3, th4], [th2], {**NUMBERS, "l1": 0.3}),
                          InvalidGeometryError, "parameters gives l1 twice"),
    "a masked array": (lambda: WIPER.solve({th2: np.ma.masked_array([0.1, 0.2], mask=[False, True])}),
                       InvalidGeometryError, r"inputs\[theta2\] must be a plain array, not a masked one"),
    **{f"tol={value!r}": (lambda value=value: WIPER.solve({th2: 1.0}, tol=value), InvalidArgumentError,
                          "tol must be a positive number") for value in ("1e-9", -1, float("nan"), True)},
    **{f"max_iter={value!r}": (lambda value=value: WIPER.solve({th2: 1.0}, max_iter=value),
                               InvalidArgumentError, "max_iter must be") for value in ("5", -1, 2.5, 10**9)},
    "the core's own name": (lambda: Mechanism([LOOP.subs(l1, COS)], [th3, th4], [th2],
                                              {l2: 0.06, l3: 0.18, l4: 0.12, COS: 0.2}),
                            InvalidGeometryError, "leading underscore are the core's own.*_cos_theta2"),
    "a name not there": (lambda: WIPER.solve({th2: 1.0}, assembly={"theta4": 1})["theta9"],
                         InvalidArgumentError, "no value named 'theta9'"),
    "a machine's name not there": (lambda: FourBar(0.06, 0.18, 0.12, 0.20).solve(1.0)["omega9"],
                                   InvalidArgumentError, "no value named 'omega9'"),
}


@pytest.mark.parametrize("case", CASES)
def test_a_bad_input_is_named(case):
    call, error, says = CASES[case]
    with pytest.raises(error, match=says):
        call()


def test_motion_of_values_that_do_not_close_the_loops_is_not_converged():
    # B from circles (closing) and a made-up pair (not closing), at θ2 = 1
    A = 0.06 * np.array([np.cos(1.0), np.sin(1.0)])
    O4 = np.array([0.20, 0.0])
    d = np.linalg.norm(O4 - A)
    base = np.arctan2(*(A - O4)[::-1])
    turn = np.arccos((0.12**2 + d**2 - 0.18**2) / (2 * 0.12 * d))
    theta4 = base - turn  # one of the two pins B, from the triangle O4, A, B
    B = O4 + 0.12 * np.array([np.cos(theta4), np.sin(theta4)])
    theta3 = np.arctan2(*(B - A)[::-1])
    motion = WIPER.motion_of({"theta3": [theta3, 0.0], "theta4": [theta4, 0.0]}, {"theta2": 1.0})
    assert motion.converged.tolist() == [True, False]


def test_values_by_name_or_symbol_and_a_machines_result_by_name():
    motion = WIPER.solve({th2: 1.0}, rates={th2: 2.0}, assembly={"theta4": 1})
    assert motion["theta4"] == motion[th4] == motion.position["theta4"] and motion["theta2"] == 1.0
    solution = FourBar(0.06, 0.18, 0.12, 0.20).solve(1.0, 2.0)
    assert solution["theta4"] == solution[1] == solution.theta4 and solution["omega4"] == solution.omega4
    with pytest.raises(TypeError):
        iter(motion)  # a plain Motion has values by name only
