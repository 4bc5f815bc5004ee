"""One solver: a machine's solve is the core's solve of its declaration.  The same Motion to the bit
from ``FourBar.solve`` and ``FourBar(...).mechanism.solve``; the kernel registered on the declaration
(the course's closed form, for speed) against the closed form the core derives from the declared loop
with no kernel; the assembly names against cross products computed here; the core's rules (σ named
by ``assembly=`` held, a closed form every angle solves reported as not determined, lengths of any
scale) met by the kernel route and the derived route alike.
"""

import dataclasses

import numpy as np
import pytest
from geometry import fourbar_pins

from course_lib.errors import InvalidArgumentError, SingularJacobianError
from course_lib.fivebar import FORWARD_ASSEMBLIES, WORKING_MODES, FiveBar
from course_lib.fivebar import _declaration as fivebar_declaration
from course_lib.fourbar import ASSEMBLIES, FourBar, _declaration
from course_lib.mechanism import Mechanism
from course_lib.motion import Motion
from course_lib.saw import ASSEMBLIES as SAW_ASSEMBLIES
from course_lib.saw import COURSE_SAW, Saw
from course_lib.saw import _declaration as saw_declaration
from course_lib.saw import analytic as saw_analytic
from course_lib.slider_crank import ASSEMBLIES as SLIDER_ASSEMBLIES
from course_lib.slider_crank import OffsetSliderCrank
from course_lib.slider_crank import _declaration as slider_declaration

RNG = np.random.default_rng(2026)
#: Random linkages: lengths spread over three decades, every Grashof class among them.
LINKAGES = [FourBar(*lengths) for lengths in np.exp(RNG.uniform(np.log(1e-3), 0.0, (40, 4)))]
SWEEP = np.r_[np.linspace(-7.0, 7.0, 301), RNG.uniform(-4.0, 4.0, 50)]


def derived(linkage: FourBar):
    """The four-bar's declaration with its lengths and no kernel: the core's own closed form."""
    return _declaration().with_parameters({"l1": linkage.l1, "l2": linkage.l2, "l3": linkage.l3,
                                           "l4": linkage.l4})


def same_bits(a, b) -> bool:
    """Equal arrays or numbers, NaN where the other is NaN, to the bit."""
    a, b = np.asarray(a), np.asarray(b)
    return a.shape == b.shape and a.dtype == b.dtype and np.array_equal(a, b, equal_nan=a.dtype.kind == "f")


def both_routes(with_kernel, without, assembly):
    """The sweep solved through the registered kernel and through the derived closed form, checked to agree:
    the same instants found, positions to 1e-12, rates to 1e-9 of their size away from singularities;
    returns both and the instants compared."""
    kernel, core = (mechanism.solve({"theta2": SWEEP}, {"theta2": 10.0}, {"theta2": 5.0}, assembly=assembly,
                                    on_failure="nan") for mechanism in (with_kernel, without))
    assert np.array_equal(kernel.converged, core.converged)
    found = np.asarray(kernel.converged) & ~np.asarray(core.near_singular)
    for name in kernel.position:
        gap = np.abs(kernel.position[name] - core.position[name])[np.asarray(kernel.converged)]
        assert gap.max(initial=0.0) < 1e-12, name
        for part in ("velocity", "acceleration"):
            mine, theirs = getattr(kernel, part)[name][found], getattr(core, part)[name][found]
            assert (np.abs(mine - theirs) / (1.0 + np.abs(theirs))).max(initial=0.0) < 1e-9, (name, part)
    return kernel, core, found


def assert_same_motion(machine: Motion, core: Motion) -> None:
    for field in dataclasses.fields(Motion):
        mine, theirs = getattr(machine, field.name), getattr(core, field.name)
        if isinstance(mine, dict) or hasattr(mine, "keys"):
            assert list(mine) == list(theirs), field.name
            assert all(same_bits(mine[k], theirs[k]) for k in mine), field.name
        elif field.name in ("message", "newton"):
            assert mine == theirs, field.name
        else:
            assert same_bits(mine, theirs), field.name


