"""course_lib.mechanism at its edges: dead centres, limits, toggles and change points; continuation
that cannot be fooled; the closed forms the core derives; declarations and shapes checked when given.

Expected values come from plain geometry written here (law of cosines, circle–line intersections), the
course's hand-written closed forms (Norton's A, B, C of lesson 03; the five-bar's a1 … c2 of the course
material), the hand-written saw.analytic, and central differences — never from the code under test.
"""

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from course_lib import saw
from course_lib.errors import CourseLibError, InvalidGeometryError, SingularJacobianError
from course_lib.fivebar import _declarations as fivebar_declarations
from course_lib.fourbar import FourBar
from course_lib.mechanism import NEAR_SINGULAR, SINGULAR, Mechanism

th, th2, th3, th4, th5 = sp.symbols("theta theta2 theta3 theta4 theta5")
x_A, y_B, L = sp.symbols("x_A y_B L")
l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
LENGTH = 0.2
# elliptical trammel driven by its slider A = (x_A, 0); B = A + L(cos θ, sin θ) slides on the y axis
TRAMMEL = Mechanism([sp.Matrix([x_A + L * sp.cos(th), L * sp.sin(th) - y_B])], [th, y_B], [x_A], {L: LENGTH})
TRAMMEL_GUESS = {th: 1.0, y_B: 0.15}
LOOP = sp.Matrix(
    [
        l2 * sp.cos(th2) + l3 * sp.cos(th3) - l4 * sp.cos(th4) - l1,
        l2 * sp.sin(th2) + l3 * sp.sin(th3) - l4 * sp.sin(th4),
    ]
)


def fourbar(ground, crank, coupler, rocker):
    return Mechanism([LOOP], [th3, th4], [th2], {l1: ground, l2: crank, l3: coupler, l4: rocker})


def wrapped(angle):
    return np.angle(np.exp(1j * np.asarray(angle)))


# ------------------------------------------------------------------ exact at dead centres and limits


def test_trammel_driven_to_its_dead_centre_refuses_rates_and_says_so():
    # at x_A = −L, θ = 0: the row ∂(L sin θ − y_B)/∂θ stays but ∂(x_A + L cos θ)/∂θ = 0 — a whole row of J
    with pytest.raises(SingularJacobianError, match=r"x_A=-0\.2\b.*toggle, limit or change point"):
        TRAMMEL.solve({x_A: -LENGTH}, rates={x_A: 1.0}, guess=TRAMMEL_GUESS)
    motion = TRAMMEL.solve({x_A: -LENGTH}, guess=TRAMMEL_GUESS)
    assert motion.singular is True and motion.near_singular is True and "singular" in motion.message
    assert abs(motion.position["y_B"]) < 1e-7


def test_piston_driven_slider_crank_at_bottom_dead_centre_refuses_rates():
    a, b, c, x = 0.075, 0.170, 0.045, sp.Symbol("x")
    crank = Mechanism(
        [sp.Matrix([l2 * sp.cos(th2) + l3 * sp.cos(th3) - x, l2 * sp.sin(th2) + l3 * sp.sin(th3) - l1])],
        [th2, th3],
        [x],
        {l1: c, l2: a, l3: b},
    )
    extreme = math.sqrt((a + b) ** 2 - c**2)  # crank and rod in line, stretched
    guess = {th2: 0.3, th3: 0.2}
    with pytest.raises(SingularJacobianError, match="x=0.24"):
        crank.solve({x: extreme}, rates={x: 1.0}, guess=guess)
    motion = crank.solve({x: extreme}, guess=guess)
    assert motion.singular is True
    assert abs(wrapped(motion.position["theta2"] - math.atan2(c, extreme))) < 1e-7


def test_non_grashof_fourbar_at_its_limit_refuses_rates_and_sweeps_to_it():
    ground, crank, coupler, rocker = 0.20, 0.15, 0.10, 0.12
    limit = math.acos((ground**2 + crank**2 - (coupler + rocker) ** 2) / (2 * ground * crank))
    linkage = fourbar(ground, crank, coupler, rocker)
    guess = {th3: 1.0, th4: 2.0}
    with pytest.raises(SingularJacobianError, match="theta2=1.33"):
        linkage.solve({th2: limit}, rates={th2: 1.0}, guess=guess)
    sweep = linkage.solve({th2: np.linspace(0.0, limit, 41)}, guess=guess)
    assert sweep.converged.all() and sweep.singular[-1] and not sweep.singular[:-1].any()
    # coupler and rocker in line at the limit: |AO4| = l3 + l4 puts B between A and O4, so A → B (θ3) and
    # O4 → B (θ4) point opposite ways — θ3 − θ4 = π, not 0 (B = A + l3·e3 = O4 + l4·e4)
    assert abs(wrapped(sweep.position["theta3"][-1] - sweep.position["theta4"][-1] - np.pi)) < 1e-6


