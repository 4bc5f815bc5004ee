"""Headless tests of the explorers: drive the widgets, compare the drawing with independent geometry."""

import base64
import gc
import io
import re

import ipywidgets
import matplotlib.pyplot as plt
import numpy as np
import pytest
from geometry import circle_intersections, fourbar_pins
from matplotlib.figure import Figure
from matplotlib.patches import Circle
from PIL import Image

from course_lib.errors import CourseLibError, InvalidGeometryError
from course_lib.fivebar import FiveBar
from course_lib.fourbar import FourBar
from course_lib.saw import Saw
from course_lib.widgets import (
    ExplorerSpec,
    build_explorer,
    fivebar_explorer,
    fourbar_explorer,
    mechanism_explorer,
    saw_explorer,
)

NAN, INF = float("nan"), float("inf")
#: a number shown as nan or inf ("θ3 = nan°", "|P2P4| = inf m", "P3 = (nan, …)")
NAN_SHOWN = re.compile(r"(=|\(|,)\s*[-+]?(nan|inf)\b", re.IGNORECASE)


def _figures_alive() -> int:
    gc.collect()
    return sum(isinstance(obj, Figure) for obj in gc.get_objects())


def _xy(line):
    x, y = line.get_data()
    return np.asarray(x, float), np.asarray(y, float)


@pytest.mark.parametrize("branch", ["open", "crossed"])
def test_fourbar_drawing_matchescircle_intersections(branch):
    explorer = fourbar_explorer(crank=0.06, coupler=0.18, rocker=0.12, ground=0.20, assembly=branch)
    for theta2_deg in (-150.0, -30.0, 0.0, 45.0, 100.0, 170.0):
        _check_fourbar_state(explorer, theta2_deg, branch)


def _check_fourbar_state(explorer, theta2_deg, branch):
    readout = explorer.update(theta2_deg=theta2_deg)
    assert readout.status == "ok"
    A, B = fourbar_pins(0.20, 0.06, 0.18, 0.12, np.radians(theta2_deg), branch)
    x, y = _xy(explorer.artists["coupler"])
    np.testing.assert_allclose([x[0], y[0], x[1], y[1]], [*A, *B], atol=1e-12)
    x, y = _xy(explorer.artists["rocker"])
    np.testing.assert_allclose([x[1], y[1]], [0.20, 0.0], atol=1e-15)
    # the readout's θ3, θ4 and μ (law of cosines on triangle A-B-O4) agree with this geometry
    theta3 = np.degrees(np.arctan2(*(B - A)[::-1]))
    theta4 = np.degrees(np.arctan2(B[1], B[0] - 0.20))
    cos_joint = (0.18**2 + 0.12**2 - np.sum((np.array([0.20, 0.0]) - A) ** 2)) / (2 * 0.18 * 0.12)
    joint = np.degrees(np.arccos(cos_joint))
    mu = min(joint, 180 - joint)
    assert f"θ3 = {theta3:.2f}°" in explorer.message
    assert f"θ4 = {theta4:.2f}°" in explorer.message
    assert f"μ = {mu:.2f}°" in explorer.message
    x, y = _xy(explorer.artists["mu_cursor"])
    np.testing.assert_allclose([x[0], y[0]], [theta2_deg, mu], atol=1e-9)


def test_fourbar_coupler_curve_and_point_match_independent_geometry():
    explorer = fourbar_explorer(crank=0.05, coupler=0.15, rocker=0.14, ground=0.18)
    explorer.update(p=0.10, delta_deg=40.0, theta2_deg=75.0)
    x, y = _xy(explorer.artists["coupler_curve"])
    theta2 = np.linspace(-np.pi, np.pi, len(x))
    for k in range(0, len(x), 36):
        A, B = fourbar_pins(0.18, 0.05, 0.15, 0.14, theta2[k], "open")
        direction = np.arctan2(*(B - A)[::-1]) + np.radians(40.0)
        P = A + 0.10 * np.array([np.cos(direction), np.sin(direction)])
        np.testing.assert_allclose([x[k], y[k]], P, atol=1e-12)
    A, B = fourbar_pins(0.18, 0.05, 0.15, 0.14, np.radians(75.0), "open")
    direction = np.arctan2(*(B - A)[::-1]) + np.radians(40.0)
    px, py = _xy(explorer.artists["point_p"])
    np.testing.assert_allclose([px[0], py[0]], A + 0.10 * np.array([np.cos(direction), np.sin(direction)]),
                               atol=1e-12)


@pytest.mark.parametrize(
    ("lengths", "expected"),
    [
        (dict(crank=0.06, coupler=0.18, rocker=0.12, ground=0.20), "Grashof crank-rocker"),
        (dict(crank=0.12, coupler=0.18, rocker=0.20, ground=0.06), "Grashof double-crank"),
        (dict(crank=0.18, coupler=0.06, rocker=0.20, ground=0.12), "Grashof double-rocker"),
        (dict(crank=0.15, coupler=0.10, rocker=0.12, ground=0.20), "non-Grashof triple-rocker"),
    ],
)
def test_fourbar_readout_names_grashof_class(lengths, expected):
    ordered = sorted(lengths.values())
    # Norton's rule, from the sorted lengths (s + l against p + q), as the expectation's sanity check
    assert (ordered[0] + ordered[3] > ordered[1] + ordered[2]) == expected.startswith("non")
    explorer = fourbar_explorer(**lengths, theta2=0.0)
    assert expected + ":" in explorer.message


