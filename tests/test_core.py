"""errors, planar, symbolic, mobility, plotting: checked against independent routes."""


import matplotlib.pyplot as plt
import numpy as np
import pytest
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st

from course_lib import errors, planar, symbolic
from course_lib.errors import InvalidGeometryError, UnreachableError
from course_lib.mobility import gruebler
from course_lib.newton import newton
from course_lib.plotting import animation_html, draw_linkage, plot_convergence

angles = st.floats(min_value=-20, max_value=20, allow_nan=False)
lengths = st.floats(min_value=1e-3, max_value=10, allow_nan=False)


# --- errors -----------------------------------------------------------------
@pytest.mark.parametrize("value", [0.0, -0.1, np.nan, np.inf, "abc", None])
def test_require_positive_names_the_input(value):
    with pytest.raises(InvalidGeometryError, match="rocker"):
        errors.require_positive("rocker", value)


def test_require_positive_allows_zero_only_when_asked():
    assert errors.require_positive("l5", 0, allow_zero=True) == 0.0
    with pytest.raises(InvalidGeometryError, match="l5"):
        errors.require_positive("l5", 0)


def test_require_finite_reports_the_first_bad_entry():
    with pytest.raises(InvalidGeometryError, match=r"t must be finite.*entry 2 of 3"):
        errors.require_finite("t", [0.0, 1.0, np.nan])


def test_require_choice_lists_valid_choices():
    with pytest.raises(InvalidGeometryError, match="'open', 'crossed'; got 'opne'"):
        errors.require_choice("branch", "opne", ("open", "crossed"))
    with pytest.raises(InvalidGeometryError):
        errors.require_choice("mode", True, (1, -1))  # True == 1, but a bool is not a mode


def test_report_unreachable_scalar_and_array():
    with pytest.raises(UnreachableError, match="theta2=3") as info:
        errors.report_unreachable(np.bool_(True), {"theta2": 3.0}, "no assembly")
    assert "index" not in str(info.value)
    bad = np.array([[False, True], [True, False]])
    with pytest.raises(UnreachableError, match=r"2 of 4 inputs unreachable, first at index 1") as info:
        errors.report_unreachable(bad, {"x3": [[0, 5], [6, 0]], "y3": 1.0}, "out of reach")
    assert "x3=5, y3=1" in str(info.value)
    assert info.value.mask is bad
    errors.report_unreachable(bad, {"x3": 0}, "ignored", on_failure="nan")  # no raise


def test_error_hierarchy():
    for cls in (errors.UnreachableError, errors.ConvergenceError, errors.SingularJacobianError,
                errors.InvalidGeometryError, errors.InvalidArgumentError):
        assert issubclass(cls, errors.CourseLibError)
    # a misuse that is not geometry is its own class, still caught by code written for the older one
    assert issubclass(errors.InvalidArgumentError, errors.InvalidGeometryError)
    assert issubclass(errors.InvalidArgumentError, ValueError)


def test_the_newton_module_stays_reachable_and_callable():
    import importlib
    import types

    import course_lib
    import course_lib.newton as module
    from course_lib import newton as from_package
    from course_lib.newton import newton as function

    assert isinstance(module, types.ModuleType) and module is importlib.import_module("course_lib.newton")
    assert module.newton is function and module.newton_batch is course_lib.newton_batch
    assert from_package is module and course_lib.newton is module and "newton" in course_lib.__all__
    # calling the module runs the function: code that imported the function from the package still works
    assert from_package(lambda x: x * x - 9.0, 1.0).x == pytest.approx(3.0, abs=1e-12)
    square = lambda x: x * x - 9.0  # noqa: E731
    assert from_package(square, 1.0).iterations == function(square, 1.0).iterations


# --- planar -----------------------------------------------------------------
@given(lengths, angles)
def test_polar_equals_complex_exponential(length, angle):
    z = length * np.exp(1j * angle)
    np.testing.assert_allclose(planar.polar(length, angle), [z.real, z.imag], atol=1e-12)
    np.testing.assert_allclose(planar.to_complex(planar.polar(length, angle)), z, atol=1e-12)