@pytest.mark.parametrize("assembly", ["open", "crossed"])
@pytest.mark.parametrize("linkage", LINKAGES[:12] + [FourBar(0.06, 0.18, 0.12, 0.20), FourBar(1, 1, 1, 1)])
def test_the_machine_solve_is_its_declaration_solve_to_the_bit(linkage, assembly):
    assert_machine_is_its_core(linkage.solve, linkage.mechanism, assembly, ASSEMBLIES[assembly], omega2=10.0)


def assert_machine_is_its_core(solve, mechanism, assembly, sigma, omega2):
    """``solve(theta2, omega2, alpha2, assembly=...)`` of a machine and its declaration's solve with that σ:
    the same Motion to the bit, on a sweep, one instant, and a sweep with a rate per instant."""
    for theta2, rate, alpha2 in ((SWEEP, omega2, -3.0), (0.7, 2.0, 0.5), (SWEEP[:40], SWEEP[:40], 1.0)):
        machine = solve(theta2, rate, alpha2, assembly=assembly, on_failure="nan")
        core = mechanism.solve({"theta2": theta2}, {"theta2": rate}, {"theta2": alpha2}, assembly=sigma,
                               on_failure="nan")
        assert type(core) is Motion and isinstance(machine, Motion)
        assert_same_motion(machine, core)


@pytest.mark.parametrize("sigma", [+1, -1])
def test_the_registered_kernel_agrees_with_the_closed_form_the_core_derives(sigma):
    checked = 0
    for linkage in LINKAGES:
        kernel, core, found = both_routes(linkage.mechanism, derived(linkage), {"theta4": sigma})
        assert same_bits(kernel.assembly["theta4"], core.assembly["theta4"])
        checked += int(np.count_nonzero(found))
    assert checked > 500  # instants away from toggles where both routes close the loop: not a vacuous test


@pytest.mark.parametrize(("assembly", "sigma"), [("open", +1), ("crossed", -1)])
def test_the_assembly_names_are_the_side_of_b_a_cross_product_decides(assembly, sigma):
    # open: B left of the directed line A → O4, computed here from two circles and a cross product
    for linkage in LINKAGES[:20]:
        motion = linkage.solve(SWEEP, assembly=assembly, on_failure="nan")
        found = np.asarray(motion.converged)
        A, B = fourbar_pins(linkage.l1, linkage.l2, linkage.l3, linkage.l4, SWEEP[found], assembly)
        to_O4, to_B = np.array([linkage.l1, 0.0]) - A, B - A
        cross = to_O4[:, 0] * to_B[:, 1] - to_O4[:, 1] * to_B[:, 0]
        clear = np.abs(cross) > 1e-9 * linkage.l3 * linkage.l4  # not at a toggle, where B is on the line
        assert set(np.sign(cross[clear])) <= {sigma}
        assert set(np.ravel(motion.assembly["theta4"])[found]) <= {sigma} and motion.assembly is not None
        joints = linkage.mechanism.joints(motion)
        assert np.abs(joints["B"][found] - B).max(initial=0.0) < 1e-9 * max(linkage.l3, linkage.l4, 1e-3)


def test_a_named_assembly_holds_through_a_change_point_a_guess_follows_the_motion():
    rhombus = FourBar(1, 1, 1, 1)  # A passes O4 at θ2 = 0: a change point
    theta2 = np.linspace(0.3, 2 * np.pi - 0.3, 60)
    for assembly, sigma in (("open", 1), ("crossed", -1)):
        held = rhombus.solve(theta2, assembly=assembly)
        assert set(np.ravel(held.assembly["theta4"])) == {sigma} and "change point" not in held.message
    followed = rhombus.mechanism.solve({"theta2": theta2}, guess={"theta3": 0.0, "theta4": 0.3})
    assert np.abs(np.angle(np.exp(1j * (followed.position["theta4"] - theta2)))).max() < 1e-9  # θ4 = θ2


