"""The singularity rule computed fast takes the same decisions: σ_min(J̃) < SINGULAR (and < NEAR_SINGULAR).

σ_min of a stack of 2×2 J̃ computed in place (``_smallest_two``) against the SVD, and to the bit against the
closed form written out here; the two decisions a sweep takes with the bound |det J̃| / ‖J̃‖_F
(``Mechanism._below``, σ_min computed only where the bound cannot settle them) against σ_min computed at
every instant: on stacks built with σ_min on and around each threshold, on random stacks (sizes over
hundreds of decades, zeros, NaN, inf), on random linkages at random angles and near their toggles, and on
sweeps through a toggle, where the masks a solve returns equal, instant by instant, the public
``is_singular`` and ``smallest_singular_value`` of its own positions.
"""

import numpy as np
import pytest

from course_lib.fourbar import FourBar
from course_lib.mechanism.singular import NEAR_SINGULAR, SINGULAR, _smallest_two

RNG = np.random.default_rng(32)
#: Random linkages: lengths spread over three decades, every Grashof class among them.
LINKAGES = [FourBar(*lengths) for lengths in np.exp(RNG.uniform(np.log(1e-3), 0.0, (30, 4)))]
#: Linkages that stop at a toggle (non-Grashof, or a Grashof rocker input): the sweeps below cross one.
TOGGLING = [FourBar(0.15, 0.10, 0.12, 0.20), FourBar(0.12, 0.06, 0.18, 0.20), FourBar(1.0, 0.9, 0.4, 0.45)]


def closed_form(J, rows, columns):
    """σ_min of each J̃ (J with row i divided by rows[i], then column j by columns[j]) by the formula
    |det J̃| / σ_max, σ_max² = (‖J̃‖²_F + √(‖J̃‖⁴_F − 4 det² J̃)) / 2, 0 where σ_max is 0 or not a number."""
    A = J / rows[:, None] / columns[None, :]
    with np.errstate(all="ignore"):
        frobenius = ((A[..., 0, 0] ** 2 + A[..., 0, 1] ** 2) + A[..., 1, 0] ** 2) + A[..., 1, 1] ** 2
        det = A[..., 0, 0] * A[..., 1, 1] - A[..., 0, 1] * A[..., 1, 0]
        largest = np.sqrt((frobenius + np.sqrt(np.maximum(frobenius**2 - 4 * det**2, 0.0))) / 2)
        return np.where(largest > 0, np.abs(det) / largest, 0.0)


