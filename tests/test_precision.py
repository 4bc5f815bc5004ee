"""The precision rule every numeric checker keeps, tried as a student would type answers.

For each checker the right answer comes from an independent route (circle intersections, finite
differences, sympy, the course's closed forms typed here); then the same answer is given

* in full and rounded to the precision the checker states: ✔;
* rounded to one digit fewer: ✘ "right to … : give more digits", never a hint about the method;
* with one sign flipped, in another order, or (angles) in degrees: never ✔.
"""

from __future__ import annotations

import numpy as np
import pytest
from geometry import circle_intersections
from test_checks import (
    BENCH,
    MY_SAW,
    ROBOT,
    _fivebar_points,
    _rates_by_sympy,
    _saw_by_slider_crank,
    fourbar_by_circles,
)
from test_checks_ex06 import DECLARED, GUESS, L4, R2, D, by_hand, ram_by_differences

from course_lib import checks
from course_lib.fourbar import FourBar

TRIPLE = FourBar(0.14, 0.12, 0.10, 0.20)  # a triple-rocker: its largest crank angle is a toggle


def _crank_angle():
    theta4 = np.radians(135.0)
    B = np.array([BENCH.l1 + BENCH.l4 * np.cos(theta4), BENCH.l4 * np.sin(theta4)])
    roots = [np.arctan2(A[1], A[0]) for A in circle_intersections([0.0, 0.0], BENCH.l2, B, BENCH.l3)]
    return next(root for root in roots if 0 < root < np.pi), (BENCH, theta4)


def _saw_rates():
    theta2, omega2, h = np.pi / 2, 6.472, 1e-6
    ahead, behind = (np.array(_saw_by_slider_crank(theta2 + s * h)[:3]) for s in (1, -1))
    return (ahead - behind) / (2 * h) * omega2, (MY_SAW, theta2, omega2)


def _fivebar_forward():
    theta1, theta4 = np.radians(70.0), np.radians(125.0)
    P2, P4 = _fivebar_points(theta1, theta4)
    first, second = circle_intersections(P2, 0.15, P4, 0.16)
    return min(first, second, key=lambda p: p[1]), (ROBOT, theta1, theta4, -1)


def _fivebar_theta4():
    x3, y3 = -0.03, 0.2
    P5 = np.array([-ROBOT.l5 / 2, 0.0])
    right = circle_intersections(P5, ROBOT.l4, [x3, y3], ROBOT.l3)[1]  # σ2 = −1: elbow right of P5 → P3
    return np.arctan2(*(right - P5)[::-1]), (ROBOT, x3, y3, -1)


def _fivebar_inverse():
    x3, y3 = 0.02, 0.21
    P1, P5 = np.array([ROBOT.l5 / 2, 0.0]), np.array([-ROBOT.l5 / 2, 0.0])
    # working mode (−1, +1): elbow 2 right of P1 → P3, elbow 4 left of P5 → P3
    P2 = circle_intersections(P1, ROBOT.l1, [x3, y3], ROBOT.l2)[1]
    P4 = circle_intersections(P5, ROBOT.l4, [x3, y3], ROBOT.l3)[0]
    return (np.arctan2(*(P2 - P1)[::-1]), np.arctan2(*(P4 - P5)[::-1])), (ROBOT, x3, y3, (-1, +1))


def _point_velocity():
    tip = 0.080 * np.array([np.cos(np.radians(135.0)), np.sin(np.radians(135.0))])
    return -12.0 * np.array([-tip[1], tip[0]]), (0.080, 135.0, 12.0, True)


def _time_ratio(crank, distance):
    beta = np.arcsin(crank / distance)
    return (np.pi + 2 * beta) / (np.pi - 2 * beta)


def _ex06_position(position, theta2):
    """Task 2's check cell, the declaration and its guess right: the position to 4 decimals."""
    return checks.check_shaper_position((DECLARED, GUESS, position), theta2)


