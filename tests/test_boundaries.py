"""Properties at the edges where closed forms break: the five-bar's workspace boundary, the dead
centres of the offset slider-crank and of a crank-rocker, and the toggle of a double-rocker.

Every expected position comes from plain geometry written here (distances to the pivots, the law
of cosines for the dead-centre angles), never from the code under test.  Near an edge the library
must either solve with finite numbers or refuse with a named error (or mask, on request) — no NaN
handed out as an answer, no raw numpy warning or error.
"""

import contextlib
import math
import warnings

import numpy as np
import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from course_lib.errors import UnreachableError
from course_lib.fivebar import WORKING_MODES, FiveBar
from course_lib.fourbar import FourBar
from course_lib.slider_crank import OffsetSliderCrank

SETTINGS = settings(deadline=None, max_examples=60, derandomize=True)
LINK = st.floats(0.05, 0.3)
TURN = st.floats(-math.pi, math.pi)
SMALL = st.floats(1e-9, 1e-3)                 # a relative step off an edge, clear of rounding
BRANCHES = ("open", "crossed")


@contextlib.contextmanager
def strict():
    """Warnings are errors and numpy's floating-point troubles raise (underflow aside)."""
    with warnings.catch_warnings(), np.errstate(all="raise", under="ignore"):
        warnings.simplefilter("error")
        yield


# ------------------------------------------------------------------ five-bar workspace edges
def edge_point(robot, leg, outer, phi, step):
    """A point at relative distance ``step`` off one edge of one leg's annulus: from that leg's
    pivot at (1 ∓ step)·(crank + distal) on the outer edge or (1 ± step)·|crank − distal| on the
    inner one (the first sign inside, the second outside), in the direction ``phi``.
    Returns (inside point, outside point, pivot of the other leg, its crank, its distal)."""
    if leg == 1:
        pivot, crank, distal = (robot.l5 / 2, 0.0), robot.l1, robot.l2
        other = (-robot.l5 / 2, 0.0), robot.l4, robot.l3
    else:
        pivot, crank, distal = (-robot.l5 / 2, 0.0), robot.l4, robot.l3
        other = (robot.l5 / 2, 0.0), robot.l1, robot.l2
    radius = crank + distal if outer else abs(crank - distal)
    inward = -1 if outer else 1
    points = [(pivot[0] + radius * (1 + sign * step) * math.cos(phi),
               pivot[1] + radius * (1 + sign * step) * math.sin(phi)) for sign in (inward, -inward)]
    return (*points, *other)


def comfortably_reaches(point, pivot, crank, distal, margin=1e-3):
    distance = math.hypot(point[0] - pivot[0], point[1] - pivot[1])
    return abs(crank - distal) + margin < distance < crank + distal - margin


ROBOT_SHAPE = dict(l1=LINK, l2=LINK, l3=LINK, l4=LINK, l5=st.one_of(st.just(0.0), st.floats(0.001, 0.2)),
                   leg=st.sampled_from([1, 4]), outer=st.booleans(), phi=TURN, step=SMALL)


@SETTINGS
@given(**ROBOT_SHAPE, modes=st.sampled_from(WORKING_MODES))
def test_a_point_just_inside_a_workspace_edge_round_trips(l1, l2, l3, l4, l5, leg, outer, phi, step, modes):
    robot = FiveBar(l1, l2, l3, l4, l5)
    inside, _, *other = edge_point(robot, leg, outer, phi, step)
    assume(outer or abs((l1 - l2) if leg == 1 else (l4 - l3)) > 0.01)   # an inner edge worth the name
    assume(comfortably_reaches(inside, *other))
    with strict():
        theta1, theta4 = robot.inverse(*inside, modes=modes)
        assert math.isfinite(theta1) and math.isfinite(theta4)
        assert robot.inverse(*inside, modes=modes, on_failure="nan").reachable
        # the cranks put P2 and P4 where the distal links reach the point: independent check
        p2 = (robot.l5 / 2 + l1 * math.cos(theta1), l1 * math.sin(theta1))
        p4 = (-robot.l5 / 2 + l4 * math.cos(theta4), l4 * math.sin(theta4))
        assert abs(math.dist(p2, inside) - l2) < 1e-9 * l2
        assert abs(math.dist(p4, inside) - l3) < 1e-9 * l3
        parallel = robot.singularity_measures(theta1, theta4, *inside).parallel
        assume(abs(parallel) > 1e-3)   # the forward solution is well conditioned there
        back = [robot.forward(theta1, theta4, mode=mode) for mode in (1, -1)]
    assert min(math.dist(point, inside) for point in back) < 1e-9 * max(l1, l2, l3, l4)