def around_thresholds(rows, columns, count=4000):
    """J (count, 2, 2) whose J̃ has σ_min on and within a few parts in 1e15 of SINGULAR, NEAR_SINGULAR and
    2·NEAR_SINGULAR (the bound's own threshold), and spread from 1e-12 to 1, σ_max from 1e-3 to 1e3."""
    marks = np.array([SINGULAR, NEAR_SINGULAR, 2 * NEAR_SINGULAR])
    near = RNG.choice(marks, count // 2) * (1 + RNG.integers(-8, 9, count // 2) * 2.0**-52)
    spread = 10.0 ** RNG.uniform(-12, 0, count - count // 2)
    largest = 10.0 ** RNG.uniform(-3, 3, count)
    smallest = np.minimum(np.r_[near, spread] * largest, largest)

    def rotation(angle):
        return np.stack([np.stack([np.cos(angle), -np.sin(angle)], -1),
                         np.stack([np.sin(angle), np.cos(angle)], -1)], -2)

    U, V = rotation(RNG.uniform(-np.pi, np.pi, count)), rotation(RNG.uniform(-np.pi, np.pi, count))
    scaled = U @ (np.stack([largest, smallest], -1)[..., None] * np.swapaxes(V, -1, -2))
    return scaled * rows[:, None] * columns[None, :]


def wild(count=4000, decades=300):
    """J (count, 2, 2): entries over ±10^-decades … 10^decades, rows nearly or exactly dependent (σ_min
    from rounding noise up), zeros, NaN, inf."""
    J = RNG.standard_normal((count, 2, 2)) * 10.0 ** RNG.uniform(-decades, decades, (count, 1, 1))
    dependent = RNG.random(count) < 0.5
    J[dependent, 1] = J[dependent, 0] * RNG.uniform(-2, 2, (dependent.sum(), 1)) * (
        1 + RNG.choice([0.0, 1e-16, 1e-13, 1e-9, 1e-6, 1e-3, 2e-2], (dependent.sum(), 1)))
    J[RNG.random(count) < 0.05] = 0.0
    bad = RNG.random((count, 2, 2)) < 0.01
    J[bad] = RNG.choice([np.nan, np.inf, -np.inf], bad.sum())
    return J


def decisions(mechanism, J):
    """The fast rule's two masks at J (N, 2, 2)."""
    singular, near = np.empty(len(J), bool), np.empty(len(J), bool)
    mechanism._below(J, singular, near)
    return singular, near


def every_instant(mechanism, J):
    """The two masks with σ_min computed at every instant (the closed form written out here)."""
    smallest = closed_form(J, *mechanism._scales)
    return ~(smallest >= SINGULAR), ~(smallest >= NEAR_SINGULAR)


@pytest.mark.parametrize("stack", ["thresholds", "wild", "moderate"])
def test_sigma_min_of_a_two_by_two_stack_is_the_closed_form_to_the_bit_and_the_svds(stack):
    rows, columns = 10.0 ** RNG.uniform(-3, 3, 2), 10.0 ** RNG.uniform(-3, 3, 2)
    J = {"thresholds": lambda: around_thresholds(rows, columns), "wild": wild,
         "moderate": lambda: wild(decades=3)}[stack]()
    fast, written = _smallest_two(J, rows, columns), closed_form(J, rows, columns)
    assert fast.shape == written.shape and np.array_equal(fast, written, equal_nan=True)
    scaled = J / rows[:, None] / columns[None, :]
    size = np.abs(scaled).max(axis=(1, 2))  # the formula's fourth powers neither overflow nor underflow
    moderate = np.isfinite(scaled).all(axis=(1, 2)) & (size < 1e60) & (size > 1e-60)
    values = np.linalg.svd(scaled[moderate], compute_uv=False)
    assert (np.abs(fast[moderate] - values[:, 1]) <= 1e-13 * values[:, 0]).all()
    one = J[7]  # a single matrix: a number's shape
    assert _smallest_two(one, rows, columns).shape == () and _smallest_two(one, rows, columns) == fast[7]


@pytest.mark.parametrize("stack", ["thresholds", "wild", "moderate"])
def test_the_bound_settles_nothing_the_rule_would_decide_otherwise(stack):
    mechanism = LINKAGES[0].mechanism
    J = {"thresholds": lambda: around_thresholds(*mechanism._scales), "wild": wild,
         "moderate": lambda: wild(decades=3)}[stack]()
    fast, exact = decisions(mechanism, J), every_instant(mechanism, J)
    assert np.array_equal(fast[0], exact[0]) and np.array_equal(fast[1], exact[1])
    if stack == "thresholds":  # both sides of both thresholds met
        assert exact[0].any() and (~exact[0]).any() and (exact[1] & ~exact[0]).any() and (~exact[1]).any()


@pytest.mark.parametrize("index", range(len(LINKAGES)))
def test_random_linkages_at_random_angles_and_near_their_toggles_take_the_same_decisions(index):
    linkage = LINKAGES[index]
    toggles = np.array(linkage.input_range().toggle_angles + (0.0, np.pi))
    offsets = np.r_[0.0, np.geomspace(1e-15, 1e-2, 27), -np.geomspace(1e-15, 1e-2, 27)]
    theta2 = np.r_[RNG.uniform(-np.pi, np.pi, 400), (toggles[:, None] + offsets).ravel()]
    for assembly in ("open", "crossed"):
        motion = linkage.solve(theta2, assembly=assembly, on_failure="nan")
        q = np.stack([motion.theta3, motion.theta4], -1)
        found = np.isfinite(q).all(axis=1)
        J = linkage.mechanism.jacobian(q[found], theta2[found, None])
        fast, exact = decisions(linkage.mechanism, J), every_instant(linkage.mechanism, J)
        assert np.array_equal(fast[0], exact[0]) and np.array_equal(fast[1], exact[1])


@pytest.mark.parametrize("linkage", TOGGLING)
@pytest.mark.parametrize("route", ["machine", "core without assembly", "positions, masks read later"])
def test_a_sweep_through_a_toggle_returns_the_masks_of_the_public_rule_exactly(linkage, route):
    toggle = max(linkage.input_range().toggle_angles)
    theta2 = np.unique(np.r_[np.linspace(toggle - 0.05, toggle + 0.01, 40_001),
                             toggle + np.linspace(-1e-9, 1e-9, 2001), toggle])
    if route == "machine":
        motion = linkage.solve(theta2, 10.0, 5.0, on_failure="nan")
    elif route == "core without assembly":
        motion = linkage.mechanism.solve({"theta2": theta2}, {"theta2": 10.0}, {"theta2": 5.0},
                                         on_failure="nan")
    else:
        motion = linkage.solve(theta2, on_failure="nan")
    q = np.stack([motion.position["theta3"], motion.position["theta4"]], -1)
    found = np.asarray(motion.converged)
    safe = np.where(found[:, None], q, 0.0)
    u = theta2[:, None]
    singular = found & linkage.mechanism.is_singular(safe, u)
    near = found & ~(linkage.mechanism.smallest_singular_value(safe, u) >= NEAR_SINGULAR)
    assert np.array_equal(motion.singular, singular)
    assert np.array_equal(motion.near_singular, near)
    assert singular.any() and (near & ~singular).any() and (found & ~near).any() and (~found).any()
    if route != "positions, masks read later":  # rates NaN exactly where the rule says singular
        for name in ("theta3", "theta4"):
            assert np.array_equal(np.isnan(motion.velocity[name]), ~found | singular)
