"""What the lessons tell a student to try, tried: the explorers driven to the lengths, angles and times that
the "Things to try" of lesson 11 give, and a few statements of lessons 05, 07, 09 and 10 checked again."""

import re

import numpy as np
import pytest
from geometry import fourbar_pins

from course_lib.fivebar import WORKING_MODES, FiveBar
from course_lib.fourbar import FourBar
from course_lib.profile import first_turn_time, motor_profile
from course_lib.saw import analytic, joint_positions
from course_lib.widgets import fivebar_explorer, fourbar_explorer, saw_explorer

T = first_turn_time()
ROBOT = dict(l1=0.10, l2=0.15, l3=0.15, l4=0.10, l5=0.08)
WIPER = dict(crank=0.06, coupler=0.18, rocker=0.12, ground=0.20)


def _shown(pattern: str, message: str) -> float:
    """The number a readout shows after ``pattern`` (a regular expression ending where the number starts)."""
    found = re.search(pattern + r"(-?\d+(?:\.\d+)?)", message)
    assert found, f"{pattern!r} not in the readout:\n{message}"
    return float(found.group(1))


# ------------------------------------------------------------------------- lesson 11, the four-bar explorer


def test_fourbar_smallest_transmission_angle_is_where_crank_and_ground_line_up():
    explorer = fourbar_explorer(**WIPER, theta2=np.radians(60))
    theta2, mu = explorer.artists["mu_curve"].get_data()
    assert abs(theta2[np.nanargmin(mu)]) < 1e-9  # θ2 = 0°, not 180°, for the wiper
    shown = {}
    for angle in (0.0, 180.0):  # crank along the ground, pointing towards O4 and away from it
        assert explorer.update(theta2_deg=angle).status == "ok"
        shown[angle] = _shown(r"transmission angle μ = ", explorer.message)
    assert shown[0.0] < shown[180.0] and abs(shown[0.0] - np.nanmin(mu)) < 5e-3


def test_fourbar_explorer_draws_the_transmission_angle_acute_under_its_40_degree_line():
    explorer = fourbar_explorer(**WIPER)
    theta2, mu = explorer.artists["mu_curve"].get_data()
    # |AO4| from triangle O2 A O4, then the joint angle at B from triangle A B O4 (law of cosines twice)
    AO4 = np.sqrt(0.20**2 + 0.06**2 - 2 * 0.20 * 0.06 * np.cos(np.radians(theta2)))
    joint = np.degrees(np.arccos((0.18**2 + 0.12**2 - AO4**2) / (2 * 0.18 * 0.12)))
    assert joint.max() > 110  # the joint angle at B passes 90° over the turn …
    np.testing.assert_allclose(mu, np.minimum(joint, 180 - joint), atol=1e-9)  # … and μ is drawn acute
    panel = explorer.figure.axes[1]
    assert mu.max() <= 90 and panel.get_ylim() == (0.0, 92.0)
    assert any(list(line.get_ydata()) == [40, 40] for line in panel.lines)


def test_fourbar_crossed_branch_changes_the_coupler_curve_not_the_grashof_class():
    explorer = fourbar_explorer(**WIPER)
    grashof = explorer.message.splitlines()[3]
    curve = np.array(explorer.artists["coupler_curve"].get_data())
    assert explorer.update(assembly="crossed").status == "ok"
    assert explorer.message.splitlines()[3] == grashof and grashof.startswith("Grashof crank-rocker")
    assert np.nanmax(np.abs(np.array(explorer.artists["coupler_curve"].get_data()) - curve)) > 0.01


def test_fourbar_crank_longer_than_coupler_is_non_grashof_with_circles_that_fail_to_meet():
    explorer = fourbar_explorer(**WIPER)
    assert explorer.update(crank=0.15, coupler=0.10).status == "ok"
    assert "non-Grashof" in explorer.message and "input range: θ2 in [" in explorer.message
    assert explorer.update(theta2_deg=120.0).status == "unreachable"
    assert "do not meet" in explorer.message
    assert explorer.artists["reach_A"].get_visible() and explorer.artists["reach_O4"].get_visible()


