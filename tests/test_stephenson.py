"""The Stephenson II six-bar of benchmarks/bench_stephenson.py: the core solves it on Newton's route (no
block reduces to a closed form) and agrees with the hand closed form written there with numpy alone.

Independent routes: the loops evaluated here from the points (O2, A, B, C, D, E, O6) written out again,
central differences of the hand positions, and single instants solved alone from a guess near the same
assembly.
"""

import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).parents[1] / "benchmarks"))

import bench_stephenson as bench  # noqa: E402

NAMES = ("theta3", "theta4", "theta5", "theta6")
OMEGA2, ALPHA2 = 10.0, 5.0
COUNT = 720  # above the batched route's threshold of 64 instants


@pytest.fixture(scope="module")
def mechanism():
    return bench.stephenson_ii()


@pytest.fixture(scope="module")
def theta2():
    return np.linspace(0.0, 2 * np.pi, COUNT)


@pytest.fixture(scope="module")
def hand(theta2):
    return bench.by_hand(theta2, OMEGA2, ALPHA2)


@pytest.fixture(scope="module")
def motion(mechanism, theta2):
    return mechanism.solve({"theta2": theta2}, {"theta2": OMEGA2}, {"theta2": ALPHA2}, guess=bench.GUESS)


def wrapped(angle):
    return np.angle(np.exp(1j * np.asarray(angle)))


def e(angle):
    return np.array([np.cos(angle), np.sin(angle)])


def loop_residuals(theta2, q):
    """Both vector loops from the points, largest component: D reached through C and through B, E
    through C and through O6."""
    theta3, theta4, theta5, theta6 = q
    A, B = bench.L2 * e(theta2), bench.B2 * e(theta2 + bench.BETA)
    C = A + bench.L3 * e(theta3)
    through_b = B + bench.L4 * e(theta4)
    through_o6 = np.array([[bench.GX], [bench.GY]]) + bench.L6 * e(theta6)
    return max(np.abs(C + bench.P * e(theta5) - through_b).max(),
               np.abs(C + bench.Q * e(theta5 + bench.DELTA) - through_o6).max())


def test_no_block_has_a_closed_form(mechanism):
    assert mechanism.closed_forms == [None]


def test_the_hand_and_the_core_positions_close_both_loops(theta2, hand, motion):
    assert loop_residuals(theta2, hand[0]) < 1e-12
    assert loop_residuals(theta2, np.stack([motion.position[name] for name in NAMES])) < 1e-12


def test_the_hand_bracket_holds_one_root_at_every_sampled_crank_angle():
    # the window the hand solution brackets θ5 in holds one sign change of f, on a fine scan
    theta5 = np.linspace(*bench.WINDOW, 2001)
    for angle in np.linspace(0.0, 2 * np.pi, 25):
        A, B = bench.L2 * e(angle), bench.B2 * e(angle + bench.BETA)
        f = bench._closure(theta5, A[0], A[1], B[0], B[1])[3]
        assert np.isfinite(f).all()
        assert np.count_nonzero(np.diff(np.sign(f))) == 1


def test_the_crank_turns_fully_on_one_assembly_far_from_singular(motion, hand):
    assert motion.converged.all() and not motion.near_singular.any() and motion.message == ""
    # C never changes side of the line the hand solution measures it from: the couplers never line up
    assert np.abs(np.sin(hand[0][0] - hand[0][1])).min() > 0.5
    # one assembly all the way round: the positions a turn later are those at the start, to within a turn
    for name in NAMES:
        assert abs(wrapped(motion.position[name][-1] - motion.position[name][0])) < 1e-9


def test_core_positions_and_rates_match_the_hand_closed_form(motion, hand):
    for k, name in enumerate(NAMES):
        assert np.abs(wrapped(motion.position[name] - hand[0][k])).max() < 1e-9
        assert np.abs(motion.velocity[name] - hand[1][k]).max() < 1e-9
        size = max(1.0, np.abs(hand[2][k]).max())  # rad/s², up to a few tens here
        assert np.abs(motion.acceleration[name] - hand[2][k]).max() < 1e-9 * size


def test_hand_rates_match_central_differences(theta2, hand):
    sample = theta2[::37]
    h = 1e-5
    ahead, behind = np.stack(bench.positions(sample + h)), np.stack(bench.positions(sample - h))
    slope = wrapped(ahead - behind) / (2 * h)
    assert np.abs(slope * OMEGA2 - hand[1][:, ::37]).max() < 1e-7
    faster, slower = bench.by_hand(sample + h, OMEGA2, ALPHA2), bench.by_hand(sample - h, OMEGA2, ALPHA2)
    acceleration = (faster[1] - slower[1]) / (2 * h) * OMEGA2 + slope * ALPHA2
    assert np.abs(acceleration - hand[2][:, ::37]).max() < 1e-6 * max(1.0, np.abs(hand[2]).max())


def test_the_sweep_agrees_with_each_instant_solved_alone(mechanism, theta2, motion, hand):
    # each instant alone, by Newton from the hand solution rounded to 0.05 rad (near the same assembly)
    for k in range(0, COUNT, 45):
        guess = {name: round(float(hand[0][j][k]) * 20) / 20 for j, name in enumerate(NAMES)}
        alone = mechanism.solve({"theta2": theta2[k]}, {"theta2": OMEGA2}, {"theta2": ALPHA2}, guess=guess)
        for name in NAMES:
            assert abs(wrapped(alone.position[name] - motion.position[name][k])) < 1e-10
            assert abs(alone.velocity[name] - motion.velocity[name][k]) < 1e-9


def test_the_sweep_runs_on_newtons_batched_route(mechanism, theta2, monkeypatch):
    # the sweep is solved by the batched route (path followed, then all instants at once), not instant by
    # instant: its Newton runs on arrays of instants
    from course_lib.mechanism import continuation

    calls = []
    batched = continuation.Continuation._batched

    def spy(self, *args, **kwargs):
        calls.append(batched(self, *args, **kwargs))
        return calls[-1]

    monkeypatch.setattr(continuation.Continuation, "_batched", spy)
    mechanism.solve({"theta2": theta2}, guess=bench.GUESS)
    assert calls == [True]


def test_the_benchmark_reports_agreement_on_a_short_sweep(capsys):
    result = bench.main(2000, 1)
    assert result["max_position_diff_rad"] < 1e-9 and result["max_velocity_diff_rad_s"] < 1e-9
    assert result["max_velocity_vs_differences"] < 1e-6
    assert "ratio" in capsys.readouterr().out
