"""The Stephenson III six-bar of benchmarks/bench_sixbar.py (two closed-form blocks the core derives) on the
core's row-by-row paths.

The rule's two decisions for n > 2 settled by the bound |det J̃| / ‖J̃‖_F^(n−1) (``Mechanism._below``) equal
those of σ_min computed at every instant (``Mechanism._smallest``, the rule as written) on stacks built with
σ_min around each threshold and on wild stacks (zeros, NaN, inf, sizes over hundreds of decades).  The
rates by rows equal, to the bit, those of the general block-by-block solve (the row path switched off), at
signed zeros and singular instants too, and agree with the hand closed form of the benchmark (an independent
route).  A cos or sin kept by its argument's bits is the one of that argument (−0.0 and 0.0 differ in sin),
and the gap between positions is the largest scaled difference, angles modulo a turn, as computed here with
``math`` one value at a time.
"""

import math
import sys
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

from course_lib.mechanism import Mechanism
from course_lib.mechanism.compiled import _recalled
from course_lib.mechanism.singular import NEAR_SINGULAR, SINGULAR

sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))

import bench_sixbar as bench  # noqa: E402

NAMES = ("theta3", "theta4", "theta5", "theta6")
RNG = np.random.default_rng(33)


@pytest.fixture(scope="module")
def sixbar():
    return bench.stephenson()


@pytest.fixture(scope="module")
def toggling():
    """The same six-bar on a four-bar whose crank stops at two toggles (not Grashof)."""
    th2, th3, th4, th5, th6 = sp.symbols("theta2:7")

    def R(length, angle):
        return sp.Matrix([length * sp.cos(angle), length * sp.sin(angle)])

    loops = [R(0.12, th2) + R(0.10, th3) - R(0.15, th4) - sp.Matrix([0.2, 0]),
             R(0.12, th2) + R(0.1, th3 + 0.4) + R(0.2, th5) - sp.Matrix([0.05, 0.22]) - R(0.15, th6)]
    return Mechanism(loops, [th3, th4, th5, th6], [th2], {})


def structured(sixbar, count):
    """Random J (count, 4, 4) with the six-bar's block structure (no coupling of a block to the unknowns of
    a later one), the second block nearly singular by a gap spread from 1e-14 to 10."""
    blocks = sixbar._structure["blocks"]
    J = RNG.normal(size=(count, 4, 4))
    (first_rows, _), (_, second_columns) = blocks
    J[np.ix_(np.arange(count), first_rows, second_columns)] = 0.0
    rows, columns = blocks[1]
    gap = 10.0 ** RNG.uniform(-14, 1, count)
    base = RNG.normal(size=(count, 2))
    J[:, rows[0], columns[0]], J[:, rows[0], columns[1]] = base[:, 0], base[:, 1]
    J[:, rows[1], columns[0]], J[:, rows[1], columns[1]] = base[:, 0], base[:, 1] * (1 + gap)
    return J * np.outer(*sixbar._scales)  # J̃ of order 1, J in the declaration's sizes


def decisions_by_sigma(sixbar, J):
    smallest = sixbar._smallest(J)
    return ~(smallest >= SINGULAR), ~(smallest >= NEAR_SINGULAR)


def test_the_bound_settles_the_rule_as_sigma_min_does(sixbar):
    J = structured(sixbar, 20_000)
    singular, near = np.empty(len(J), bool), np.empty(len(J), bool)
    sixbar._below(J, singular, near)
    expected = decisions_by_sigma(sixbar, J)
    assert np.array_equal(singular, expected[0]) and np.array_equal(near, expected[1])
    assert 0 < near.sum() < len(J) and 0 < singular.sum()  # both thresholds crossed in the stack


def test_the_bound_settles_the_rule_on_wild_stacks(sixbar):
    J = structured(sixbar, 6000)
    J *= 10.0 ** RNG.uniform(-150, 150, (len(J), 1, 1))
    picks = RNG.integers(0, len(J), 300)
    J[picks[:100], 0, 0] = np.nan
    J[picks[100:200], 1, 1] = np.inf
    J[picks[200:], 2] = 0.0
    singular, near = np.empty(len(J), bool), np.empty(len(J), bool)
    with np.errstate(all="ignore"):
        sixbar._below(J, singular, near)
        expected = decisions_by_sigma(sixbar, J)
    assert np.array_equal(singular, expected[0]) and np.array_equal(near, expected[1])
    assert singular[picks[:200]].all()


def solved(mechanism, monkeypatch, by_rows, *args, **kwargs):
    if not by_rows:
        monkeypatch.setattr(Mechanism, "_rates_by_rows", lambda self, *a, **k: None)
    try:
        return mechanism.solve(*args, **kwargs)
    finally:
        monkeypatch.undo()


def same_bits(a, b):
    a, b = np.asarray(a, float), np.asarray(b, float)
    return a.shape == b.shape and np.array_equal(a.view(np.int64), b.view(np.int64))