def test_a_closed_form_every_angle_solves_is_not_determined_by_either_route():
    for mechanism in (FourBar(1, 1, 1, 1).mechanism, derived(FourBar(1, 1, 1, 1))):
        with pytest.raises(SingularJacobianError, match=r"not determined at theta2=0\b"):
            mechanism.solve({"theta2": [0.5, 0.0]})
        motion = mechanism.solve({"theta2": [0.5, 0.0]}, on_failure="nan")
        assert motion.converged.tolist() == [True, False] and motion.singular.tolist() == [False, True]
        assert "not determined" in motion.message


@pytest.mark.parametrize("scale", [1e-300, 1e-50, 1e50, 1e300])
def test_any_scale_of_the_lengths_gives_the_same_angles_and_rates(scale):
    # the kernel works in lengths divided by the longest; the derived closed form's discriminant is of
    # degree four in the lengths, within a double's range from lengths of 1e-50 to 1e50
    reference = FourBar(0.06, 0.18, 0.12, 0.20).solve(1.0, 10.0, 3.0)
    scaled = FourBar(0.06 * scale, 0.18 * scale, 0.12 * scale, 0.20 * scale)
    for mechanism in (scaled.mechanism, derived(scaled))[:1 if abs(np.log10(scale)) > 50 else 2]:
        motion = mechanism.solve({"theta2": 1.0}, {"theta2": 10.0}, {"theta2": 3.0}, assembly={"theta4": 1})
        for part in ("position", "velocity", "acceleration"):
            for name in ("theta3", "theta4"):
                assert getattr(motion, part)[name] == pytest.approx(getattr(reference, part)[name], rel=1e-12)


@pytest.mark.parametrize(("unknown", "kernel", "message"), [
    ("theta2", lambda p, k, s: None, "unknown must name"),
    ("theta4", "not callable", "kernel must be a function"),
])
def test_a_bad_kernel_registration_is_refused_by_name(unknown, kernel, message):
    with pytest.raises(InvalidArgumentError, match=message):
        derived(FourBar(1, 2, 3, 4)).with_kernel(unknown, kernel)


def test_a_kernel_that_returns_the_wrong_names_is_named():
    broken = derived(FourBar(0.06, 0.18, 0.12, 0.20)).with_kernel("theta3", lambda p, k, s: ({"x": 1.0}, 1.0))
    with pytest.raises(InvalidArgumentError, match="kernel of theta4 must return the values of"):
        broken.solve({"theta2": 0.3})


# ------------------------------------------------------------------ the offset slider-crank
SLIDERS = [OffsetSliderCrank(*lengths) for lengths in
           np.c_[np.exp(RNG.uniform(np.log(1e-2), 0.0, (12, 2))), RNG.uniform(-0.5, 0.5, 12)]]


def derived_slider(slider: OffsetSliderCrank):
    return slider_declaration().with_parameters({"crank": slider.crank, "rod": slider.rod,
                                                 "offset": slider.offset})


@pytest.mark.parametrize("assembly", ["left", "right"])
@pytest.mark.parametrize("slider", SLIDERS[:6] + [OffsetSliderCrank(0.075, 0.170, 0.045)])
def test_the_slider_crank_solve_is_its_declaration_solve_to_the_bit(slider, assembly):
    for theta2, omega2, alpha2 in ((SWEEP, 10.0, -3.0), (0.7, 2.0, 0.5)):
        machine = slider.solve(theta2, omega2, alpha2, assembly=assembly, on_failure="nan")
        core = slider.mechanism.solve({"theta2": theta2}, {"theta2": omega2}, {"theta2": alpha2},
                                      assembly=SLIDER_ASSEMBLIES[assembly], on_failure="nan")
        assert_same_motion(machine, core)


