"""One assembly vocabulary: every machine's result carries ``Motion.assembly``, the core's σ = −sign(det J_b),
and each machine's own names for its assemblies (branch, mode, modes) map onto it as documented.  The
geometry is computed here, independently: pins by circle intersections, sides by cross products."""

import numpy as np
import pytest
import sympy as sp
from geometry import circle_intersections, fourbar_pins

from course_lib.errors import InvalidGeometryError
from course_lib.fivebar import FiveBar
from course_lib.fourbar import FourBar
from course_lib.mechanism import Mechanism
from course_lib.saw import Saw
from course_lib.slider_crank import OffsetSliderCrank


def cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


THETA2 = np.radians(np.arange(0.0, 360.0, 10.0))
WIPER = FourBar(0.06, 0.18, 0.12, 0.20)


@pytest.mark.parametrize(("branch", "sigma"), [("open", +1), ("crossed", -1)])
def test_the_four_bars_branches_are_sigmas_of_the_core(branch, sigma):
    solution = WIPER.solve(THETA2, branch=branch)
    assert set(np.ravel(solution.assembly["theta3"])) == set(np.ravel(solution.assembly["theta4"])) == {sigma}
    A, B = fourbar_pins(0.20, 0.06, 0.18, 0.12, THETA2, branch)  # open: B left of A → O4
    assert set(np.sign(cross(np.array([0.20, 0.0]) - A, B - A))) == {sigma}
    # the machine's solve and its declaration's solve with that σ: the same assembly
    core = WIPER.mechanism.solve({"theta2": THETA2}, assembly={"theta3": sigma})
    assert np.abs(np.angle(np.exp(1j * (core.position["theta4"] - solution.theta4)))).max() < 1e-12
    assert np.array_equal(core.assembly["theta4"], solution.assembly["theta4"])


@pytest.mark.parametrize(("branch", "sigma"), [("left", +1), ("right", -1)])
def test_the_slider_cranks_branches_are_sigmas_of_the_core(branch, sigma):
    crank = OffsetSliderCrank(0.075, 0.170, 0.045)
    motion = crank.solve(THETA2, branch=branch)
    assert set(np.ravel(motion.assembly["theta3"])) == {sigma}
    core = crank.mechanism.solve({"theta2": THETA2}, assembly={"xC": sigma})
    assert np.abs(core.position["xC"] - motion.xC).max() < 1e-12


ROBOT = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
RNG = np.random.default_rng(7)
T1, T4 = RNG.uniform(-np.pi, np.pi, 400), RNG.uniform(-np.pi, np.pi, 400)


def elbows(theta1, theta4):
    P2 = np.stack([0.04 + 0.10 * np.cos(theta1), 0.10 * np.sin(theta1)], axis=-1)
    P4 = np.stack([-0.04 + 0.10 * np.cos(theta4), 0.10 * np.sin(theta4)], axis=-1)
    return P2, P4


@pytest.mark.parametrize("sigma", [+1, -1])
def test_the_five_bars_arms_up_is_sigma_plus_one_by_a_cross_product(sigma):
    P2, P4 = elbows(T1, T4)
    left, right = circle_intersections(P2, 0.15, P4, 0.15)  # left / right of the directed line P2 → P4
    reach = np.isfinite(left).all(axis=1)
    motion = ROBOT.mechanism.solve({"theta1": T1, "theta4": T4}, assembly={"y3": sigma}, on_failure="nan")
    P3 = np.stack([motion.position["x3"], motion.position["y3"]], axis=-1)
    assert reach.sum() > 200 and np.array_equal(np.isfinite(P3).all(axis=1), reach)
    # arms up: P3 left of the line P4 → P2, i.e. right of P2 → P4
    expected = right if sigma > 0 else left
    assert np.abs(P3[reach] - expected[reach]).max() < 1e-12
    assert set(np.sign(cross(P2 - P4, P3 - P4))[reach]) == {sigma}
    assert set(np.ravel(motion.assembly["x3"])[reach]) == {sigma}
    # the course's mode (+1: the larger Y3) is that σ while P2 is right of P4, the other where it is left
    course = ROBOT.forward(T1, T4, mode=sigma, on_failure="nan")
    D = P2[:, 0] - P4[:, 0]
    assert np.abs(course.y3 - P3[:, 1])[reach & (D > 1e-9)].max() < 1e-12
    assert set(np.ravel(course.assembly["y3"])[reach]) == {-1, 1}
    assert np.array_equal(np.ravel(course.assembly["y3"])[reach], sigma * np.sign(D[reach]).astype(int))


