"""Each entry of an answer counts its own digits: an answer with one entry written short (and right to its
digits) is told to give more digits, never sent to its method; an entry written in full but off still is.
References computed here: the motor's T = √(6π/A) and final speed (2/3)·A·T, a tip's velocity ω k̂ × R."""

import math

import numpy as np
import pytest

from course_lib import checks
from course_lib.checks.engine import FIGURES

MORE = "give more digits"


def motor(alpha_max):
    T = math.sqrt(6 * math.pi / alpha_max)
    return T, 2 / 3 * alpha_max * T * 60 / (2 * math.pi)  # s, rpm


@pytest.mark.parametrize(("answer", "says"), [
    ((1.535, 78.2), MORE),        # rpm to 3 figures, T in full
    ((1.54, 78.18), MORE),        # T to 3 figures, rpm in full
    ((1.535, 78.18), "Correct"),
])
def test_the_motor_start_counts_each_entrys_digits(answer, says):
    T, rpm = motor(8.0)
    assert (round(T, 3), round(rpm, 2)) == (1.535, 78.18)  # the answers above are these, rounded
    assert says in checks.check_motor_start(answer, alpha_max=8.0).message


def test_an_entry_written_in_full_but_off_is_not_a_rounding():
    feedback = checks.check_motor_start((1.536, 78.2), alpha_max=8.0)  # 1.536: four figures, and wrong
    assert not feedback.ok and MORE not in feedback.message


def test_a_velocity_with_one_component_short_is_told_to_give_more_digits():
    omega, angle = -12.0, math.radians(135.0)
    v = omega * 0.080 * np.array([-math.sin(angle), math.cos(angle)])  # ω k̂ × R
    full = tuple(float(f"{c:.4g}") for c in v)
    short = (full[0], float(f"{v[1]:.3g}"))
    assert checks.check_point_velocity(full, 0.080, 135.0, 12.0, clockwise=True).ok
    feedback = checks.check_point_velocity(short, 0.080, 135.0, 12.0, clockwise=True)
    assert not feedback.ok and MORE in feedback.message


@pytest.mark.parametrize(("answer", "says"), [
    ((78.18, 1.535), "the right numbers in another order"),
    ((1535.0, 78.18), "entry 1 is the right value in milli-units"),
])
def test_units_and_order_are_recognised_before_any_method_hint(answer, says):
    assert (round(motor(8.0)[0], 3), round(motor(8.0)[1], 2)) == (1.535, 78.18)
    feedback = checks.check_motor_start(answer, alpha_max=8.0)
    assert not feedback.ok and says in feedback.message


def test_a_velocity_in_mm_per_s_or_in_another_order_is_named():
    omega, angle = 12.0, math.radians(30.0)
    v = omega * 0.080 * np.array([-math.sin(angle), math.cos(angle)])  # ω k̂ × R, counter-clockwise
    swapped = checks.check_point_velocity((v[1], v[0]), 0.080, 30.0, 12.0, clockwise=False)
    in_mm = checks.check_point_velocity(tuple(1000 * v), 0.080, 30.0, 12.0, clockwise=False)
    assert "swapped" in swapped.message and "mm/s" in in_mm.message  # the checker's own words speak first


@pytest.mark.parametrize(("root", "says"), [
    (2.0946, "right to 4 decimals"), (2.09455, "right to 5 decimals"), (2.094551, "Correct"),
    (2.1, "does not satisfy"),
])
def test_newtons_root_to_fewer_decimals_is_told_to_give_more_digits(root, says):
    wallis = max(r.real for r in np.roots([1, 0, -2, -5]) if abs(r.imag) < 1e-12)  # x³ − 2x − 5 = 0
    assert round(wallis, 6) == 2.094551
    assert says in checks.check_newton_iterations((root, 4)).message


@pytest.mark.parametrize(("check", "answer", "cause"), [
    # a digit written wrong is not a rounding: 2.09456 has its fifth decimal wrong (the root is 2.0945514…)
    (lambda a: checks.check_newton_iterations(a), (2.09456, 4), "keep iterating"),
    (lambda a: checks.check_newton_iterations(a), (2.094552, 4), "how the last digit is rounded"),
    # lesson 00's link vector (0, 0.06) m: a third figure wrong, and a zero written as 0.0001
    (lambda a: checks.check_link_vector(a, 0.06, 90.0), (0.0, 0.0599), "cos θ and sin θ"),
    (lambda a: checks.check_link_vector(a, 0.06, 90.0), (0.0001, 0.06), "cos θ and sin θ"),
])
def test_a_digit_written_wrong_is_not_asked_for_more_digits(check, answer, cause):
    feedback = check(answer)
    assert not feedback.ok and "more digits" not in feedback.message and cause in feedback.message


def test_an_entry_written_short_must_be_right_to_every_digit_written():
    # 1.53 has three figures written, and the third is off (1.5354 → 1.54): not "right to 2, give more"
    assert FIGURES.more_digits((1.53, 78.2), (1.5354, 78.18)) is None
    assert "right to 3 significant figures" in FIGURES.more_digits((1.535, 78.2), (1.5354, 78.18)).message