@pytest.mark.parametrize(("assembly", "side"), [("left", -1), ("right", +1)])
def test_the_slider_kernel_agrees_with_the_derived_closed_form_and_its_side_with_circles(assembly, side):
    checked = 0
    for slider in SLIDERS:
        kernel, _, found = both_routes(slider.mechanism, derived_slider(slider), SLIDER_ASSEMBLIES[assembly])
        # C where the circle of radius rod about A meets y = offset, on the named side of A, computed here
        ax, ay = slider.crank * np.cos(SWEEP), slider.crank * np.sin(SWEEP)
        with np.errstate(invalid="ignore"):
            run = side * np.sqrt(slider.rod**2 - (slider.offset - ay) ** 2)
        assert np.abs(kernel.position["xC"] - (ax + run))[found].max(initial=0.0) < 1e-12
        checked += int(np.count_nonzero(found))
    assert checked > 500


# ------------------------------------------------------------ a motion is used only with its own mechanism
def test_another_machines_motion_is_refused_by_name_where_it_would_be_drawn_with_these_lengths():
    desk, other = FourBar(0.06, 0.18, 0.12, 0.20), FourBar(0.1, 0.3, 0.2, 0.35)
    with pytest.raises(InvalidArgumentError, match="does not close these loops"):
        desk.mechanism.joints(other.solve(0.5))
    # the same loops with a coupler point declared: the same lengths, so drawn
    P = desk.with_coupler_point(0.09, 0.0).joints(desk.solve(0.5))["P"]
    A, B = fourbar_pins(0.20, 0.06, 0.18, 0.12, 0.5, "open")
    np.testing.assert_allclose(P, A + 0.5 * (B - A), atol=1e-12)  # p = l3/2, δ = 0: the coupler's middle


def test_point_motion_reads_the_input_rates_from_the_motion_and_refuses_others():
    desk = FourBar(0.06, 0.18, 0.12, 0.20)
    theta2, omega2, alpha2 = np.linspace(0.0, 6.0, 7), 2.0, 0.5
    motion = desk.solve(theta2, omega2, alpha2)
    A, V_A, A_A = desk.mechanism.point_motion(motion)["A"]
    # the crank pin by hand: V = ω2 k̂ × R2, A = α2 k̂ × R2 − ω2² R2
    R2 = 0.06 * np.stack([np.cos(theta2), np.sin(theta2)], axis=-1)
    turned = np.stack([-R2[:, 1], R2[:, 0]], axis=-1)
    np.testing.assert_allclose(V_A, omega2 * turned, atol=1e-14)
    np.testing.assert_allclose(A_A, alpha2 * turned - omega2**2 * R2, atol=1e-13)
    with pytest.raises(InvalidArgumentError, match="rates are not the ones"):
        desk.mechanism.point_motion(motion, rates={"theta2": 3.0})
    with pytest.raises(InvalidArgumentError, match="accelerations are not the ones"):
        desk.mechanism.point_motion(motion, rates={"theta2": omega2}, accelerations={"theta2": 0.0})


# The five-bar: forward (X3, Y3 from θ1, θ4) and inverse (θ1, θ4 from X3, Y3), each the core's solve of one
# declaration with the course's closed forms registered as kernels.
ROBOTS = [FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)] + [
    FiveBar(*lengths) for lengths in np.c_[RNG.uniform(0.05, 0.2, (5, 4)), RNG.uniform(0.0, 0.1, 5)]]
CRANKS = RNG.uniform(-np.pi, np.pi, (2, 300))
POINTS = RNG.uniform(-0.35, 0.35, (2, 300))


def lengths_of(robot: FiveBar) -> dict:
    return {name: getattr(robot, name) for name in ("l1", "l2", "l3", "l4", "l5")}


def pins(robot: FiveBar, theta1, theta4):
    """P1, P2, P4, P5 from the lengths and the crank angles, written here."""
    P1, P5 = np.array([robot.l5 / 2, 0.0]), np.array([-robot.l5 / 2, 0.0])
    P2 = P1[:, None] + robot.l1 * np.array([np.cos(theta1), np.sin(theta1)])
    P4 = P5[:, None] + robot.l4 * np.array([np.cos(theta4), np.sin(theta4)])
    return P1[:, None], P2, P4, P5[:, None]