def _ex06_stroke(stroke_and_ratio):
    """Task 4's check cell, cutting right: stroke and time ratio to 3 significant figures."""
    return checks.check_ram_stroke((stroke_and_ratio, "left"))


FIGURES, DECIMALS = (4, False), (4, True)
# name: (checker, (reference, arguments), (digits, decimals), angles)
LINK = 0.06 * np.array([np.cos(np.pi / 6), np.sin(np.pi / 6)])
T8 = np.sqrt(6 * np.pi / 8.0)  # θ2(T) = A·T²/3 = 2π with A = 8 rad/s²; the final speed is 2·A·T/3
SHAPER_AT_60 = np.array(by_hand(np.radians(60.0)))
CASES = {
    "lesson 00 link vector": (checks.check_link_vector, (LINK, (0.06, 30.0)), FIGURES, False),
    "lesson 02 crank angle": (checks.check_crank_angle_for_rocker, _crank_angle(), DECIMALS, True),
    "lesson 03 / ex03 θ4": (checks.check_fourbar_theta4,
                            (fourbar_by_circles(BENCH, np.radians(120.0), "crossed")[1],
                             (BENCH, np.radians(120.0), "crossed")), DECIMALS, True),
    "lesson 04 speed of B": (checks.check_rocker_pin_speed,
                             (abs(_rates_by_sympy(BENCH, np.radians(120.0), 10.0, 0.0, "open")[0]) * BENCH.l4,
                              (BENCH, np.radians(120.0), 10.0)), FIGURES, False),
    "lesson 05 motor start": (checks.check_motor_start,
                              ((T8, 2 * 8.0 * T8 / 3 * 60 / (2 * np.pi)), (8.0,)), FIGURES, False),
    "lesson 06 saw rates": (checks.check_saw_rates, _saw_rates(), FIGURES, False),
    "lesson 09 five-bar θ4": (checks.check_fivebar_theta4, _fivebar_theta4(), DECIMALS, True),
    "lesson 10 reach height": (checks.check_reach_height,
                               (np.sqrt((ROBOT.l1 + ROBOT.l2) ** 2 - (0.03 + ROBOT.l5 / 2) ** 2),
                                (ROBOT, -0.03)), DECIMALS, False),
    "lesson 12 time ratio": (checks.check_quick_return_time_ratio, (_time_ratio(0.05, 0.08), (0.05, 0.08)),
                             (3, False), False),
    "ex01 point velocity": (checks.check_point_velocity, _point_velocity(), FIGURES, False),
    "ex03 rocker rates": (checks.check_fourbar_rates,
                          (_rates_by_sympy(BENCH, 3.5, 15.0, -40.0, "open")[:2],
                           (BENCH, 3.5, 15.0, -40.0, "open")), FIGURES, False),
    "ex03 toggle angle": (lambda v, linkage: checks.check_toggle_angle((v, "extended"), linkage),
                          (np.arccos((0.20**2 + 0.14**2 - 0.22**2) / (2 * 0.20 * 0.14)), (TRIPLE,)),
                          DECIMALS, True),
    "ex04 position": (checks.check_saw_position, (_saw_by_slider_crank(np.radians(50.0))[:3],
                                                  (MY_SAW, np.radians(50.0))), DECIMALS, (False, True, True)),
    "ex04 a_r": (checks.check_saw_slider_acceleration,
                 (_saw_by_slider_crank(np.radians(50.0), 6.0, 4.0)[3], (MY_SAW, np.radians(50.0), 6.0, 4.0)),
                 FIGURES, False),
    "lesson 08 / ex05 forward": (checks.check_fivebar_forward, _fivebar_forward(), (6, True), False),
    "ex05 inverse": (checks.check_fivebar_inverse, _fivebar_inverse(), DECIMALS, True),
    "ex06 position": (_ex06_position, (SHAPER_AT_60, (np.radians(60.0),)), DECIMALS,
                      (True, False, True, False)),
    "ex06 ram motion": (checks.check_ram_motion, (ram_by_differences(np.radians(60.0), 8.0),
                                                  (np.radians(60.0), 8.0)), FIGURES, False),
    "ex06 stroke and ratio": (_ex06_stroke, ((2 * L4 * R2 / D, _time_ratio(R2, D)), ()),
                              (3, False), False),
}