@SETTINGS
@given(**ROBOT_SHAPE, modes=st.sampled_from(WORKING_MODES))
def test_a_point_just_outside_a_workspace_edge_is_refused_or_masked(l1, l2, l3, l4, l5, leg, outer, phi, step,
                                                                    modes):
    robot = FiveBar(l1, l2, l3, l4, l5)
    _, outside, *other = edge_point(robot, leg, outer, phi, step)
    assume(outer or abs((l1 - l2) if leg == 1 else (l4 - l3)) > 0.01)
    assume(comfortably_reaches(outside, *other))
    with strict():
        with pytest.raises(UnreachableError, match=f"leg {leg} "):
            robot.inverse(*outside, modes=modes)
        masked = robot.inverse(*outside, modes=modes, on_failure="nan")
        assert not masked.reachable and math.isnan(masked.theta1) and math.isnan(masked.theta4)
        grid = robot.workspace([outside[0]], [outside[1]], modes)
    assert not grid.reachable.any() and np.isnan(grid.parallel).all()


@SETTINGS
@given(exponent=st.floats(0.0, 308.0), phi=TURN, modes=st.sampled_from(WORKING_MODES))
def test_a_point_far_outside_the_workspace_is_refused_by_name(exponent, phi, modes):
    robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)          # reaches 0.29 m from the middle at most
    point = (10.0**exponent * math.cos(phi), 10.0**exponent * math.sin(phi))   # 1 m … 1e308 m away
    with strict():
        with pytest.raises(UnreachableError, match="cannot reach the point"):
            robot.inverse(*point, modes=modes)
        masked = robot.inverse(*point, modes=modes, on_failure="nan")
        grid = robot.workspace([point[0]], [point[1]], modes)
    assert not masked.reachable and math.isnan(masked.theta1) and math.isnan(masked.theta4)
    assert not grid.reachable.any() and np.isnan(grid.theta1).all()


# ------------------------------------------------------------------ slider-crank dead centres
def slider_dead_centres(crank, rod, offset, branch):
    """(θ2, slider x) where crank and rod lie in line, B on the line y = offset: stretched,
    B = (rod + crank)·(cos θ2, sin θ2); folded, B = (crank − rod)·(cos θ2, sin θ2)."""
    stretched, folded = math.asin(offset / (rod + crank)), math.asin(offset / (rod - crank))
    if branch == "right":    # B to the right of O2
        angles = stretched, folded - math.pi
    else:
        angles = math.pi - stretched, -folded
    return [(theta2, length * math.cos(theta2)) for theta2, length in zip(angles, (rod + crank, crank - rod),
                                                                          strict=True)]


@SETTINGS
@given(crank=st.floats(0.01, 0.3), extra=st.floats(0.01, 0.5), offset=st.floats(-0.3, 0.3),
       branch=st.sampled_from(["right", "left"]), omega2=st.floats(0.5, 50.0), step=st.floats(1e-7, 1e-2))
