"""course_lib.saw against the report's printed numbers, a sympy derivation, finite differences,
the closed form and the textbook slider-crank."""

import numpy as np
import pytest
import sympy as sp
from hypothesis import given, settings
from hypothesis import strategies as st

from course_lib import saw
from course_lib.errors import (
    ConvergenceError,
    InvalidGeometryError,
    SingularJacobianError,
    UnreachableError,
)
from course_lib.newton import finite_difference_jacobian
from course_lib.slider_crank import OffsetSliderCrank

REPORT_AT_REST = np.array([-0.099672, -0.468422, 2.873694])  # report, sections 5.2.1 and 5.2.2
SEEDS = [saw.SEED_PRINTED, saw.SEED_CODE]
angles = st.floats(min_value=-10.0, max_value=10.0)
speeds = st.floats(min_value=-8.0, max_value=8.0)


# ------------------------------------------------------------------ a sympy derivation, from the loop


def sympy_equations():
    """Loop r1 = r2 + r3 and slider line in components, differentiated in time with sympy alone."""
    t = sp.Symbol("t")
    r1, th1, th2, th3 = (sp.Function(name)(t) for name in ("r1", "th1", "th2", "th3"))
    r1y, r2, r3 = 0.045, 0.075, 0.170
    position = [
        -r1 * sp.cos(th1) + r2 * sp.cos(th2) + r3 * sp.cos(th3),
        r1 * sp.sin(th1) - r2 * sp.sin(th2) - r3 * sp.sin(th3),
        r1 * sp.sin(th1) - r1y,
    ]
    names = sp.symbols("r1 theta1 theta3 v_r omega1 omega3 a_r alpha1 alpha3")
    motor = sp.symbols("theta2 omega2 alpha2")
    order = [(r1, names[0], names[3], names[6]), (th1, names[1], names[4], names[7]),
             (th3, names[2], names[5], names[8]), (th2, motor[0], motor[1], motor[2])]

    def to_symbols(expr):
        for function, _, qd, qdd in order:
            expr = expr.subs(function.diff(t, 2), qdd).subs(function.diff(t), qd)
        for function, q, _, _ in order:
            expr = expr.subs(function, q)
        return expr

    velocity = [to_symbols(sp.diff(f, t)) for f in position]
    acceleration = [to_symbols(sp.diff(f, t, 2)) for f in position]
    position = [to_symbols(f) for f in position]
    return names, motor, position, velocity, acceleration


EQUATIONS = sympy_equations()


def sympy_functions():
    names, motor, position, velocity, acceleration = EQUATIONS
    residual = sp.Matrix(position + velocity + acceleration)
    jacobian = residual.jacobian(sp.Matrix(names))
    return (
        sp.lambdify([names, motor], residual, "numpy"),
        sp.lambdify([names, motor], jacobian, "numpy"),
    )


SYMPY_RESIDUAL, SYMPY_JACOBIAN = sympy_functions()


@given(st.lists(st.floats(min_value=-3.0, max_value=3.0), min_size=12, max_size=12))
@settings(max_examples=60)
def test_residuals_and_9x9_jacobian_match_sympy(values):
    x = np.array(values[:9])
    x[0] = x[0] / 10 + 0.3 * np.sign(x[0] or 1)  # keep r1 away from 0
    motor = values[9:]
    expected = np.asarray(SYMPY_RESIDUAL(x, motor), float).ravel()
    assert np.allclose(saw.system_residual(x, *motor), expected, atol=1e-12)
    assert np.allclose(saw.system_jacobian(x), np.asarray(SYMPY_JACOBIAN(x, motor), float), atol=1e-12)


def test_printed_velocity_and_acceleration_equations_match_sympy():
    names, motor, _, velocity, acceleration = EQUATIONS
    r1, th1, th3, v_r, w1, w3, a_r, al1, al3 = names
    th2, w2, al2 = motor
    r2, r3 = 0.075, 0.170
    s, c = sp.sin, sp.cos
    printed_velocity = [  # the report's eqs. (10)–(12)
        w1 * r1 * s(th1) - v_r * c(th1) - w2 * r2 * s(th2) - w3 * r3 * s(th3),
        v_r * s(th1) + w1 * r1 * c(th1) - w2 * r2 * c(th2) - w3 * r3 * c(th3),
        v_r * s(th1) + w1 * r1 * c(th1),
    ]
    printed_acceleration = [  # the report's eqs. (13)–(15)
        r1 * c(th1) * w1**2 + 2 * v_r * s(th1) * w1 - r2 * c(th2) * w2**2 - r3 * c(th3) * w3**2
        - a_r * c(th1) + al1 * r1 * s(th1) - al2 * r2 * s(th2) - al3 * r3 * s(th3),
        -r1 * s(th1) * w1**2 + 2 * v_r * c(th1) * w1 + r2 * s(th2) * w2**2 + r3 * s(th3) * w3**2
        + a_r * s(th1) + al1 * r1 * c(th1) - al2 * r2 * c(th2) - al3 * r3 * c(th3),
        -r1 * s(th1) * w1**2 + 2 * v_r * c(th1) * w1 + a_r * s(th1) + al1 * r1 * c(th1),
    ]
    printed = printed_velocity + printed_acceleration
    for derived, expected in zip(velocity + acceleration, printed, strict=True):
        assert sp.simplify(derived - expected) == 0


