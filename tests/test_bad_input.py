"""Every bad input a student can type gets a named course_lib error that names the argument and
shows its value (library), a Feedback (checkers, see test_checks_bad_input.py for the full table)
or a readable status (explorers).

The table is built from a few lists of bad values per kind of argument (a length, an angle or an
array of them, a choice among names, a tolerance, a count) crossed with every public function
that takes such an argument.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from course_lib import checks, mobility, planar, profile, saw
from course_lib.errors import CourseLibError
from course_lib.fivebar import FiveBar
from course_lib.fourbar import FourBar
from course_lib.newton import newton, newton_batch
from course_lib.slider_crank import OffsetSliderCrank
from course_lib.widgets import fivebar_explorer, fourbar_explorer, saw_explorer

DESK = FourBar(0.06, 0.18, 0.12, 0.20)
ROBOT = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
SAW_TEXTBOOK = OffsetSliderCrank(0.075, 0.170, 0.045)
# an assembled pose of the robot, and the methods that take one
POSE = dict(zip(("theta1", "theta4", "x3", "y3"), (1.2, 1.9, *ROBOT.forward(1.2, 1.9)), strict=True))
FIVEBAR_POSE_METHODS = ("singularity_measures", "jacobian_end_effector", "jacobian_cranks", "constraints")

# ---------------------------------------------------------------- bad values, by kind
NOT_A_NUMBER = ["0.06", True, False, None, 1j, "abc", b"1", {"l": 1}, {1.0}, [0.1, "x"], [[0.1], [0.2, 0.3]]]
NOT_A_LENGTH = NOT_A_NUMBER + [-1.0, 0.0, math.nan, math.inf, -math.inf, [0.1, 0.2]]
NOT_AN_ANGLE = NOT_A_NUMBER + [math.nan, math.inf, -math.inf, [0.1, math.nan], np.array([1.0, np.inf])]
NOT_A_CHOICE = ["Sideways", None, 2, True, 1.5, ["open"]]


def shown(value) -> list[str]:
    """Texts of which one must appear in the message: the value itself, or its first bad entry."""
    texts = [repr(value), str(value)]
    try:
        array = np.asarray(value, dtype=float).ravel()
        texts += [str(entry) for entry in array if not np.isfinite(entry)]
    except (TypeError, ValueError):
        pass
    return texts


def refuses(call, name: str, value) -> None:
    with pytest.raises(CourseLibError) as caught:
        call(value)
    message = str(caught.value)
    assert name in message, message
    assert any(text in message for text in shown(value)), message


# ---------------------------------------------------------------- the library table
LENGTH_CALLS = {
    **{f"FourBar.{name}": (lambda value, name=name: FourBar(**{**dict(crank=0.06, coupler=0.18, rocker=0.12,
                                                                        ground=0.2), name: value}), name)
       for name in ("crank", "coupler", "rocker", "ground")},
    **{f"FiveBar.{name}": (lambda value, name=name: FiveBar(**{**dict(l1=0.1, l2=0.15, l3=0.15, l4=0.1,
                                                                       l5=0.08), name: value}), name)
       for name in ("l1", "l2", "l3", "l4")},
    **{f"OffsetSliderCrank.{name}": (lambda value, name=name: OffsetSliderCrank(
        **{**dict(crank=0.075, rod=0.17, offset=0.045), name: value}), name) for name in ("crank", "rod")},
    **{f"Saw.{name}": (lambda value, name=name: saw.Saw(**{**dict(r1y=0.045, r2=0.075, r3=0.17),
                                                             name: value}), name) for name in ("r2", "r3")},
}
ANGLE_CALLS = {
    "FourBar.solve.theta2": (lambda value: DESK.solve(value), "theta2"),
    "FourBar.solve.omega2": (lambda value: DESK.solve(0.3, omega2=value), "omega2"),
    "FourBar.solve.alpha2": (lambda value: DESK.solve(0.3, alpha2=value), "alpha2"),
    "FourBar.joints": (lambda value: DESK.joints(value), "theta2"),
    "FourBar.transmission_angle": (lambda value: DESK.transmission_angle(value), "theta2"),
    "FourBar.coupler_point.delta": (lambda value: DESK.coupler_point(0.3, p=0.05, delta=value), "delta"),
    "OffsetSliderCrank.solve": (lambda value: SAW_TEXTBOOK.solve(value), "theta2"),
    "FiveBar.forward.theta1": (lambda value: ROBOT.forward(value, 2.0), "theta1"),
    "FiveBar.forward.theta4": (lambda value: ROBOT.forward(1.0, value), "theta4"),
    "FiveBar.inverse.x3": (lambda value: ROBOT.inverse(value, 0.2), "x3"),
    "FiveBar.inverse.y3": (lambda value: ROBOT.inverse(0.0, value), "y3"),
    **{f"FiveBar.{method}.{name}": (lambda value, method=method, name=name: getattr(ROBOT, method)(
        **{**POSE, name: value}), name) for method in FIVEBAR_POSE_METHODS for name in POSE},
    # joints' first argument is a motion; its older spelling takes the pose by position
    **{f"FiveBar.joints.{name}": (lambda value, k=k: ROBOT.joints(
        *[value if j == k else given for j, given in enumerate(POSE.values())]), name)
       for k, name in enumerate(POSE)},
    "saw.analytic": (lambda value: saw.analytic(value), "theta2"),
    "saw.solve_consecutive": (lambda value: saw.solve_consecutive(value), "theta2"),
    "saw.solve_simultaneous": (lambda value: saw.solve_simultaneous(value), "theta2"),
    "saw.joint_positions": (lambda value: saw.joint_positions(value), "theta2"),
    "profile.motor_profile": (lambda value: profile.motor_profile(value), "t"),
    "planar.polar.angle": (lambda value: planar.polar(0.1, value), "angle"),
    "planar.wrap_angle": (lambda value: planar.wrap_angle(value), "angle"),
}
CHOICE_CALLS = {
    "FourBar.solve.branch": (lambda value: DESK.solve(0.3, branch=value), "branch"),
    "saw.solve_consecutive.variant": (lambda value: saw.solve_consecutive(0.3, variant=value), "variant"),
    "OffsetSliderCrank.solve.branch": (lambda value: SAW_TEXTBOOK.solve(0.3, branch=value), "branch"),
    "FiveBar.forward.mode": (lambda value: ROBOT.forward(1.0, 2.0, mode=value), "mode"),
    "saw.sweep.method": (lambda value: saw.sweep(5, method=value), "method"),
}
DISTANCE_CALLS = {  # zero is a fine distance
    "coupler_point.p": (lambda value: DESK.coupler_point(0.3, p=value, delta=0.0), "p"),
    "FiveBar.l5": (lambda value: FiveBar(0.1, 0.15, 0.15, 0.1, value), "l5"),
}
TABLES = ((LENGTH_CALLS, NOT_A_LENGTH), (DISTANCE_CALLS, [v for v in NOT_A_LENGTH if v != 0.0]),
          (ANGLE_CALLS, NOT_AN_ANGLE), (CHOICE_CALLS, NOT_A_CHOICE))
CASES = [
    pytest.param(call, name, value, id=f"{label}={value!r}"[:80])
    for table, values in TABLES
    for label, (call, name) in table.items()
    for value in values
]


@pytest.mark.parametrize(("call", "name", "value"), CASES)
def test_a_bad_argument_is_named_with_its_value(call, name, value):
    refuses(call, name, value)


def test_the_table_is_large():
    assert len(CASES) >= 500


# ---------------------------------------------------------------- Newton's settings
def cubic(x):
    return x**3 - 2 * x + 2


def cubic_slope(x):
    return 3 * x * x - 2


@pytest.mark.parametrize(("setting", "value"), [
    *(("tol", value) for value in (None, "1e-6", True, math.nan, -1.0, 0.0, math.inf)),
    *(("residual_tol", value) for value in ("1e-6", True, math.nan, -1.0, 0.0)),   # None: not used
])
def test_newton_settings_are_checked(setting, value):
    refuses(lambda v: newton(cubic, 0.5, jac=cubic_slope, **{setting: v}), setting, value)


@pytest.mark.parametrize("value", [None, math.nan, math.inf, 0, -3, True, "50", 2.5, 10**7])
def test_newton_max_iter_is_checked_and_bounded(value):
    refuses(lambda v: newton(cubic, 0.5, jac=cubic_slope, max_iter=v), "max_iter", value)


@pytest.mark.parametrize("solver", [newton, newton_batch])
def test_newton_reports_a_residual_of_the_wrong_kind(solver):
    seed = np.array([[0.5, 0.5]]) if solver is newton_batch else np.array([0.5, 0.5])
    def identity(x):
        return np.broadcast_to(np.eye(2), x.shape + (2,))

    for F in (lambda x: None, lambda x: x.astype(complex) * 1j):
        with pytest.raises(CourseLibError, match="F returned"):
            solver(F, seed, jac=identity)
    if solver is newton:
        with pytest.raises(CourseLibError, match="F returned .*nan"):
            solver(lambda x: np.full_like(x, np.nan), seed, jac=identity)
    else:   # a batch reports the rows that failed instead of raising for one of them
        batch = solver(lambda x: np.full_like(x, np.nan), seed, jac=identity)
        assert not batch.converged.any() and "non-finite" in batch.message
    with pytest.raises(CourseLibError, match="jac"):
        solver(lambda x: x, seed, jac=lambda x: np.ones(3))


def test_newton_on_a_two_cycle_stops_within_its_bound():
    # x³ − 2x + 2 from 0 cycles 0 → 1 → 0 forever: the run ends at the cap, with a bounded history
    with pytest.raises(CourseLibError):
        newton(cubic, 0.0, jac=cubic_slope, max_iter=10**7)
    with pytest.raises(CourseLibError) as caught:
        newton(cubic, 0.0, jac=cubic_slope, max_iter=10_000)
    assert len(caught.value.result.history) <= 10_001


@pytest.mark.parametrize("links", [None, "4", 4.5, -1, True, math.nan])
def test_gruebler_counts_are_whole_numbers(links):
    refuses(lambda value: mobility.gruebler(links=value, full_joints=4), "links", links)


# ---------------------------------------------------------------- checkers and explorers
SILLY = [None, "abc", True, math.nan, math.inf, [4], (2.09, None), {"a": 1}, 1j, [[1], [2, 3]]]


@pytest.mark.parametrize("answer", SILLY, ids=repr)
@pytest.mark.parametrize("checker", [
    lambda a: checks.check_newton_iterations(a),
    lambda a: checks.check_mobility(a),
    lambda a: checks.check_fourbar_theta4(a, DESK, 1.0, "open"),
    lambda a: checks.check_link_vector(a, 0.06, 90.0),
])
def test_a_checker_answers_anything_with_feedback(checker, answer):
    feedback = checker(answer)
    assert isinstance(feedback, checks.Feedback) and not feedback.ok and feedback.message


EXPLORER_STATES = {
    fourbar_explorer: [{"assembly": "Open"}, {"assembly": None}, {"theta2_deg": math.nan}, {"crank": -1.0},
                       {"crank": 0.02, "coupler": 0.02, "rocker": 0.02, "ground": 0.02, "theta2_deg": 0.0}],
    saw_explorer: [{"t": math.nan}, {"t": -5.0}, {"t": "1"}],
    fivebar_explorer: [{"kinematics": "Forward"}, {"sigma": 2}, {"theta1_deg": math.nan}, {"x3": 10.0}],
}


@pytest.mark.parametrize(
    ("build", "state"), [(build, state) for build, states in EXPLORER_STATES.items() for state in states],
    ids=lambda v: getattr(v, "__name__", repr(v)),
)
def test_an_explorer_answers_any_state_with_a_status(build, state):
    explorer = build()
    readout = explorer.update(**state)
    assert readout.status in ("ok", "invalid", "unreachable", "singular", "error")
    assert "= nan" not in readout.text.lower()   # a refused NaN may be named, never shown as a result
    assert explorer.update().status in ("ok", "invalid", "unreachable", "singular", "error")  # still works


@pytest.mark.parametrize("scale", [1e-200, 1e-70, 1e70, 1e200])
def test_a_five_bar_outside_its_length_range_is_refused_not_wrong(scale):
    # at 1e-200 m the closed form's fourth powers underflow: it used to return a point 3× off
    refuses(lambda l1: FiveBar(l1, 0.15 * scale, 0.15 * scale, 0.1 * scale, 0.08 * scale), "l1", 0.1 * scale)


@pytest.mark.parametrize("scale", [1e-50, 1e50])
def test_a_five_bar_inside_its_length_range_scales(scale):
    # every position scales with the lengths: the pen's point at any size is the desk robot's, scaled
    desk = ROBOT.forward(1.0, 2.0)
    scaled = FiveBar(0.1 * scale, 0.15 * scale, 0.15 * scale, 0.1 * scale, 0.08 * scale).forward(1.0, 2.0)
    assert np.allclose(np.array(scaled) / scale, np.array(desk), rtol=1e-12, atol=0)


@pytest.mark.parametrize("time", [1e308, 1e13, -1.0])
def test_motor_profile_refuses_a_time_it_cannot_hold(time):
    refuses(profile.motor_profile, "t", time)


OTHER_SEED = [0.2, 0.2, 0.3, 0, 0, 0, 0, 0, 0]   # rod pointing right: Newton reaches the other assembly


@pytest.mark.parametrize("solve", [
    lambda: saw.solve_consecutive(0.0, x0=OTHER_SEED),
    lambda: saw.solve_simultaneous(0.0, x0=OTHER_SEED),
    lambda: saw.sweep(20, method="batched", x0=OTHER_SEED),
    lambda: saw.sweep(20, method="consecutive", x0=OTHER_SEED),
])
def test_the_saw_names_the_seed_that_reaches_the_other_assembly(solve):
    # the other assembly: the slider line crossed with the rod pointing right, cos θ3 > 0
    with pytest.raises(CourseLibError, match=r"x0=\[0\.2, 0\.2, 0\.3.*other assembly.*points right"):
        solve()


@pytest.mark.parametrize(("call", "names"), [
    (lambda: DESK.solve([0.1, 0.2, 0.3], [1.0, 2.0]), ("theta2", "omega2")),
    (lambda: DESK.loop_residual([0.1, 0.2], [0.1, 0.2, 0.3], 0.0), ("theta2", "theta3")),
    (lambda: SAW_TEXTBOOK.solve([0.1, 0.2, 0.3], [1.0, 2.0]), ("theta2", "omega2")),
    (lambda: ROBOT.forward([1.0, 2.0, 3.0], [1.0, 2.0]), ("theta1", "theta4")),
    (lambda: ROBOT.inverse([0.0, 0.01, 0.02], [0.2, 0.2]), ("x3", "y3")),
])
def test_arrays_that_do_not_broadcast_are_named_with_their_shapes(call, names):
    with pytest.raises(CourseLibError, match="broadcast") as caught:
        call()
    assert all(name in str(caught.value) for name in names) and "(3,)" in str(caught.value)


@pytest.mark.parametrize("call", [
    lambda: DESK.loop_residual(np.nan, 0.0, 0.0), lambda: DESK.loop_jacobian(0.0, np.inf),
])
def test_nan_is_refused_by_name_not_passed_through(call):
    with pytest.raises(CourseLibError, match="must be finite"):
        call()


@pytest.mark.parametrize("value", [math.nan, math.inf, -math.inf])
@pytest.mark.parametrize("name", list(POSE))
@pytest.mark.parametrize("rates", [
    lambda pose: ROBOT.velocity_jacobian(**pose),
    lambda pose: ROBOT.end_effector_velocity(**pose, omega1=1.0, omega4=-1.0),
    lambda pose: ROBOT.crank_rates(**pose, vx=0.0, vy=0.1),
], ids=["velocity_jacobian", "end_effector_velocity", "crank_rates"])
def test_five_bar_rates_name_a_non_finite_pose(rates, name, value):
    # not "the configuration is not assembled: residual nan": the argument itself, by name
    with pytest.raises(CourseLibError, match=rf"^{name} must be finite in (rad|m); got {value}$"):
        rates({**POSE, name: value})
    assert np.all(np.isfinite(rates(POSE)))