def rounded(values, digits: int, decimals: bool) -> np.ndarray:
    """``values`` as a student writes them to ``digits`` significant figures (or decimals)."""
    values = np.atleast_1d(np.asarray(values, float))
    if decimals:
        return np.round(values, digits)
    return np.array([float(f"{value:.{digits - 1}e}") for value in values])


def last_digit(reference, digits: int, decimals: bool) -> np.ndarray:
    """One unit of the last digit asked for, per entry of ``reference``."""
    if decimals:
        return np.full(np.shape(reference), 10.0**-digits)
    return 10.0 ** (np.floor(np.log10(np.abs(reference) + 1e-300)) - digits + 1)


def judge(checker, answer, arguments):
    answer = np.atleast_1d(np.asarray(answer, float))
    return checker(float(answer[0]) if answer.size == 1 else answer, *arguments)


@pytest.mark.parametrize("name", CASES)
def test_right_answers_pass_in_full_and_rounded_as_the_checker_states(name):
    checker, (reference, arguments), (digits, decimals), _ = CASES[name]
    assert judge(checker, reference, arguments).ok
    for kept in (digits, digits + 1, digits + 3):
        feedback = judge(checker, rounded(reference, kept, decimals), arguments)
        assert feedback.ok, (kept, feedback)
    kind = "decimals" if decimals else "significant figures"
    assert f"{digits} {kind}" in (checker.__doc__ or checks.check_toggle_angle.__doc__)


@pytest.mark.parametrize("name", CASES)
def test_answers_with_one_digit_fewer_are_asked_for_more_digits(name):
    checker, (reference, arguments), (digits, decimals), _ = CASES[name]
    short = rounded(reference, digits - 1, decimals)
    feedback = judge(checker, short, arguments)
    reference = np.atleast_1d(np.asarray(reference, float))
    unit = last_digit(reference, digits, decimals)
    if np.all(np.abs(short - reference) <= 0.5 * unit):
        assert feedback.ok, feedback  # the shorter rounding happens to be as close (it ends in a zero)
    elif np.all(np.abs(short - reference) <= 0.51 * unit):
        pass  # within the checker's 2 % slack for a reference on a rounding boundary: either verdict
    else:
        assert not feedback.ok and "give more digits" in feedback.message, feedback
        kind = "decimals" if decimals else "significant figures"
        assert f"right to {digits - 1} {kind}" in feedback.message, feedback


@pytest.mark.parametrize("name", CASES)
def test_slips_never_pass(name):
    checker, (reference, arguments), (digits, decimals), angles = CASES[name]
    reference = np.atleast_1d(np.asarray(reference, float))
    unit = last_digit(reference, digits, decimals)
    for k in np.flatnonzero(np.abs(reference) > 10 * np.broadcast_to(unit, reference.shape)):
        flipped = reference.copy()
        flipped[k] = -flipped[k]
        mask = np.broadcast_to(np.asarray(angles, bool), reference.shape)
        if mask[k] and abs(np.angle(np.exp(2j * reference[k]))) < 1e-3:
            continue  # an angle of 0 or π is its own negative modulo 2π
        feedback = judge(checker, flipped, arguments)
        assert not feedback.ok and "give more digits" not in feedback.message, (k, feedback)
    if reference.size > 1 and len(set(np.round(reference, 6))) == reference.size:
        feedback = judge(checker, reference[::-1], arguments)
        assert not feedback.ok, feedback
    mask = np.broadcast_to(np.asarray(angles, bool), reference.shape)
    if mask.any():
        degrees = np.where(mask, np.degrees(reference), reference)
        for written in (degrees, np.where(mask, np.round(degrees, 2), degrees)):
            feedback = judge(checker, written, arguments)
            assert not feedback.ok and "degrees" in feedback.message, feedback