@given(st.floats(min_value=-0.5, max_value=-0.05), st.floats(-1.4, -0.1), angles, angles)
@settings(max_examples=60)
def test_substituted_jacobian_is_eq17_and_matches_finite_differences(r1, theta1, theta3, theta2):
    q = np.array([r1, theta1, theta3])
    jac = saw.position_jacobian(q, variant="substituted")
    r1y, r3 = 0.045, 0.170
    printed = np.array([  # the report's eq. (17)
        [np.sin(theta1), r1 * np.cos(theta1), 0.0],
        [0.0, r1y * (1 / np.tan(theta1) ** 2 + 1), -r3 * np.sin(theta3)],
        [0.0, 0.0, -r3 * np.cos(theta3)],
    ])
    assert np.allclose(jac, printed, atol=1e-14)
    for variant in ("loop", "substituted"):
        numeric = finite_difference_jacobian(
            lambda v, variant=variant: saw.position_residual(v, theta2, variant=variant), q
        )
        assert np.allclose(saw.position_jacobian(q, variant=variant), numeric, atol=1e-7)


def test_substituted_system_has_the_same_root():
    for variant in ("loop", "substituted"):
        assert np.allclose(saw.position_residual(saw.analytic(0.7)[:3], 0.7, variant=variant), 0, atol=1e-14)


# ------------------------------------------------------------------ the report's numbers at rest


@pytest.mark.parametrize("seed", SEEDS, ids=["printed-seed", "code-seed"])
@pytest.mark.parametrize("variant", ["loop", "substituted"])
def test_at_rest_reproduces_the_report(seed, variant):
    consecutive = saw.solve_consecutive(0.0, 0.0, 0.0, seed, variant=variant)
    simultaneous = saw.solve_simultaneous(0.0, 0.0, 0.0, seed, variant=variant)
    for solution in (consecutive, simultaneous):
        assert np.max(np.abs(solution.x[:3] - REPORT_AT_REST)) < 5e-7
        assert np.max(np.abs(solution.x[3:])) < 1e-10
    # the report's counts: 4 (position), 2 (velocity), 5 (simultaneous)
    assert consecutive.stages["position"].iterations == 4
    assert consecutive.stages["velocity"].iterations == 2
    assert simultaneous.iterations == 5
    # the report's 4 for the acceleration stage is not reproducible: the stage is linear, so
    # the first step lands on the solution and the second (of size ~0) confirms it
    acceleration = consecutive.stages["acceleration"]
    assert acceleration.iterations == 2
    assert acceleration.residual_norms[1] < 1e-14


def test_linear_stages_converge_in_one_step_anywhere():
    solution = saw.solve_consecutive(1.1, 4.0, -3.0, tol=1e-12)
    for stage in ("velocity", "acceleration"):
        result = solution.stages[stage]
        assert result.residual_norms[1] < 1e-12
        assert result.step_norms[1] < 1e-12
    direct = saw.solve_consecutive(1.1, 4.0, -3.0, tol=1e-12, linear_stages="direct")
    assert direct.stages["velocity"].iterations == direct.stages["acceleration"].iterations == 1
    assert np.allclose(direct.x, solution.x, atol=1e-12)


def test_sign_convention_of_the_report():
    x = saw.analytic(np.linspace(0, 2 * np.pi, 73))
    assert np.all(x[:, 0] < 0)  # r1 negative ...
    assert np.all((x[:, 1] > -np.pi / 2) & (x[:, 1] < 0))  # ... with θ1 in (−π/2, 0)
    assert np.all((x[:, 2] > np.pi / 2) & (x[:, 2] < 3 * np.pi / 2))  # rod pointing left
    slider = saw.joint_positions(np.linspace(0, 2 * np.pi, 73))[:, 2]
    assert np.allclose(x[:, 0:1] * np.stack([np.cos(x[:, 1]), np.sin(x[:, 1])], axis=1), slider, atol=1e-15)


