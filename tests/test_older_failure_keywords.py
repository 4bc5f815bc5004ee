"""The one failure keyword ``on_failure=`` and its older spellings ``on_unreachable=``, ``on_singular=``:
read as ``on_failure=`` with a ``DeprecationWarning`` until the version CHANGELOG names, by one shim
(``errors.older_failure_keywords``).  The only place besides the shim where those spellings appear."""

import math
import pathlib
import re

import numpy as np
import pytest

from course_lib import errors, saw
from course_lib.errors import InvalidGeometryError, UnreachableError
from course_lib.fivebar import FiveBar
from course_lib.fourbar import FourBar

ROOT = pathlib.Path(__file__).parents[1]
OLDER = errors.OLDER_FAILURE_KEYWORDS
ROBOT = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
SHORT_ROD = saw.Saw(r1y=0.045, r2=0.075, r3=0.1)  # cannot reach the line when the crank points down
DESK = FourBar(0.20, 0.06, 0.18, 0.12)


def test_the_older_spellings_warn_give_the_same_result_and_go_in_the_named_version():
    assert errors.failure_policy() == "raise" and errors.failure_policy("nan") == "nan"
    with pytest.raises(InvalidGeometryError, match=r"on_failure must be one of 'raise', 'nan'; got 'skip'"):
        errors.failure_policy("skip")
    pen = ROBOT.forward(1.2, 1.9)
    calls = {"on_unreachable": lambda **kw: ROBOT.inverse(0.0, 0.5, **kw).theta1,  # out of reach: NaN
             "on_singular": lambda **kw: ROBOT.velocity_jacobian(1.2, 1.9, pen.x3, pen.y3, **kw)}
    assert set(calls) == set(OLDER)
    for older, call in calls.items():
        expected = rf"{older}= is the older spelling of on_failure= and goes in course_lib 2\.0\.0"
        with pytest.warns(DeprecationWarning, match=expected):
            np.testing.assert_array_equal(call(**{older: "nan"}), call(on_failure="nan"))
        with pytest.warns(DeprecationWarning), pytest.raises(
                errors.InvalidArgumentError, match=rf"on_failure='nan', {older}='raise'"):
            call(on_failure="nan", **{older: "raise"})
        with pytest.warns(DeprecationWarning), pytest.raises(InvalidGeometryError,
                                                             match=rf"{older} must be one of 'raise', 'nan'"):
            call(**{older: "skip"})
    changelog = (ROOT / "CHANGELOG.md").read_text()
    assert "on_unreachable" in changelog and errors.OLDER_FAILURE_REMOVED_IN in changelog


@pytest.mark.parametrize("call, older", [
    (lambda **kw: ROBOT.inverse(0.0, 0.2, **kw), "on_unreachable"),
    (lambda **kw: ROBOT.crank_rates(1.2, 1.9, *ROBOT.forward(1.2, 1.9), 0.0, 0.0, **kw), "on_singular"),
    (lambda **kw: DESK.solve(0.1, **kw), "on_unreachable"),
    (lambda **kw: saw.analytic(0.0, **kw), "on_unreachable"),
])
def test_a_bad_value_of_an_older_spelling_is_named(call, older):
    with pytest.warns(DeprecationWarning), pytest.raises(InvalidGeometryError, match=older):
        call(**{older: "ignore"})


def test_the_four_bar_reads_the_older_spelling_on_every_method():
    triple = FourBar(0.15, 0.10, 0.12, 0.20)
    # the loop closes where |A O4| lies between |l3 − l4| and l3 + l4 (the triangle A, B, O4)
    reach = [abs(0.10 - 0.12) <= math.hypot(0.15 * math.cos(t) - 0.20, 0.15 * math.sin(t)) <= 0.10 + 0.12
             for t in (0.0, 2.0)]
    with pytest.warns(DeprecationWarning):
        old = triple.solve([0.0, 2.0], on_unreachable="nan")
    assert old.mask.tolist() == [not r for r in reach] == [False, True]
    calls = {"joints": lambda **kw: triple.joints(2.0, **kw)[2],  # B
             "transmission_angle": lambda **kw: triple.transmission_angle(2.0, **kw),
             "coupler_point": lambda **kw: triple.coupler_point(2.0, 0.1, 0.0, **kw).position}
    for name, call in calls.items():
        with pytest.raises(UnreachableError):
            call()
        with pytest.warns(DeprecationWarning):
            assert np.isnan(call(on_unreachable="nan")).all(), name
    with pytest.warns(DeprecationWarning), pytest.raises(InvalidGeometryError,
                                                         match=r"on_failure='nan', on_unreachable='raise'"):
        triple.solve(2.0, on_unreachable="raise", on_failure="nan")


def test_the_five_bar_and_the_saw_read_the_older_spellings():
    theta1, theta4 = 1.2, 1.9
    pen = ROBOT.forward(theta1, theta4)
    at = (theta1, theta4, pen.x3, pen.y3)
    with pytest.warns(DeprecationWarning):
        np.testing.assert_array_equal(ROBOT.velocity_jacobian(*at, on_singular="nan"),
                                      ROBOT.velocity_jacobian(*at, on_failure="nan"))
    with pytest.warns(DeprecationWarning):
        old = saw.analytic([0.0, -np.pi / 2], saw=SHORT_ROD, on_unreachable="nan")
    np.testing.assert_array_equal(old, saw.analytic([0.0, -np.pi / 2], saw=SHORT_ROD, on_failure="nan"))
    assert np.isnan(old[1]).all() and np.isfinite(old[0]).all()


def test_no_older_spelling_outside_the_shim_this_test_and_the_texts_that_announce_its_removal():
    announced = {"CHANGELOG.md", "README.md", "docs/glossary.md", "course_lib/errors.py",
                 "tests/test_older_failure_keywords.py", "tests/test_lesson_vocabulary.py"}
    pattern = re.compile("|".join(OLDER))
    found = set()
    for folder in ("course_lib", "tests", "benchmarks", "tools", "notebooks", "docs"):
        for path in (ROOT / folder).rglob("*"):
            if path.suffix in {".py", ".ipynb", ".md"} and pattern.search(path.read_text(errors="ignore")):
                found.add(path.relative_to(ROOT).as_posix())
    for name in ("README.md", "CHANGELOG.md"):
        if pattern.search((ROOT / name).read_text()):
            found.add(name)
    assert found <= announced, sorted(found - announced)