def cross(a, b):
    return a[0] * b[1] - a[1] * b[0]


def robot_routes(robot: FiveBar):
    """The forward declaration and the inverse one (loops solved the other way round), with no kernel."""
    forward = fivebar_declaration().with_parameters(lengths_of(robot))
    inverse = Mechanism(list(forward.equations), list(forward.inputs), list(forward.unknowns),
                        lengths_of(robot))
    return forward, inverse


@pytest.mark.parametrize("robot", ROBOTS)
def test_the_five_bar_forward_is_its_declaration_solve_to_the_bit(robot):
    theta1, theta4 = CRANKS
    inputs = {"theta1": theta1, "theta4": theta4}
    for name, sigma in FORWARD_ASSEMBLIES.items():
        machine = robot.forward(theta1, theta4, assembly=name, on_failure="nan")
        assert_same_motion(machine, robot.mechanism.solve(inputs, assembly=sigma, on_failure="nan"))
    _, P2, P4, _ = pins(robot, theta1, theta4)
    right = np.where(P2[0] - P4[0] >= 0, 1, -1)  # the course's σ (larger Y3) is the core's: P2 right of P4
    for mode in (1, -1):
        machine = robot.forward(theta1, theta4, mode, on_failure="nan")
        assert_same_motion(machine, robot.mechanism.solve(inputs, assembly={"x3": mode * right},
                                                          on_failure="nan"))
        moving = robot.motion(theta1, theta4, mode, 1.0, -2.0, 0.5, 0.0, on_failure="nan")
        assert_same_motion(moving, robot.mechanism.solve(inputs, {"theta1": 1.0, "theta4": -2.0},
                                                         {"theta1": 0.5, "theta4": 0.0},
                                                         assembly={"x3": mode * right}, on_failure="nan"))


@pytest.mark.parametrize("robot", ROBOTS)
def test_the_five_bar_inverse_is_its_declaration_solve_to_the_bit(robot):
    core = robot.inverse(0.0, 0.2, on_failure="nan")  # the loops solved the other way round
    for modes in WORKING_MODES:
        machine = robot.inverse(*POINTS, modes, on_failure="nan")
        declared = core_of(robot, "inverse").solve({"x3": POINTS[0], "y3": POINTS[1]},
                                                    assembly={"theta1": -modes[0], "theta4": -modes[1]},
                                                    on_failure="nan")
        assert_same_motion(machine, declared)
        assert machine.modes == modes and type(core) is type(machine)


def core_of(robot, kind):
    return robot._cores[kind]


@pytest.mark.parametrize("robot", ROBOTS)
def test_the_five_bar_kernels_agree_with_the_closed_forms_the_core_derives(robot):
    forward, inverse = robot_routes(robot)
    size = max(robot.l1, robot.l2, robot.l3, robot.l4)
    cases = [(robot.mechanism, forward, {"theta1": CRANKS[0], "theta4": CRANKS[1]}, "x3", [1, -1]),
             (core_of(robot, "inverse"), inverse, {"x3": POINTS[0], "y3": POINTS[1]}, "theta1", [1, -1])]
    for with_kernel, without, inputs, key, sigmas in cases:
        rates = {name: 1.0 + k for k, name in enumerate(inputs)}
        for sigma in sigmas:
            assembly = {name: sigma for name in with_kernel._block_of()}
            mine, theirs = (m.solve(inputs, rates, rates, assembly=assembly, on_failure="nan")
                            for m in (with_kernel, without))
            assert np.array_equal(mine.converged, theirs.converged), key
            assert np.asarray(mine.converged).sum() > 30, key
            found = np.asarray(mine.converged) & ~np.asarray(theirs.near_singular)
            for name in mine.position:
                unit = 1.0 if name.startswith("theta") else size
                gap = np.abs(mine.position[name] - theirs.position[name])
                # the derived closed form divides by terms that can be small (its residual reaches 1e-11
                # of l² here): the routes agree to 1e-9; near a singularity, where rounding grows like √ε,
                # to 1e-6; the kernel's own loops close to rounding (below)
                assert gap[found].max() < 1e-9 * unit, name
                assert gap[np.asarray(mine.converged)].max() < 1e-6 * unit, name
                for part in ("velocity", "acceleration"):
                    a, b = getattr(mine, part)[name][found], getattr(theirs, part)[name][found]
                    assert (np.abs(a - b) / (1.0 + np.abs(b))).max() < 1e-9, (name, part)
            assert all(np.array_equal(mine.assembly[k], theirs.assembly[k]) for k in mine.assembly)
            q = np.stack([mine.position[s.name] for s in with_kernel.unknowns], -1)
            u = np.stack([inputs[s.name] for s in with_kernel.inputs], -1)
            closure = np.abs(with_kernel.residual(q, u))[np.asarray(mine.converged)]
            assert closure.max() < 1e-14 * size**2, key


