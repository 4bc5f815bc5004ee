"""A declaration checks itself on both routes (closed form and Newton): symbols declared with other
assumptions than the loops' are the same symbols (one symbol per name), a declared point that stretches its
link is named, an empty sweep is an empty motion, sympy numbers are numbers; and near_singular is on before
the rates exceed 100 times their size (a five-bar leg stretched).  References: the wiper four-bar's pins by
circle intersections computed here; the leg's rates by central differences of its inverse by hand."""

import numpy as np
import pytest
import sympy as sp

from course_lib.errors import InvalidGeometryError
from course_lib.mechanism import Mechanism

L1, L2, L3, L4 = 0.20, 0.06, 0.18, 0.12


def pins(theta2):
    """A and B of the wiper's open assembly (B left of A → O4), by intersecting circles by hand."""
    theta2 = np.asarray(theta2, float)
    A = L2 * np.stack([np.cos(theta2), np.sin(theta2)], -1)
    d = np.array([L1, 0.0]) - A
    dist = np.hypot(d[..., 0], d[..., 1])
    along = (dist**2 + L3**2 - L4**2) / (2 * dist)
    half = np.sqrt(L3**2 - along**2)
    ux, uy = d[..., 0] / dist, d[..., 1] / dist
    return A, np.stack([A[..., 0] + along * ux - half * uy, A[..., 1] + along * uy + half * ux], -1)


def wiper(th2, th3, th4, route="closed", points=None):
    """The wiper's loop written with the plain symbols; unknowns and inputs given as ``th2``…``th4``
    (whatever their assumptions).  ``route="newton"``: B's coordinates as unknowns too (no closed form)."""
    t2, t3, t4 = sp.symbols("theta2 theta3 theta4")
    if route == "closed":
        loop = sp.Matrix([L2 * sp.cos(t2) + L3 * sp.cos(t3) - L4 * sp.cos(t4) - L1,
                          L2 * sp.sin(t2) + L3 * sp.sin(t3) - L4 * sp.sin(t4)])
        return Mechanism([loop], [th3, th4], [th2], points=points,
                         links={"coupler": ("A", "B"), "rocker": ("O4", "B")} if points else ())
    xB, yB = sp.symbols("x_B y_B")
    rows = [L2 * sp.cos(t2) + L3 * sp.cos(t3) - xB, L2 * sp.sin(t2) + L3 * sp.sin(t3) - yB,
            (xB - L1) ** 2 + yB**2 - L4**2]
    return Mechanism(rows, [th3, xB, yB], [th2], points=points,
                     links={"coupler": ("A", "B"), "rocker": ("O4", "B")} if points else ())


SWEEP = np.linspace(0.0, 6.0, 13)


@pytest.mark.parametrize("real", ["unknowns", "inputs", "both"])
@pytest.mark.parametrize("route", ["closed", "newton"])
def test_symbols_with_other_assumptions_are_the_loops_symbols(real, route):
    plain = sp.symbols("theta2 theta3 theta4")
    marked = sp.symbols("theta2 theta3 theta4", real=True)
    th2 = marked[0] if real in ("inputs", "both") else plain[0]
    th3, th4 = marked[1:] if real in ("unknowns", "both") else plain[1:]
    linkage = wiper(th2, th3, th4, route)
    moving = linkage.unknowns + linkage.inputs
    assert {s.name for s in linkage.equations.free_symbols} == {s.name for s in moving}
    A, B = pins(SWEEP)
    theta3 = np.arctan2(B[:, 1] - A[:, 1], B[:, 0] - A[:, 0])
    guess = {th3: theta3[0]} | ({th4: np.arctan2(B[0, 1], B[0, 0] - L1)} if route == "closed" else
                                 {"x_B": B[0, 0], "y_B": B[0, 1]})
    motion = linkage.solve({th2: SWEEP}, guess=guess)
    assert np.abs(np.angle(np.exp(1j * (motion.position["theta3"] - theta3)))).max() < 1e-10


def test_a_point_typo_is_named_on_the_newton_route():
    th2, th3 = sp.symbols("theta2 theta3")
    xB, yB = sp.symbols("x_B y_B")
    A = sp.Matrix([L2 * sp.cos(th2), L2 * sp.sin(th2)])
    typo = {"A": A, "B": sp.Matrix([xB, xB]), "O4": sp.Matrix([L1, 0])}  # y written as x
    A0, B0 = pins(SWEEP)
    guess = {th3: np.arctan2(B0[0, 1] - A0[0, 1], B0[0, 0] - A0[0, 0]), "x_B": B0[0, 0], "y_B": B0[0, 1]}
    says = r"links: (coupler \(A–B\)|rocker \(O4–B\)) changes length"
    with pytest.raises(InvalidGeometryError, match=says):
        wiper(th2, th3, None, "newton", typo).solve({th2: SWEEP}, guess=guess)
    right = wiper(th2, th3, None, "newton", typo | {"B": sp.Matrix([xB, yB])})
    assert np.abs(right.joints(right.solve({th2: SWEEP}, guess=guess))["B"] - B0).max() < 1e-10