def test_slider_crank_dead_centres_stop_the_slider(crank, extra, offset, branch, omega2, step):
    rod = crank + abs(offset) + extra     # the crank turns fully, the rod never stands upright
    machine = OffsetSliderCrank(crank, rod, offset)
    for dead, x in slider_dead_centres(crank, rod, offset, branch):
        with strict():
            motion = machine.solve(dead, omega2, branch=branch)
            near = machine.solve([dead - step, dead + step], omega2, branch=branch)
        assert abs(motion.xC - x) < 1e-12 * rod                # B where rod and crank line up
        assert abs(motion.v_xC) < 1e-12 * omega2 * crank         # and the slider stands still there
        assert np.isfinite(np.array(near)).all()
        assert near.v_xC[0] * near.v_xC[1] < 0                      # turning back


# ------------------------------------------------------------------ four-bar dead centres and toggles
def crank_rocker_dead_centres(crank, coupler, rocker, ground):
    """θ2 with crank and coupler in line (the rocker's extremes), by the law of cosines in the
    triangle O2-O4-B: |O2B| = coupler + crank (stretched, B along the crank) or coupler − crank
    (folded, B against it), each above and below the ground line; with the expected B."""
    found = []
    for reach, turn in ((coupler + crank, 0.0), (coupler - crank, math.pi)):
        angle = math.acos((ground**2 + reach**2 - rocker**2) / (2 * ground * reach))
        for side in (1, -1):
            b = (reach * math.cos(side * angle), reach * math.sin(side * angle))
            found.append((side * angle - turn, b))
    return found


@SETTINGS
@given(crank=st.floats(0.02, 0.1), others=st.lists(st.floats(0.15, 1.0), min_size=3, max_size=3),
       omega2=st.floats(0.5, 50.0))
def test_a_crank_rocker_at_its_dead_centres_has_a_resting_rocker(crank, others, omega2):
    coupler, rocker, ground = others
    shortest_plus_longest = crank + max(others)
    assume(shortest_plus_longest < sum(others) - max(others) - 1e-3)   # Grashof, the crank shortest
    linkage = FourBar(crank, coupler, rocker, ground)
    for theta2, b in crank_rocker_dead_centres(crank, coupler, rocker, ground):
        with strict():
            solutions = {branch: linkage.solve(theta2, omega2, branch=branch) for branch in BRANCHES}
            joints = {branch: linkage.joints(theta2, branch) for branch in BRANCHES}
        # the assembly with B where crank and coupler line up
        branch = min(joints, key=lambda name: math.dist(joints[name][2], b))
        assert math.dist(joints[branch][2], b) < 1e-9
        assert abs(solutions[branch].omega4) < 1e-9 * omega2


@SETTINGS
@given(coupler=st.floats(0.02, 0.1), others=st.lists(st.floats(0.15, 1.0), min_size=3, max_size=3),
       step=st.floats(1e-9, 1e-3))
def test_a_double_rocker_driven_to_its_toggle_solves(coupler, others, step):
    crank, rocker, ground = others
    assume(coupler + max(others) < sum(others) - max(others) - 1e-3)  # Grashof, the coupler shortest
    linkage = FourBar(crank, coupler, rocker, ground)
    limits = linkage.input_range()
    assert not limits.full_rotation and limits.toggle_angles     # a double-rocker's crank cannot turn
    for toggle in limits.toggle_angles:
        a = (crank * math.cos(toggle), crank * math.sin(toggle))
        reach = math.dist(a, (ground, 0.0))
        # at a toggle coupler and rocker are in line: |A O4| = rocker ± coupler
        assert min(abs(reach - (rocker + coupler)), abs(reach - (rocker - coupler))) < 1e-9
        inward = next(step * (1 if toggle == start else -1) for start, end in limits.intervals
                      if toggle in (start, end))
        with strict():
            at_toggle = {branch: linkage.joints(toggle, branch) for branch in BRANCHES}
            near = linkage.solve(toggle + inward, omega2=1.0, branch="open")
        # the two assemblies meet at the toggle, B on the line through A and O4
        assert math.dist(at_toggle["open"][2], at_toggle["crossed"][2]) < 1e-6 * crank
        assert all(np.isfinite(np.array(near)))