@given(angles, lengths)
def test_cross_k_is_numpy_cross_with_z(angle, length):
    r = planar.polar(length, angle)
    expected = np.cross([0.0, 0.0, 1.0], [r[0], r[1], 0.0])[:2]
    np.testing.assert_allclose(planar.cross_k(r), expected, atol=1e-15)
    np.testing.assert_allclose(planar.from_complex(1j * planar.to_complex(r)), expected, atol=1e-15)


@given(angles)
def test_wrap_angle_range_and_equivalence(angle):
    wrapped = float(planar.wrap_angle(angle))
    assert -np.pi < wrapped <= np.pi
    assert abs(np.exp(1j * wrapped) - np.exp(1j * angle)) < 1e-12


def test_loop_residual_broadcasts_and_detects_an_open_loop():
    theta = np.linspace(0, 2 * np.pi, 7)
    # a rhombus of side 1 with one free angle always closes: R2 + R3 − R4 − R1 with R3 = R1, R4 = R2
    closed = planar.loop_residual([1, 1, 1, 1], [theta, 0.0, theta, 0.0], [1, 1, -1, -1])
    assert closed.shape == (7, 2)
    assert np.abs(closed).max() < 1e-15
    opened = planar.loop_residual([1, 2, 1, 1], [theta, 0.0, theta, 0.0], [1, 1, -1, -1])
    np.testing.assert_allclose(opened, np.tile([1.0, 0.0], (7, 1)), atol=1e-15)


# --- symbolic ---------------------------------------------------------------
def test_d_dt_matches_hand_differentiation_of_the_fourbar_loop():
    theta2, theta3 = symbolic.time_symbols("theta2", "theta3")
    l2, l3 = sp.symbols("l2 l3", positive=True)
    w2, w3, a2, a3 = sp.symbols("omega2 omega3 alpha2 alpha3", real=True)
    x = l2 * sp.cos(theta2) + l3 * sp.cos(theta3)
    t2, t3 = sp.symbols("theta2 theta3", real=True)
    velocity = -w2 * l2 * sp.sin(t2) - w3 * l3 * sp.sin(t3)
    acceleration = (-a2 * l2 * sp.sin(t2) - w2**2 * l2 * sp.cos(t2)
                    - a3 * l3 * sp.sin(t3) - w3**2 * l3 * sp.cos(t3))
    assert sp.simplify(symbolic.static(symbolic.d_dt(x)) - velocity) == 0
    assert sp.simplify(symbolic.static(symbolic.d_dt(x, 2)) - acceleration) == 0


def test_d_dt_names_rates_of_lengths():
    (r1,) = symbolic.time_symbols("r1")
    assert symbolic.d_dt(r1**2) == 2 * r1 * sp.Symbol("v_r1", real=True)
    assert symbolic.d_dt(r1, 2) == sp.Symbol("a_r1", real=True)


@given(st.floats(min_value=-3.1, max_value=3.1))
def test_half_angle_substitution_is_exact(angle):
    theta, u = sp.symbols("theta u")
    expr = 3 * sp.cos(theta) + 2 * sp.sin(theta)
    value = float(symbolic.half_angle(expr, theta, u).subs(u, np.tan(angle / 2)))
    assert abs(value - (3 * np.cos(angle) + 2 * np.sin(angle))) < 1e-9


def test_jacobian_and_lambdify_against_finite_differences():
    theta3, theta4 = symbolic.time_symbols("theta3", "theta4")
    loop = [0.18 * sp.cos(theta3) - 0.12 * sp.cos(theta4), 0.18 * sp.sin(theta3) - 0.12 * sp.sin(theta4)]
    J = symbolic.lambdify([theta3, theta4], symbolic.jacobian(loop, [theta3, theta4]))
    F = symbolic.lambdify([theta3, theta4], sp.Matrix(loop))
    point, h = np.array([0.4, 1.3]), 1e-6
    numeric = np.column_stack([
        (F(*(point + h * e)) - F(*(point - h * e))).ravel() / (2 * h) for e in np.eye(2)
    ])
    np.testing.assert_allclose(J(*point), numeric, atol=1e-9)


