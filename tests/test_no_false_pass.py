"""No false ✔: every form of a position that a checker accepts satisfies all of the task's loop equations.

Each checker is offered the reference position turned every way a student might write it — each angle plus
0, ±π or 2π, each length with either sign — and every answer it accepts is put back into the loops,
typed here from the course's equations (not taken from the checkers).
"""

from __future__ import annotations

import itertools

import numpy as np
from test_checks import MY_SAW, ROBOT, _saw_by_slider_crank
from test_checks_ex06 import DECLARED, GUESS, L4, L5, R2, D, H, by_hand

from course_lib import checks

TURNS = (0.0, np.pi, -np.pi, 2 * np.pi)


def variants(position, angles):
    """The position with each angle turned by 0, ±π or 2π and each length of either sign."""
    choices = [[value + turn for turn in TURNS] if angle else [value, -value]
               for value, angle in zip(position, angles, strict=True)]
    return [np.array(choice) for choice in itertools.product(*choices)]


def accepted(checker, position, angles, *arguments):
    found = [answer for answer in variants(position, angles) if checker(answer, *arguments).ok]
    assert found, "the reference itself must pass"
    return found


def test_every_shaper_position_accepted_closes_both_loops():
    theta2 = np.radians(60.0)
    def check(position, theta2):  # Task 2's check cell: the declaration, its guess and the position
        return checks.check_shaper_position((DECLARED, GUESS, position), theta2)

    answers = accepted(check, by_hand(theta2), (1, 0, 1, 0), theta2)
    for theta4, r4, theta5, x in answers:
        block = [r4 * np.cos(theta4) - R2 * np.cos(theta2), r4 * np.sin(theta4) - D - R2 * np.sin(theta2)]
        ram = [L4 * np.cos(theta4) + L5 * np.cos(theta5) - x, L4 * np.sin(theta4) + L5 * np.sin(theta5) - H]
        assert np.abs([*block, *ram]).max() < 1e-12, (theta4, r4, theta5, x)


def test_every_saw_position_accepted_closes_the_saw_equations():
    theta2 = np.radians(50.0)
    reference = _saw_by_slider_crank(theta2)[:3]
    for r1, theta1, theta3 in accepted(checks.check_saw_position, reference, (0, 1, 1), MY_SAW, theta2):
        Fx = -r1 * np.cos(theta1) + MY_SAW.r2 * np.cos(theta2) + MY_SAW.r3 * np.cos(theta3)
        Fy = r1 * np.sin(theta1) - MY_SAW.r2 * np.sin(theta2) - MY_SAW.r3 * np.sin(theta3)
        Fc = r1 * np.sin(theta1) - MY_SAW.r1y
        assert np.abs([Fx, Fy, Fc]).max() < 1e-12, (r1, theta1, theta3)


def test_every_fivebar_answer_accepted_closes_both_legs():
    l1, l2, l3, l4, l5 = ROBOT.l1, ROBOT.l2, ROBOT.l3, ROBOT.l4, ROBOT.l5

    def legs(theta1, theta4, x3, y3):  # EcL2 and EcL3 of the course
        return [(x3 - l1 * np.cos(theta1) - l5 / 2) ** 2 + (y3 - l1 * np.sin(theta1)) ** 2 - l2**2,
                (x3 - l4 * np.cos(theta4) + l5 / 2) ** 2 + (y3 - l4 * np.sin(theta4)) ** 2 - l3**2]

    theta1, theta4 = np.radians(70.0), np.radians(125.0)
    point = np.array(tuple(ROBOT.forward(theta1, theta4, mode=-1)))
    for x3, y3 in accepted(checks.check_fivebar_forward, point, (0, 0), ROBOT, theta1, theta4, -1):
        assert np.abs(legs(theta1, theta4, x3, y3)).max() < 1e-12 and y3 == point[1]
    x3, y3 = 0.02, 0.21
    cranks = np.array(tuple(ROBOT.inverse(x3, y3, modes=(-1, 1))))
    for angles in accepted(checks.check_fivebar_inverse, cranks, (1, 1), ROBOT, x3, y3, (-1, 1)):
        assert np.abs(legs(*angles, x3, y3)).max() < 1e-12