def test_fourbar_unreachable_gives_message_not_exception():
    # non-Grashof: |AO4| at θ2 = 120° is sqrt(0.2² + 0.15² + 0.2·0.15) = 0.304 m > l3 + l4 = 0.22 m
    explorer = fourbar_explorer(crank=0.15, coupler=0.10, rocker=0.12, ground=0.20)
    distance = np.sqrt(0.20**2 + 0.15**2 - 2 * 0.20 * 0.15 * np.cos(np.radians(120.0)))
    readout = explorer.update(theta2_deg=120.0)
    assert readout.status == "unreachable"
    assert "outside the input range" in explorer.message
    assert f"|AO4| = {distance:.3f} m > l3 + l4 = 0.220 m" in explorer.message
    assert "color:#b00020" in explorer.readout.value
    assert not explorer.artists["coupler"].get_visible()
    assert explorer.artists["reach_O4"].get_visible()
    # the input range limit: cos θ = (l1² + l2² − (l3 + l4)²)/(2 l1 l2)
    limit = np.degrees(np.arccos((0.20**2 + 0.15**2 - 0.22**2) / (2 * 0.20 * 0.15)))
    assert f"[{-limit:.1f}°, {limit:.1f}°]" in explorer.message
    # and back inside the range the linkage is drawn again
    assert explorer.update(theta2_deg=limit - 2.0).status == "ok"
    assert explorer.artists["coupler"].get_visible()
    assert not explorer.artists["reach_O4"].get_visible()


def test_fourbar_folded_side_unreachable_message():
    # |AO4| < |l3 − l4|: crank 0.10, ground 0.12, coupler 0.25, rocker 0.10; at θ2 = 0 |AO4| = 0.02 < 0.15
    explorer = fourbar_explorer(crank=0.10, coupler=0.25, rocker=0.10, ground=0.12)
    assert explorer.update(theta2_deg=0.0).status == "unreachable"
    assert "|AO4| = 0.020 m < |l3 − l4| = 0.150 m" in explorer.message