@pytest.mark.parametrize("modes", [(1, 1), (1, -1), (-1, 1), (-1, -1)])
def test_the_five_bars_inverse_modes_map_onto_sigma(modes):
    x3, y3 = RNG.uniform(-0.1, 0.1, 300), RNG.uniform(0.05, 0.22, 300)
    result = ROBOT.inverse(x3, y3, modes=modes, on_failure="nan")
    found = np.isfinite(result.theta1) & np.isfinite(result.theta4)
    assert found.sum() > 200
    P1, P5, P3 = np.array([0.04, 0.0]), np.array([-0.04, 0.0]), np.stack([x3, y3], axis=-1)
    P2, P4 = elbows(result.theta1, result.theta4)
    # each leg's σ: +1 where it turns counter-clockwise at its elbow (l1 then l2; l4 then l3)
    assert set(np.sign(cross(P2 - P1, P3 - P2))[found]) == {-modes[0]}
    assert set(np.sign(cross(P4 - P5, P3 - P4))[found]) == {-modes[1]}
    assert set(np.ravel(result.assembly["theta1"])[found]) == {-modes[0]}
    assert set(np.ravel(result.assembly["theta4"])[found]) == {-modes[1]}


th2, th3, th4, th5, th6 = sp.symbols("theta2:7", real=True)


def two_loops():
    def R(length, angle):
        return length * sp.Matrix([sp.cos(angle), sp.sin(angle)])

    O4, O6 = sp.Matrix([0.20, 0]), sp.Matrix([0.36, 0])
    A, B = R(0.06, th2), O4 + R(0.12, th4)
    C, D = O4 + R(0.12, th4 - 0.26), O6 + R(0.08, th6)
    return Mechanism([A + R(0.18, th3) - B, C + R(0.20, th5) - D], [th3, th4, th5, th6], [th2])


def test_a_partial_assembly_names_the_block_left_to_choose():
    six_bar = two_loops()
    motion = six_bar.solve({th2: np.radians([30.0, 40.0])}, assembly={"theta3": -1})
    assert "theta5/theta6" in motion.message and "σ = +1 taken" in motion.message
    assert set(motion.assembly["theta4"]) == {-1} and set(motion.assembly["theta6"]) == {+1}
    both = six_bar.solve({th2: np.radians([30.0, 40.0])}, assembly={"theta3": -1, "theta5": -1})
    assert "taken" not in both.message and set(both.assembly["theta6"]) == {-1}


def test_several_inputs_keep_each_instants_sigma_in_any_order():
    order = RNG.permutation(len(T1))
    shuffled = ROBOT.mechanism.solve({"theta1": T1[order], "theta4": T4[order]}, assembly={"x3": 1},
                                     on_failure="nan")
    alone = ROBOT.mechanism.solve({"theta1": T1, "theta4": T4}, assembly={"x3": 1}, on_failure="nan")
    assert np.array_equal(shuffled.position["y3"], alone.position["y3"][order], equal_nan=True)


def test_sigma_of_another_block_is_refused_by_name():
    with pytest.raises(InvalidGeometryError, match="two σ for one block"):
        two_loops().solve({th2: 0.5}, assembly={"theta5": 1, "theta6": -1})


@pytest.mark.parametrize(("name", "sigma"), [("open", +1), ("crossed", -1)])
def test_a_machine_takes_its_assembly_by_alias_or_by_sigma(name, sigma):
    by_branch = WIPER.solve(THETA2, branch=name)
    for assembly in (name, {"theta4": sigma}, {"theta3": sigma}):
        chosen = WIPER.solve(THETA2, assembly=assembly)
        assert np.array_equal(chosen.theta4, by_branch.theta4) and set(chosen.assembly["theta4"]) == {sigma}
    crank = OffsetSliderCrank(0.075, 0.170, 0.045)
    side = "left" if sigma > 0 else "right"
    assert np.array_equal(crank.solve(THETA2, assembly={"xC": sigma}).xC, crank.solve(THETA2, branch=side).xC)
    assert np.array_equal(crank.solve(THETA2, assembly=side).xC, crank.solve(THETA2, branch=side).xC)