def test_fourbar_drag_link_of_lesson_11_turns_its_rocker_fully():
    explorer = fourbar_explorer(**WIPER)
    readout = explorer.update(ground=0.05, crank=0.10, coupler=0.12, rocker=0.11)
    assert readout.status == "ok"
    assert "Grashof double-crank: s + l = 0.170 m < p + q = 0.210 m (shortest: ground" in explorer.message
    assert "θ2 turns fully" in explorer.message
    rocker = []
    for theta2 in np.arange(0.0, 361.0, 10.0):
        assert explorer.update(theta2_deg=theta2).status == "ok"
        rocker.append(np.radians(_shown(r"θ4 = ", explorer.message)))
    assert abs(np.unwrap(rocker)[-1] - np.unwrap(rocker)[0] - 2 * np.pi) < 1e-3  # one full turn of the rocker
    # the wiper with only its ground shortened stays non-Grashof (s + l = l1 + 0.18 > 0.18 = p + q)
    for ground in (0.059, 0.05, 0.02):
        shortened = fourbar_explorer(**(WIPER | {"ground": ground}))
        assert "non-Grashof triple-rocker" in shortened.message
        assert FourBar(**(WIPER | {"ground": ground})).grashof().name == "non-Grashof triple-rocker"


# ---------------------------------------------------------------------------- lesson 11, the saw explorer


def _blade(theta2, omega2, alpha2=0.0):
    """r1, θ1, v_r and the slider's own speed ẋ = v_r cos θ1 − r1 ω1 sin θ1 (lesson 07)."""
    r1, theta1, _, v_r, omega1 = np.asarray(analytic(theta2, omega2, alpha2)).T[:5]
    return r1, theta1, v_r, v_r * np.cos(theta1) - r1 * omega1 * np.sin(theta1)


def test_saw_v_r_is_not_the_slider_speed():
    # lesson 11 item 1 (and lesson 07): v_r = ẋ cos θ1, so |v_r| < |ẋ|; at full speed 0.605 against 0.626 m/s
    _, theta1, v_r, x_dot = _blade(np.linspace(0, 2 * np.pi, 20001), 10 * T / 3)
    np.testing.assert_allclose(v_r, x_dot * np.cos(theta1), atol=1e-12)
    assert abs(np.abs(v_r).max() - 0.605) < 5e-4 and abs(np.abs(x_dot).max() - 0.626) < 5e-4
    explorer = saw_explorer()
    for t in np.linspace(T, 2 * T, 7):
        assert explorer.update(t=t).status == "ok"
        theta2, omega2, _ = motor_profile(t)
        _, theta1, v_r, x_dot = _blade(theta2, omega2)
        assert abs(_shown(r"v_r = ", explorer.message) - float(v_r)) < 1e-5
        assert abs(float(v_r)) <= abs(float(x_dot)) * float(np.cos(theta1)) + 1e-12


def test_saw_fastest_blade_is_on_the_return_stroke_near_240_degrees():
    crank = np.linspace(0, 2 * np.pi, 20001)
    _, _, _, x_dot = _blade(crank, 10 * T / 3)
    peak = np.abs(x_dot).argmax()
    assert abs(np.degrees(crank[peak]) - 240) < 0.5 and x_dot[peak] > 0  # moving back towards the crank


def test_saw_strokes_cutting_away_from_the_crank_and_the_quicker_return():
    # lesson 07, section 1: ẋ < 0 (away from the crank) over 197.7° of crank, ẋ > 0 over 162.3°
    crank = np.radians(np.arange(0.05, 360.0, 0.1))
    _, _, _, x_dot = _blade(crank, 1.0)
    x = joint_positions(crank)[:, 2, 0]
    assert np.array_equal(np.sign(x_dot[1:-1]), np.sign(x[2:] - x[:-2]))  # ẋ agrees with the drawn slider
    assert abs(0.1 * (x_dot > 0).sum() - 162.3) < 0.15 and abs(0.1 * (x_dot < 0).sum() - 197.7) < 0.15


@pytest.mark.parametrize("boundary", [T / 3, 2 * T / 3, T])
def test_saw_accelerations_kink_where_the_jerk_switches_positions_and_velocities_do_not(boundary):
    h = 1e-5
    values = [analytic(*motor_profile(boundary + k * h)) for k in (-1, 0, 1)]
    left, right = (values[1] - values[0]) / h, (values[2] - values[1]) / h  # one-sided slopes
    jumps = np.abs(right - left)
    assert np.all(jumps[:6] < 1e-3)    # r1, θ1, θ3, v_r, ω1, ω3: smooth
    assert np.all(jumps[6:] > 1e-2)    # a_r, α1, α3: a kink
    explorer = saw_explorer()
    assert explorer.update(t=boundary - 0.01).status == "ok" and "start-up" in explorer.message
    assert explorer.update(t=boundary + 0.01).status == "ok"
    assert ("steady speed" if boundary == T else "start-up") in explorer.message


