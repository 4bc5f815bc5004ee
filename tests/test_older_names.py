"""Renamed library names keep their older spelling (docs/glossary.md, "Older spellings"): the older name still
works and gives what the new one gives, and only the new one is public."""

import dataclasses

import numpy as np
import pytest

from course_lib import BatchNewtonResult, NewtonResult, newton, newton_batch, saw

# ------------------------------------------ saw: the Jacobians of velocity_residual and acceleration_residual

POSITIONS = np.array([[-0.0997, -0.4684, 2.8737], [-0.2, 0.3, 2.5], [-0.12, -0.1, 3.1]])


def by_columns(residual) -> np.ndarray:
    """∂(residual)/∂(its first argument), column by column: the residuals are linear in it, so column k is
    residual(e_k) − residual(0), with no derivative taken."""
    zero = residual(np.zeros(3))
    return np.stack([residual(np.eye(3)[k]) - zero for k in range(3)], axis=-1)


@pytest.mark.parametrize("position", POSITIONS.tolist())
def test_the_saws_older_jacobian_names_give_the_residuals_jacobians(position):
    velocity = [0.3, -1.2, 0.7]
    expected_v = by_columns(lambda v: saw.velocity_residual(v, position, 0.4, 2.5))
    expected_a = by_columns(lambda a: saw.acceleration_residual(a, velocity, position, 0.4, 2.5, 5.0))
    for older, new, expected in ((saw.velocity_jacobian, saw.velocity_residual_jacobian, expected_v),
                                 (saw.acceleration_jacobian, saw.acceleration_residual_jacobian, expected_a)):
        assert np.abs(new(position) - expected).max() < 1e-12
        np.testing.assert_array_equal(older(position), new(position))


def test_the_saws_older_jacobian_names_are_aliases_out_of_all():
    assert saw.velocity_jacobian is saw.velocity_residual_jacobian
    assert saw.acceleration_jacobian is saw.acceleration_residual_jacobian
    assert {"velocity_residual_jacobian", "acceleration_residual_jacobian"} <= set(saw.__all__)
    assert not {"velocity_jacobian", "acceleration_jacobian"} & set(saw.__all__)


# ------------------------------------------ Newton's results: ill_conditioned, singular its older name

def test_a_newton_runs_singular_is_its_ill_conditioned():
    # from x = 0 the derivative 2x of x² − 2 is zero: Newton's step test stops the run before any update
    stuck = newton(lambda x: x**2 - 2.0, 0.0, jac=lambda x: 2.0 * x, on_failure="report")
    found = newton(lambda x: x**2 - 2.0, 1.0, jac=lambda x: 2.0 * x)
    assert (stuck.ill_conditioned, stuck.converged, stuck.iterations) == (True, False, 0)
    assert (found.ill_conditioned, found.converged) == (False, True)
    for run in (stuck, found):
        assert run.singular is run.ill_conditioned


def test_a_batchs_singular_is_its_ill_conditioned():
    # rows 0 and 2 start where 2x = 0; row 1 converges to √2
    start = np.array([[0.0], [1.0], [0.0]])
    batch = newton_batch(lambda x: x**2 - 2.0, start, jac=lambda x: 2 * x[:, :, None])
    assert batch.ill_conditioned.tolist() == [True, False, True]
    assert batch.converged.tolist() == [False, True, False]
    assert batch.singular is batch.ill_conditioned


@pytest.mark.parametrize("kind", [NewtonResult, BatchNewtonResult])
def test_singular_is_a_read_only_older_name_not_a_field(kind):
    names = [field.name for field in dataclasses.fields(kind)]
    assert "ill_conditioned" in names and "singular" not in names
    assert isinstance(kind.singular, property) and kind.singular.fset is None
    if kind is NewtonResult:
        run = newton(lambda x: x**2 - 2.0, 0.0, jac=lambda x: 2.0 * x, on_failure="report")
    else:
        run = newton_batch(lambda x: x**2 - 2.0, np.zeros((1, 1)), jac=lambda x: 2 * x[:, :, None])
    assert isinstance(run, kind)
    with pytest.raises(dataclasses.FrozenInstanceError):
        run.singular = False
    assert np.all(run.ill_conditioned) and np.all(run.singular)


def test_a_linear_stacks_singular_is_its_ill_conditioned():
    from course_lib.newton import LinearStack
    J = np.array([[[2.0, 0.0], [0.0, 4.0]], [[1.0, 1.0], [2.0, 2.0]], [[1.0, 2.0], [3.0, 4.0]]])
    stack = LinearStack(J)
    assert stack.ill_conditioned.tolist() == [False, True, False]  # det 8, 0, −2
    assert stack.singular is stack.ill_conditioned