def test_the_singularity_rule_ignores_units():
    # the same trammel in millimetres: the same σ_min(J̃) at the same configurations
    millimetres = TRAMMEL.with_parameters({"L": 200.0})
    q = np.array([[0.7, LENGTH * math.sin(0.7)], [1e-5, LENGTH * math.sin(1e-5)]])
    u = -LENGTH * np.cos(q[:, :1])
    ratio = TRAMMEL.smallest_singular_value(q, u)
    scaled = millimetres.smallest_singular_value(q * [1, 1000], u * 1000)
    np.testing.assert_allclose(ratio, scaled, rtol=1e-9)
    assert ratio[1] < NEAR_SINGULAR and ratio[0] > NEAR_SINGULAR and SINGULAR < NEAR_SINGULAR


def test_a_parameter_named_t_is_not_time():
    x, t, u = sp.symbols("x t u")
    follower = Mechanism([x - t * sp.cos(u)], [x], [u], {t: 2.0})
    motion = follower.solve({u: 0.3}, {u: 1.5}, {u: 0.7}, guess={x: 1.0})
    # x = t cos u: ẍ = −t cos u·u̇² − t sin u·ü
    assert motion.acceleration["x"] == pytest.approx(
        -2.0 * math.cos(0.3) * 1.5**2 - 2.0 * math.sin(0.3) * 0.7
    )


def test_parallelogram_through_its_change_point_stays_a_parallelogram_and_says_so():
    linkage = fourbar(0.2, 0.1, 0.2, 0.1)
    for theta2 in (np.linspace(3.0, 3.3, 31), np.radians(np.arange(0, 721, 90.0)), np.linspace(2.0, 4.5, 6)):
        motion = linkage.solve({th2: theta2}, guess={th3: 0.0, th4: theta2[0]})
        assert np.abs(wrapped(motion.position["theta4"] - theta2)).max() < 1e-9  # θ4 = θ2: a parallelogram
        assert np.abs(wrapped(motion.position["theta3"])).max() < 1e-9
        assert "change point" in motion.message


# ------------------------------------------------------------------ continuation that cannot be fooled


def whitworth():
    """Whitworth quick-return: crank r2 about O2 = (0, d) (d < r2: the slotted lever turns fully), the
    block A on the lever at r4 from O4; the lever's other end B = −l4 along it drives the ram C on y = h."""
    r2, d, r4, l4, l5, h, x_C = sp.symbols("r2 d r4 l4 l5 h x_C")
    lever = sp.Matrix([r2 * sp.cos(th2) - r4 * sp.cos(th4), d + r2 * sp.sin(th2) - r4 * sp.sin(th4)])
    ram = sp.Matrix([-l4 * sp.cos(th4) + l5 * sp.cos(th5) - x_C, -l4 * sp.sin(th4) + l5 * sp.sin(th5) - h])
    return Mechanism(
        [lever, ram], [th4, r4, th5, x_C], [th2], {r2: 0.1, d: 0.04, l4: 0.08, l5: 0.25, h: -0.05}
    )


def whitworth_geometry(theta2):
    pin = np.stack([0.1 * np.cos(theta2), 0.04 + 0.1 * np.sin(theta2)])
    theta4, r4 = np.arctan2(pin[1], pin[0]), np.hypot(*pin)
    B = -0.08 * np.stack([np.cos(theta4), np.sin(theta4)])
    x_C = B[0] + np.sqrt(0.25**2 - (-0.05 - B[1]) ** 2)  # C to the right of B
    return r4, x_C


@pytest.mark.parametrize("step", [1.0, 30.0, 90.0])
def test_whitworth_keeps_its_assembly_whatever_the_step(step):
    theta2 = np.radians(np.arange(0.0, 720.0 + step / 2, step))
    motion = whitworth().solve({th2: theta2}, guess={"theta4": 0.4, "r4": 0.1, "theta5": 0.0, "x_C": 0.2})
    r4, x_C = whitworth_geometry(theta2)
    np.testing.assert_allclose(motion.position["r4"], r4, atol=1e-12)
    np.testing.assert_allclose(motion.position["x_C"], x_C, atol=1e-12)
    assert np.abs(np.diff(motion.position["theta4"])).max() <= np.radians(step) * 2 + 1e-9