# ------------------------------------------------------------------ closed form, rates, textbook form


@given(angles, speeds, st.floats(min_value=-20.0, max_value=20.0))
@settings(max_examples=40)
def test_analytic_equals_newton(theta2, omega2, alpha2):
    exact = saw.analytic(theta2, omega2, alpha2)
    seed = np.concatenate([exact[:3] + [0.002, -0.03, 0.04], np.zeros(6)])
    for solution in (
        saw.solve_consecutive(theta2, omega2, alpha2, seed, tol=1e-12),
        saw.solve_simultaneous(theta2, omega2, alpha2, seed, tol=1e-12),
    ):
        assert np.allclose(solution.x, exact, rtol=1e-10, atol=1e-11)


@given(angles, speeds, st.floats(min_value=-20.0, max_value=20.0))
@settings(max_examples=60)
def test_rates_match_finite_differences(theta2, omega2, alpha2):
    # along θ2(t) = θ2 + ω2 t + α2 t²/2 the unknowns' time derivatives are the rates
    h = 1e-4

    def state(t):
        return saw.analytic(theta2 + omega2 * t + alpha2 * t**2 / 2, omega2 + alpha2 * t, alpha2)

    plus, minus, here = state(h), state(-h), state(0.0)
    scale = 1 + np.abs(here)
    assert np.allclose((plus[:6] - minus[:6]) / (2 * h), here[3:9], atol=1e-5 * scale[3:9].max())


@given(angles, speeds, st.floats(min_value=-20.0, max_value=20.0))
def test_saw_equals_textbook_slider_crank(theta2, omega2, alpha2):
    x = saw.analytic(theta2, omega2, alpha2)
    r1, th1, th3, v_r, w1, w3, a_r, al1, al3 = x
    machine = OffsetSliderCrank(crank=0.075, rod=0.170, offset=0.045)
    motion = machine.solve(theta2, omega2, alpha2, branch="left")
    s1, c1 = np.sin(th1), np.cos(th1)
    assert abs(r1 * c1 - motion.x) < 1e-14
    assert abs(v_r * c1 - r1 * s1 * w1 - motion.v) < 1e-12
    slider_a = a_r * c1 - 2 * v_r * s1 * w1 - r1 * c1 * w1**2 - r1 * s1 * al1
    assert abs(slider_a - motion.a) < 1e-10 * (1 + abs(motion.a))
    # the same angle: the report's θ3 in (π/2, 3π/2), one instant of the core's in [−π, π]
    assert abs(np.angle(np.exp(1j * (th3 - motion.theta3)))) < 1e-13
    assert abs(w3 - motion.omega3) < 1e-12
    assert abs(al3 - motion.alpha3) < 1e-10 * (1 + abs(motion.alpha3))


# ------------------------------------------------------------------ the sweep over the motor profile


@pytest.fixture(scope="module")
def sweeps():
    return {
        method: saw.sweep(200, method=method)
        for method in ("consecutive", "simultaneous", "batched", "analytic")
    }


def test_sweep_methods_agree(sweeps):
    exact = sweeps["analytic"].x
    for method in ("consecutive", "simultaneous", "batched"):
        result = sweeps[method]
        assert np.max(np.abs(result.x - exact)) < 1e-9, method
        assert np.all(result.iterations >= 2)
    assert np.max(np.abs(sweeps["consecutive"].x - sweeps["simultaneous"].x)) < 1e-9
    assert sweeps["consecutive"].stage_iterations.shape == (200, 3)
    assert sweeps["simultaneous"].iterations[0] == 5  # the first point starts from the printed seed


def test_sweep_with_a_tight_tolerance_matches_analytic():
    exact = saw.sweep(200, method="analytic").x
    scale = np.max(np.abs(exact), axis=0)
    for method in ("consecutive", "simultaneous", "batched"):
        result = saw.sweep(200, method=method, tol=1e-12)
        assert np.all(np.abs(result.x - exact) <= 1e-12 * np.maximum(scale, 1)), method