def test_saw_a_r_is_not_zero_at_steady_speed():
    explorer = saw_explorer()
    for t in (1.2 * T, 1.5 * T, 1.8 * T):
        assert explorer.update(t=t).status == "ok" and "steady speed" in explorer.message
        assert _shown(r"α2 = ", explorer.message) == 0.0 and abs(_shown(r"a_r = ", explorer.message)) > 0.05


# ----------------------------------------------------------------------- lesson 11, the five-bar explorer


def test_fivebar_flipping_sigma_mirrors_the_end_effector_about_p2p4():
    explorer = fivebar_explorer(**ROBOT)
    robot = FiveBar(**ROBOT)
    ends = {}
    for sigma in (1, -1):
        assert explorer.update(theta1_deg=70.0, theta4_deg=110.0, sigma=sigma).status == "ok"
        x, y = explorer.artists["end_effector"].get_data()
        ends[sigma] = np.array([x[0], y[0]])
    P = robot.joints(np.radians(70.0), np.radians(110.0), 0.0, 0.0)
    P2, P4 = P[1], P[3]
    u = (P4 - P2) / np.hypot(*(P4 - P2))
    mirrored = P2 + 2 * np.dot(ends[1] - P2, u) * u - (ends[1] - P2)
    np.testing.assert_allclose(ends[-1], mirrored, atol=1e-12)


def test_fivebar_crank_pins_together_give_a_parallel_singularity_warning():
    explorer = fivebar_explorer(**ROBOT)
    for sigma in (1, -1):
        readout = explorer.update(theta1_deg=114.0, theta4_deg=66.0, sigma=sigma)
        assert readout.status == "ok"
        assert "near a parallel (type-2) singularity" in explorer.message
        assert abs(_shown(r"parallel ", explorer.message)) < 0.01
    P = FiveBar(**ROBOT).joints(np.radians(114.0), np.radians(66.0), 0.0, 0.0)
    assert abs(np.hypot(*(P[1] - P[3])) - 1.3e-3) < 5e-5


def test_fivebar_forward_mode_never_turns_red_for_the_course_robot():
    # |P2P4| ≤ l1 + l4 + l5 = 0.28 m < l2 + l3 = 0.30 m: every crank pair assembles
    robot = FiveBar(**ROBOT)
    cranks1, cranks4 = np.meshgrid(np.radians(np.arange(360.0)), np.radians(np.arange(360.0)))
    assert robot.forward(cranks1, cranks4, mode=1, on_failure="nan").reachable.all()
    explorer = fivebar_explorer(**ROBOT)
    for theta1 in np.arange(0.0, 360.0, 15.0):
        for theta4 in np.arange(0.0, 360.0, 15.0):
            assert explorer.update(theta1_deg=theta1, theta4_deg=theta4).status == "ok", (theta1, theta4)
    assert explorer.update(theta1_deg=0.0, theta4_deg=180.0).status == "ok"  # cranks wide open
    assert "color:#b00020" not in explorer.readout.value


@pytest.mark.parametrize(("target", "word"),
                         [((0.25, 0.15), "fully stretched"), ((0.04, 0.02), "fully folded")])
def test_fivebar_target_out_of_the_workspace_names_the_leg_and_how(target, word):
    explorer = fivebar_explorer(**ROBOT, kinematics="inverse")
    assert explorer.update(x3=target[0], y3=target[1]).status == "unreachable"
    assert "leg 1 (l1, l2): distance" in explorer.message and word in explorer.message