def test_inputs_in_any_order_give_the_same_assembly():
    stroke = np.linspace(-0.19, 0.19, 40)
    shuffled = np.random.default_rng(5).permutation(stroke)
    motion = TRAMMEL.solve({x_A: shuffled}, guess=TRAMMEL_GUESS)
    np.testing.assert_allclose(motion.position["y_B"], np.sqrt(LENGTH**2 - shuffled**2), atol=1e-12)
    np.testing.assert_allclose(motion.position["theta"], np.arccos(-shuffled / LENGTH), atol=1e-12)


def test_trammel_over_its_whole_stroke_including_both_dead_centres():
    stroke = np.linspace(-LENGTH, LENGTH, 41)
    motion = TRAMMEL.solve({x_A: stroke}, guess=TRAMMEL_GUESS)
    assert motion.converged.all() and motion.singular[[0, -1]].all() and not motion.singular[1:-1].any()
    np.testing.assert_allclose(motion.position["y_B"], np.sqrt(LENGTH**2 - stroke**2), atol=1e-7)


SAW = saw._core(saw.COURSE_SAW)  # one 3×3 block: Newton with continuation


@pytest.mark.parametrize("step", [5.0, 60.0, 120.0])
def test_newton_route_follows_the_saw_in_any_order_and_step(step):
    assert SAW.closed_forms == [None]
    theta2 = np.radians(np.arange(0.0, 720.0 + step / 2, step))
    order = np.random.default_rng(1).permutation(theta2.size)
    guess = dict(zip(("r1", "theta1", "theta3"), saw.SEED_CODE[:3], strict=True))
    motion = SAW.solve({"theta2": theta2[order]}, {"theta2": 2.0}, guess=guess)
    expected = saw.analytic(theta2[order], 2.0)
    np.testing.assert_allclose(motion.position["r1"], expected[..., 0], atol=1e-10)
    assert np.abs(wrapped(motion.position["theta3"] - expected[..., 2])).max() < 1e-10
    np.testing.assert_allclose(motion.velocity["r1"], expected[..., 3], atol=1e-9)


def newton_fourbar():
    """The four-bar with B's coordinates as unknowns: one 3×3 block, no closed form — Newton's route."""
    xB, yB = sp.symbols("x_B y_B")
    rows = [
        l2 * sp.cos(th2) + l3 * sp.cos(th3) - xB,
        l2 * sp.sin(th2) + l3 * sp.sin(th3) - yB,
        (xB - l1) ** 2 + yB**2 - l4**2,
    ]
    return Mechanism(rows, [th3, xB, yB], [th2], {l1: 0.20, l2: 0.15, l3: 0.10, l4: 0.12})


def test_newton_route_starting_at_a_toggle_reaches_every_reachable_input():
    linkage = newton_fourbar()
    assert linkage.closed_forms == [None]
    limit = math.acos((0.2**2 + 0.15**2 - 0.22**2) / (2 * 0.2 * 0.15))
    theta2 = limit - np.concatenate([[0.0], np.geomspace(1e-9, 1e-3, 8), np.linspace(2e-3, 1.0, 30)])
    motion = linkage.solve({th2: theta2}, guess={th3: 1.0, "x_B": 0.25, "y_B": 0.1})
    assert motion.converged.all()
    # B on both circles: about A (coupler) and about O4 (rocker), and one assembly all along
    A = 0.15 * np.stack([np.cos(theta2), np.sin(theta2)], -1)
    B = np.stack([motion.position["x_B"], motion.position["y_B"]], -1)
    np.testing.assert_allclose(np.hypot(*(B - A).T), 0.10, atol=1e-12)
    np.testing.assert_allclose(np.hypot(B[:, 0] - 0.2, B[:, 1]), 0.12, atol=1e-12)
    AB, AO4 = B[1:] - A[1:], [0.2, 0.0] - A[1:]
    side = np.sign(AB[:, 0] * AO4[:, 1] - AB[:, 1] * AO4[:, 0])
    assert abs(side.sum()) == side.size
    assert np.abs(np.diff(motion.position["theta3"])).max() < 0.2


