"""Newton–Raphson: scalars, systems, batches, and the ways it must fail loudly."""

import numpy as np
import pytest
import scipy.optimize
from hypothesis import given
from hypothesis import strategies as st

from course_lib.errors import ConvergenceError, InvalidGeometryError, SingularJacobianError
from course_lib.newton import finite_difference_jacobian, newton, newton_batch


def test_sqrt2_to_1e12_from_one():
    result = newton(lambda x: x**2 - 2.0, 1.0, jac=lambda x: 2.0 * x)
    assert result.converged
    assert abs(result.x - np.sqrt(2.0)) < 1e-12
    assert len(result.history) == result.iterations + 1
    assert result.history[0] == 1.0
    assert len(result.step_norms) == result.iterations
    assert len(result.residual_norms) == result.iterations + 1
    # the course's rule: the last step is below tol, the one before is not
    assert result.step_norms[-1] < 1e-6 <= result.step_norms[-2]


def test_hand_iterates_of_sqrt2():
    # x_{n+1} = (x_n + 2/x_n)/2 written out by hand: 1, 3/2, 17/12, 577/408
    result = newton(lambda x: x**2 - 2.0, 1.0, jac=lambda x: 2.0 * x)
    np.testing.assert_allclose(result.history[:4], [1.0, 1.5, 17 / 12, 577 / 408], rtol=1e-15)


def test_finite_difference_jacobian_when_none_given():
    result = newton(lambda x: np.cos(x) - x, 1.0)
    reference = scipy.optimize.brentq(lambda x: np.cos(x) - x, 0.0, 1.0, xtol=1e-15)
    assert abs(result.x - reference) < 1e-10


def test_zero_derivative_start_raises_singular():
    with pytest.raises(SingularJacobianError, match=r"x=0\.0"):
        newton(lambda x: x**2 - 2.0, 0.0, jac=lambda x: 2.0 * x)


def test_no_real_root_raises_convergence_error_with_history():
    with pytest.raises(ConvergenceError) as info:
        newton(lambda x: x**2 + 1.0, 2.0, jac=lambda x: 2.0 * x, max_iter=30)
    result = info.value.result
    assert not result.converged
    assert result.iterations == 30
    assert len(result.history) == 31
    assert np.all(result.residual_norms >= 1.0)  # x² + 1 ≥ 1 everywhere


def test_divergence_to_infinity_is_a_convergence_error():
    # arctan: Newton from |x0| > 1.3917 overshoots further every step
    with pytest.raises(ConvergenceError) as info:
        newton(np.arctan, 2.0, jac=lambda x: 1 / (1 + x**2), max_iter=8)
    assert np.all(np.diff(np.abs(info.value.result.history)) > 0)
    # left to run, the derivative 1/(1 + x²) underflows to zero: a singular Jacobian far away
    with pytest.raises(SingularJacobianError) as info, np.errstate(over="ignore"):
        newton(np.arctan, 2.0, jac=lambda x: 1 / (1 + x**2), max_iter=200)
    assert abs(info.value.x) > 1e100


def test_system_matches_closed_form_intersection():
    # circle x² + y² = 4 meets the line y = x + 1 at x = (−1 + √7)/2
    def F(v):
        return np.array([v[0] ** 2 + v[1] ** 2 - 4.0, v[1] - v[0] - 1.0])

    def J(v):
        return np.array([[2 * v[0], 2 * v[1]], [-1.0, 1.0]])

    result = newton(F, np.array([1.0, 1.0]), jac=J, tol=1e-12)
    x = (-1 + np.sqrt(7)) / 2
    np.testing.assert_allclose(result.x, [x, x + 1], atol=1e-14)
    assert result.history.shape == (result.iterations + 1, 2)
    assert result.step_components.shape == (result.iterations, 2)
    np.testing.assert_allclose(np.linalg.norm(result.step_components, axis=1), result.step_norms)


def test_singular_system_names_condition_number():
    def F(v):
        return np.array([v[0] + v[1] - 1.0, 2 * v[0] + 2 * v[1] - 3.0])

    with pytest.raises(SingularJacobianError, match="condition number"):
        newton(F, np.zeros(2), jac=lambda v: np.array([[1.0, 1.0], [2.0, 2.0]]))


def test_residual_check_refuses_tiny_steps_far_from_a_root():
    # a wrong, far too steep Jacobian makes every step tiny (3e-8 < tol) while F = x − 3 stays ≈ −3
    with pytest.raises(ConvergenceError) as info:
        newton(lambda x: x - 3.0, 0.0, jac=lambda x: 1e8, max_iter=5)
    result = info.value.result
    assert np.all(result.step_norms < 1e-6)
    assert np.all(result.residual_norms > 2.9)


