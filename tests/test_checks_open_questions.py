"""Every question a task asks is graded, and what follows a wrong answer reads as a sentence.

ex06 Task 4 asks for the crank angles where the ram stops and ex04 Task 2 whether r1 is negative and why: both
are graded now, each with its own feedback.  ex01 Task 4's feedback on a wrong letter answers what that letter
claims (its count, its joints), and the cell after ex01 Task 3 prints a sentence, never "nan", whatever the
student stored.  The references are independent: the stops by a root search of O4A · O2A = 0, r1 and θ1 from
the slider-crank by hand (tests/test_checks.py), the counts by 3(L − 1) − 2 J1 − J2 written out.
"""

from __future__ import annotations

import contextlib
import io
import math
import pathlib
import warnings

import nbformat
import numpy as np
import pytest
import scipy.optimize
from test_checks import _saw_by_slider_crank, rejects
from test_checks_ex06 import R2, D, sweep_ratio

from course_lib import checks
from course_lib.planar import polar

ROOT = pathlib.Path(__file__).resolve().parent.parent
STROKE_AND_RATIO = (2 * 0.30 * R2 / D, sweep_ratio(R2, D, 100_000))  # the chord of B's arc; a fine sweep


def _code(path: pathlib.Path) -> list[str]:
    return [cell.source for cell in nbformat.read(path, as_version=4).cells if cell.cell_type == "code"]


# ---------------------------------------------------------------- ex06 Task 4: the stops


def stops_by_root_search():
    """The crank angles in [0, 2π) where O4A ⟂ O2A (the lever, and so the ram, stops), by brentq."""
    def dot(theta2):  # O4A · O2A, O4 at the origin, O2 = (0, d), A = O2 + r2 (cos θ2, sin θ2)
        a = np.array([R2 * math.cos(theta2), D + R2 * math.sin(theta2)])
        return float(a @ (a - np.array([0.0, D])))

    quarters = ((math.pi, 1.5 * math.pi), (1.5 * math.pi, 2 * math.pi))  # one root in each
    return [scipy.optimize.brentq(dot, low, high, xtol=1e-14) for low, high in quarters]


def stroke(stops, cutting="left"):
    return checks.check_ram_stroke((STROKE_AND_RATIO, stops, cutting))


def test_the_notebook_grades_the_stops():
    for folder in ("solutions", "exercises"):
        sources = _code(ROOT / "notebooks" / folder / "ex06_your_own_mechanism.ipynb")
        assert "checks.check_ram_stroke((stroke_and_ratio, stops, cutting))" in sources, folder


def test_the_stops_pass_in_the_forms_a_student_writes():
    stops = stops_by_root_search()
    for answer in (stops, stops[::-1], np.array(stops) - 2 * np.pi, [round(s, 3) for s in stops],
                   tuple(np.float32(s) for s in stops)):
        feedback = stroke(answer)
        assert feedback.ok and "stops" in feedback.message, feedback


def test_stops_found_by_interpolating_a_sweep_of_a_few_hundred_angles_pass():
    """The task's route: ω4 changes sign between two samples; the lever's angle by hand, its rate by the chain
    rule of θ4 = atan2(d + r2 sin θ2, r2 cos θ2), its zero interpolated."""
    for count in (200, 361, 721):
        theta2 = np.linspace(0.0, 2 * np.pi, count)
        y, x = D + R2 * np.sin(theta2), R2 * np.cos(theta2)
        omega4 = (x * R2 * np.cos(theta2) + y * R2 * np.sin(theta2)) / (x**2 + y**2)  # dθ4/dθ2
        change = np.flatnonzero(np.diff(np.signbit(omega4)))
        step = theta2[change + 1] - theta2[change]
        stops = theta2[change] - omega4[change] * step / (omega4[change + 1] - omega4[change])
        assert stroke(stops).ok, count
        rejects(stroke(theta2[change]), "interpolate")  # the nearest samples alone are off by up to a step


@pytest.mark.parametrize(("answer", "says"), [
    (lambda s: np.degrees(s), "degrees"),
    (lambda s: (s[0] - math.pi, s[1] - math.pi), "sin θ2 = +r2/d"),  # the half turn: β and π − β
    (lambda s: (s[0], 1.0), "one stop is right"),
    (lambda s: (s[0], s[0]), "not the crank angles"),
    (lambda s: (0.1, 0.2), "not the crank angles"),
    (lambda s: None, "stops is still None"),
    (lambda s: s[0], "a single number"),
    (lambda s: (s[0], float("nan")), "NaN"),
    (lambda s: "3.55, 5.87", "string"),
])
def test_wrong_stops_are_named_and_never_a_tick(answer, says):
    stops = stops_by_root_search()
    rejects(stroke(answer(stops)), says, hidden=tuple(round(s, 3) for s in stops))