# ------------------------------------------------------------------ closed forms derived by the core


def proportional(ours, theirs):
    """(a, b, c) equal to (A, B, C) up to one nonzero factor: every 2×2 cross product vanishes."""
    return all(
        sp.simplify(sp.expand_trig(ours[i] * theirs[j] - ours[j] * theirs[i])) == 0
        for i, j in ((0, 1), (0, 2), (1, 2))
    )


def test_the_fourbar_quadratic_is_nortons():
    (form,) = fourbar(0.2, 0.06, 0.18, 0.12).closed_forms
    assert form.unknowns == (th4, th3) and form.kind == "angle"
    K1, K2, K3 = l1 / l2, l1 / l4, (l2**2 - l3**2 + l4**2 + l1**2) / (2 * l2 * l4)
    c2, s2 = sp.cos(th2), sp.sin(th2)
    norton = (c2 - K1 - K2 * c2 + K3, -2 * s2, K1 - (K2 + 1) * c2 + K3)
    assert proportional(form.quadratic, norton)


def test_the_fivebar_inverse_half_angle_coefficients_are_the_courses():
    inverse = fivebar_declarations()["inverse"]
    X3, Y3, t1, t4 = sp.symbols("x3 y3 theta1 theta4")
    k1, k2, k3, k4, k5 = sp.symbols("l1:6")
    a1 = k1**2 - k2**2 - k1 * k5 + k5**2 / 4 + 2 * k1 * X3 - k5 * X3 + X3**2 + Y3**2
    b1, c1 = -4 * k1 * Y3, k1**2 - k2**2 + k1 * k5 + k5**2 / 4 - 2 * k1 * X3 - k5 * X3 + X3**2 + Y3**2
    a2 = -(k3**2) + k4**2 + k4 * k5 + k5**2 / 4 + 2 * k4 * X3 + k5 * X3 + X3**2 + Y3**2
    b2, c2 = -4 * k4 * Y3, -(k3**2) + k4**2 - k4 * k5 + k5**2 / 4 - 2 * k4 * X3 + k5 * X3 + X3**2 + Y3**2
    forms = {form.unknowns[0]: form for form in inverse.closed_forms}
    assert set(forms) == {t1, t4}
    assert proportional(forms[t1].quadratic, (a1, b1, c1))
    assert proportional(forms[t4].quadratic, (a2, b2, c2))


@pytest.mark.parametrize("name", ["whitworth", "sixbar", "trammel", "fivebar"])
def test_course_kinds_reduce(name):
    if name == "whitworth":
        mechanism = whitworth()
    elif name == "trammel":
        mechanism = TRAMMEL
    elif name == "fivebar":
        mechanism = fivebar_declarations()["forward"]
    else:
        import sys
        from pathlib import Path

        sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))
        from bench_sixbar import stephenson

        mechanism = stephenson()
    assert all(form is not None for form in mechanism.closed_forms)


# ------------------------------------------------------------------ declarations checked when made

x, y, u = sp.symbols("x y u")
GOOD = dict(unknowns=[x], inputs=[u])


@pytest.mark.parametrize(
    ("loops", "message"),
    [
        ([x - sp.Abs(sp.cos(u))], r"loops\[0\] uses Abs, which is not smooth"),
        ([x - sp.sign(u)], r"loops\[0\] uses sign"),
        ([x - sp.Heaviside(u)], r"loops\[0\] uses Heaviside"),
        ([x - sp.Max(u, 0)], r"loops\[0\] uses Max"),
        ([x - sp.Min(u, 0)], r"loops\[0\] uses Min"),
        ([x - sp.Piecewise((u, u > 0), (0, True))], r"loops\[0\] uses Piecewise"),
        ([x - sp.I * u], r"loops\[0\] must be real"),
        ([x > u], r"loops\[0\] must be a sympy expression"),
    ],
)
def test_a_bad_row_is_refused_by_name(loops, message):
    with pytest.raises(InvalidGeometryError, match=message):
        Mechanism(loops, **GOOD)


def test_eq_rows_and_matrix_eq_are_loops():
    by_eq = Mechanism([sp.Eq(x, sp.cos(u))], [x], [u])
    by_matrix = Mechanism(sp.Eq(sp.Matrix([x, y]), sp.Matrix([sp.cos(u), sp.sin(u)])), [x, y], [u])
    assert by_eq.solve({u: 0.5}, guess={x: 1.0}).position["x"] == pytest.approx(math.cos(0.5))
    assert by_matrix.solve({u: 0.5}, guess={x: 1.0, y: 0.0}).position["y"] == pytest.approx(math.sin(0.5))