@pytest.mark.parametrize("kwargs", [{"tol": 0.0}, {"tol": np.nan}, {"max_iter": 0}, {"max_iter": 2.5}])
def test_bad_settings(kwargs):
    with pytest.raises(InvalidGeometryError):
        newton(lambda x: x, 1.0, **kwargs)


def test_bad_seed_and_shape():
    with pytest.raises(InvalidGeometryError, match="x0"):
        newton(lambda x: x, np.nan)
    with pytest.raises(InvalidGeometryError, match="residuals"):
        newton(lambda v: np.array([v[0]]), np.zeros(2))


def test_finite_difference_jacobian_batched():
    x = np.array([[1.0, 2.0], [0.5, -1.0]])
    J = finite_difference_jacobian(lambda v: np.stack([np.sin(v[:, 0]) * v[:, 1], v[:, 1] ** 3], -1), x)
    exact = np.zeros((2, 2, 2))
    exact[:, 0, 0] = np.cos(x[:, 0]) * x[:, 1]
    exact[:, 0, 1] = np.sin(x[:, 0])
    exact[:, 1, 1] = 3 * x[:, 1] ** 2
    np.testing.assert_allclose(J, exact, atol=1e-9)


def _system(A, c, target):
    """F(x) = A x + c tanh(x) − (A x* + c tanh(x*)): root x*, well posed for small c."""
    rhs = A @ target + c * np.tanh(target)

    def F(x):
        return A @ x + c * np.tanh(x) - rhs

    def J(x):
        return A + np.diag(c / np.cosh(x) ** 2)

    return F, J


@given(
    st.integers(min_value=1, max_value=5),
    st.integers(min_value=0, max_value=2**32 - 1),
)
def test_property_random_well_posed_systems(n, seed):
    rng = np.random.default_rng(seed)
    A = np.eye(n) * 3 + rng.uniform(-0.5, 0.5, (n, n))
    c = rng.uniform(-1, 1, n)
    target = rng.uniform(-2, 2, n)
    F, J = _system(A, c, target)
    result = newton(F, target + rng.uniform(-0.3, 0.3, n), jac=J, tol=1e-10)
    assert result.converged
    np.testing.assert_allclose(result.x, target, atol=1e-9)
    errors = np.linalg.norm(result.history - target, axis=1)
    # quadratic convergence: e_{n+1} <= C e_n^2 once close (C bounded by the problem's curvature)
    close = (errors[:-1] < 1e-2) & (errors[:-1] > 1e-7)
    assert np.all(errors[1:][close] <= 10 * errors[:-1][close] ** 2 + 1e-14)


def test_batch_matches_single_solves_and_scipy():
    rng = np.random.default_rng(7)
    n_systems = 50
    targets = rng.uniform(1.0, 10.0, (n_systems, 1))

    result = newton_batch(lambda x: x**3 - targets, np.full((n_systems, 1), 2.0),
                          jac=lambda x: 3 * x[:, :, None] ** 2, tol=1e-12)
    assert result.converged.all()
    np.testing.assert_allclose(result.x[:, 0], np.cbrt(targets[:, 0]), rtol=1e-13)
    for k in (0, 17, 49):
        single = newton(lambda x, k=k: x**3 - targets[k, 0], 2.0, jac=lambda x: 3 * x**2, tol=1e-12)
        assert single.iterations == result.iterations[k]
        assert abs(single.x - result.x[k, 0]) < 1e-15


def test_batch_reports_singular_and_unconverged_rows_without_raising():
    x0 = np.array([[0.0], [1.0], [2.0]])  # row 0 starts at a zero derivative
    offsets = np.array([[2.0], [2.0], [-1.0]])  # row 2: x² + 1 = 0 has no real root
    result = newton_batch(lambda x: x**2 - offsets, x0, jac=lambda x: 2 * x[:, :, None], max_iter=40)
    assert result.ill_conditioned.tolist()[0] is True
    assert result.converged.tolist() == [False, True, False]
    assert abs(result.x[1, 0] - np.sqrt(2)) < 1e-12