def test_sweep_follows_the_profile(sweeps):
    result = sweeps["analytic"]
    assert abs(result.t[-1] - 2 * np.sqrt(6 * np.pi / 5)) < 1e-12
    assert result.omega2[0] == 0.0 and abs(result.omega2[-1] - 6.472) < 5e-4
    # slider velocity from finite differences of the slider position in time (a fine analytic sweep)
    result = saw.sweep(4000, method="analytic")
    slider = result.r1 * np.cos(result.theta1)
    v = result.v_r * np.cos(result.theta1) - result.r1 * np.sin(result.theta1) * result.omega1
    assert np.allclose(np.gradient(slider, result.t)[1:-1], v[1:-1], atol=1e-4)


def test_batched_sweep_repeats_the_single_point_solver():
    # every point of a batched sweep starts from the printed seed: it must take the same Newton
    # steps as solve_consecutive from that seed, which evaluates the public residual functions
    batched = saw.sweep(40, method="batched")
    for k in (0, 7, 23, 39):
        single = saw.solve_consecutive(batched.theta2[k], batched.omega2[k], batched.alpha2[k],
                                       saw.SEED_PRINTED)
        assert batched.stage_iterations[k].tolist() == [s.iterations for s in single.stages.values()]
        np.testing.assert_allclose(batched.x[k], single.x, rtol=1e-12, atol=1e-12)


def test_direct_linear_stages_in_sweeps():
    newton_version = saw.sweep(50, method="consecutive")
    direct = saw.sweep(50, method="consecutive", linear_stages="direct")
    batched = saw.sweep(50, method="batched", linear_stages="direct")
    assert np.allclose(direct.x, newton_version.x, atol=1e-9)
    assert np.allclose(batched.x, newton_version.x, atol=1e-9)
    assert np.all(direct.stage_iterations[:, 1:] == 1)


# ------------------------------------------------------------------ bad input


SHORT_ROD = saw.Saw(r1y=0.045, r2=0.075, r3=0.1)  # cannot reach the line when the crank points down


@pytest.mark.parametrize("field,value", [("r1y", 0.0), ("r1y", np.nan), ("r2", -0.075), ("r2", 0.0),
                                         ("r3", np.inf), ("r3", "long")])
def test_bad_lengths(field, value):
    with pytest.raises(InvalidGeometryError, match=field):
        saw.Saw(**{field: value})


def test_unreachable_names_theta2():
    for call in (
        lambda: saw.solve_consecutive(-np.pi / 2, saw=SHORT_ROD),
        lambda: saw.solve_simultaneous(-np.pi / 2, saw=SHORT_ROD),
        lambda: saw.analytic([0.0, -np.pi / 2], saw=SHORT_ROD),
        lambda: saw.sweep(40, method="analytic", saw=SHORT_ROD),
    ):
        with pytest.raises(UnreachableError, match="theta2"):
            call()
    values = saw.analytic([0.0, -np.pi / 2], saw=SHORT_ROD, on_failure="nan")
    assert np.all(np.isfinite(values[0])) and np.all(np.isnan(values[1]))


def test_limit_position_is_singular():
    toggle = saw.Saw(r1y=0.045, r2=0.075, r3=0.045 + 0.075)  # rod vertical when θ2 = −π/2
    for call in (
        lambda: saw.solve_consecutive(-np.pi / 2, saw=toggle),
        lambda: saw.solve_simultaneous(-np.pi / 2, saw=toggle),
        lambda: saw.analytic(-np.pi / 2, saw=toggle),
    ):
        with pytest.raises(SingularJacobianError, match="theta2"):
            call()


def test_singular_seed():
    seed = saw.SEED_PRINTED.copy()
    seed[2] = np.pi / 2  # rod perpendicular to the slider line: det J = −r1 r3 cos θ3 = 0
    with pytest.raises(SingularJacobianError, match="position stage at theta2=0"):
        saw.solve_consecutive(0.0, x0=seed)
    with pytest.raises(SingularJacobianError, match="simultaneous stage at theta2=0"):
        saw.solve_simultaneous(0.0, x0=seed)


def test_convergence_failure_is_named():
    with pytest.raises(ConvergenceError, match="theta2"):
        saw.solve_simultaneous(0.3, max_iter=3)  # needs 5 from the printed seed
    with pytest.raises(ConvergenceError, match="position stage at theta2=0.3"):
        saw.solve_consecutive(0.3, max_iter=2)