@pytest.mark.parametrize("modes", WORKING_MODES)
def test_fivebar_crossing_the_red_curve_flips_the_parallel_measure(modes):
    robot = FiveBar(**ROBOT)
    explorer = fivebar_explorer(**ROBOT, mode="inverse", sigma1=modes[0], sigma2=modes[1])
    curve = np.column_stack(explorer.artists["singularity"].get_data())
    assert len(curve) > 0
    for point in curve[np.argsort(np.hypot(*curve.T))]:  # the curve point nearest the base first
        for step in ([0.01, 0.0], [0.0, 0.01]):
            sides = [point - step, point + step]
            solved = [robot.inverse(*side, modes=modes, on_failure="nan") for side in sides]
            if not all(bool(s.reachable) for s in solved):
                continue
            measures = [robot.singularity_measures(s.theta1, s.theta4, *side).parallel
                        for s, side in zip(solved, sides, strict=True)]
            if measures[0] * measures[1] >= 0 or min(abs(m) for m in measures) < 1e-3:
                continue
            shown = []
            for side in sides:
                assert explorer.update(x3=side[0], y3=side[1]).status == "ok"
                shown.append(_shown(r"parallel ", explorer.message))
            assert shown[0] * shown[1] < 0  # the readout's parallel measure changes sign across the curve
            return
    pytest.fail(f"no crossing of the red curve found for modes {modes}")


# ------------------------------------------------------------------------ lessons 05, 09 and 10, re-checked


def test_motor_start_up_thirds_of_time_and_two_more_turns_by_2T():
    theta2 = motor_profile(np.array([0.0, T / 3, 2 * T / 3, T, 2 * T]))[0]
    np.testing.assert_allclose(np.degrees(np.diff(theta2[:4])), [20.0, 120.0, 220.0], atol=1e-9)
    np.testing.assert_allclose(np.degrees(theta2[3:]), [360.0, 1080.0], atol=1e-9)


def test_fivebar_worst_round_trips_are_at_a_parallel_singularity():
    robot = FiveBar(**ROBOT)
    xs, ys = np.meshgrid(np.linspace(-0.2, 0.2, 41), np.linspace(-0.2, 0.25, 46))
    for modes in ((1, 1), (-1, -1)):
        back = robot.inverse(xs, ys, modes=modes, on_failure="nan")
        ok = back.reachable
        up, down = (robot.forward(back.theta1[ok], back.theta4[ok], mode=s) for s in (+1, -1))
        miss = np.minimum(np.hypot(up.x3 - xs[ok], up.y3 - ys[ok]),
                          np.hypot(down.x3 - xs[ok], down.y3 - ys[ok]))
        j = miss.argmax()
        measures = robot.singularity_measures(back.theta1[ok][j], back.theta4[ok][j], xs[ok][j], ys[ok][j])
        assert abs(measures.parallel) < 1e-4
        assert min(abs(measures.serial_leg1), abs(measures.serial_leg4)) > 0.9  # no leg near stretched
        np.testing.assert_allclose(np.abs([xs[ok][j], ys[ok][j]]), [0.15, 0.09], atol=1e-12)


def test_fivebar_stretched_leg_gains_force_loses_velocity_and_hides_from_the_condition_number():
    robot = FiveBar(**ROBOT)
    gap = np.array([1e-4, 1e-6, 1e-8])
    # X3 = 0.02: leg 4 stretches; the torque for 1 N along its distal link falls like √gap, its rate grows
    y = np.sqrt(0.25**2 - 0.06**2) - gap
    line = robot.inverse(0.02, y, modes=(-1, 1))
    J = robot.velocity_jacobian(line.theta1, line.theta4, 0.02, y)
    P = robot.joints(line.theta1, line.theta4, 0.02, y)
    torque = np.einsum("kji,kj->ki", J, (P[:, 2] - P[:, 3]) / 0.15)
    rates = robot.crank_rates(line.theta1, line.theta4, 0.02, y, 0.0, 0.05)
    assert np.all(np.abs(torque[:, 0]) < 1e-12)
    np.testing.assert_allclose(np.abs(torque[:-1, 1]) / np.abs(torque[1:, 1]), 10.0, rtol=0.02)
    np.testing.assert_allclose(np.abs(rates[1:, 1]) / np.abs(rates[:-1, 1]), 10.0, rtol=0.02)
    # X3 = 0: both legs stretch together; the rates blow up, the condition number tends to 6.17 only
    y = np.sqrt(0.25**2 - 0.04**2) - gap
    centre = robot.inverse(0.0, y, modes=(-1, 1))
    condition = np.linalg.cond(robot.velocity_jacobian(centre.theta1, centre.theta4, 0.0, y))
    rates = robot.crank_rates(centre.theta1, centre.theta4, 0.0, y, 0.0, 0.05)
    assert condition.max() < 6.17 and abs(condition[-1] - 6.16) < 0.005 and np.abs(rates[-2]).min() > 85.0


