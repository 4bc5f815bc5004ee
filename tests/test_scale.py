"""The core is scale-invariant over 1e-90 … 1e90 m: a linkage declared with every length λ times gives the
same angles, λ times the lengths and joint coordinates, and the same σ, singular masks, change points and
messages — on the closed-form route (the wiper four-bar of tests/test_mechanism.py, a parallelogram through
its change point, a slider-crank driven by its slider) and on Newton's route (the four-bar with B's
coordinates as unknowns, one 3×3 block with no closed form).  Each declaration at 1 m is first checked
against a route of its own (circle intersections, the four-bar's velocity formulas), then every scale
against it.  A declaration that is not homogeneous in its lengths is solved as declared.
"""

from __future__ import annotations

import math

import numpy as np
import pytest
import sympy as sp
from test_mechanism import LOOP, WIPER_POINTS, l1, l2, l3, l4, th2, th3, th4
from test_mechanism import WIPER_LENGTHS as NUMBERS

from course_lib.errors import ConvergenceError
from course_lib.mechanism import Mechanism, scaling
from course_lib.thresholds import UNIT_RANGE

SCALES = (1e-90, 1e-45, 1.0, 1e45, 1e78, 1e90)
WIPER = Mechanism([LOOP], [th3, th4], [th2], NUMBERS, points=WIPER_POINTS,
                  links=[("O2", "A"), ("A", "B"), ("B", "O4")], ground=["O2", "O4"])
THETA2 = np.linspace(0.0, 2 * np.pi, 25)
OMEGA2, ALPHA2 = 10.0, 5.0


def scaled(mechanism: Mechanism, scale: float, lengths) -> Mechanism:
    return mechanism.with_parameters({k: v * scale for k, v in mechanism.parameters.items() if k in lengths})


def circles(P, r1, Q, r2, side):
    """X with |XP| = r1 and |XQ| = r2, left (side +1) or right (−1) of the directed line P → Q, by hand."""
    P, Q = np.broadcast_arrays(np.asarray(P, float), np.asarray(Q, float))
    d = Q - P
    dist = np.hypot(d[..., 0], d[..., 1])
    along = (dist**2 + r1**2 - r2**2) / (2 * dist)
    half = np.sqrt(r1**2 - along**2)
    ux, uy = d[..., 0] / dist, d[..., 1] / dist
    return np.stack([P[..., 0] + along * ux - side * half * uy, P[..., 1] + along * uy + side * half * ux],
                    -1)


def turn_gap(a, b):
    """|a − b| for angles, a whole turn apart counting as equal."""
    return np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b)))))


# ---------------------------------------------------------------- the wiper, closed-form route
def wiper_at(scale, **options):
    return scaled(WIPER, scale, NUMBERS).solve({th2: THETA2}, {th2: OMEGA2}, {th2: ALPHA2}, **options)


REFERENCE = wiper_at(1.0, assembly={"theta4": 1})


def test_the_wiper_at_1_m_is_the_one_of_circles_and_of_the_velocity_formulas():
    A = 0.06 * np.stack([np.cos(THETA2), np.sin(THETA2)], -1)
    B = circles(A, 0.18, np.array([0.20, 0.0]), 0.12, +1)  # σ = +1: B left of A → O4
    theta3 = np.arctan2(B[:, 1] - A[:, 1], B[:, 0] - A[:, 0])
    theta4 = np.arctan2(B[:, 1], B[:, 0] - 0.20)
    assert turn_gap(REFERENCE.position["theta3"], theta3).max() < 1e-12
    assert turn_gap(REFERENCE.position["theta4"], theta4).max() < 1e-12
    # ω3 = l2 ω2 sin(θ4 − θ2) / (l3 sin(θ3 − θ4)), ω4 = l2 ω2 sin(θ3 − θ2) / (l4 sin(θ3 − θ4))
    omega3 = 0.06 * OMEGA2 * np.sin(theta4 - THETA2) / (0.18 * np.sin(theta3 - theta4))
    omega4 = 0.06 * OMEGA2 * np.sin(theta3 - THETA2) / (0.12 * np.sin(theta3 - theta4))
    np.testing.assert_allclose(REFERENCE.velocity["theta3"], omega3, rtol=0, atol=1e-11)
    np.testing.assert_allclose(REFERENCE.velocity["theta4"], omega4, rtol=0, atol=1e-11)
    np.testing.assert_allclose(WIPER.joints(REFERENCE)["B"], B, rtol=0, atol=1e-14)


