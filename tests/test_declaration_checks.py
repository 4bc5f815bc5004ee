"""A declaration checks itself: a declared point that stretches its link is named, a misspelt keyword gets
"did you mean", sympy numbers are numbers, an empty sweep is an empty motion, and with_parameters takes a
partial update.  References: the wiper's loop and circle intersections computed here."""

import numpy as np
import pytest
import sympy as sp
from geometry import fourbar_pins

from course_lib.errors import (
    InvalidArgumentError,
    InvalidGeometryError,
    SingularJacobianError,
    UnreachableError,
)
from course_lib.mechanism import Mechanism

th2, th3, th4 = sp.symbols("theta2 theta3 theta4")
l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
LOOP = sp.Matrix([l2 * sp.cos(th2) + l3 * sp.cos(th3) - l4 * sp.cos(th4) - l1,
                  l2 * sp.sin(th2) + l3 * sp.sin(th3) - l4 * sp.sin(th4)])
NUMBERS = {l1: 0.20, l2: 0.06, l3: 0.18, l4: 0.12}
A = sp.Matrix([l2 * sp.cos(th2), l2 * sp.sin(th2)])


def wiper(B, **more):
    points = {"O2": sp.zeros(2, 1), "A": A, "B": B, "O4": sp.Matrix([l1, 0]), **more}
    return Mechanism([LOOP], [th3, th4], [th2], NUMBERS, points=points,
                     links={"crank": ("O2", "A"), "coupler": ("A", "B"), "rocker": ("O4", "B")},
                     plates={"coupler": ("A", "B", "P")} if "P" in more else None)


B = sp.Matrix([l1 + l4 * sp.cos(th4), l4 * sp.sin(th4)])


def test_a_point_written_with_the_wrong_unknown_is_named_by_its_link():
    typo = wiper(sp.Matrix([l1 + l4 * sp.cos(th3), l4 * sp.sin(th4)]))  # θ3 where θ4 belongs
    says = r"links: coupler \(A–B\) changes length .* points\['A'\] or points\['B'\] is not where the loops"
    with pytest.raises(InvalidGeometryError, match=says):
        typo.solve({th2: np.linspace(0, 6, 13)}, assembly={"theta4": 1})
    right = wiper(B).solve({th2: np.linspace(0, 6, 13)}, assembly={"theta4": 1})
    _, B_circles = fourbar_pins(0.20, 0.06, 0.18, 0.12, np.linspace(0, 6, 13), "open")
    assert np.abs(wiper(B).joints(right)["B"] - B_circles).max() < 1e-12


def test_a_plate_that_is_not_rigid_is_named_by_its_side():
    P = A + sp.Matrix([0.05 * sp.cos(th4), 0.05 * sp.sin(th4)])  # on the crank's pin but turning with θ4
    with pytest.raises(InvalidGeometryError, match=r"plate 'coupler' side (BP|PA)"):
        wiper(B, P=P).solve({th2: [0.5, 1.0]}, assembly={"theta4": 1})
    rigid = A + sp.Matrix([0.05 * sp.cos(th3 + 0.7), 0.05 * sp.sin(th3 + 0.7)])  # turns with the coupler
    assert wiper(B, P=rigid).solve({th2: [0.5, 1.0]}, assembly={"theta4": 1}).converged.all()


@pytest.mark.parametrize(("call", "says"), [
    (lambda: Mechanism([LOOP], unknown=[th3, th4], inputs=[th2], parameters=NUMBERS),
     "Mechanism takes no keyword unknown= (did you mean unknowns=?)"),
    (lambda: Mechanism([LOOP], [th3, th4], [th2], params=NUMBERS),
     "no keyword params= (did you mean parameters=?)"),
    (lambda: wiper(B).solve({th2: 1.0}, guesses={th3: 0.4, th4: 1.6}),
     "no keyword guesses= (did you mean guess=?)"),
    (lambda: wiper(B).solve({th2: 1.0}, tolerance=1e-9), "no keyword tolerance= (did you mean tol=?)"),
])
def test_a_misspelt_keyword_gets_did_you_mean(call, says):
    with pytest.raises(InvalidArgumentError) as caught:
        call()
    assert says in str(caught.value)


def test_sympy_numbers_are_numbers_as_inputs_rates_and_guesses():
    linkage = wiper(B)
    exact = linkage.solve({th2: sp.pi / 3}, rates={th2: sp.Integer(2)},
                          guess={th3: sp.Rational(2, 5), th4: 1.6})
    plain = linkage.solve({th2: float(sp.pi / 3)}, rates={th2: 2.0}, guess={th3: 0.4, th4: 1.6})
    assert exact.position == plain.position and exact.velocity == plain.velocity
    listed = linkage.solve({th2: [sp.pi / 3, 1.0]}, assembly={"theta4": 1})
    alone = linkage.solve({th2: float(sp.pi / 3)}, assembly={"theta4": 1})
    assert listed.position["theta4"][0] == alone.position["theta4"]


def test_an_empty_sweep_is_an_empty_motion():
    empty = wiper(B).solve({th2: []}, rates={th2: 1.0})
    assert empty.position["theta4"].shape == empty.velocity["theta3"].shape == empty.converged.shape == (0,)


def test_with_parameters_takes_a_partial_update():
    longer = wiper(B).with_parameters({"l3": 0.20})
    assert dict(longer.parameters) == {**NUMBERS, l3: 0.20}
    _, B_circles = fourbar_pins(0.20, 0.06, 0.20, 0.12, 1.0, "open")
    pins = longer.joints(longer.solve({th2: 1.0}, assembly={"theta3": 1}))
    assert np.abs(pins["B"] - B_circles).max() < 1e-12


def six_bar(l6):
    """Two loops sharing θ4 (a Watt six-bar); loop 2's output dyad C–D–O6 of lengths 0.05 and ``l6``."""
    th5, th6 = sp.symbols("theta5 theta6")

    def R(length, angle):
        return length * sp.Matrix([sp.cos(angle), sp.sin(angle)])

    O4, O6 = sp.Matrix([0.20, 0]), sp.Matrix([0.36, 0])
    C = O4 + R(0.12, th4 - 0.26)
    return Mechanism([R(0.06, th2) + R(0.18, th3) - O4 - R(0.12, th4), C + R(0.05, th5) - O6 - R(l6, th6)],
                     [th3, th4, th5, th6], [th2])


def test_a_loop_that_cannot_close_is_named():
    with pytest.raises(UnreachableError, match=r"cannot be closed at theta2=0\.0 .*, in loops\[1\]:"):
        six_bar(0.03).solve({th2: [0.0, 0.5]})  # |C O6| > 0.05 + 0.03 everywhere


def test_the_loop_at_a_limit_is_named_where_the_rates_are_singular():
    # choose l6 so that at θ2 = 1 the output dyad is stretched straight: C, D, O6 on one line
    _, B_pin = fourbar_pins(0.20, 0.06, 0.18, 0.12, 1.0, "open")
    theta4 = np.arctan2(B_pin[1], B_pin[0] - 0.20)
    C = np.array([0.20, 0.0]) + 0.12 * np.array([np.cos(theta4 - 0.26), np.sin(theta4 - 0.26)])
    l6 = np.linalg.norm(C - np.array([0.36, 0.0])) - 0.05
    with pytest.raises(SingularJacobianError, match=r"J is singular at theta2=1\.0\b.*, in loops\[1\]:"):
        six_bar(l6).solve({th2: 1.0}, rates={th2: 1.0}, assembly={"theta3": 1})