@pytest.mark.parametrize("robot", ROBOTS)
def test_arms_up_puts_p3_left_of_the_line_p4_to_p2_by_a_cross_product(robot):
    theta1, theta4 = CRANKS
    _, P2, P4, _ = pins(robot, theta1, theta4)
    for name, side in (("arms up", 1), ("arms down", -1)):
        result = robot.forward(theta1, theta4, assembly=name, on_failure="nan")
        found = np.asarray(result.converged)
        P3 = np.array([result.x3, result.y3])
        turn = cross(P2 - P4, P3 - P4)[found]
        clear = np.abs(turn) > 1e-9  # away from the parallel singularity, where both sides meet
        assert found.sum() > 30 and (np.sign(turn[clear]) == side).all()
        assert (np.asarray(result.assembly["x3"])[found] == side).all()
    up, down = (robot.forward(theta1, theta4, mode, on_failure="nan") for mode in (1, -1))
    found = np.asarray(up.converged)
    assert (np.asarray(up.y3)[found] >= np.asarray(down.y3)[found] - 1e-15).all()  # the course's: larger Y3


@pytest.mark.parametrize("robot", ROBOTS)
def test_the_working_modes_are_minus_the_core_sigma_each_leg_turns_at_its_elbow(robot):
    for modes in WORKING_MODES:
        result = robot.inverse(*POINTS, modes, on_failure="nan")
        found = np.asarray(result.converged)
        P1, P2, P4, P5 = pins(robot, np.asarray(result.theta1), np.asarray(result.theta4))
        P3 = POINTS
        for turn, mode, key in ((cross(P2 - P1, P3 - P2), modes[0], "theta1"),
                                (cross(P4 - P5, P3 - P4), modes[1], "theta4")):
            clear = found & (np.abs(turn) > 1e-9)  # a leg stretched or folded has no side
            assert clear.sum() > 20 and (np.sign(turn[clear]) == -mode).all(), (modes, key)
            assert (np.asarray(result.assembly[key])[found] == -mode).all()


def whole_sweep(monkeypatch, mechanism, *args, **keywords):
    """``mechanism.solve`` by the route that solves every instant's positions first and then the rates (the
    block-by-block route switched off)."""
    with monkeypatch.context() as patch:
        patch.setattr(Mechanism, "_sweepable", lambda *_: False)
        return mechanism.solve(*args, **keywords)