# --- mobility ---------------------------------------------------------------
@pytest.mark.parametrize(
    ("links", "full", "half", "expected"),
    [
        (4, 4, 0, 1),   # four-bar
        (5, 5, 0, 2),   # five-bar
        (3, 3, 0, 0),   # triangle
        (5, 6, 0, 0),   # two triangles sharing a side: still a rigid truss
        (6, 8, 0, -1),  # the four-vertex truss with both diagonals (K4): preloaded
        (6, 7, 0, 1),   # Watt / Stephenson six-bar
        (3, 2, 1, 1),   # cam and follower: two pins and one half joint
        (1, 0, 0, 0),   # the ground alone
    ],
)
def test_gruebler_table(links, full, half, expected):
    # expected values: the known mobility of each textbook mechanism (joint counts enumerated by hand)
    assert gruebler(links, full, half) == expected


@pytest.mark.parametrize("bad", [{"links": 0, "full_joints": 0}, {"links": 4, "full_joints": -1},
                                 {"links": 4.5, "full_joints": 4}, {"links": True, "full_joints": 1}])
def test_gruebler_rejects_bad_counts(bad):
    with pytest.raises(InvalidGeometryError):
        gruebler(**bad)


# --- plotting ---------------------------------------------------------------
def test_draw_linkage_draws_each_link_through_its_joints():
    points = np.array([[0.0, 0.0], [0.03, 0.05], [0.19, 0.10], [0.20, 0.0]])
    links = [(0, 1, "l2"), (1, 2, "l3"), (2, 3, "l4"), (3, 0, "l1")]
    ax = draw_linkage(points, links, ground=[0, 3], title="four-bar")
    lines = {line.get_gid(): line for line in ax.lines}
    for k, (i, j, label) in enumerate(links, 1):  # drawn by draw, as "link k" between the joints
        np.testing.assert_array_equal(np.column_stack(lines[f"link {k}"].get_data()), points[[i, j]])
        label_text = next(t for t in ax.texts if t.get_gid() == f"label link {k}")
        assert label_text.get_text() == label
    texts = sorted(t.get_text() for t in ax.texts)
    assert texts == ["1", "2", "3", "4", "l1", "l2", "l3", "l4"] and ax.get_title() == "four-bar"
    plt.close(ax.figure)


@pytest.mark.parametrize(("points", "links"), [([[0, 0], [np.nan, 1]], [(0, 1, "a")]),
                                               ([[0, 0], [1, 1]], [(0, 2, "a")]),
                                               ([0, 0, 1], [])])
def test_draw_linkage_rejects_bad_input(points, links):
    with pytest.raises(InvalidGeometryError):
        draw_linkage(points, links)
    plt.close("all")


def test_plot_convergence_errors_against_the_exact_root():
    result = newton(lambda x: x**2 - 2, 1.0)
    fig = plot_convergence(result, exact=np.sqrt(2), names=["x"])
    error_line = fig.axes[1].lines[0]
    np.testing.assert_allclose(error_line.get_ydata()[:3], np.abs([1 - np.sqrt(2), 1.5 - np.sqrt(2),
                                                                  17 / 12 - np.sqrt(2)]))
    with pytest.raises(InvalidGeometryError, match="names"):
        plot_convergence(result, names=["x", "y"])
    plt.close("all")


def test_animation_html_has_one_frame_per_call():
    fig, ax = plt.subplots()
    (line,) = ax.plot([0, 1], [0, 0])
    calls = []
    html = animation_html(fig, lambda k: calls.append(k) or line.set_ydata([0, k]), frames=3)
    assert "<script" in html and "frames[2]" in html
    assert calls[-3:] == [0, 1, 2]
    with pytest.raises(InvalidGeometryError):
        animation_html(plt.figure(), lambda k: None, frames=0)
    plt.close("all")