def assert_same_motion(motion, reference, scale, lengths=(), angles_tol=1e-13):
    """Angles (and their rates) equal; the ``lengths`` (and their rates) equal after dividing by ``scale``."""
    for part in ("position", "velocity", "acceleration"):
        found, expected = getattr(motion, part), getattr(reference, part)
        for name, values in expected.items():
            size = max(1.0, float(np.nanmax(np.abs(values))))
            got = np.asarray(found[name]) / (scale if name in lengths else 1.0)
            angle = part == "position" and name not in lengths
            gap = turn_gap(got, values) if angle else np.abs(got - values)
            assert np.array_equal(np.isnan(got), np.isnan(values)), (part, name)
            assert np.nanmax(gap, initial=0.0) <= angles_tol * size, (part, name, np.nanmax(gap))
    for mask in ("converged", "singular", "near_singular"):
        assert np.array_equal(getattr(motion, mask), getattr(reference, mask)), mask
    assert motion.message == reference.message
    if reference.assembly is not None:
        assert {k: np.asarray(v).tolist() for k, v in motion.assembly.items()} == \
            {k: np.asarray(v).tolist() for k, v in reference.assembly.items()}


@pytest.mark.parametrize("scale", SCALES)
@pytest.mark.parametrize("how", [{"assembly": {"theta4": 1}}, {}, {"guess": {th3: 0.4, th4: 1.6}}])
def test_the_wiper_declared_at_any_scale_moves_as_at_1_m(scale, how):
    motion = wiper_at(scale, **how)
    assert motion.converged.all() and not motion.singular.any()
    assert_same_motion(motion, REFERENCE, scale)
    assert motion.inputs["theta2"] is not None and np.array_equal(motion.inputs["theta2"], THETA2)
    linkage = scaled(WIPER, scale, NUMBERS)
    joints, expected = linkage.joints(motion), WIPER.joints(REFERENCE)
    for name in ("O2", "A", "B", "O4"):
        np.testing.assert_allclose(joints[name] / scale, expected[name], rtol=0, atol=1e-15)
    points, expected = linkage.point_motion(motion), WIPER.point_motion(REFERENCE)
    for name in ("A", "B"):
        for found, wanted in zip(points[name], expected[name], strict=True):
            np.testing.assert_allclose(found / scale, wanted, rtol=0, atol=1e-13 * np.abs(wanted).max())


@pytest.mark.parametrize("scale", SCALES)
def test_one_instant_from_a_guess_and_the_public_rates_at_any_scale(scale):
    linkage = scaled(WIPER, scale, NUMBERS)
    one = linkage.solve({th2: 0.7}, {th2: OMEGA2}, guess={th3: 0.4, th4: 1.6})
    at_1 = WIPER.solve({th2: 0.7}, {th2: OMEGA2}, guess={th3: 0.4, th4: 1.6})
    assert one.newton.converged and turn_gap(one.newton.x, at_1.newton.x).max() < 1e-13
    assert turn_gap(one.position["theta4"], at_1.position["theta4"]) < 1e-13
    q = np.array([[one.position["theta3"], one.position["theta4"]]])
    q_rate, _, singular = linkage.rates(q, [[0.7]], [[OMEGA2]])
    np.testing.assert_allclose(q_rate[0], [at_1.velocity["theta3"], at_1.velocity["theta4"]], rtol=1e-13)
    assert not singular[0]
    assert abs(linkage.smallest_singular_value(q, [[0.7]])[0]
               - WIPER.smallest_singular_value(q, [[0.7]])[0]) < 1e-13


# ---------------------------------------------------------------- a change point, and σ named per instant
PARALLELOGRAM = {l1: 0.2, l2: 0.1, l3: 0.2, l4: 0.1}
CROSSING = np.linspace(2.5, 3.9, 15)