def test_constant_repeated_and_dependent_rows_are_named():
    with pytest.raises(InvalidGeometryError, match=r"loops\[0\] does not involve any unknown"):
        Mechanism([3 + u, x + y - u], [x, y], [u])
    with pytest.raises(InvalidGeometryError, match=r"loops\[1\] repeats loops\[0\]"):
        Mechanism([x + y - u, -x - y + u], [x, y], [u])
    with pytest.raises(InvalidGeometryError, match=r"loops\[0\], loops\[1\] depend on each other"):
        Mechanism([x * y - u, 2 * x * y - u**2], [x, y], [u])


def test_parameters_match_by_name_and_take_sympy_constants():
    angle, plain_l4 = sp.Symbol("gamma"), sp.Symbol("l4")
    loop = LOOP.subs(th2, th2 + angle)
    linkage = Mechanism(
        [loop], [th3, th4], [th2], {"l1": 0.2, l2: 0.06, l3: 0.18, plain_l4: 0.12, angle: sp.pi / 6}
    )
    assert linkage.parameters[angle] == pytest.approx(math.pi / 6)
    shifted = linkage.solve({th2: 0.4}, guess={th3: 0.4, th4: 1.6}).position["theta4"]
    assert shifted == pytest.approx(FourBar(0.06, 0.18, 0.12, 0.2).solve(0.4 + math.pi / 6).theta4)
    with pytest.raises(InvalidGeometryError, match=r"parameters\[gamma\] must be a number; got x"):
        Mechanism([loop], [th3, th4], [th2], {l1: 0.2, l2: 0.06, l3: 0.18, l4: 0.12, angle: x})


@pytest.mark.parametrize(
    ("points", "links", "message"),
    [
        ([("A", sp.Matrix([x, 0]))], (), r"points must be a dict"),
        ({1: sp.Matrix([x, 0])}, (), r"points must be keyed by names"),
        ({"A": sp.Matrix([sp.Abs(x), 0])}, (), r"points\['A'\]\[0\] uses Abs"),
        ({"A": sp.Matrix([x, 0])}, "AB", r"links must be a list of pairs"),
        ({"A": sp.Matrix([x, 0])}, [("A",)], r"links\[0\] must be a pair"),
        ({"A": sp.Matrix([x, 0])}, [("A", "A")], r"links\[0\] joins 'A' to itself"),
    ],
)
def test_points_and_links_are_checked(points, links, message):
    with pytest.raises(InvalidGeometryError, match=message):
        Mechanism([x - sp.cos(u)], [x], [u], points=points, links=links)


# ------------------------------------------------------------------ every public method checks its shapes

FOLLOWER = Mechanism(
    [x - sp.cos(u)], [x], [u], points={"O": sp.zeros(2, 1), "P": sp.Matrix([x, 0])}, links=[("O", "P")]
)
BAD_CALLS = {
    "residual.q": (lambda v: FOLLOWER.residual(v, [0.0]), "q"),
    "residual.u": (lambda v: FOLLOWER.residual([0.0], v), "u"),
    "jacobian.q": (lambda v: FOLLOWER.jacobian(v, [0.0]), "q"),
    "input_jacobian.u": (lambda v: FOLLOWER.input_jacobian([0.0], v), "u"),
    "velocity_residual.q_rate": (lambda v: FOLLOWER.velocity_residual(v, [0.0], [0.0], [1.0]), "q_rate"),
    "unknown_rates.q": (lambda v: FOLLOWER.unknown_rates(v, [0.0], [1.0]), "q"),
    "unknown_rates.u_rate": (lambda v: FOLLOWER.unknown_rates([1.0], [0.0], v), "u_rate"),
    "system.x": (lambda v: FOLLOWER.system(v, [0.0], [0.0], [0.0]), "x"),
    "newton_function.u": (lambda v: FOLLOWER.newton_function(v), "u"),
    "consecutive.seed": (lambda v: FOLLOWER.consecutive([0.0], [1.0], [0.0], v), "seed"),
    "simultaneous.u": (lambda v: FOLLOWER.simultaneous(v, [1.0], [0.0], [1.0, 0.0, 0.0]), "u"),
    "smallest_singular_value.q": (lambda v: FOLLOWER.smallest_singular_value(v, [0.0]), "q"),
    "joints.motion": (lambda v: FOLLOWER.joints(v), "motion"),
    "solve.guess": (lambda v: FOLLOWER.solve({u: 0.1}, guess={x: v}), "guess"),
    "solve.inputs": (lambda v: FOLLOWER.solve({u: v}, guess={x: 1.0}), "inputs"),
}
BAD_VALUES = [[1.0, 2.0], [[1.0, 2.0]], "0.5", None, [np.inf], {"x": 1.0}]