@pytest.mark.parametrize("case", ["turn", "at rest", "toggle"])
def test_rates_by_rows_are_those_of_the_block_solve_to_the_bit(sixbar, toggling, monkeypatch, case):
    theta2 = np.linspace(0.0, 2 * np.pi, 3001)
    if case == "turn":
        mechanism, args = sixbar, ({"theta2": theta2}, {"theta2": 10 + np.sin(theta2)}, {"theta2": 3.0})
        kwargs = {"guess": bench.GUESS}
    elif case == "at rest":  # q̇ = 0: the signed zeros of the sums
        mechanism, args = sixbar, ({"theta2": theta2}, {"theta2": 0.0}, {"theta2": -2.0})
        kwargs = {"assembly": {"theta3": -1, "theta5": 1}}
    else:  # through the toggles: singular instants, NaN rates
        mechanism, args = toggling, ({"theta2": np.linspace(-np.pi, np.pi, 4001)}, {"theta2": 1.0},
                                     {"theta2": 0.5})
        kwargs = {}
    fast = solved(mechanism, monkeypatch, True, *args, on_failure="nan", **kwargs)
    slow = solved(mechanism, monkeypatch, False, *args, on_failure="nan", **kwargs)
    for name in NAMES:
        assert same_bits(fast.velocity[name], slow.velocity[name])
        assert same_bits(fast.acceleration[name], slow.acceleration[name])
    assert np.array_equal(fast.singular, slow.singular) and fast.message == slow.message
    if case == "toggle":  # instants beyond the toggles: not found, no rates
        assert np.isnan(fast.velocity["theta3"]).any() and not fast.converged.all()
    if case == "at rest":
        assert (fast.velocity["theta4"] == 0).all()


def test_rates_by_rows_where_told_singular_are_those_of_the_block_solve(sixbar, monkeypatch):
    theta2 = np.linspace(0.0, 2 * np.pi, 1001)
    motion = sixbar.solve({"theta2": theta2}, guess=bench.GUESS)
    q, u = np.stack([motion.position[n] for n in NAMES], axis=-1), theta2[:, None]
    singular = RNG.random(len(theta2)) < 0.2
    arguments = (q, u, np.full_like(u, 4.0), np.full_like(u, -1.0))
    fast = sixbar.unknown_rates(*arguments, singular=singular)
    monkeypatch.setattr(Mechanism, "_rates_by_rows", lambda self, *a, **k: None)
    slow = sixbar.unknown_rates(*arguments, singular=singular)
    assert same_bits(fast[0], slow[0]) and same_bits(fast[1], slow[1])
    assert np.isnan(fast[0][singular]).all() and np.isfinite(fast[0][~singular]).all()


def test_rates_agree_with_the_hand_closed_form(sixbar):
    theta2 = np.linspace(0.0, 2 * np.pi, 2001)
    omega2 = 10 + np.sin(theta2)
    motion = sixbar.solve({"theta2": theta2}, {"theta2": omega2}, {"theta2": 3.0}, guess=bench.GUESS)
    position, velocity, acceleration = bench.by_hand(theta2, omega2, 3.0)
    for k, name in enumerate(NAMES):
        turns = (motion.position[name] - position[k]) / (2 * np.pi)
        assert np.abs(turns - np.round(turns)).max() < 1e-11
        assert np.abs(motion.velocity[name] - velocity[k]).max() < 1e-9 * np.abs(velocity[k]).max()
        largest = np.abs(acceleration[k]).max()
        assert np.abs(motion.acceleration[name] - acceleration[k]).max() < 1e-9 * largest


def test_a_kept_cos_or_sin_is_the_one_of_its_argument():
    memo, values = {}, np.array([0.0, 1.0, 2.5])
    first = _recalled(memo, "x", np.sin, values)
    assert _recalled(memo, "x", np.sin, values.copy()) is first  # the same bits: taken from the memo
    signed = np.array([-0.0, 1.0, 2.5])  # equal to values, other bits: computed again
    again = _recalled(memo, "x", np.sin, signed)
    assert math.copysign(1.0, again[0]) == -1.0 and math.copysign(1.0, first[0]) == 1.0
    assert np.array_equal(_recalled(memo, "x", np.sin, values + 1.0), [math.sin(v + 1.0) for v in values])


def test_the_gap_between_positions_is_the_largest_scaled_difference(sixbar):
    a, b = RNG.uniform(-20, 20, (500, 4)), RNG.uniform(-20, 20, (500, 4))
    a[7, 2] = np.nan
    scale = sixbar._scales[1]
    expected = []
    for p, r in zip(a, b, strict=True):
        gaps = []
        for j in range(4):  # every unknown an angle: the difference taken to within π
            d = p[j] - r[j]
            if math.isnan(d):
                gaps.append(math.nan)
                continue
            gaps.append(abs(d - 2 * math.pi * round(d / (2 * math.pi))) * scale[j])
        expected.append(math.nan if any(math.isnan(g) for g in gaps) else max(gaps))
    got = sixbar._distance(a, b)
    assert np.allclose(got, expected, rtol=1e-14, atol=0, equal_nan=True)
    assert sixbar._distance(a[0], b[0]) == pytest.approx(expected[0], rel=1e-14)