def test_batch_with_residual_and_jacobian_from_one_function():
    # jac=True: F returns (residuals, Jacobians); the run must be the one with separate callables
    x0 = np.array([[0.0], [1.0], [2.0], [-3.0]])
    offsets = np.array([[2.0], [2.0], [-1.0], [5.0]])
    separate = newton_batch(lambda x: x**2 - offsets, x0, jac=lambda x: 2 * x[:, :, None], max_iter=40)
    together = newton_batch(lambda x: (x**2 - offsets, 2 * x[:, :, None]), x0, jac=True, max_iter=40)
    for name in ("x", "converged", "iterations", "ill_conditioned", "step_norms", "residual_norms"):
        np.testing.assert_array_equal(getattr(together, name), getattr(separate, name), err_msg=name)
    assert together.ill_conditioned.tolist() == [True, False, False, False]
    np.testing.assert_allclose(together.x[[1, 3], 0], [np.sqrt(2), -np.sqrt(5)], rtol=1e-12)


def test_batch_finite_difference_two_unknowns():
    # circle of radius r_i meets the line y = x: x = r/√2
    radii = np.array([1.0, 2.0, 3.0])

    def F(v):
        return np.stack([v[:, 0] ** 2 + v[:, 1] ** 2 - radii**2, v[:, 1] - v[:, 0]], -1)

    result = newton_batch(F, np.ones((3, 2)), tol=1e-12)
    assert result.converged.all()
    np.testing.assert_allclose(result.x[:, 0], radii / np.sqrt(2), rtol=1e-12)


def test_batch_bad_seed_shape():
    with pytest.raises(InvalidGeometryError, match="x0"):
        newton_batch(lambda x: x, np.zeros(3))


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_singularity_measure_matches_numpy_determinant(n):
    from course_lib.newton import hadamard_ratio

    J = np.random.default_rng(n).normal(size=(20, n, n))
    if n > 1:
        J[0, -1] = J[0, 0]  # two equal rows: exactly singular
    expected = np.abs(np.linalg.det(J)) / np.prod(np.linalg.norm(J, axis=2), axis=1)
    np.testing.assert_allclose(hadamard_ratio(J), expected, rtol=1e-10, atol=1e-15)
    assert n == 1 or hadamard_ratio(J)[0] < 1e-15


# ------------------------------------------------------------------ one rule, one result shape, bad input


def test_max_iter_is_capped_so_a_cycle_cannot_run_for_minutes():
    # x³ − 2x + 2 from 0 cycles 0 → 1 → 0 … forever; 10⁷ updates would take minutes and grow the history
    with pytest.raises(InvalidGeometryError, match=r"max_iter must be at most 10,000.*max_iter=10000000"):
        newton(lambda x: x**3 - 2 * x + 2, 0.0, jac=lambda x: 3 * x * x - 2, max_iter=10**7)
    with pytest.raises(InvalidGeometryError, match=r"max_iter=20000"):
        newton_batch(lambda x: x, np.ones((2, 1)), max_iter=20_000)
    with pytest.raises(ConvergenceError) as info:
        newton(lambda x: x**3 - 2 * x + 2, 0.0, jac=lambda x: 3 * x * x - 2, max_iter=10_000)
    assert info.value.result.history.shape == (10_001,)
    np.testing.assert_array_equal(info.value.result.history[:4], [0.0, 1.0, 0.0, 1.0])


@pytest.mark.parametrize(("setting", "value"), [
    ("tol", None), ("tol", "1e-6"), ("tol", True), ("tol", np.nan), ("tol", 0.0), ("tol", -1e-6),
    ("max_iter", np.nan), ("max_iter", np.inf), ("max_iter", None), ("max_iter", 0), ("max_iter", True),
    ("residual_tol", np.nan), ("residual_tol", -1.0), ("residual_tol", 0.0), ("on_failure", "ignore"),
])
def test_bad_settings_are_named_with_their_value(setting, value):
    for solve, seed in ((newton, 1.0), (newton_batch, np.ones((2, 1)))):
        with pytest.raises(InvalidGeometryError, match=rf"{setting} must .*got {value!r}"):
            solve(lambda x: x - 0.5, seed, **{setting: value})


def test_residual_tol_inf_is_the_matlab_rule():
    result = newton(lambda x: x - 3.0, 0.0, jac=lambda x: 1e8, max_iter=5, residual_tol=np.inf)
    assert result.converged and result.iterations == 1


@pytest.mark.parametrize(("F", "jac", "message"), [
    (lambda v: v - 1, lambda v: np.eye(3), r"jac must return a Jacobian of shape \(2, 2\).*shape \(3, 3\)"),
    (lambda v: v - 1, lambda v: np.ones(2), r"jac must return a Jacobian of shape \(2, 2\).*shape \(2,\)"),
    (lambda v: None, None, r"F returned None at x=\[0\.5, 0\.5\]"),
    (lambda v: v - 1, lambda v: None, r"jac returned None at x=\[0\.5, 0\.5\]"),
    (lambda v: v + 1j, None, r"F returned complex numbers at x=\[0\.5, 0\.5\]"),
    (lambda v: [v[0], None], None, r"F must return real numbers; got \[.*0\.5\), None\]"),
])
def test_misbehaving_callables_are_named(F, jac, message):
    with pytest.raises(InvalidGeometryError, match=message):
        newton(F, np.array([0.5, 0.5]), jac=jac)