@pytest.mark.parametrize(
    ("call", "name", "value"),
    [
        pytest.param(call, name, value, id=f"{label}={value!r}")
        for label, (call, name) in BAD_CALLS.items()
        for value in BAD_VALUES
        if not (label == "solve.inputs" and isinstance(value, list) and value[0] != np.inf)
    ],
)
def test_a_bad_argument_is_named_with_its_value(call, name, value):
    with pytest.raises(CourseLibError) as caught:
        call(value)
    message = str(caught.value)
    assert name in message, message
    assert repr(value) in message or str(value) in message or "inf" in message, message


def test_extra_entries_are_refused():
    with pytest.raises(InvalidGeometryError, match=r"rates has the key 'omega'"):
        FOLLOWER.solve({u: 0.1}, rates={"omega": 1.0}, guess={x: 1.0})
    with pytest.raises(InvalidGeometryError, match=r"guess has the key 'y'"):
        FOLLOWER.solve({u: 0.1}, guess={x: 1.0, "y": 2.0})
    with pytest.raises(InvalidGeometryError, match=r"some of \[L\] and nothing else; got \['L', 'M'\]"):
        TRAMMEL.with_parameters({"L": 0.2, "M": 1.0})


def test_inputs_are_printed_at_full_precision():
    near = LENGTH * (1 - 1e-13)
    with pytest.raises(SingularJacobianError, match=repr(-near).replace(".", r"\.")):
        TRAMMEL.solve({x_A: -near}, rates={x_A: 1.0}, guess=TRAMMEL_GUESS)


# ------------------------------------------------------------------ properties near dead centres


@settings(deadline=None, max_examples=40, derandomize=True)
@given(gap=st.floats(1e-14, 1e-1), speed=st.floats(0.1, 10.0))
def test_trammel_near_its_dead_centre_is_exact_or_refused(gap, speed):
    position = -LENGTH * (1 - gap)
    motion = TRAMMEL.solve({x_A: position}, guess=TRAMMEL_GUESS)
    height = LENGTH * math.sqrt(gap * (2 - gap))  # y_B = √(L² − x_A²)
    assert abs(motion.position["y_B"] - height) <= 1e-7 * LENGTH
    if motion.singular:
        with pytest.raises(SingularJacobianError):
            TRAMMEL.solve({x_A: position}, rates={x_A: speed}, guess=TRAMMEL_GUESS)
    else:
        rates = TRAMMEL.solve({x_A: position}, rates={x_A: speed}, guess=TRAMMEL_GUESS).velocity
        exact = -position * speed / height  # ẏ_B = −x_A·ẋ_A / y_B
        assert rates["y_B"] == pytest.approx(exact, rel=1e-3)


@settings(deadline=None, max_examples=30, derandomize=True)
@given(gap=st.floats(1e-12, 1e-2), count=st.integers(3, 40))
def test_a_sweep_ending_near_a_limit_never_loses_an_instant(gap, count):
    ground, crank, coupler, rocker = 0.20, 0.15, 0.10, 0.12
    limit = math.acos((ground**2 + crank**2 - (coupler + rocker) ** 2) / (2 * ground * crank))
    theta2 = np.linspace(-1.0, limit - gap, count)
    motion = fourbar(ground, crank, coupler, rocker).solve({th2: theta2}, guess={th3: 1.0, th4: 2.0})
    # the guess closes the loop at θ2 = −1 on FourBar's open assembly (B left of A → O4), and a sweep keeps
    # the assembly its first instant is on: the crossed one meets it only at the limit, never reached here
    expected = FourBar(crank, coupler, rocker, ground).solve(theta2, branch="open")
    assert motion.converged.all()
    assert np.abs(wrapped(motion.position["theta4"] - expected.theta4)).max() < 1e-6