def test_fourbar_slider_event_redraws_and_reuses_one_figure():
    fignums = len(plt.get_fignums())
    explorer = fourbar_explorer()
    alive = _figures_alive()
    figure, image, text = explorer.figure, explorer.image.value, explorer.readout.value
    explorer.controls["theta2_deg"].value = 100.0  # as a user moving the slider
    assert explorer.image.value != image and explorer.readout.value != text
    assert "θ2 = 100.0°" in explorer.message
    for k in range(24):
        explorer.controls["theta2_deg"].value = -180.0 + 15 * k
        if k % 8 == 0:
            explorer.controls["coupler"].value = 0.15 + 0.002 * k
            explorer.controls["assembly"].value = ("open", "crossed")[k % 16 // 8]
    assert explorer.figure is figure
    assert len(plt.get_fignums()) == fignums
    assert _figures_alive() == alive


def test_fourbar_incremental_render_equals_full_render():
    explorer = fourbar_explorer()
    explorer.update(theta2_deg=10.0)
    explorer.update(theta2_deg=130.0)  # only the moving artists redrawn over the cached background
    incremental = explorer.image.value
    assert explorer.render(full=True) == incremental
    explorer.update(crank=0.15, coupler=0.10, rocker=0.12, ground=0.20, theta2_deg=10.0)
    explorer.update(theta2_deg=120.0)
    assert explorer.render(full=True) == explorer.image.value


def test_update_rejects_unknown_input():
    with pytest.raises(InvalidGeometryError, match="'theta2'"):
        fourbar_explorer().update(theta2=1.0)


# ------------------------------------------------------------------------------------------ power saw
R1Y, R2, R3 = 0.045, 0.075, 0.170  # the course's saw (m)


def _saw_positions(t):
    """r1, θ1, θ3 and the pins A, B from the geometry: B on y = r1y, |AB| = r3, B left of A."""
    from course_lib.profile import motor_profile

    theta2 = float(motor_profile(t).theta2)
    A = R2 * np.array([np.cos(theta2), np.sin(theta2)])
    B = np.array([A[0] - np.sqrt(R3**2 - (R1Y - A[1]) ** 2), R1Y])
    theta1 = np.arctan(B[1] / B[0])  # the report keeps θ1 in (−π/2, π/2], so r1 < 0 here
    r1 = B[1] / np.sin(theta1)
    theta3 = np.arctan2(B[1] - A[1], B[0] - A[0]) % (2 * np.pi)  # the rod points left: θ3 in (π/2, 3π/2)
    return np.array([r1, theta1, theta3]), A, B


def _saw_by_finite_differences(t, h=1e-4):
    """The nine unknowns: positions from geometry, rates by central differences in time."""
    minus, _, _ = _saw_positions(t - h)
    here, A, B = _saw_positions(t)
    plus, _, _ = _saw_positions(t + h)
    velocity = (plus - minus) / (2 * h)
    acceleration = (plus - 2 * here + minus) / h**2
    return np.concatenate([here, velocity, acceleration]), A, B


def test_saw_cursors_and_drawing_match_finite_differences():
    from course_lib.widgets import saw_explorer

    explorer = saw_explorer()
    for t in (0.4, 1.0, 1.7, 2.5, 3.3):
        assert explorer.update(t=t).status == "ok"
        expected, A, B = _saw_by_finite_differences(t)
        names = ("r1", "theta1", "theta3", "v_r", "omega1", "omega3", "a_r", "alpha1", "alpha3")
        drawn = np.array([_xy(explorer.artists[f"point_{name}"])[1][0] for name in names])
        np.testing.assert_allclose(drawn[:3], expected[:3], atol=1e-12)
        np.testing.assert_allclose(drawn[3:6], expected[3:6], rtol=1e-6, atol=1e-7)
        np.testing.assert_allclose(drawn[6:], expected[6:], rtol=1e-4, atol=1e-4)
        x, y = _xy(explorer.artists["rod"])
        np.testing.assert_allclose([x[0], y[0], x[1], y[1]], [*A, *B], atol=1e-12)
        assert all(_xy(explorer.artists[f"cursor_{name}"])[0][0] == t for name in names)
        assert f"r1 = {expected[0]:.5f} m" in explorer.message
        assert f"θ3 = {expected[2]:.5f} rad" in explorer.message


def test_saw_rest_values_are_the_reports():
    from course_lib.widgets import saw_explorer

    explorer = saw_explorer(t=0.0)
    # the course report: at rest r1 ≈ −0.0997 m, θ1 ≈ −0.4684 rad; nothing moves yet
    assert "r1 = -0.09967 m, θ1 = -0.46842 rad" in explorer.message
    assert "v_r = 0.00000 m/s" in explorer.message and "-0.00000" not in explorer.message


def test_saw_play_button_drives_the_time_slider():
    from course_lib.widgets import saw_explorer

    explorer = saw_explorer(frames=60)
    step = explorer.controls["t"].step
    np.testing.assert_allclose(step, 2 * np.sqrt(6 * np.pi / 5) / 60, rtol=1e-12)  # two turns of 2T
    image = explorer.image.value
    explorer.play.value = 45  # as the Play button ticking
    assert abs(explorer.state["t"] - 45 * step) < 1e-12
    assert f"t = {45 * step:.3f} s (steady speed" in explorer.message
    assert explorer.image.value != image
    explorer.controls["t"].value = 10 * step  # and the slider moves the Play button back
    assert explorer.play.value == 10


def test_saw_reuses_one_figure_and_blits_exactly():
    from course_lib.widgets import saw_explorer

    fignums = len(plt.get_fignums())
    explorer = saw_explorer()
    alive = _figures_alive()
    for k in range(0, 120, 5):
        explorer.play.value = k
    assert len(plt.get_fignums()) == fignums and _figures_alive() == alive
    assert explorer.render(full=True) == explorer.image.value


# ------------------------------------------------------------------------------------------ five-bar
L1, L2, L3, L4, L5 = 0.10, 0.15, 0.15, 0.10, 0.08
P1, P5 = np.array([L5 / 2, 0.0]), np.array([-L5 / 2, 0.0])


def test_fivebar_forward_matchescircle_intersections():
    from course_lib.widgets import fivebar_explorer

    explorer = fivebar_explorer()
    for theta1_deg, theta4_deg in ((70.0, 110.0), (30.0, 150.0), (-20.0, -160.0)):
        theta1, theta4 = np.radians(theta1_deg), np.radians(theta4_deg)
        P2 = P1 + L1 * np.array([np.cos(theta1), np.sin(theta1)])
        P4 = P5 + L4 * np.array([np.cos(theta4), np.sin(theta4)])
        both = circle_intersections(P2, L2, P4, L3)
        up, down = sorted(both, key=lambda point: point[1], reverse=True)  # σ = +1: the larger Y3
        for sigma, expected in ((1, up), (-1, down)):
            assert explorer.update(theta1_deg=theta1_deg, theta4_deg=theta4_deg, sigma=sigma).status == "ok"
            x, y = _xy(explorer.artists["end_effector"])
            np.testing.assert_allclose([x[0], y[0]], expected, atol=1e-12)
            x, y = _xy(explorer.artists["l2"])
            np.testing.assert_allclose([x[0], y[0]], P2, atol=1e-12)
            shown = [f"{round(value, 4) + 0.0:.4f}" for value in expected]
            assert f"P3 = ({shown[0]}, {shown[1]}) m" in explorer.message


def test_fivebar_inverse_working_modes_close_the_legs():
    from course_lib.widgets import fivebar_explorer

    explorer = fivebar_explorer(kinematics="inverse")
    assert explorer.controls["theta1_deg"].disabled and not explorer.controls["x3"].disabled
    target = np.array([0.05, 0.18])
    elbows1, elbows4 = set(), set()
    for sigma1 in (1, -1):
        for sigma2 in (1, -1):
            readout = explorer.update(x3=target[0], y3=target[1], sigma1=sigma1, sigma2=sigma2)
            assert readout.status == "ok"
            x, y = _xy(explorer.artists["l2"])
            P2, P3 = np.array([x[0], y[0]]), np.array([x[1], y[1]])
            x, y = _xy(explorer.artists["l3"])  # l3 is declared P3 → P4
            P4 = np.array([x[1], y[1]])
            np.testing.assert_allclose(P3, target, atol=1e-15)
            # P2 is one of the two independent circle intersections, and the legs close
            candidates = circle_intersections(P1, L1, target, L2)
            assert min(np.hypot(*(P2 - c)) for c in candidates) < 1e-12
            np.testing.assert_allclose([np.hypot(*(P2 - P1)), np.hypot(*(P4 - P5)), np.hypot(*(P4 - P3))],
                                       [L1, L4, L3], atol=1e-12)
            elbows1.add(tuple(np.round(P2, 9)))
            elbows4.add(tuple(np.round(P4, 9)))
    assert len(elbows1) == 2 and len(elbows4) == 2  # σ1 and σ2 each pick one of two elbows


def test_fivebar_workspace_shading_is_the_annulus_intersection():
    from course_lib.widgets import fivebar_explorer

    explorer = fivebar_explorer()
    shade = explorer.artists["workspace"].get_array()
    left, right, bottom, top = explorer.artists["workspace"].get_extent()
    grid = np.linspace(left, right, shade.shape[1])
    X, Y = np.meshgrid(grid, np.linspace(bottom, top, shade.shape[0]))
    d1, d5 = np.hypot(X - P1[0], Y - P1[1]), np.hypot(X - P5[0], Y - P5[1])
    inside = (d1 <= L1 + L2) & (d1 >= abs(L1 - L2)) & (d5 <= L4 + L3) & (d5 >= abs(L4 - L3))
    edge = (np.abs(d1 - (L1 + L2)) < 1e-9) | (np.abs(d5 - (L4 + L3)) < 1e-9)
    np.testing.assert_array_equal((shade[..., 3] > 0)[~edge], inside[~edge])


def test_fivebar_unreachable_states_explained():
    from course_lib.widgets import fivebar_explorer

    explorer = fivebar_explorer(kinematics="inverse")
    readout = explorer.update(x3=0.25, y3=0.25)
    assert readout.status == "unreachable"
    distance = np.hypot(0.25 - L5 / 2, 0.25)
    assert f"leg 1 (l1, l2): distance {distance:.4f} m > 0.2500 m" in explorer.message
    assert explorer.artists["target"].get_visible() and not explorer.artists["end_effector"].get_visible()
    assert explorer.update(x3=0.0, y3=0.2).status == "ok"
    # forward: distal links of 0.10 m cannot bridge |P2P4| = l5 + l1 + l4 = 0.28 m
    short = fivebar_explorer(l1=0.10, l2=0.10, l3=0.10, l4=0.10, l5=0.08, theta1=0.0, theta4=np.pi)
    assert short.status == "unreachable"
    assert "|P2P4| = 0.2800 m > l2 + l3 = 0.2000 m" in short.message
    assert short.artists["reach_a"].get_visible()


def test_fivebar_reuses_one_figure_and_blits_exactly():
    from course_lib.widgets import fivebar_explorer

    fignums = len(plt.get_fignums())
    explorer = fivebar_explorer()
    alive = _figures_alive()
    for k in range(10):
        explorer.controls["theta1_deg"].value = 40.0 + 3 * k
    explorer.update(kinematics="inverse")
    for k in range(10):
        explorer.controls["x3"].value = -0.05 + 0.01 * k
    assert len(plt.get_fignums()) == fignums and _figures_alive() == alive
    assert explorer.render(full=True) == explorer.image.value


# ------------------------------------------------------------------------------ changing a control
def test_length_change_keeps_limits_while_the_picture_fits_and_refits_when_it_leaves():
    explorer = fourbar_explorer()
    ax = explorer.figure.axes[0]
    limits = ax.get_xlim(), ax.get_ylim()
    explorer.update(coupler=0.17, theta2_deg=30.0)
    assert (ax.get_xlim(), ax.get_ylim()) == limits  # the picture still fits: nothing but the links redrawn
    assert explorer.render(full=True) == explorer.image.value
    explorer.update(ground=0.40, rocker=0.35, coupler=0.30)  # O4 + l4 = 0.75 m leaves the old limits
    (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
    assert x1 >= 0.75 and y1 >= 0.35 and y0 <= -0.35
    assert explorer.render(full=True) == explorer.image.value
    explorer.update(ground=0.05, crank=0.02, coupler=0.05, rocker=0.04)  # far smaller: refit to it
    assert ax.get_xlim()[1] - ax.get_xlim()[0] < 0.5 * (x1 - x0)


def test_mode_and_working_mode_changes_draw_the_singularity_curve_of_that_mode():
    explorer = fivebar_explorer(kinematics="inverse")
    curves = {}
    for sigma1, sigma2 in ((1, 1), (-1, 1), (1, -1), (1, 1)):
        explorer.update(sigma1=sigma1, sigma2=sigma2)
        x, y = _xy(explorer.artists["singularity"])
        curves.setdefault((sigma1, sigma2), (x.copy(), y.copy()))
        np.testing.assert_array_equal(x, curves[(sigma1, sigma2)][0])  # cached per mode, same curve
        assert explorer.render(full=True) == explorer.image.value
    assert len(curves[(1, 1)][0]) > 0 and not np.array_equal(curves[(1, 1)][0], curves[(-1, 1)][0])
    explorer.update(kinematics="forward")
    assert len(_xy(explorer.artists["singularity"])[0]) == 0
    assert explorer.render(full=True) == explorer.image.value


# ------------------------------------------------------------------------------ display
@pytest.mark.parametrize("build", [fourbar_explorer, saw_explorer, fivebar_explorer])
def test_display_bundle_carries_widget_view_picture_and_readout(build):
    explorer = build()
    bundle = explorer._repr_mimebundle_()
    assert bundle["application/vnd.jupyter.widget-view+json"]["model_id"] == explorer.widget.model_id
    picture = np.asarray(Image.open(io.BytesIO(base64.b64decode(bundle["image/png"]))).convert("RGB"))
    figure = np.asarray(Image.open(io.BytesIO(explorer.image.value)).convert("RGB"))
    width, height = explorer.canvas.get_width_height()
    assert picture.shape[1] == width and picture.shape[0] > height + 20
    difference = np.abs(picture[:height].astype(int) - figure)  # the figure (256 colours again) ...
    assert difference.max() <= 8 and difference.mean() < 0.05
    # ... and the readout under it
    assert (picture[height:] < 128).any()
    lines = bundle["text/plain"].splitlines()
    assert lines[0] == f"{explorer.name} explorer (ok)" and lines[1:] == list(explorer.last.lines)
    explorer.update(**{next(iter(explorer.controls)): NAN})
    after = explorer._repr_mimebundle_()
    assert after != bundle and after["text/plain"].splitlines()[0] == f"{explorer.name} explorer (invalid)"


def test_display_bundle_through_ipython_and_after_close():
    from IPython.core.formatters import DisplayFormatter

    explorer = fourbar_explorer()
    data, _ = DisplayFormatter().format(explorer)
    assert {"application/vnd.jupyter.widget-view+json", "image/png", "text/plain"} <= set(data)
    assert "HBox" not in data["text/plain"]
    explorer.widget.close()  # a closed widget has no view any more; the picture remains
    bundle = explorer._repr_mimebundle_()
    assert "application/vnd.jupyter.widget-view+json" not in bundle and "image/png" in bundle


# ------------------------------------------------------------------------------ bad values
# (builder, update arguments, statuses allowed, text the readout must contain or None)
BAD_UPDATES = [
    (fourbar_explorer, {"assembly": "Open"}, {"ok"}, None),
    (fourbar_explorer, {"assembly": " CROSSED "}, {"ok"}, "crossed assembly"),
    (fourbar_explorer, {"assembly": None}, {"invalid"},
     "assembly: refused None, not one of 'open', 'crossed'; kept 'open'"),
    (fourbar_explorer, {"assembly": "sideways"}, {"invalid"}, "refused"),
    (fourbar_explorer, {"assembly": 1}, {"invalid"}, "assembly: refused 1, not one of"),
    (fourbar_explorer, {"assembly": True}, {"invalid"}, "refused"),
    (fourbar_explorer, {"theta2_deg": NAN}, {"invalid"},
     "θ2 (°): refused NaN, not a number; kept 60"),
    (fourbar_explorer, {"theta2_deg": INF}, {"invalid"}, "not a finite number"),
    (fourbar_explorer, {"theta2_deg": -INF}, {"invalid"}, "not a finite number"),
    (fourbar_explorer, {"theta2_deg": "90"}, {"invalid"}, "θ2 (°): refused '90', not a number; kept 60"),
    (fourbar_explorer, {"theta2_deg": None}, {"invalid"}, "not a number"),
    (fourbar_explorer, {"theta2_deg": True}, {"invalid"}, "not a number"),
    (fourbar_explorer, {"theta2_deg": [1.0, 2.0]}, {"invalid"}, "not a number"),
    (fourbar_explorer, {"theta2_deg": np.array([1.0, 2.0])}, {"invalid"}, "not a number"),
    (fourbar_explorer, {"theta2_deg": 1 + 2j}, {"invalid"}, "not a number"),
    (fourbar_explorer, {"theta2_deg": np.float32(45.0)}, {"ok"}, "θ2 = 45.0°"),
    (fourbar_explorer, {"theta2_deg": np.array(45.0)}, {"ok"}, "θ2 = 45.0°"),
    (fourbar_explorer, {"theta2_deg": 400.0}, {"ok"}, "θ2 (°) = 400 taken as 40 (the same direction)"),
    (fourbar_explorer, {"theta2_deg": -540.0}, {"ok"}, "taken as -180"),
    (fourbar_explorer, {"crank": -1.0}, {"ok"},
     "crank l2 (m) = -1 is outside the slider's range [0.02, 0.4]: set to 0.02"),
    (fourbar_explorer, {"crank": 1e300}, {"ok", "unreachable"}, "set to 0.4"),
    (fourbar_explorer, {"coupler": NAN}, {"invalid"}, "refused NaN"),
    (fourbar_explorer, {"p": -INF}, {"invalid"}, "not a finite number"),
    (fourbar_explorer, {"delta_deg": 1e6}, {"ok"}, "taken as"),
    (fourbar_explorer, {"ground": 0.02, "crank": 0.02, "coupler": 0.02, "rocker": 0.02, "theta2_deg": 0.0},
     {"ok", "singular"}, None),
    (fourbar_explorer, {"ground": 0.40, "crank": 0.40, "coupler": 0.02, "rocker": 0.02, "theta2_deg": 90.0},
     {"unreachable"}, "|AO4|"),
    (saw_explorer, {"t": NAN}, {"invalid"}, "time t (s): refused NaN"),
    (saw_explorer, {"t": INF}, {"invalid"}, "not a finite number"),
    (saw_explorer, {"t": "1"}, {"invalid"}, "not a number"),
    (saw_explorer, {"t": -1.0}, {"ok"}, "set to 0"),
    (saw_explorer, {"t": 1e9}, {"ok"}, "outside the slider's range"),
    (fivebar_explorer, {"kinematics": "Forward"}, {"ok"}, "forward, σ = +1"),
    (fivebar_explorer, {"kinematics": "INVERSE"}, {"ok"}, "inverse, modes"),
    (fivebar_explorer, {"kinematics": "sideways"}, {"invalid"},
     "kinematics: refused 'sideways', not one of 'forward', 'inverse'; kept 'forward'"),
    (fivebar_explorer, {"kinematics": None}, {"invalid"}, "refused"),
    (fivebar_explorer, {"sigma": 2}, {"invalid"}, "assembly σ: refused 2, not one of 1, -1; kept 1"),
    (fivebar_explorer, {"sigma": 0}, {"invalid"}, "refused"),
    (fivebar_explorer, {"sigma": True}, {"invalid"}, "refused"),
    (fivebar_explorer, {"sigma": NAN}, {"invalid"}, "refused"),
    (fivebar_explorer, {"sigma": -1.0}, {"ok"}, "σ = -1"),
    (fivebar_explorer, {"sigma": "-1"}, {"ok"}, "σ = -1"),
    (fivebar_explorer, {"sigma": "+1 (ARMS UP)"}, {"ok"}, "σ = +1"),
    (fivebar_explorer, {"sigma1": 3, "kinematics": "inverse"}, {"invalid"},
     "σ1 (θ1 root): refused 3, not one of 1, -1"),
    (fivebar_explorer, {"sigma2": "down", "kinematics": "inverse"}, {"invalid"}, "refused"),
    (fivebar_explorer, {"theta1_deg": NAN}, {"invalid"}, "θ1 (°): refused NaN"),
    (fivebar_explorer, {"theta4_deg": -INF}, {"invalid"}, "not a finite number"),
    (fivebar_explorer, {"x3": NAN, "kinematics": "inverse"}, {"invalid"}, "X3 (m): refused NaN"),
    (fivebar_explorer, {"y3": "0.1", "kinematics": "inverse"}, {"invalid"}, "not a number"),
    (fivebar_explorer, {"x3": 10.0, "y3": 10.0, "kinematics": "inverse"}, {"unreachable"},
     "X3 (m) = 10 is outside the slider's range [-0.32, 0.32]: set to 0.32"),
    (fivebar_explorer, {"theta1_deg": 0.0, "theta4_deg": 180.0, "sigma": -1}, {"ok", "unreachable"}, None),
]


@pytest.mark.parametrize(("build", "state", "statuses", "text"), BAD_UPDATES,
                         ids=[f"{build.__name__}-{state}" for build, state, _, _ in BAD_UPDATES])
def test_update_never_raises_and_explains(build, state, statuses, text):
    explorer = build()
    before = explorer.state
    readout = explorer.update(**state)
    assert readout.status in statuses, readout.text
    if text is not None:
        assert text in readout.text
    assert not NAN_SHOWN.search(readout.text), readout.text
    if readout.status == "invalid":  # a refused value leaves its control as it was, and says so in red
        refused = [key for key in state if f"{explorer.controls[key].description}" in readout.lines[0]]
        assert refused and all(explorer.state[key] == before[key] for key in refused)
        assert "color:#b00020" in explorer.readout.value
    # and the explorer keeps working: a good value afterwards is drawn as usual
    main = {"four-bar": "theta2_deg", "power saw": "t", "five-bar": "theta1_deg"}[explorer.name]
    explorer.update(**({"kinematics": "forward"} if explorer.name == "five-bar" else {}))
    image = explorer.image.value
    good = explorer.update(**{main: 1.0, **({"ground": 0.2, "crank": 0.06, "coupler": 0.18, "rocker": 0.12}
                                             if explorer.name == "four-bar" else {})})
    assert good.status == "ok", good.text
    assert explorer.image.value != image and explorer.render(full=True) == explorer.image.value


EXTREME_LENGTHS = (0.02, 0.21, 0.40)


def test_no_state_of_the_fourbar_sliders_shows_nan():
    explorer = fourbar_explorer()
    seen = set()
    for ground in EXTREME_LENGTHS:
        for crank in EXTREME_LENGTHS:
            for coupler in EXTREME_LENGTHS:
                for rocker in EXTREME_LENGTHS:
                    for theta2 in (-180.0, 0.0, 180.0):
                        readout = explorer.update(ground=ground, crank=crank, coupler=coupler, rocker=rocker,
                                                  theta2_deg=theta2, p=0.40, delta_deg=180.0)
                        seen.add(readout.status)
                        assert readout.status in {"ok", "unreachable", "singular"}, readout.text
                        assert not NAN_SHOWN.search(readout.text), readout.text
    assert {"ok", "unreachable"} <= seen


def test_no_state_of_the_fivebar_sliders_shows_nan():
    explorer = fivebar_explorer()
    limit = explorer.controls["x3"].max
    for mode in ("forward", "inverse"):
        for a in (-180.0, -90.0, 0.0, 90.0, 180.0):
            for b in (-180.0, 0.0, 90.0, 180.0):
                for sigma in (1, -1):
                    if mode == "forward":
                        state = dict(theta1_deg=a, theta4_deg=b, sigma=sigma)
                    else:
                        state = dict(x3=a / 180 * limit, y3=b / 180 * limit, sigma1=sigma, sigma2=-sigma)
                    readout = explorer.update(kinematics=mode, **state)
                    assert readout.status in {"ok", "unreachable", "singular"}, readout.text
                    assert not NAN_SHOWN.search(readout.text), readout.text


def test_a_failing_draw_step_is_reported_not_raised():
    explorer = fourbar_explorer()
    explorer.draw = lambda state, changed: 1 / 0
    readout = explorer.refresh()
    assert readout.status == "error" and "division by zero" in readout.text


# (builder, arguments, name the message must give) — each raises a named course_lib error
BAD_BUILDERS = [
    (fourbar_explorer, {"crank": -1.0}, "crank"),
    (fourbar_explorer, {"crank": 0.0}, "crank"),
    (fourbar_explorer, {"coupler": 1.0}, "coupler"),
    (fourbar_explorer, {"rocker": NAN}, "rocker"),
    (fourbar_explorer, {"ground": INF}, "ground"),
    (fourbar_explorer, {"crank": "0.1"}, "crank"),
    (fourbar_explorer, {"crank": True}, "crank"),
    (fourbar_explorer, {"crank": None}, "crank"),
    (fourbar_explorer, {"p": -0.1}, "p"),
    (fourbar_explorer, {"p": 2.0}, "p"),
    (fourbar_explorer, {"branch": "sideways"}, "branch"),
    (fourbar_explorer, {"assembly": "sideways"}, "assembly"),
    (fourbar_explorer, {"assembly": None}, "assembly"),
    (fourbar_explorer, {"theta2": NAN}, "theta2"),
    (fourbar_explorer, {"theta2": "1"}, "theta2"),
    (fourbar_explorer, {"delta": INF}, "delta"),
    (saw_explorer, {"frames": 1}, "frames"),
    (saw_explorer, {"frames": 2.5}, "frames"),
    (saw_explorer, {"frames": "10"}, "frames"),
    (saw_explorer, {"frames": True}, "frames"),
    (saw_explorer, {"frames": NAN}, "frames"),
    (saw_explorer, {"t_end": 0.0}, "t_end"),
    (saw_explorer, {"t_end": -1.0}, "t_end"),
    (saw_explorer, {"t_end": NAN}, "t_end"),
    (saw_explorer, {"t_end": 1e308}, "t_end"),
    (saw_explorer, {"t": -0.5}, "t"),
    (saw_explorer, {"t": 100.0}, "t"),
    (saw_explorer, {"t": NAN}, "t"),
    (saw_explorer, {"interval_ms": 0}, "interval_ms"),
    (saw_explorer, {"interval_ms": NAN}, "interval_ms"),
    (fivebar_explorer, {"mode": "sideways"}, "mode"),
    (fivebar_explorer, {"kinematics": "sideways"}, "kinematics"),
    (fivebar_explorer, {"sigma": 0}, "sigma"),
    (fivebar_explorer, {"sigma1": 2}, "sigma1"),
    (fivebar_explorer, {"sigma2": None}, "sigma2"),
    (fivebar_explorer, {"theta1": NAN}, "theta1"),
    (fivebar_explorer, {"theta4": "2"}, "theta4"),
    (fivebar_explorer, {"x3": 5.0}, "x3"),
    (fivebar_explorer, {"y3": NAN}, "y3"),
    (fivebar_explorer, {"l1": -1.0}, "l1"),
    (fivebar_explorer, {"l5": NAN}, "l5"),
]


@pytest.mark.parametrize(("build", "arguments", "name"), BAD_BUILDERS,
                         ids=[f"{build.__name__}-{arguments}" for build, arguments, _ in BAD_BUILDERS])
def test_builder_refuses_out_of_range_arguments_by_name(build, arguments, name):
    with pytest.raises(CourseLibError) as caught:
        build(**arguments)
    message = str(caught.value)
    assert message.startswith(f"{name} ") or f" {name} " in message, message
    assert repr(arguments[name]) in message or str(arguments[name]) in message, message


@pytest.mark.parametrize(("build", "arguments", "key", "value"), [
    (fourbar_explorer, {"theta2": 7.0}, "theta2_deg", pytest.approx(np.degrees(7.0) - 360.0)),
    (fourbar_explorer, {"branch": "Crossed"}, "assembly", "crossed"),
    (fourbar_explorer, {"assembly": "Crossed"}, "assembly", "crossed"),
    (fourbar_explorer, {"crank": 0.02, "p": 0.0}, "crank", 0.02),
    (saw_explorer, {"t": np.float64(1.5), "frames": 60.0}, "t", 1.5),
    (fivebar_explorer, {"sigma": -1.0, "mode": "Inverse"}, "kinematics", "inverse"),
    (fivebar_explorer, {"sigma": -1.0, "kinematics": "Inverse"}, "sigma", -1),
])
def test_builder_accepts_equivalent_arguments(build, arguments, key, value):
    explorer = build(**arguments)
    assert explorer.state[key] == value
    assert explorer.status in {"ok", "unreachable"}


def test_png_keeps_the_figures_colours_also_those_that_appear_later():
    explorer = fourbar_explorer(crank=0.15, coupler=0.10, rocker=0.12, ground=0.20, theta2=0.0)
    explorer.update(theta2_deg=120.0)  # unreachable: red text, dashed circles (not in the first picture)
    shown = np.asarray(Image.open(io.BytesIO(explorer.image.value)).convert("RGB")).astype(int)
    drawn = np.asarray(explorer.canvas.buffer_rgba())[..., :3].astype(int)
    for colour in ((255, 255, 255), (176, 0, 32), (31, 119, 180)):  # white, the error red, the crank's blue
        where = np.all(drawn == colour, axis=2)
        assert where.any() and np.all(shown[where] == colour)
    assert np.mean(np.abs(shown - drawn)) < 0.5  # anti-aliased blends: the nearest of 255 colours


@pytest.mark.parametrize("machine", [FourBar(0.06, 0.18, 0.12, 0.20), Saw()], ids=["four-bar", "saw"])
def test_mechanism_explorer_takes_a_machine_as_its_declaration(machine):
    turn = machine.motion(np.radians(np.arange(-180.0, 180.0, 10.0)))
    by_machine = mechanism_explorer(machine, turn)
    by_declaration = mechanism_explorer(machine.mechanism, turn)
    assert list(by_machine.controls) == list(by_declaration.controls) == ["theta2_deg"]
    for degrees in (-120.0, 35.0, 150.0):
        assert by_machine.update(theta2_deg=degrees) == by_declaration.update(theta2_deg=degrees)
        assert by_machine.last.status == "ok"
    assert by_machine.render() == by_declaration.render()


@pytest.mark.parametrize("mode", [+1, -1])
def test_explore_gives_each_input_a_slider_and_keeps_the_motions_assembly(mode):
    # the five-bar's two cranks: P3 checked against the two circles about P2 and P4, computed here
    robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
    cranks = np.meshgrid(np.radians(np.arange(0.0, 180.0, 15.0)), np.radians(np.arange(0.0, 180.0, 15.0)))
    arms = mechanism_explorer(robot, robot.forward(*cranks, mode=mode, on_failure="nan"))
    assert list(arms.controls) == ["theta1_deg", "theta4_deg"]
    for theta1, theta4 in ((50.0, 120.0), (20.0, 160.0), (95.0, 100.0)):
        readout = arms.update(theta1_deg=theta1, theta4_deg=theta4)
        assert readout.status == "ok"
        t1, t4 = np.radians(theta1), np.radians(theta4)
        P2 = np.array([0.04 + 0.10 * np.cos(t1), 0.10 * np.sin(t1)])
        P4 = np.array([-0.04 + 0.10 * np.cos(t4), 0.10 * np.sin(t4)])
        both = circle_intersections(P2, 0.15, P4, 0.15)
        P3 = max(both, key=lambda p: p[1]) if mode > 0 else min(both, key=lambda p: p[1])  # the larger Y3
        shown = [float(line.split("=")[1]) for line in readout.lines[:2]]  # 4 significant figures
        assert np.allclose(shown, P3, rtol=5e-4, atol=1e-12)


def test_explore_says_where_several_inputs_leave_no_assembly():
    far = FiveBar(0.10, 0.05, 0.05, 0.10, 0.08)  # distal links too short for cranks pointing apart
    spread = np.meshgrid(np.radians(np.arange(60.0, 120.0, 5.0)), np.radians(np.arange(60.0, 120.0, 5.0)))
    apart = mechanism_explorer(far, far.forward(*spread, mode=+1, on_failure="nan"))
    readout = apart.update(theta1_deg=-10.0, theta4_deg=-170.0)  # |P2P4| ≈ 0.28 > l2 + l3 = 0.10
    assert readout.status == "unreachable"
    assert "theta1 = -10°, theta4 = -170°" in " ".join(readout.lines)


@pytest.mark.parametrize("machine", [object(), "FourBar", 3.0], ids=["object", "text", "number"])
def test_mechanism_explorer_refuses_what_is_neither_a_mechanism_nor_a_machine_by_name(machine):
    turn = Saw().motion(np.radians(np.arange(-180.0, 180.0, 10.0)))
    with pytest.raises(InvalidGeometryError, match="mechanism must be"):
        mechanism_explorer(machine, turn)


def _crank_spec(**changes):
    """A one-slider crank on the builder: unreachable beyond 90°, where it shows its reach circle."""
    slider = ipywidgets.FloatSlider(value=30.0, min=-180.0, max=180.0, description="θ (°)")

    def panels(figure):
        ax = figure.add_subplot()
        ax.set(xlim=(-1.5, 1.5), ylim=(-1.5, 1.5))
        return ax, {}, {"reach": ax.add_patch(Circle((0, 0), 1.0, fill=False, animated=True))}

    def draw(stage, state, geometry_changed):
        stage.artists["reach"].set_visible(False)
        theta = np.radians(state["theta_deg"])
        if abs(state["theta_deg"]) > 90.0:
            return stage.failed({"O": (0.0, 0.0)}, "too far", "unreachable", ["beyond 90°"],
                                circles=[("reach", (0.0, 0.0), 0.5)])
        pins = {"O": (0.0, 0.0), "A": (np.cos(theta), np.sin(theta))}
        return stage.solved(pins, [f"θ = {state['theta_deg']:g}"])

    spec = {"name": "crank", "controls": {"theta_deg": slider}, "size": (3.0, 3.0), "panels": panels,
            "linkage": {"links": {"crank": ("O", "A")}}, "draw": draw}
    return ExplorerSpec(**{**spec, **changes})


def test_a_specification_on_the_builder_gets_statuses_failure_text_and_stills():
    explorer = build_explorer(_crank_spec())
    assert explorer.update(theta_deg=45.0) == explorer.last and explorer.message == "θ = 45"
    assert np.allclose(explorer.artists["crank"].get_xydata()[1], [np.cos(np.pi / 4), np.sin(np.pi / 4)])
    readout = explorer.update(theta_deg=120.0)
    assert readout.status == "unreachable" and explorer.artists["failure"].get_text() == "too far"
    assert explorer.artists["reach"].get_visible() and explorer.artists["reach"].get_radius() == 0.5
    assert explorer.update(theta_deg=float("nan")).status == "invalid"
    assert explorer.update(theta_deg=10.0).status == "ok" and explorer.artists["failure"].get_text() == ""
    assert explorer.render()[:4] == explorer.picture()[:4] == b"\x89PNG"
    assert "image/png" in explorer._repr_mimebundle_()
    with pytest.raises(InvalidGeometryError, match="unknown explorer input"):
        explorer.update(phi=1.0)


def test_the_builder_refuses_a_bad_linkage_by_name():
    with pytest.raises(CourseLibError, match="styles"):
        build_explorer(_crank_spec(linkage={"links": {"crank": ("O", "A")}, "styles": {"rod": {}}}))


def _turned_fourbar():
    linkage = FourBar(0.06, 0.18, 0.12, 0.20)
    return mechanism_explorer(linkage, linkage.motion(np.radians(np.arange(-180.0, 180.0, 10.0))))


@pytest.mark.parametrize("build, angles", [
    (fourbar_explorer, ["theta2_deg", "delta_deg"]), (fivebar_explorer, ["theta1_deg", "theta4_deg"]),
    (_turned_fourbar, ["theta2_deg"]), (saw_explorer, []),
], ids=["four-bar", "five-bar", "explore", "saw"])
def test_angle_sliders_step_a_tenth_of_a_degree_across_the_explorer(build, angles):
    # a class found θ2 moving 3° a pixel in a 340 px slider: the angles now span the explorer, above it
    explorer = build()
    degrees = [key for key, control in explorer.controls.items() if control.description.endswith("(°)")]
    assert degrees == angles
    top, (column, _view) = explorer.widget.children[:-1], explorer.widget.children[-1].children
    assert list(top) == [explorer.controls[key] for key in angles]
    assert not set(top) & set(column.children)
    span = float(column.layout.width.removesuffix("px")) + explorer.figure.bbox.width
    for key in angles:
        slider = explorer.controls[key]
        assert (slider.min, slider.max, slider.step, slider.readout_format) == (-180.0, 180.0, 0.1, ".1f")
        assert slider.layout.width == "100%" and slider.layout.max_width == f"{span:.0f}px"
        assert span - 120 - 80 > 360  # less the label and the readout, a turn over more than 360 px
    if angles == ["theta2_deg", "delta_deg"]:
        assert explorer.update(theta2_deg=60.5).lines[0].startswith("θ2 = 60.5°")