def test_nan_from_F_or_jac_is_said_so_not_called_singular():
    with pytest.raises(ConvergenceError, match=r"F returned \[nan\] at x=-1\.0"):
        newton(lambda x: np.sqrt(x) - 2, -1.0, jac=lambda x: 0.5 / np.sqrt(x))
    with pytest.raises(ConvergenceError, match=r"jac returned \[\[nan\]\] at x=0\.5, after 0 iterations"):
        newton(lambda x: x - 2, 0.5, jac=lambda x: np.nan)
    # F defined at the seed, NaN after the first step (x < 0)
    with pytest.raises(ConvergenceError, match="non-finite value appeared after 1 iterations"):
        newton(lambda x: np.sqrt(x) + 1.0, 0.25, jac=lambda x: 0.5 / np.sqrt(x))
    batch = newton_batch(lambda x: np.sqrt(x) - 2, np.array([[-1.0], [1.0]]),
                         jac=lambda x: 0.5 / np.sqrt(x)[:, :, None])
    assert batch.converged.tolist() == [False, True] and batch.ill_conditioned.tolist() == [False, False]
    assert "row 0: a non-finite value appeared" in batch.message


def test_one_result_shape_and_one_rule_for_failures():
    single = newton(lambda x: x**2 + 1.0, 2.0, jac=lambda x: 2 * x, max_iter=5, on_failure="report")
    batch = newton_batch(lambda x: x**2 + 1.0, np.array([[2.0]]), jac=lambda x: 2 * x[:, :, None], max_iter=5)
    for name in ("x", "converged", "ill_conditioned", "iterations", "message", "step_norms",
                 "residual_norms"):
        assert hasattr(single, name) and hasattr(batch, name)
    assert not single.converged and single.iterations == 5 and "max_iter=5" in single.message
    assert batch.converged.tolist() == [False] and "max_iter=5 iterations" in batch.message
    assert single.x == batch.x[0, 0] and single.residual_norms[-1] == batch.residual_norms[0]
    with pytest.raises(ConvergenceError, match="1 of 1 systems did not converge") as info:
        newton_batch(lambda x: x**2 + 1.0, np.array([[2.0]]), jac=lambda x: 2 * x[:, :, None], max_iter=5,
                     on_failure="raise")
    assert info.value.result.iterations.tolist() == [5]
    stuck = newton(lambda x: x**2 - 2.0, 0.0, jac=lambda x: 2.0 * x, on_failure="report")
    assert stuck.ill_conditioned and not stuck.converged and "condition number > 1e+12" in stuck.message
    with pytest.raises(SingularJacobianError, match="row 0: its Jacobian is ill-conditioned"):
        newton_batch(lambda x: x**2 - 2.0, np.zeros((1, 1)), jac=lambda x: 2 * x[:, :, None],
                     on_failure="raise")


def test_batch_callables_of_the_wrong_shape_are_named():
    with pytest.raises(InvalidGeometryError, match=r"jac must return Jacobians of shape \(3, 2, 2\)"):
        newton_batch(lambda x: x - 1, np.zeros((3, 2)), jac=lambda x: np.zeros((3, 2)))
    with pytest.raises(InvalidGeometryError, match=r"F must return residuals of shape \(3, 2\).*\(3,\)"):
        newton_batch(lambda x: x[:, 0], np.zeros((3, 2)))
    with pytest.raises(InvalidGeometryError, match=r"with jac=True, F must return \(residuals, Jacobians\)"):
        newton_batch(lambda x: x - 1, np.zeros((3, 2)), jac=True)


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_linear_solver_equals_numpy_solve(n):
    from course_lib.newton import linear_solver

    rng = np.random.default_rng(10 + n)
    J, b = rng.normal(size=(50, n, n)) + 2 * np.eye(n), rng.normal(size=(50, n))
    np.testing.assert_allclose(linear_solver(J)(b), np.linalg.solve(J, b[..., None])[..., 0], rtol=1e-10,
                               atol=1e-12)