@pytest.mark.parametrize("route", ["closed", "newton"])
def test_an_empty_sweep_is_an_empty_motion_on_both_routes(route):
    th2, th3, th4 = sp.symbols("theta2 theta3 theta4")
    linkage = wiper(th2, th3, th4, route)
    guess = {th3: 0.4, th4: 1.6} if route == "closed" else {th3: 0.4, "x_B": 0.15, "y_B": 0.1}
    for empty in ([], np.empty((0, 3))):
        motion = linkage.solve({th2: empty}, rates={th2: 1.0}, guess=guess)
        assert motion.position["theta3"].shape == motion.velocity["theta3"].shape == np.shape(empty)
        assert motion.converged.shape == np.shape(empty) and motion.message == ""


@pytest.mark.parametrize("route", ["closed", "newton"])
def test_sympy_numbers_are_numbers_on_both_routes(route):
    th2, th3, th4 = sp.symbols("theta2 theta3 theta4")
    linkage = wiper(th2, th3, th4, route)
    A, B = pins(float(sp.pi / 3))
    theta3 = float(np.arctan2(B[1] - A[1], B[0] - A[0]))
    rest = ({th4: sp.atan2(sp.Float(B[1]), sp.Float(B[0] - L1))} if route == "closed"
            else {"x_B": sp.Float(B[0]), "y_B": sp.Rational(int(B[1] * 1e6), 10**6)})
    exact = {th3: sp.Float(theta3)} | rest
    motion = linkage.solve({th2: sp.pi / 3}, rates={th2: sp.Integer(2)}, guess=exact)
    assert motion.converged and abs(motion.position["theta3"] - theta3) < 1e-12


# ------------------------------------------------------- near_singular warns before the rates blow up
LEG1, LEG2 = 0.10, 0.15  # a five-bar leg: crank O1P2 (θ1), distal link P2P3 (θ2), P3 = (X, Y) given


def leg():
    th1, th2, X, Y = sp.symbols("theta1 theta2 X Y")
    loop = sp.Matrix([LEG1 * sp.cos(th1) + LEG2 * sp.cos(th2) - X,
                      LEG1 * sp.sin(th1) + LEG2 * sp.sin(th2) - Y])
    return Mechanism([loop], [th1, th2], [X, Y])


def leg_angles(X, Y):
    """θ1, θ2 by the law of cosines (elbow left of O1 → P3), by hand."""
    reach, heading = np.hypot(X, Y), np.arctan2(Y, X)
    at_crank = np.arccos(np.clip((LEG1**2 + reach**2 - LEG2**2) / (2 * LEG1 * reach), -1, 1))
    P2 = LEG1 * np.array([np.cos(heading + at_crank), np.sin(heading + at_crank)])
    return heading + at_crank, np.arctan2(Y - P2[1], X - P2[0])


def leg_rate(X, Y, h):
    """The largest |θ̇| for P3 moving at unit speed along x, by central differences of the hand inverse."""
    return max(abs(a - b) / (2 * h) for a, b in zip(leg_angles(X + h, Y), leg_angles(X - h, Y), strict=True))


def test_near_singular_is_on_before_the_rates_exceed_100_times_their_size():
    linkage = leg()
    regular = np.hypot(LEG1, LEG2) / np.sqrt(2)  # the elbow near a right angle
    size = leg_rate(regular, regular, 1e-7)
    stretched = LEG1 + LEG2
    for gap in np.geomspace(1e-9, 3e-2, 25) * stretched:
        X = (stretched - gap) / np.sqrt(2)
        ratio = leg_rate(X, X, 1e-3 * gap) / size
        guess = dict(zip(("theta1", "theta2"), leg_angles(X, X), strict=True))
        motion = linkage.solve({"X": X, "Y": X}, guess=guess)
        assert motion.converged
        if ratio > 100:
            assert motion.near_singular, (gap, ratio)
        if ratio < 10:
            assert not motion.near_singular, (gap, ratio)
    at_rest = dict(zip(("theta1", "theta2"), leg_angles(regular, regular), strict=True))
    one = linkage.solve({"X": regular, "Y": regular}, guess=at_rest)
    assert not one.near_singular