def test_lesson02_both_crank_angles_for_a_rocker_at_100_degrees_are_on_the_open_assembly():
    # B = O4 + l4(cos 100°, sin 100°) fixed; A = l2(cos θ2, sin θ2) lies l3 from B: two θ2 per turn (law of
    # cosines about O2), and at each the open assembly (B left of A → O4, two circles) puts B back at 100°
    l1, l2, l3, l4 = 0.20, 0.06, 0.18, 0.12
    B = np.array([l1 + l4 * np.cos(np.radians(100.0)), l4 * np.sin(np.radians(100.0))])
    spread = np.arccos((B @ B + l2**2 - l3**2) / (2 * l2 * np.hypot(*B)))
    roots = np.arctan2(B[1], B[0]) + np.array([1.0, -1.0]) * spread
    np.testing.assert_allclose(roots, [1.419225, -0.253024], atol=5e-7)
    A, pin = fourbar_pins(l1, l2, l3, l4, roots, "open")
    np.testing.assert_allclose(pin, [B, B], atol=1e-12)


# ---------------------------------------------------- statements a fresh reading found false, read back
def _notebook_text(name: str) -> str:
    import json
    from pathlib import Path

    path = Path(__file__).parents[1] / "notebooks" / name
    return "\n".join("".join(cell["source"]) for cell in json.loads(path.read_text())["cells"])


def test_no_lesson_says_the_saws_loop_has_no_closed_form():
    """Lessons 00, 05–07 use the saw's closed form (``saw.analytic``, eqs. 20–28): it has one."""
    from pathlib import Path

    for path in sorted((Path(__file__).parents[1] / "notebooks").glob("*.ipynb")):
        text = _notebook_text(path.name)
        assert not re.search(r"saw, whose loop has no closed form", text), path.name


def test_arrow_scales_are_lengths_per_rate():
    """A drawn arrow of scale × vector is a length: 0.1 m per m/s, never '0.1 s per m/s'."""
    text = _notebook_text("04_fourbar_velocity_acceleration.ipynb")
    assert "0.1 m per m/s" in text and "0.01 m per m/s²" in text
    assert not re.search(r"\d s²? per m/s", text)


def test_the_block_slides_fastest_at_the_levers_stops_and_the_six_bars_second_loop_never_toggles():
    """Lesson 12: at the stops (θ2 = 210°, 330°) ω4 = 0 and |v_r4| = r2·ω2 = 0.5 m/s, from the block on the
    ray O4 → A (r4 = |O4A|, differentiated by central differences here); the six-bar's arm O4C and coupler CD
    never line up, by circle intersections of its second four-bar."""
    r2, d, omega2 = 0.05, 0.10, 10.0
    for degrees, v_expected in ((210.0, -0.5), (330.0, 0.5)):
        theta, h = np.radians(degrees), 1e-6
        r4 = [np.hypot(r2 * np.cos(t), d + r2 * np.sin(t)) for t in (theta - h, theta + h)]
        angle = [np.arctan2(d + r2 * np.sin(t), r2 * np.cos(t)) for t in (theta - h, theta + h)]
        assert abs((r4[1] - r4[0]) / (2 * h) * omega2 - v_expected) < 1e-6
        assert abs((angle[1] - angle[0]) / (2 * h) * omega2) < 1e-6
    text = _notebook_text("12_your_own_mechanism.ipynb")
    assert "passes no toggle of its own" not in text and "never lines up with its coupler $CD$" in text


def test_lesson_12_counts_joints_as_lesson_01_and_says_which_loops_reduce():
    """A pin joining k links is k − 1 joints (lesson 01): on ex01's six-bar with a triple pin, counting each
    pin once would give one loop instead of two; and not every loop reads as lesson 03's quadratic (the
    saw's block is Newton's, `closed_forms == [None]`)."""
    from course_lib.saw import Saw

    bodies = [{"O2", "A"}, {"A", "B"}, {"B", "O4"}, {"B", "C"}, {"C", "O6"},  # B joins three links
              {"O2", "O4", "O6"}]
    pins = set().union(*bodies)
    by_pin = sum(sum(pin in body for body in bodies) - 1 for pin in pins)
    assert (len(pins) - len(bodies) + 1, by_pin - len(bodies) + 1) == (1, 2)
    text = _notebook_text("12_your_own_mechanism.ipynb")
    assert "each counted once" not in text and "a pin joining $k$ links is $k - 1$ joints" in text
    assert "reads every loop" not in text and Saw().mechanism.closed_forms == [None]
