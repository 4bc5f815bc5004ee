"""course_lib.profile against sympy integration, scipy quadrature and the report's numbers."""

import math

import numpy as np
import pytest
import sympy as sp
from hypothesis import given
from hypothesis import strategies as st
from scipy.integrate import cumulative_trapezoid, solve_ivp

from course_lib.errors import InvalidGeometryError
from course_lib.profile import first_turn_time, motor_profile

T = first_turn_time()


def sympy_profile():
    """Integrate the piecewise α2 twice in sympy, constants fixed by continuity, T from θ2(T) = 2π."""
    t, Tsym, tau = sp.symbols("t T tau", positive=True)
    A = 5
    alphas = [3 * A * tau / Tsym, sp.Integer(A), 3 * A - 3 * A * tau / Tsym, sp.Integer(0)]
    starts = [0, Tsym / 3, 2 * Tsym / 3, Tsym]
    omegas, thetas = [], []
    omega_start, theta_start = sp.Integer(0), sp.Integer(0)
    for alpha, start, end in zip(alphas, starts, starts[1:] + [None], strict=True):
        omega = omega_start + sp.integrate(alpha, (tau, start, t))
        theta = theta_start + sp.integrate(omega.subs(t, tau), (tau, start, t))
        omegas.append(sp.expand(omega))
        thetas.append(sp.expand(theta))
        if end is not None:  # continuity: the next piece starts where this one ends
            omega_start, theta_start = omega.subs(t, end), theta.subs(t, end)
    T_value = sp.solve(sp.Eq(thetas[3].subs(t, Tsym), 2 * sp.pi), Tsym)[0]
    return t, Tsym, T_value, omegas, thetas


def test_first_turn_time_matches_sympy_and_report():
    _, _, T_value, _, _ = sympy_profile()
    assert abs(float(T_value) - T) < 1e-14
    assert sp.simplify(T_value - sp.sqrt(6 * sp.pi / 5)) == 0
    assert abs(T - 1.9416) < 5e-5  # report: T = 1.942 s
    assert abs(2 * T - 3.883) < 5e-4  # report: 2T = 3.883 s


def test_pieces_match_sympy_integration():
    t, Tsym, T_value, omegas, thetas = sympy_profile()
    # the seed README's corrected pieces of the course's eq. (5)
    expected = [
        5 * t**3 / (2 * Tsym),
        5 * t**2 / 2 - 5 * Tsym * t / 6 + 5 * Tsym**2 / 54,
        5 * Tsym**2 / 6 - sp.Rational(25, 6) * Tsym * t + sp.Rational(15, 2) * t**2 - 5 * t**3 / (2 * Tsym),
        sp.Rational(10, 3) * Tsym * t - sp.Rational(5, 3) * Tsym**2,
    ]
    for derived, printed in zip(thetas, expected, strict=True):
        assert sp.simplify(derived - printed) == 0
    times = np.linspace(0, 2 * T, 301)
    profile = motor_profile(times)
    intervals = [times < T / 3, (times >= T / 3) & (times < 2 * T / 3), (times >= 2 * T / 3) & (times < T)]
    intervals.append(times >= T)
    for mask, omega, theta in zip(intervals, omegas, thetas, strict=True):
        omega_f = sp.lambdify(t, omega.subs(Tsym, T_value), "numpy")
        theta_f = sp.lambdify(t, theta.subs(Tsym, T_value), "numpy")
        assert np.allclose(profile.omega2[mask], omega_f(times[mask]), atol=1e-12)
        assert np.allclose(profile.theta2[mask], theta_f(times[mask]), atol=1e-12)


def test_profile_matches_numerical_integration_of_alpha():
    times = np.linspace(0, 2 * T, 20001)
    profile = motor_profile(times)
    omega = cumulative_trapezoid(profile.alpha2, times, initial=0.0)
    assert np.max(np.abs(omega - profile.omega2)) < 1e-6
    ode = solve_ivp(
        lambda s, y: [y[1], float(motor_profile(s).alpha2)],
        (0, 2 * T),
        [0.0, 0.0],
        t_eval=times[::1000],
        rtol=1e-10,
        atol=1e-12,
        max_step=T / 30,
    )
    assert np.allclose(ode.y[0], profile.theta2[::1000], atol=1e-7)
    assert np.allclose(ode.y[1], profile.omega2[::1000], atol=1e-7)


def test_report_values():
    profile = motor_profile(np.array([0.0, T / 3, T / 2, T, 1.5 * T, 2 * T]))
    assert profile.alpha2.tolist()[0] == 0.0
    assert abs(profile.alpha2[2] - 5.0) < 1e-12  # holds 5 rad/s² in the middle third
    assert abs(profile.omega2[3] - 10 * T / 3) < 1e-12
    assert abs(profile.omega2[3] - 6.472) < 5e-4  # final speed
    assert abs(profile.omega2[3] * 60 / (2 * math.pi) - 61.8) < 0.05  # rpm
    assert abs(profile.theta2[3] - 2 * math.pi) < 1e-12
    assert np.all(profile.alpha2[3:] == 0.0)
    assert np.allclose(profile.omega2[3:], 10 * T / 3, atol=1e-12)


@pytest.mark.parametrize("boundary", [T / 3, 2 * T / 3, T])
def test_continuity_at_phase_boundaries(boundary):
    eps = 1e-9
    before, after = motor_profile(boundary - eps), motor_profile(boundary + eps)
    # over 2·eps a continuous quantity moves by at most (its rate bound)·2·eps: ω2 ≤ 6.5, α2 ≤ 5, jerk ≤ 7.8
    assert abs(float(before.theta2) - float(after.theta2)) < 7 * 2 * eps
    assert abs(float(before.omega2) - float(after.omega2)) < 5 * 2 * eps + 1e-14
    assert abs(float(before.alpha2) - float(after.alpha2)) < 8 * 2 * eps  # α2 is continuous too


@given(st.floats(min_value=1e-3, max_value=4.0))
def test_rates_match_finite_differences(s):
    h = 1e-6
    if any(abs(s - b) < 2 * h for b in (T / 3, 2 * T / 3, T)):
        return
    plus, minus, here = motor_profile(s + h), motor_profile(s - h), motor_profile(s)
    assert abs((plus.theta2 - minus.theta2) / (2 * h) - here.omega2) < 1e-6
    assert abs((plus.omega2 - minus.omega2) / (2 * h) - here.alpha2) < 1e-5


def test_shapes_follow_input():
    assert motor_profile(1.0).theta2.shape == ()
    assert motor_profile(np.zeros((2, 3))).omega2.shape == (2, 3)


def test_other_alpha_max_scales_time():
    assert abs(first_turn_time(alpha_max=20.0) - T / 2) < 1e-14
    end = motor_profile(first_turn_time(20.0), alpha_max=20.0)
    assert abs(float(end.theta2) - 2 * math.pi) < 1e-12


@pytest.mark.parametrize("bad", [-1e-9, -1.0, np.nan, np.inf, [0.0, -2.0], "soon"])
def test_bad_times_raise(bad):
    with pytest.raises(InvalidGeometryError, match="t"):
        motor_profile(bad)


@pytest.mark.parametrize("bad", [0.0, -5.0, np.nan, np.inf])
def test_bad_alpha_max_raises(bad):
    with pytest.raises(InvalidGeometryError, match="alpha_max"):
        first_turn_time(bad)
    with pytest.raises(InvalidGeometryError, match="alpha_max"):
        motor_profile(1.0, alpha_max=bad)