def test_the_stops_are_judged_after_the_numbers_and_before_the_cutting_direction():
    stops = stops_by_root_search()
    half = ((STROKE_AND_RATIO[0] / 2, STROKE_AND_RATIO[1]), stops, "left")
    rejects(checks.check_ram_stroke(half), "half the stroke")
    rejects(stroke(np.degrees(stops), "right"), "degrees")
    rejects(stroke(stops, "right"), "cutting is not")
    assert checks.check_ram_stroke((STROKE_AND_RATIO, "left")).ok  # without stops: the two others alone


# ---------------------------------------------------------------- ex04 Task 2: is r1 negative, and why?


def test_the_notebook_grades_the_sign_of_r1():
    for folder in ("solutions", "exercises"):
        sources = _code(ROOT / "notebooks" / folder / "ex04_power_saw.ipynb")
        assert "checks.check_saw_r1_sign(r1_sign)" in sources, folder


def test_the_right_statement_holds_for_the_saw_of_the_task():
    """(a): θ1 in (−π/2, π/2], the slider left of O2 (x < 0), so r1 < 0 — by the slider-crank by hand."""
    r1, theta1 = _saw_by_slider_crank(np.radians(50.0))[:2]
    assert -math.pi / 2 < theta1 <= math.pi / 2 and r1 * math.cos(theta1) < 0 and r1 < 0
    for answer in ("a", "A", " (a) "):
        assert checks.check_saw_r1_sign(answer).ok


@pytest.mark.parametrize(("letter", "says"), [("b", "θ1 + π"), ("c", "converged"), ("d", "seed"),
                                              ("e", "one letter"), (None, "No answer yet"),
                                              (1, "one letter")])
def test_each_wrong_statement_is_answered_for_what_it_claims(letter, says):
    rejects(checks.check_saw_r1_sign(letter), says)


# ---------------------------------------------------------------- ex01 Task 4: feedback on what was claimed


def test_a_wrong_letter_is_answered_for_what_it_claims_not_pointed_at_the_right_one():
    links_less_one = 3 * (4 - 1) - 2 * 6  # (a): the ground dropped, a link fewer
    as_half_joints = 3 * (5 - 1) - 2 * 4 - 1 * 2  # (d): C and D as half joints
    a, d = (checks.check_redundant_parallelogram(letter).message for letter in "ad")
    assert f"{links_less_one}".replace("-", "−") in a and f"M = 3·4 − 2·4 − 2 = {as_half_joints}" in d
    for message in (a, d):
        assert "assum" not in message and "geometry" not in message, message  # (b)'s words stay in (b)
    solution = nbformat.read(ROOT / "notebooks" / "solutions" / "ex01_vector_loops_and_mobility.ipynb",
                             as_version=4)
    hint = next(line for cell in solution.cells for line in cell.source.splitlines()
                if line.startswith("# HINT:") and "why_it_moves" in cell.source)
    assert "independent" not in hint and "recount" in hint, hint  # the hint does not hand over (b)


# ---------------------------------------------------------------- ex01 after Task 3: a sentence, never nan


def _velocity_cell() -> str:
    sources = _code(ROOT / "notebooks" / "exercises" / "ex01_vector_loops_and_mobility.ipynb")
    return next(source for source in sources if "angle between v_A and the crank" in source)


@pytest.mark.parametrize("velocity_A", [
    (0.0, 0.0), [0.96], (0.1, 0.2, 0.3), "abc", (float("nan"), 1.0), (1.0, float("inf")),
    12.0 * np.asarray(polar(0.080, np.radians(135.0))),  # along the crank: the cosine is ±1 to round-off
    -12.0 * np.asarray(polar(0.080, np.radians(135.0))), [[0.0], [0.0]], {"vx": 1.0},
])
def test_the_cell_after_task_3_prints_a_sentence_for_any_answer(velocity_A):
    printed = io.StringIO()
    namespace = {"np": np, "polar": polar, "velocity_A": velocity_A}
    with contextlib.redirect_stdout(printed), warnings.catch_warnings():
        warnings.simplefilter("error")
        exec(_velocity_cell(), namespace)
    text = printed.getvalue()
    assert text.strip() and "nan" not in text.lower() and "inf" not in text.lower(), text
    if np.ndim(velocity_A) == 1 and len(velocity_A) == 2 and np.all(np.isfinite(velocity_A)) \
            and np.any(velocity_A):
        assert "angle between v_A and the crank:" in text and "°" in text, text  # 0° or 180°: a number
    else:
        assert "not a velocity yet" in text, text