@pytest.mark.parametrize(
    "call,name",
    [
        (lambda: saw.solve_consecutive(np.nan), "theta2"),
        (lambda: saw.solve_consecutive([0.0, 1.0]), "theta2"),
        (lambda: saw.solve_simultaneous(0.0, np.inf), "omega2"),
        (lambda: saw.solve_consecutive(0.0, 0.0, np.nan), "alpha2"),
        (lambda: saw.solve_consecutive(0.0, x0=[0.1, 0.2]), "x0"),
        (lambda: saw.solve_simultaneous(0.0, x0=[np.nan] * 9), "x0"),
        (lambda: saw.solve_consecutive(0.0, variant="polar"), "variant"),
        (lambda: saw.solve_consecutive(0.0, linear_stages="guess"), "linear_stages"),
        (lambda: saw.solve_consecutive(0.0, tol=-1.0), "tol"),
        (lambda: saw.analytic("up"), "theta2"),
        (lambda: saw.analytic(0.0, on_failure="ignore"), "on_failure"),
        (lambda: saw.sweep(1), "n"),
        (lambda: saw.sweep(10.5), "n"),
        (lambda: saw.sweep(10, method="secant"), "method"),
        (lambda: saw.sweep(10, t_end=-1.0), "t_end"),
        (lambda: saw.position_residual([0.1, 0.2], 0.0), "position"),
        (lambda: saw.system_jacobian(np.zeros(3)), "x"),
    ],
)
def test_bad_input_is_named(call, name):
    with pytest.raises(InvalidGeometryError, match=name):
        call()


# ------------------------------------------------------------------ the saw is its declaration


def test_the_course_closed_form_against_the_core_derivation_from_the_declaration():
    # the course's eqs. 20–28, written by hand in analytic, against the core's solve of the declared loop:
    # positions by the core's own route (closed form where the loop reduces, else Newton and continuation)
    # and rates by its linear solves: independent routes, both from θ2(t) of the motor profile
    t = np.linspace(0.0, 3.8, 40)
    theta2, omega2, alpha2 = saw.motor_profile(t)
    closed = saw.COURSE_SAW.motion(theta2, omega2, alpha2)
    core = saw.COURSE_SAW.mechanism.solve({"theta2": theta2}, {"theta2": omega2}, {"theta2": alpha2},
                                          guess={"r1": -0.1, "theta1": -0.5, "theta3": 3.0})
    for name in ("r1", "theta1", "theta3"):
        np.testing.assert_allclose(core.position[name], closed.position[name], atol=1e-12)
        np.testing.assert_allclose(core.velocity[name], closed.velocity[name], atol=1e-11)
        np.testing.assert_allclose(core.acceleration[name], closed.acceleration[name], atol=1e-9)
    # the joints are the declared points: C, the slider pin, on the slider line y = r1y at x = r1 cos θ1
    joints = saw.COURSE_SAW.joints(theta2)
    np.testing.assert_allclose(joints[:, 2, 1], 0.045, atol=1e-15)
    np.testing.assert_allclose(joints[:, 2, 0], closed.position["r1"] * np.cos(closed.position["theta1"]),
                               atol=1e-15)
    assert list(saw.COURSE_SAW.mechanism.points) == ["O2", "A", "C"]


def test_the_limit_position_is_the_core_rule_and_one_failure_keyword():
    toggle = saw.Saw(r1y=0.045, r2=0.075, r3=0.045 + 0.075)  # rod vertical when θ2 = −π/2
    q = saw.analytic(-np.pi / 2 + 1e-3, saw=toggle)[:3]
    assert not toggle.mechanism.is_singular(q, [-np.pi / 2 + 1e-3])
    assert toggle.mechanism.is_singular([q[0], q[1], np.pi / 2], [-np.pi / 2])
    new = saw.analytic([0.0, -np.pi / 2], saw=SHORT_ROD, on_failure="nan")
    assert np.isfinite(new[0]).all() and np.isnan(new[1]).all()
    assert SHORT_ROD.motion([0.0, -np.pi / 2], on_failure="nan").converged.tolist() == [True, False]


def test_a_limit_position_error_carries_the_unknowns_there():
    short = saw.Saw(0.045, 0.075, 0.12)
    theta2 = np.arcsin((0.045 - 0.12) / 0.075)  # A lies r3 straight below the slider line: rod ⟂ line
    with pytest.raises(SingularJacobianError) as caught:
        saw.analytic(theta2, 1.0, saw=short)
    r1, theta1, theta3 = caught.value.x
    A = 0.075 * np.array([np.cos(theta2), np.sin(theta2)])
    C = r1 * np.array([np.cos(theta1), np.sin(theta1)])
    assert abs(C[1] - 0.045) < 1e-12 and abs(np.hypot(*(C - A)) - 0.12) < 1e-12   # C on the line, |AC| = r3
    assert abs(np.cos(theta3)) < 1e-7                                             # the rod ⟂ the line