@pytest.mark.parametrize("scale", SCALES)
def test_a_change_point_is_met_where_it_is_at_any_scale(scale):
    linkage = Mechanism([LOOP], [th3, th4], [th2], {k: v * scale for k, v in PARALLELOGRAM.items()})
    motion = linkage.solve({th2: CROSSING}, {th2: 1.0}, guess={th3: 0.0, th4: 2.5}, on_failure="nan")
    # a parallelogram all the way (θ3 = 0, θ4 = θ2): at θ2 = π the four pins line up, and the motion goes on
    assert turn_gap(motion.position["theta3"], 0.0).max() < 1e-9
    assert turn_gap(motion.position["theta4"], CROSSING).max() < 1e-9
    assert "change point" in motion.message and "theta2≈3.14159" in motion.message
    reference = Mechanism([LOOP], [th3, th4], [th2], PARALLELOGRAM).solve(
        {th2: CROSSING}, {th2: 1.0}, guess={th3: 0.0, th4: 2.5}, on_failure="nan")
    # beside the change point the rates grow like 1 / σ_min(J̃): the rounding of λ·l shows more there
    assert_same_motion(motion, reference, scale, angles_tol=1e-11)


# ---------------------------------------------------------------- an input that is a length
x_C, phi2, phi3 = sp.symbols("x_C phi2 phi3")
a, b = sp.symbols("a b", positive=True)
SLIDER = Mechanism([sp.Matrix([a * sp.cos(phi2) + b * sp.cos(phi3) - x_C,
                               a * sp.sin(phi2) + b * sp.sin(phi3)])], [phi2, phi3], [x_C], {a: 0.1, b: 0.3},
                   points={"O2": sp.zeros(2, 1), "A": sp.Matrix([a * sp.cos(phi2), a * sp.sin(phi2)]),
                           "C": sp.Matrix([x_C, 0])}, links=[("O2", "A"), ("A", "C")])
SLIDES = np.array([0.25, 0.3, 0.35, 0.4])  # 0.4 = a + b: the dyad stretched, J singular there


@pytest.mark.parametrize("scale", SCALES)
def test_an_input_that_is_a_length_is_named_in_the_declarations_units(scale):
    linkage = scaled(SLIDER, scale, (a, b))
    given = SLIDES * scale
    motion = linkage.solve({x_C: given}, {x_C: 2.0 * scale}, assembly={"phi2": 1}, on_failure="nan")
    reference = SLIDER.solve({x_C: SLIDES}, {x_C: 2.0}, assembly={"phi2": 1}, on_failure="nan")
    # A by hand: on the circle about O2 (radius a) and about C (radius b)
    A = circles(np.zeros(2), 0.1, np.stack([SLIDES[:3], 0 * SLIDES[:3]], -1), 0.3, +1)
    assert turn_gap(reference.position["phi2"][:3], np.arctan2(A[:, 1], A[:, 0])).max() < 1e-12
    assert reference.singular.tolist() == [False, False, False, True]
    said, told = f"x_C={float(SLIDES[-1])!r}", f"x_C={float(given[-1])!r}"
    assert said in reference.message and told in motion.message
    assert motion.message.replace(told, "") == reference.message.replace(said, "")
    for part in ("position", "velocity"):
        for name in ("phi2", "phi3"):
            found, expected = getattr(motion, part)[name], getattr(reference, part)[name]
            np.testing.assert_allclose(found[:3], expected[:3], rtol=0, atol=1e-12)
    # at the toggle the root is double: the rounding of λ·a + λ·b against λ·0.4 moves it by up to √ε
    assert turn_gap(motion.position["phi2"][3], 0.0) < 1e-7
    assert turn_gap(reference.position["phi2"][3], 0.0) < 1e-7
    assert np.isnan(motion.velocity["phi2"][3]) and np.isnan(reference.velocity["phi2"][3])
    assert np.array_equal(motion.inputs["x_C"], given)
    np.testing.assert_allclose(linkage.joints(motion)["C"][:, 0] / scale, SLIDES, rtol=1e-15, atol=0)


# ---------------------------------------------------------------- Newton's route
theta2, theta3, x_B, y_B = sp.symbols("theta2 theta3 x_B y_B")
c2, c3, g, c4 = sp.symbols("c2 c3 g c4", positive=True)  # crank, coupler, ground, rocker
BY_B = Mechanism([c2 * sp.cos(theta2) + c3 * sp.cos(theta3) - x_B,
                  c2 * sp.sin(theta2) + c3 * sp.sin(theta3) - y_B,
                  (x_B - g) ** 2 + y_B**2 - c4**2], [theta3, x_B, y_B], [theta2],
                 {c2: 0.15, c3: 0.10, g: 0.20, c4: 0.12},
                 points={"O2": sp.zeros(2, 1), "A": sp.Matrix([c2 * sp.cos(theta2), c2 * sp.sin(theta2)]),
                         "B": sp.Matrix([x_B, y_B]), "O4": sp.Matrix([g, 0])},
                 links=[("O2", "A"), ("A", "B"), ("B", "O4")])
