"""course_lib.slider_crank against a sympy chain-rule derivation, the mirror image, and the saw."""

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from course_lib import saw
from course_lib.errors import InvalidGeometryError, SingularJacobianError, UnreachableError
from course_lib.slider_crank import OffsetSliderCrank

MACHINE = OffsetSliderCrank(crank=0.075, rod=0.170, offset=0.045)
angles = st.floats(min_value=-10.0, max_value=10.0)
speeds = st.floats(min_value=-8.0, max_value=8.0)
accelerations = st.floats(min_value=-20.0, max_value=20.0)


def sympy_slider(sign):
    """x(θ2) in closed form; v = x'(θ2) ω2 and a = x''(θ2) ω2² + x'(θ2) α2 by the chain rule."""
    th, w, al = sp.symbols("theta2 omega2 alpha2")
    crank, rod, offset = sp.Rational(75, 1000), sp.Rational(170, 1000), sp.Rational(45, 1000)
    height = offset - crank * sp.sin(th)
    x = crank * sp.cos(th) + sign * sp.sqrt(rod**2 - height**2)
    theta3 = sp.atan2(height, x - crank * sp.cos(th))
    dx, dtheta3 = sp.diff(x, th), sp.diff(theta3, th)
    values = [x, dx * w, sp.diff(x, th, 2) * w**2 + dx * al, theta3, dtheta3 * w,
              sp.diff(theta3, th, 2) * w**2 + dtheta3 * al]
    return sp.lambdify([th, w, al], values, "numpy")


SYMPY = {"right": sympy_slider(+1), "left": sympy_slider(-1)}


@pytest.mark.parametrize("branch", ["right", "left"])
@given(theta2=angles, omega2=speeds, alpha2=accelerations)
@settings(max_examples=80)
def test_matches_sympy_chain_rule(branch, theta2, omega2, alpha2):
    x, v, a, theta3, omega3, alpha3 = SYMPY[branch](theta2, omega2, alpha2)
    motion = MACHINE.solve(theta2, omega2, alpha2, branch=branch)
    assert abs(motion.xC - x) < 1e-14
    assert abs(motion.v_xC - v) < 1e-12
    assert abs(motion.a_xC - a) < 1e-11 * (1 + abs(a))
    assert abs(np.cos(motion.theta3) - np.cos(theta3)) < 1e-14
    assert abs(np.sin(motion.theta3) - np.sin(theta3)) < 1e-14
    assert abs(motion.omega3 - omega3) < 1e-12
    assert abs(motion.alpha3 - alpha3) < 1e-11 * (1 + abs(alpha3))


@given(theta2=angles, omega2=speeds, alpha2=accelerations)
def test_left_branch_is_the_mirror_image_of_the_right(theta2, omega2, alpha2):
    # mirroring x → −x maps an angle θ to π − θ and reverses rates
    left = MACHINE.solve(theta2, omega2, alpha2, branch="left")
    right = MACHINE.solve(np.pi - theta2, -omega2, -alpha2, branch="right")
    assert abs(left.xC + right.xC) < 1e-14
    assert abs(left.v_xC + right.v_xC) < 1e-12
    assert abs(left.a_xC + right.a_xC) < 1e-11 * (1 + abs(left.a_xC))
    assert abs(np.cos(left.theta3) + np.cos(right.theta3)) < 1e-14
    assert abs(left.omega3 + right.omega3) < 1e-12


def test_branch_ranges_and_centred_crank_formula():
    theta2 = np.linspace(0, 2 * np.pi, 37)
    left, right = MACHINE.solve(theta2, branch="left"), MACHINE.solve(theta2, branch="right")
    assert np.all((left.theta3 > np.pi / 2) & (left.theta3 < 3 * np.pi / 2))
    assert np.all(np.abs(right.theta3) < np.pi / 2)
    assert np.all(left.xC < 0.075 * np.cos(theta2)) and np.all(right.xC > 0.075 * np.cos(theta2))
    centred = OffsetSliderCrank(0.05, 0.2).solve(theta2)
    assert np.allclose(centred.xC, 0.05 * np.cos(theta2) + np.sqrt(0.2**2 - (0.05 * np.sin(theta2)) ** 2))