@pytest.mark.parametrize("linkage", LINKAGES[:8] + [FourBar(0.06, 0.18, 0.12, 0.20), FourBar(1, 1, 1, 1)])
@pytest.mark.parametrize("assembly", ["open", "crossed"])
def test_block_by_block_gives_the_positions_of_the_whole_sweep_to_the_bit(monkeypatch, linkage, assembly):
    # an increasing sweep over two turns and more, longer than three blocks, through unreachable stretches and
    # (for the rotating couplers) across ±π, where the angles are carried on from block to block
    theta2 = np.linspace(-7.0, 7.0, 3 * 16_384 + 77)
    σ = ASSEMBLIES[assembly]
    mechanism = linkage.mechanism
    for rates in ({}, {"rates": {"theta2": 10.0}, "accelerations": {"theta2": 5.0}}):
        blocks = mechanism.solve({"theta2": theta2}, assembly=σ, on_failure="nan", **rates)
        whole = whole_sweep(monkeypatch, mechanism, {"theta2": theta2}, assembly=σ, on_failure="nan", **rates)
        for name in ("theta3", "theta4"):
            assert same_bits(blocks.position[name], whole.position[name]), name
            assert same_bits(blocks.assembly[name], whole.assembly[name])
        assert same_bits(blocks.converged, whole.converged) and same_bits(blocks.singular, whole.singular)
        assert blocks.message == whole.message
        if rates:  # the same rates, the cos and sin from the kernel instead of computed again: the rounding
            # of J's entries differs by ulps, amplified by 1/σ_min(J̃) in velocity and its square after
            found = np.asarray(blocks.converged)
            q = np.stack([blocks.theta3[found], blocks.theta4[found]], axis=-1)
            smallest = mechanism.smallest_singular_value(q, theta2[found, None])
            for part, power in (("velocity", 1), ("acceleration", 2)):
                for name in ("theta3", "theta4"):
                    mine, theirs = getattr(blocks, part)[name], getattr(whole, part)[name]
                    assert same_bits(np.isnan(mine), np.isnan(theirs))
                    gap = np.abs(mine - theirs)[found] / (1.0 + np.abs(theirs[found])) * smallest**power
                    assert np.nanmax(gap, initial=0.0) < 1e-12, (part, name)
    turned = np.unwrap(np.arctan2(np.sin(blocks.theta3), np.cos(blocks.theta3)))  # a check by numpy's own
    found = np.isfinite(blocks.theta3)
    if found.all():
        assert np.abs(blocks.theta3 - (turned - turned[0] + blocks.theta3[0])).max() < 1e-9


@pytest.mark.parametrize("robot", ROBOTS)
def test_the_five_bar_block_by_block_is_the_whole_sweep_to_the_bit(monkeypatch, robot):
    theta1, theta4 = np.meshgrid(np.linspace(-np.pi, np.pi, 181), np.linspace(-np.pi, np.pi, 191))
    for mode in (+1, -1):
        blocks = robot.forward(theta1, theta4, mode=mode, on_failure="nan")
        whole_mechanism = whole_sweep(monkeypatch, robot.mechanism, {"theta1": theta1, "theta4": theta4},
                                      assembly={"x3": np.where(blocks.assembly["x3"] < 0, -1, 1)},
                                      on_failure="nan")  # (σ is 0 where no position is found)
        for name in ("x3", "y3"):
            assert same_bits(blocks.position[name], whole_mechanism.position[name]), name


@pytest.mark.parametrize("order", ["declared", "reversed"])
def test_a_guess_is_read_by_its_keys_in_any_order(order):
    # the unit circle cut by the line x − 0.6·y = s: at s = 0.1 the roots are y = (−0.12 ± √5.4)/2.72, by
    # hand; Newton from x = −0.9, y = 0.8 takes the one with y > 0 (a seed read in another order, x = 0.8 and
    # y = −0.9, took the other)
    import sympy as sp

    x, y, s = sp.symbols("x y s")
    circle = Mechanism([x**2 + y**2 - 1, x - 0.6 * y - s], [x, y], [s])
    guess = {x: -0.9, y: 0.8} if order == "declared" else {y: 0.8, x: -0.9}
    solved = circle.solve({s: 0.1}, guess=guess)
    upper = (-0.12 + np.sqrt(0.12**2 + 4 * 1.36 * 0.99)) / 2.72
    assert abs(solved.position["y"] - upper) < 1e-12
    assert abs(solved.position["x"] - (0.1 + 0.6 * upper)) < 1e-12