@pytest.mark.parametrize("n", [1, 2, 3, 4])
def test_linear_stack_solves_as_numpy_and_each_matrix_alone(n):
    from course_lib.newton import LinearStack, ill_conditioned, is_singular

    rng = np.random.default_rng(20 + n)
    J, b = rng.normal(size=(40, n, n)) + 2 * np.eye(n), rng.normal(size=(40, n))
    J[5] = 0.0  # singular, flagged and left out below
    stack = LinearStack(J)
    np.testing.assert_array_equal(stack.ill_conditioned, ill_conditioned(J))
    assert is_singular is ill_conditioned  # the older name
    assert stack.ill_conditioned.tolist() == [k == 5 for k in range(40)]
    kept = ~stack.ill_conditioned
    good = LinearStack(J, kept)
    x = good.solve(b[kept])
    np.testing.assert_allclose(x, np.linalg.solve(J[kept], b[kept][..., None])[..., 0],
                               rtol=1e-10, atol=1e-12)
    # a subset taken from the prepared stack and a stack laid out otherwise: same bits
    np.testing.assert_array_equal(stack.take(~stack.ill_conditioned).solve(b[~stack.ill_conditioned]), x)
    columns_first = np.ascontiguousarray(J.transpose(1, 2, 0)).transpose(2, 0, 1)
    np.testing.assert_array_equal(LinearStack(columns_first, np.flatnonzero(~stack.ill_conditioned)).solve(
        b[~stack.ill_conditioned]), x)
    np.testing.assert_array_equal(stack.matrices, J)
    # one matrix at a time, as newton steps: its first step from 0 solves J·x = b, and J[5] stops it
    for k, row in enumerate(np.cumsum(~stack.ill_conditioned) - 1):
        run = newton(lambda v, k=k: J[k] @ v - b[k], np.zeros(n), jac=lambda v, k=k: J[k],
                     on_failure="report")
        assert run.ill_conditioned == (k == 5)
        if k != 5:
            np.testing.assert_allclose(run.history[1], x[row], rtol=1e-14, atol=1e-15)


def test_batch_with_a_constant_jacobian_is_the_run_with_that_jacobian_as_a_callable():
    # an affine F = J·x + c: Newton lands in one step and sees it in the next, the answer of numpy's solve
    rng = np.random.default_rng(3)
    J, c = rng.normal(size=(30, 3, 3)) + 3 * np.eye(3), rng.normal(size=(30, 3))
    J[4] = [[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]]  # singular row of the batch

    def F(x):
        return np.einsum("nij,nj->ni", J, x) + c

    constant = newton_batch(F, np.zeros((30, 3)), jac=J, tol=1e-10)
    callable_ = newton_batch(F, np.zeros((30, 3)), jac=lambda x: J, tol=1e-10)
    for name in ("x", "converged", "iterations", "ill_conditioned", "step_norms", "residual_norms",
                 "message"):
        np.testing.assert_array_equal(getattr(constant, name), getattr(callable_, name), err_msg=name)
    ok = np.arange(30) != 4
    assert constant.ill_conditioned.tolist() == (~ok).tolist() and constant.converged.tolist() == ok.tolist()
    assert (constant.iterations[ok] == 2).all()
    np.testing.assert_allclose(constant.x[ok], np.linalg.solve(J[ok], -c[ok][..., None])[..., 0], rtol=1e-12,
                               atol=1e-14)
    with pytest.raises(InvalidGeometryError, match=r"a constant jac must be a stack of shape \(30, 3, 3\)"):
        newton_batch(F, np.zeros((30, 3)), jac=J[:2])


def test_batch_rows_stopping_at_different_updates_are_each_the_single_run():
    # rows 0–1 start on their root (stop after one update), rows 2–3 step onto x = 0 where J is singular
    # while most rows still iterate, rows 8–9 have no real root: each row as newton() alone would run it
    x0 = np.array([2.0, 3.0, 1.0, 2.0, 1.0, 5.0, 0.5, 9.0, 1.0, 2.0])
    targets = np.array([4.0, 9.0, -1.0, -4.0, 2.0, 3.0, 7.0, 0.1, -1.5, -3.0])
    batch = newton_batch(lambda x: x**2 - targets[:, None], x0[:, None], jac=lambda x: 2 * x[:, :, None],
                         tol=1e-12, max_iter=30)
    for k in range(10):
        single = newton(lambda x, k=k: x**2 - targets[k], x0[k], jac=lambda x: 2 * x, tol=1e-12, max_iter=30,
                        on_failure="report")
        assert (batch.iterations[k], batch.converged[k], batch.ill_conditioned[k]) == (
            single.iterations, single.converged, single.ill_conditioned), k
        assert batch.x[k, 0] == single.x, k
    assert batch.iterations[:2].tolist() == [1, 1]
    assert batch.ill_conditioned.tolist() == [False] * 2 + [True] * 2 + [False] * 6