def test_power_saw_mapping():
    # the saw's polar description of the slider pin: x = r1 cos θ1, r1 sin θ1 = r1y
    theta2 = np.linspace(0, 4 * np.pi, 50)
    x = saw.analytic(theta2, 3.0, 1.0)
    motion = MACHINE.solve(theta2, 3.0, 1.0, branch="left")
    assert np.allclose(x[:, 0] * np.cos(x[:, 1]), motion.xC, atol=1e-15)
    assert np.allclose(x[:, 0] * np.sin(x[:, 1]), 0.045, atol=1e-15)
    assert np.allclose(x[:, 2], motion.theta3, atol=1e-13)
    assert np.allclose(x[:, 5], motion.omega3, atol=1e-12)


def test_broadcasting():
    motion = MACHINE.solve(np.zeros((4, 1)), np.ones(3))
    assert motion.xC.shape == motion.a_xC.shape == (4, 3)


def test_unreachable_and_singular():
    short = OffsetSliderCrank(crank=0.075, rod=0.1, offset=0.045)
    with pytest.raises(UnreachableError, match="theta2=-1.5707963"):
        short.solve([0.0, -np.pi / 2])
    toggle = OffsetSliderCrank(crank=0.075, rod=0.12, offset=0.045)
    with pytest.raises(SingularJacobianError, match="theta2"):
        toggle.solve(-np.pi / 2, 1.0)


@pytest.mark.parametrize(
    "call,name",
    [
        (lambda: OffsetSliderCrank(-0.1, 0.2), "crank"),
        (lambda: OffsetSliderCrank(0.1, 0.0), "rod"),
        (lambda: OffsetSliderCrank(0.1, 0.2, np.nan), "offset"),
        (lambda: MACHINE.solve(np.inf), "theta2"),
        (lambda: MACHINE.solve(0.0, "fast"), "omega2"),
        (lambda: MACHINE.solve(0.0, 0.0, np.nan), "alpha2"),
        (lambda: MACHINE.solve(0.0, branch="open"), "branch"),
    ],
)
def test_bad_input_is_named(call, name):
    with pytest.raises(InvalidGeometryError, match=name):
        call()


def test_motion_unpacks_and_converts():
    motion = OffsetSliderCrank(0.075, 0.170, 0.045).solve([0.0, 1.0], 6.0, branch="left")
    theta3, x, omega3, v, alpha3, a = motion
    assert np.array(motion).shape == (6, 2) and np.array_equal(np.array(motion)[3], v)


def test_the_declaration_gives_joints_motion_and_the_singularity_rule():
    theta2 = np.linspace(0.0, 6.0, 25)
    joints = MACHINE.joints(theta2, branch="left")
    solved = MACHINE.solve(theta2, branch="left")
    np.testing.assert_allclose(joints[:, 2], np.stack([solved.xC, np.full(25, 0.045)], -1), atol=1e-15)
    np.testing.assert_allclose(np.linalg.norm(joints[:, 2] - joints[:, 1], axis=-1), 0.170, atol=1e-15)
    assert list(MACHINE.mechanism.points) == ["O2", "A", "C"]
    assert MACHINE.mechanism.links.names == ("crank", "rod")
    # the core's own solve of the declared loop (an independent route to the position) lands on the left
    # assembly the closed form gives
    core = MACHINE.mechanism.solve({"theta2": theta2}, guess={"theta3": float(solved.theta3[0]),
                                                              "xC": float(solved.xC[0])})
    np.testing.assert_allclose(core.position["xC"], solved.xC, atol=1e-12)
    toggle = OffsetSliderCrank(crank=0.075, rod=0.12, offset=0.045)
    motion = toggle.motion([0.0, -np.pi / 2], 1.0, on_failure="nan")
    assert motion.singular.tolist() == [False, True] and np.isnan(motion.velocity["xC"][1])
    assert toggle.mechanism.is_singular([np.pi / 2, 0.0], [-np.pi / 2])


def test_the_older_names_x_v_a_read_xC_and_its_rates():
    motion = MACHINE.solve(np.linspace(0.0, 6.0, 7), 3.0, 1.0, branch="left")
    # C = (xC, offset) is the declared point; its rates by the chain rule of the declared loop
    C, V_C, A_C = MACHINE.mechanism.point_motion(motion, rates={"theta2": 3.0},
                                                 accelerations={"theta2": 1.0})["C"]
    for older, name, column in (("x", "xC", C), ("v", "v_xC", V_C), ("a", "a_xC", A_C)):
        assert np.array_equal(getattr(motion, older), getattr(motion, name)) and motion[older] is motion[name]
        assert np.abs(getattr(motion, name) - column[:, 0]).max() < 1e-12