SWEEP = np.linspace(0.2, 1.2, 11)
B_GUESS = {theta3: -2.0, x_B: 0.1, y_B: -0.05}  # near B right of A → O4 at θ2 = 0.2


def by_b_at(scale, inputs=SWEEP, **options):
    guess = {k: v * (scale if k in (x_B, y_B) else 1.0) for k, v in B_GUESS.items()}
    return scaled(BY_B, scale, (c2, c3, g, c4)).solve({theta2: inputs}, {theta2: 2.0}, {theta2: 1.0},
                                                       guess=guess, **options)


B_REFERENCE = by_b_at(1.0)


def test_the_newton_route_at_1_m_is_the_one_of_circles():
    assert BY_B.closed_forms == [None]
    A = 0.15 * np.stack([np.cos(SWEEP), np.sin(SWEEP)], -1)
    B = circles(A, 0.10, np.array([0.20, 0.0]), 0.12, -1)
    assert np.abs(B[:, 0] - B_REFERENCE.position["x_B"]).max() < 1e-12
    assert np.abs(B[:, 1] - B_REFERENCE.position["y_B"]).max() < 1e-12
    # the rates: finite differences of the circles' B
    h = 1e-6
    ahead, behind = (circles(0.15 * np.stack([np.cos(SWEEP + s), np.sin(SWEEP + s)], -1), 0.10,
                             np.array([0.20, 0.0]), 0.12, -1) for s in (h, -h))
    np.testing.assert_allclose(B_REFERENCE.velocity["x_B"], 2.0 * (ahead - behind)[:, 0] / (2 * h), atol=1e-8)


@pytest.mark.parametrize("scale", SCALES)
def test_the_newton_route_declared_at_any_scale_moves_as_at_1_m(scale):
    motion = by_b_at(scale)
    assert motion.converged.all()
    assert_same_motion(motion, B_REFERENCE, scale, lengths=("x_B", "y_B"), angles_tol=1e-12)
    linkage = scaled(BY_B, scale, (c2, c3, g, c4))
    np.testing.assert_allclose(linkage.joints(motion)["B"] / scale, BY_B.joints(B_REFERENCE)["B"], rtol=0,
                               atol=1e-14)
    # one instant from a guess near B at θ2 = 0.7: Newton's run in the declaration's units
    guess = {theta3: -1.9, x_B: 0.12 * scale, y_B: 0.0}
    one = linkage.solve({theta2: 0.7}, guess=guess)
    at_1 = BY_B.solve({theta2: 0.7}, guess={theta3: -1.9, x_B: 0.12, y_B: 0.0})
    B = circles(0.15 * np.array([math.cos(0.7), math.sin(0.7)]), 0.10, np.array([0.20, 0.0]), 0.12, -1)
    assert at_1.newton.converged and np.abs(at_1.newton.x[1:] - B).max() < 1e-12
    assert one.newton.converged and np.abs(one.newton.x[1:] / scale - B).max() < 1e-12
    assert abs(one.newton.history[0, 1] / scale - 0.12) < 1e-15  # the guess, in the declaration's units
    # the same iterates (the run may stop an update sooner or later: tol applies in units of 2^k)
    common = min(one.newton.iterations, at_1.newton.iterations)
    gap = one.newton.history[:common + 1, 1:] / scale - at_1.newton.history[:common + 1, 1:]
    assert np.abs(gap).max() < 1e-9