@pytest.mark.parametrize(("name", "sigma"), [("arms up", +1), ("arms down", -1)])
def test_the_five_bars_forward_assembly_is_the_side_of_P4_to_P2_everywhere(name, sigma):
    P2, P4 = elbows(T1, T4)
    left, right = circle_intersections(P2, 0.15, P4, 0.15)
    reach = np.isfinite(left).all(axis=1)
    for assembly in (name, {"x3": sigma}, {"y3": sigma}):
        pen = ROBOT.forward(T1, T4, assembly=assembly, on_failure="nan")
        P3 = np.stack([pen.x3, pen.y3], axis=-1)
        assert np.abs(P3[reach] - (right if sigma > 0 else left)[reach]).max() < 1e-12
        assert set(np.ravel(pen.assembly["x3"])[reach]) == {sigma}


def test_the_five_bars_inverse_assembly_names_each_legs_sigma():
    x3, y3 = RNG.uniform(-0.1, 0.1, 200), RNG.uniform(0.05, 0.22, 200)
    for s1, s4 in ((1, 1), (1, -1), (-1, 1), (-1, -1)):
        chosen = ROBOT.inverse(x3, y3, assembly={"theta1": s1, "theta4": s4}, on_failure="nan")
        course = ROBOT.inverse(x3, y3, modes=(-s1, -s4), on_failure="nan")
        assert np.array_equal(chosen.theta1, course.theta1, equal_nan=True)
        assert np.array_equal(chosen.theta4, course.theta4, equal_nan=True)
    one_leg = ROBOT.inverse(x3, y3, modes=(1, -1), assembly={"theta1": 1}, on_failure="nan")
    assert np.array_equal(one_leg.theta4, ROBOT.inverse(x3, y3, modes=(1, -1), on_failure="nan").theta4,
                          equal_nan=True)


@pytest.mark.parametrize(("call", "match"), [
    (lambda: WIPER.solve(1.0, assembly="up"), "assembly must be one of"),
    (lambda: WIPER.solve(1.0, assembly={"theta2": 1}), "assembly must map"),
    (lambda: WIPER.solve(1.0, branch="crossed", assembly="open"), "branch and assembly disagree"),
    (lambda: ROBOT.forward(1.0, 2.0, mode=-1, assembly="arms up"), "mode and assembly"),
    (lambda: ROBOT.inverse(0.0, 0.15, assembly={"x3": 1}), "assembly must map"),
])
def test_a_wrong_assembly_is_named(call, match):
    with pytest.raises(InvalidGeometryError, match=match):
        call()


# ------------------------------------------------------------- joints: of a motion, by name, on every machine
def test_every_machines_joints_of_a_motion_are_its_declared_points_by_name():
    theta = np.linspace(-1.0, 2.0, 7)
    bar, slider, saw, robot = (FourBar(0.06, 0.18, 0.12, 0.20), OffsetSliderCrank(0.075, 0.170, 0.045), Saw(),
                               FiveBar(0.10, 0.15, 0.15, 0.10, 0.08))
    cases = {bar: (bar.solve(theta), {"A": (0.0, 0.06, "O2"), "B": (0.20, 0.12, "O4")}, ("A", "B", 0.18)),
             slider: (slider.solve(theta, assembly="left"), {"A": (0.0, 0.075, "O2")}, ("A", "C", 0.170)),
             saw: (saw.motion(theta), {"A": (0.0, 0.075, "O2")}, ("A", "C", 0.170)),
             robot: (robot.forward(np.linspace(1.0, 1.4, 7), 1.9),
                     {"P2": (0.04, 0.10, "P1"), "P4": (-0.04, 0.10, "P5")}, ("P2", "P3", 0.15))}
    for machine, (motion, on_circles, (end, other, length)) in cases.items():
        joints = machine.joints(motion)
        assert list(joints) == list(machine.mechanism.points)  # by name, declared order
        for name, (centre_x, radius, pivot) in on_circles.items():  # each pin on its pivot's circle
            assert np.allclose(joints[pivot], [centre_x, 0.0], atol=1e-15)
            assert np.abs(np.hypot(*(joints[name] - joints[pivot]).T) - radius).max() < 1e-12
        assert np.abs(np.hypot(*(joints[other] - joints[end]).T) - length).max() < 1e-12
        if machine is not robot:  # the older spelling: the same points stacked in declared order, from θ2
            older = machine.joints(theta, "left") if machine is slider else machine.joints(theta)
            assert np.array_equal(older, np.stack(list(joints.values()), axis=-2))