# ------------------------------------------------------------------------------------------ the saw
SAWS = [Saw(), Saw(r1y=-0.03, r2=0.05, r3=0.2), Saw(r1y=0.045, r2=0.075, r3=0.1)] + [
    Saw(*lengths) for lengths in zip(RNG.uniform(-0.1, 0.1, 5), *RNG.uniform(0.01, 0.3, (2, 5)), strict=True)]


def newton_saw(machine: Saw):
    """The saw's declaration with its lengths and no kernel: the core solves its block by Newton."""
    return saw_declaration("loop").with_parameters({"r1y": machine.r1y, "r2": machine.r2, "r3": machine.r3})


@pytest.mark.parametrize("assembly", ["left", "right"])
@pytest.mark.parametrize("machine", SAWS)
def test_the_saw_motion_is_its_declaration_solve_to_the_bit(machine, assembly):
    assert_machine_is_its_core(machine.motion, machine.mechanism, assembly, SAW_ASSEMBLIES[assembly],
                               omega2=6.0)


@pytest.mark.parametrize(("assembly", "side"), [("left", -1), ("right", +1)])
def test_the_saw_kernel_agrees_with_newton_on_the_declaration_and_its_side_with_a_circle(assembly, side):
    checked = 0
    for machine in SAWS:
        kernel = machine.motion(SWEEP, 6.0, -3.0, assembly=assembly, on_failure="nan")
        found = np.asarray(kernel.converged) & ~np.asarray(kernel.near_singular)
        # C where the circle of radius r3 about A meets y = r1y, on the named side of A, computed here
        ax, ay = machine.r2 * np.cos(SWEEP), machine.r2 * np.sin(SWEEP)
        with np.errstate(invalid="ignore"):
            cx = ax + side * np.sqrt(machine.r3**2 - (machine.r1y - ay) ** 2)
        assert np.array_equal(np.asarray(kernel.converged), np.isfinite(cx))
        assert np.abs(kernel.r1 * np.cos(kernel.theta1) - cx)[found].max(initial=0.0) < 1e-12
        assert np.abs(kernel.r1 * np.sin(kernel.theta1) - machine.r1y)[found].max(initial=0.0) < 1e-12
        # Newton on the declaration with no kernel, from the kernel's first position, along the same sweep
        k = int(np.flatnonzero(found)[0])
        start = {name: float(kernel.position[name][k]) for name in ("r1", "theta1", "theta3")}
        part = SWEEP[k:k + 60]
        part = part[np.asarray(kernel.converged)[k:k + 60]]
        if np.any(np.diff(part) < 0):
            part = part[:int(np.argmax(np.diff(part) < 0)) + 1]
        core = newton_saw(machine).solve({"theta2": part}, {"theta2": 6.0}, {"theta2": -3.0}, guess=start,
                                         on_failure="nan")
        again = machine.motion(part, 6.0, -3.0, assembly=assembly, on_failure="nan")
        clear = np.asarray(core.converged) & ~np.asarray(again.near_singular)
        for name in core.position:
            assert np.abs(core.position[name] - again.position[name])[clear].max(initial=0.0) < 1e-12
            for what in ("velocity", "acceleration"):
                mine, theirs = getattr(again, what)[name][clear], getattr(core, what)[name][clear]
                assert (np.abs(mine - theirs) / (1.0 + np.abs(theirs))).max(initial=0.0) < 1e-9, (name, what)
        checked += int(np.count_nonzero(found))
    assert checked > 500


def test_the_course_saw_motion_is_the_course_closed_form():
    theta2 = np.linspace(0.0, 2 * np.pi, 1000)
    motion, course = COURSE_SAW.motion(theta2, 6.0, 1.0), saw_analytic(theta2, 6.0, 1.0)
    scale = np.abs(course).max(axis=0)
    assert (np.abs(motion.x - course).max(axis=0) <= 1e-13 * scale).all()
    assert set(np.ravel(motion.assembly["theta3"])) == {1}