@pytest.mark.parametrize("scale", SCALES)
def test_a_change_point_on_newtons_route_is_met_where_it_is_at_any_scale(scale):
    # the parallelogram c2 = c4 = 0.1, c3 = g = 0.2 by B's coordinates: at θ2 = π the four pins line up, the
    # anti-parallelogram meets it, and the motion goes on as a parallelogram (θ3 = 0)
    lengths = {c2: 0.1, c3: 0.2, g: 0.2, c4: 0.1}
    theta = np.linspace(2.0, 4.5, 6)

    def solved(size):
        linkage = BY_B.with_parameters({k: v * size for k, v in lengths.items()})
        guess = {theta3: 0.0, x_B: (0.2 + 0.1 * math.cos(2.0)) * size, y_B: 0.1 * math.sin(2.0) * size}
        return linkage.solve({theta2: theta}, {theta2: 1.0}, guess=guess, on_failure="nan")

    motion, reference = solved(scale), solved(1.0)
    assert turn_gap(reference.position["theta3"], 0.0).max() < 1e-9
    assert np.abs(reference.position["x_B"] - (0.2 + 0.1 * np.cos(theta))).max() < 1e-9
    assert "change point" in reference.message and "between theta2=3.0 and theta2=3.5" in reference.message
    assert_same_motion(motion, reference, scale, lengths=("x_B", "y_B"), angles_tol=1e-11)


@pytest.mark.parametrize("scale", (1e-90, 1e90))
def test_a_newton_run_that_fails_is_told_in_the_declarations_units(scale):
    linkage = scaled(BY_B, scale, (c2, c3, g, c4))
    with pytest.raises(ConvergenceError) as caught:
        linkage.solve({theta2: 0.7}, guess={theta3: 1.0, x_B: 0.25 * scale, y_B: 0.1 * scale}, max_iter=1)
    result = caught.value.result
    assert 0.1 < result.x[1] / scale < 0.4 and 0.0 < result.x[2] / scale < 0.3  # B near (0.25, 0.1)·scale
    assert f"(last step {result.step_norms[-1]:.3g}, residual {result.residual_norms[-1]:.3g})" in \
        str(caught.value)
    # ‖F‖ of the guess by hand: its rows of degree 1, 1 and 2 in the lengths
    A = 0.15 * np.array([math.cos(0.7), math.sin(0.7)])
    rows = np.array([(A[0] + 0.10 * math.cos(1.0) - 0.25) * scale,
                     (A[1] + 0.10 * math.sin(1.0) - 0.1) * scale,
                     ((0.25 - 0.20) ** 2 + 0.1**2 - 0.12**2) * scale**2])
    peak = np.abs(rows).max()
    assert abs(result.residual_norms[0] / (peak * np.linalg.norm(rows / peak)) - 1) < 1e-12


# ---------------------------------------------------------------- what is not scaled
def test_a_declaration_not_homogeneous_in_its_lengths_is_solved_as_declared():
    x, theta, k, r = sp.symbols("x theta k r")  # k a ratio multiplying the length r: not homogeneous
    follower = Mechanism([x - k * r * sp.cos(theta)], [x], [theta], {k: 3.0, r: 1e45})
    assert follower._homogeneous is None and follower._twin() is None
    motion = follower.solve({theta: [0.0, 1.0]}, {theta: 2.0})
    np.testing.assert_allclose(motion.position["x"], 3e45 * np.cos([0.0, 1.0]), rtol=1e-15)
    np.testing.assert_allclose(motion.velocity["x"], -6e45 * np.sin([0.0, 1.0]), rtol=1e-15)


def test_a_declaration_of_ordinary_size_is_solved_as_declared_and_never_checked(monkeypatch):
    monkeypatch.setattr(scaling, "_degree", lambda *args: pytest.fail("checked at ordinary size"))
    for lengths in ({l1: 0.2, l2: 0.06, l3: 0.18, l4: 0.12}, {l1: 200.0, l2: 60.0, l3: 180.0, l4: 120.0}):
        linkage = Mechanism([LOOP], [th3, th4], [th2], lengths)
        assert linkage._twin() is None
        linkage.solve({th2: THETA2})
    assert 1 / UNIT_RANGE < 1e-3 and UNIT_RANGE > 200.0


def test_the_homogeneity_is_checked_once_per_declaration(monkeypatch):
    linkage = Mechanism([LOOP], [th3, th4], [th2], NUMBERS)  # a new declaration: nothing derived yet
    calls = []
    degree = scaling._degree
    monkeypatch.setattr(scaling, "_degree", lambda *args: calls.append(1) or degree(*args))
    for scale in (1e45, 1e-45, 1e90):
        big = scaled(linkage, scale, NUMBERS)
        for _ in range(3):
            big.solve({th2: THETA2})
    assert len(calls) == 2  # the two rows, once: shared by every with_parameters copy
