"""Every call answers on any input: sizes are judged before any work.  A checker given a million numbers
or an expression of 10⁵ symbols answers with feedback at once; an animation asked for more pixels than it
can draw within seconds is refused by name (the verdicts come before the work, so no time is asserted)."""

import numpy as np
import pytest
import sympy as sp

from course_lib import checks
from course_lib.errors import InvalidArgumentError
from course_lib.fourbar import FourBar
from course_lib.plotting import animate


@pytest.mark.parametrize(("check", "answer", "says"), [
    (checks.check_newton_update, np.ones(10**6), "holds 1,000,000 numbers"),
    (checks.check_newton_update, [0.5] * 20_000, "holds 20,000 numbers"),
    (checks.check_omega4_expression, sp.Add(*sp.symbols("x0:100000")), "more than 5000 terms"),
    (checks.check_fivebar_g, sp.Add(*sp.symbols("y0:10000")), "more than 5000 terms"),
])
def test_a_huge_answer_gets_feedback_not_a_hang(check, answer, says):
    feedback = check(answer)
    assert not feedback.ok and says in feedback.message


@pytest.mark.parametrize(("options", "says"), [
    ({"dpi": 600}, "at 600 dpi is 45 million pixels"),
    ({"dpi": 300, "max_frames": 48}, "at 300 dpi is"),
    ({"max_frames": 100_000, "dpi": 120}, "frames of"),
])
def test_an_animation_too_large_to_draw_within_seconds_is_refused(options, says):
    linkage = FourBar(0.06, 0.18, 0.12, 0.20)
    sweep = linkage.solve(np.linspace(0.0, 6.0, 5000 if "max_frames" in options else 10))
    with pytest.raises(InvalidArgumentError, match=says):
        animate(linkage, sweep, **options)


@pytest.mark.parametrize("end", [1e-9, 0.0])
def test_newton_following_an_unknown_that_grows_without_bound_gives_up_by_name(end):
    # x = 1/s followed from s = 1 towards 0: x is found while a bounded number of steps reaches it, and the
    # last instant (x = 1e9, or none at all) is reported not reached instead of followed for ever
    from course_lib.errors import UnreachableError
    from course_lib.mechanism import Mechanism

    x, s = sp.symbols("x s")
    inverse = Mechanism([1 / x - s], [x], [s])
    sweep = np.linspace(1.0, end, 50)
    motion = inverse.solve({s: sweep}, guess={x: 1.0}, on_failure="nan")
    found = np.asarray(motion.converged)
    assert found[:-1].all() and not found[-1]
    assert np.allclose(motion.position["x"][:-1], 1 / sweep[:-1], rtol=1e-9)
    assert "no assembly" in motion.message
    with pytest.raises(UnreachableError, match=r"s=(1e-09|0\.0)\b"):
        inverse.solve({s: sweep}, guess={x: 1.0})
