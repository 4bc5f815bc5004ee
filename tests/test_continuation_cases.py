"""Continuation never changes assembly unseen: linkages declared here, each checked against circle
intersections computed in the test (and against each instant solved alone).

- the Peaucellier–Lipkin cell at coarse steps keeps its cell (never the folded one, P on C) and names the
  change points where they are;
- a seven-bar of two inputs (crank θ1, slider s) on a grid or in random order keeps the assembly of its
  first instant, as each instant solved alone on it does — on the closed-form and on the Newton route;
- a near miss (the output dyad comes within 0.0022, 0.0001 or 0.00001 of its limit and parts) is not a
  change point;
- one instant exactly at a limit gets the verdict the same instant gets at the end of a sweep.
"""

import math
import re

import numpy as np
import pytest
import sympy as sp
from scipy.optimize import brentq

from course_lib.mechanism import Mechanism


def e(angle):
    return sp.Matrix([sp.cos(angle), sp.sin(angle)])


def circles(P, r1, Q, r2, side):
    """The point X with |XP| = r1 and |XQ| = r2 on the ``side`` (+1: left) of the directed line P → Q, by
    hand: the foot of the common chord on PQ, then half the chord across; NaN where the circles miss."""
    P, Q = np.broadcast_arrays(np.asarray(P, float), np.asarray(Q, float))
    d = Q - P
    dist = np.hypot(d[..., 0], d[..., 1])
    along = (dist**2 + r1**2 - r2**2) / (2 * dist)
    with np.errstate(invalid="ignore"):
        half = np.sqrt(r1**2 - along**2)
    ux, uy = d[..., 0] / dist, d[..., 1] / dist
    return np.stack([P[..., 0] + along * ux - side * half * uy, P[..., 1] + along * uy + side * half * ux],
                    -1)


def angle_of(v):
    return np.arctan2(v[..., 1], v[..., 0])


# ---------------------------------------------------------------- the Peaucellier–Lipkin inversor
R, L, S = 1.0, 2.5, 2.0  # crank O2C (O2 at distance R from O), arms OA = OB, the rhombus' sides
th1 = sp.Symbol("theta1")
phiA, alphaA, phiB, alphaB, beta1, beta2 = sp.symbols("phiA alphaA phiB alphaB beta1 beta2")


def peaucellier():
    """Three dyads: A (from O and C), B (from O and C) and P (from A and B) — P's two assemblies are the
    cell (P the mirror of C across AB) and the folded cell (P on C); they meet where |AB| = 2s."""
    C = sp.Matrix([R, 0]) + R * e(th1)
    A, B = L * e(phiA), L * e(phiB)
    return Mechanism([A - C - S * e(alphaA), B - C - S * e(alphaB), A + S * e(beta1) - B - S * e(beta2)],
                     [phiA, alphaA, phiB, alphaB, beta1, beta2], [th1],
                     points={"O": sp.zeros(2, 1), "O2": sp.Matrix([R, 0]), "C": C, "A": A, "B": B,
                             "P": A + S * e(beta1)},
                     links=[("O", "A"), ("O", "B"), ("O2", "C"), ("C", "A"), ("C", "B"), ("A", "P"),
                            ("B", "P")])


def cell(theta):
    """C, A, B and P of the cell by circle intersections: A left of O → C, B right, P = A + B − C."""
    C = np.stack([R + R * np.cos(theta), R * np.sin(theta)], -1)
    A, B = circles(np.zeros(2), L, C, S, 1), circles(np.zeros(2), L, C, S, -1)
    return C, A, B, A + B - C


def cell_guess(theta):
    C, A, B, P = cell(theta)
    return {phiA: angle_of(A), alphaA: angle_of(A - C), phiB: angle_of(B), alphaB: angle_of(B - C),
            beta1: angle_of(P - A), beta2: angle_of(P - B)}


# the cell folds flat (C = P, |AB| = 2s) where |OC| = √(L² − s²): 2R cos(θ/2) = √(L² − s²)
CROSSING = 2 * math.acos(math.sqrt(L**2 - S**2) / (2 * R))


def test_the_crossing_is_near_82_8_degrees():
    assert abs(math.degrees(CROSSING) - 82.819) < 1e-3
    C, A, B, P = cell(CROSSING)
    assert np.linalg.norm(P - C) < 1e-12 and abs(np.linalg.norm(A - B) - 2 * S) < 1e-12


@pytest.mark.parametrize("step", [10, 20, 30, 60])
def test_peaucellier_at_coarse_steps_keeps_its_cell_and_names_the_crossings(step):
    theta = np.radians(np.arange(-150, 151, step))
    linkage = peaucellier()
    motion = linkage.solve({th1: theta}, guess=cell_guess(theta[0]))
    C, _, _, P = cell(theta)
    drawn = linkage.joints(motion)["P"]
    assert np.abs(drawn - P).max() < 1e-9  # the cell at every instant: never the folded one (P on C)
    named = [float(x) for x in re.findall(r"theta1≈(-?\d+\.\d+)", motion.message)]
    assert sorted(named) == pytest.approx([-CROSSING, CROSSING], abs=1e-5), motion.message
    assert motion.message.count("change point") == 2


def test_peaucellier_draws_its_line():
    # the inversion: |OC|·|OP| = L² − s², P on the line x = (L² − s²) / (2R)
    theta = np.radians(np.arange(-150, 151, 60))
    linkage = peaucellier()
    P = linkage.joints(linkage.solve({th1: theta}, guess=cell_guess(theta[0])))["P"]
    assert np.abs(P[:, 0] - (L**2 - S**2) / (2 * R)).max() < 1e-12


# ---------------------------------------------------------------- a seven-bar of two inputs
CRANK, AB, SB = 0.5, 1.2, 1.0
th2, th3, th5, th6, xD, yD = sp.symbols("theta2 theta3 theta5 theta6 x_D y_D")
s = sp.Symbol("s")


def pin_B(theta, slide):
    """B from A = CRANK·e(θ1) and the slider S = (s, 0): |AB| = 1.2, |SB| = 1.0, B left of A → S."""
    theta, slide = np.broadcast_arrays(np.asarray(theta, float), np.asarray(slide, float))
    A = CRANK * np.stack([np.cos(theta), np.sin(theta)], -1)
    return circles(A, AB, np.stack([slide, 0 * slide], -1), SB, 1), A


def seven_bar(O6, l5, l6, route, slide=None):
    """Crank O1A (θ1), slider S (s) on the x axis, the dyad A–B–S, the output dyad B–D–O6 (l5, l6): seven
    links, two inputs (``slide``: s held there, one input).  ``route="newton"``: D by its coordinates, one
    3×3 block with no closed form."""
    A, slider = CRANK * e(th1), sp.Matrix([s if slide is None else slide, 0])
    inputs = [th1, s] if slide is None else [th1]
    B = A + AB * e(th2)
    first = A + AB * e(th2) - slider - SB * e(th3)
    if route == "closed":
        return Mechanism([first, B + l5 * e(th5) - sp.Matrix(O6) - l6 * e(th6)], [th2, th3, th5, th6],
                         inputs)
    rows = [*first, *(B + l5 * e(th5) - sp.Matrix([xD, yD])), (xD - O6[0]) ** 2 + (yD - O6[1]) ** 2 - l6**2]
    return Mechanism(rows, [th2, th3, th5, xD, yD], inputs)


def seven_bar_reference(theta, slide, O6, l5, l6, side):
    B, A = pin_B(theta, slide)
    return A, B, circles(B, l5, np.broadcast_to(np.asarray(O6, float), B.shape), l6, side)


def seven_bar_guess(theta, slide, O6, l5, l6, route):
    A, B, D = seven_bar_reference(theta, slide, O6, l5, l6, 1)
    guess = {th2: angle_of(B - A), th3: angle_of(B - [slide, 0.0]), th5: angle_of(D - B)}
    return guess | ({th6: angle_of(D - O6)} if route == "closed" else {xD: D[0], yD: D[1]})


def D_of(motion, route, l5=1.2):
    if route == "newton":
        return np.stack([motion.position["x_D"], motion.position["y_D"]], -1)
    theta = np.asarray(motion.inputs["theta1"])
    B = CRANK * np.stack([np.cos(theta), np.sin(theta)], -1) + AB * np.stack(
        [np.cos(motion.position["theta2"]), np.sin(motion.position["theta2"])], -1)
    return B + l5 * np.stack([np.cos(motion.position["theta5"]), np.sin(motion.position["theta5"])], -1)


GRID_THETA, GRID_S = np.meshgrid(np.radians(np.arange(0, 360, 10)), np.arange(1.10, 1.36, 0.05))


@pytest.mark.parametrize("route", ["closed", "newton"])
@pytest.mark.parametrize("O6", [(-0.25, -0.25), (-0.5, 1.25), (0.0, 0.5)])
def test_a_grid_and_random_order_keep_the_first_instants_assembly(route, O6):
    # l5 − l6 = 0.5 and l5 + l6 = 1.9: the workspace has holes where the dyad B–D–O6 cannot close
    O6, l5, l6 = np.array(O6), 1.2, 0.7
    theta, slide = GRID_THETA.ravel(), GRID_S.ravel()
    _, _, D = seven_bar_reference(theta, slide, O6, l5, l6, 1)
    reachable = np.flatnonzero(np.isfinite(D[:, 0]))
    linkage = seven_bar(O6, l5, l6, route)
    orders = {"grid": np.r_[reachable[0], np.delete(np.arange(theta.size), reachable[0])],
              "random": np.random.default_rng(3).permutation(theta.size)}
    orders["random"] = np.r_[reachable[0], orders["random"][orders["random"] != reachable[0]]]
    for order in orders.values():
        first = order[0]
        motion = linkage.solve({th1: theta[order], s: slide[order]}, on_failure="nan",
                               guess=seven_bar_guess(theta[first], slide[first], O6, l5, l6, route))
        found = D_of(motion, route, l5)
        expected = D[order]
        assert np.array_equal(np.isnan(found[:, 0]), np.isnan(expected[:, 0]))  # every reachable instant
        assert np.nanmax(np.abs(found - expected)) < 1e-9  # and on the first instant's assembly
        assert "change point" not in motion.message
    if route == "closed":  # each instant alone on that assembly: the same
        sigma = motion.assembly["theta6"][0]
        for k in order[:: 17]:
            alone = linkage.solve({th1: theta[k], s: slide[k]}, on_failure="nan",
                                  assembly={"theta2": motion.assembly["theta2"][0], "theta6": sigma})
            if np.isfinite(D[k, 0]):
                assert np.abs(D_of(alone, route, l5) - D[k]).max() < 1e-9


NEAR_MISS_AT = math.radians(335.0)  # where B passes nearest O6


def near_miss_pivot(gap, theta_star=NEAR_MISS_AT, slide=1.10):
    """O6 on B's path's normal at θ1 = θ*, placed (by Brent's method on the sampled distance) so that
    B's nearest approach to O6 over a turn is exactly ``gap``."""
    h = 1e-6
    B0 = pin_B(theta_star, slide)[0]
    tangent = (pin_B(theta_star + h, slide)[0] - pin_B(theta_star - h, slide)[0]) / (2 * h)
    normal = np.array([-tangent[1], tangent[0]]) / np.hypot(*tangent)
    turn = np.linspace(0, 2 * np.pi, 40001)
    path = pin_B(turn, slide)[0]

    def nearest(offset):
        return np.hypot(*(path - (B0 + offset * normal)).T).min() - gap

    return B0 + brentq(nearest, 0.3, 0.7) * normal


NEAR_MISSES = [(gap, route, inputs) for gap in (0.5022, 0.5001, 0.50001) for route in ("closed", "newton")
               for inputs in ("theta1", "theta1 and s")]


@pytest.mark.parametrize("step", [5, 10])
@pytest.mark.parametrize(("gap", "route", "inputs"), NEAR_MISSES)
def test_a_near_miss_is_not_a_change_point(gap, step, route, inputs):
    l6 = 0.7
    l5 = l6 + 0.5  # the dyad B–D–O6 folds where |B O6| = 0.5; B comes within ``gap`` of O6
    O6 = near_miss_pivot(gap)
    theta = np.radians(np.arange(0, 721, step))
    _, B, D = seven_bar_reference(theta, 1.10, O6, l5, l6, 1)
    assert np.hypot(*(B - O6).T).min() >= gap - 1e-9 and np.isfinite(D).all()
    linkage = seven_bar(O6, l5, l6, route, 1.10 if inputs == "theta1" else None)
    given = {th1: theta} if inputs == "theta1" else {th1: theta, s: 1.10}
    motion = linkage.solve(given, guess=seven_bar_guess(theta[0], 1.10, O6, l5, l6, route))
    assert np.abs(D_of(motion, route, l5) - D).max() < 1e-9
    assert "change point" not in motion.message
    if route == "closed":
        assert set(np.ravel(motion.assembly["theta6"])) == {motion.assembly["theta6"][0]}


# ---------------------------------------------------------------- one instant at a limit
def newton_fourbar():
    """The four-bar with B's coordinates as unknowns: one 3×3 block, no closed form — Newton's route."""
    theta2, theta3, x_B, y_B = sp.symbols("theta2 theta3 x_B y_B")
    rows = [0.15 * sp.cos(theta2) + 0.10 * sp.cos(theta3) - x_B, 0.15 * sp.sin(theta2) + 0.10 * sp.sin(theta3)
            - y_B, (x_B - 0.20) ** 2 + y_B**2 - 0.12**2]
    return Mechanism(rows, [theta3, x_B, y_B], [theta2])


LIMIT = math.acos((0.2**2 + 0.15**2 - 0.22**2) / (2 * 0.2 * 0.15))  # |A O4| = l3 + l4: stretched


@pytest.mark.parametrize("guess", [(1.0, 0.25, 0.1), (0.5, 0.3, 0.05), (1.2, 0.25, 0.15)])
def test_one_instant_at_a_limit_is_found_and_singular_on_the_newton_route(guess):
    linkage = newton_fourbar()
    assert linkage.closed_forms == [None]
    A = 0.15 * np.array([math.cos(LIMIT), math.sin(LIMIT)])
    B = A + (np.array([0.20, 0.0]) - A) * 0.10 / 0.22  # A, B, O4 in line
    named = dict(zip(("theta3", "x_B", "y_B"), guess, strict=True))
    one = linkage.solve({"theta2": LIMIT}, guess=named)
    end = linkage.solve({"theta2": np.linspace(LIMIT - 0.5, LIMIT, 11)}, guess={"theta3": 1.0, "x_B": 0.25,
                                                                            "y_B": 0.1})
    assert one.converged and one.singular and end.converged[-1] and end.singular[-1]
    assert abs(one.position["x_B"] - B[0]) < 1e-6 and abs(one.position["y_B"] - B[1]) < 1e-6
    assert "J is singular" in one.message


def test_newton_route_through_a_change_point_keeps_the_parallelogram_and_says_so():
    # the parallelogram l1 = l3 = 0.2, l2 = l4 = 0.1 with B's coordinates as unknowns (Newton's route): at
    # θ2 = π the four pins line up and the anti-parallelogram meets it; the motion goes on as a
    # parallelogram, θ3 = 0 (the coupler stays parallel to the ground), and the message says so
    theta2, theta3, x_B, y_B = sp.symbols("theta2 theta3 x_B y_B")
    rows = [0.1 * sp.cos(theta2) + 0.2 * sp.cos(theta3) - x_B, 0.1 * sp.sin(theta2) + 0.2 * sp.sin(theta3)
            - y_B, (x_B - 0.2) ** 2 + y_B**2 - 0.1**2]
    linkage = Mechanism(rows, [theta3, x_B, y_B], [theta2])
    for theta in (np.linspace(3.0, 3.3, 31), np.radians(np.arange(10, 721, 30.0)), np.linspace(2.0, 4.5, 6)):
        motion = linkage.solve({theta2: theta}, guess={theta3: 0.0, x_B: 0.2 + 0.1 * np.cos(theta[0]),
                                                       y_B: 0.1 * np.sin(theta[0])})
        assert np.abs(np.angle(np.exp(1j * motion.position["theta3"]))).max() < 1e-9
        assert "change point" in motion.message


# ---------------------------------------------------------------- warnings that name what failed
def test_a_partial_assembly_names_the_block_left_to_choose():
    motion = peaucellier().solve({th1: [0.3, 0.4]}, assembly={"phiA": 1, "alphaB": -1})
    assert "assembly= chose no σ for the block of beta1/beta2" in motion.message
    assert "phiA" not in motion.message and "alphaB" not in motion.message


def test_the_failing_loop_is_named_in_the_peaucellier_cell():
    from course_lib.errors import SingularJacobianError, UnreachableError

    # θ1 = 3 puts C 2R cos(1.5) = 0.14 from O, closer than L − s: the arm's dyad (loops[0]) cannot close
    with pytest.raises(UnreachableError, match=r"cannot be closed at theta1=3\.0, in loops\[0\]:"):
        peaucellier().solve({th1: 3.0}, guess=cell_guess(0.0))
    # at the crossing the rhombus is flat: P's dyad (loops[2]) is singular, the arms' are not
    with pytest.raises(SingularJacobianError, match=r"J is singular at theta1=1\.44546.*, in loops\[2\]:"):
        peaucellier().solve({th1: CROSSING}, rates={th1: 1.0}, guess=cell_guess(CROSSING - 0.01))


# ---------------------------------------------------------------- a long sweep on Newton's route, batched
def parallelogram():
    theta2, theta3, x_B, y_B = sp.symbols("theta2 theta3 x_B y_B")
    rows = [0.1 * sp.cos(theta2) + 0.2 * sp.cos(theta3) - x_B, 0.1 * sp.sin(theta2) + 0.2 * sp.sin(theta3)
            - y_B, (x_B - 0.2) ** 2 + y_B**2 - 0.1**2]
    return Mechanism(rows, [theta3, x_B, y_B], [theta2])


def one_by_one(monkeypatch, linkage, *args, **kwargs):
    """The same solve with every instant continued from the one before (the batched route switched off)."""
    from course_lib.mechanism import continuation

    with monkeypatch.context() as patch:
        patch.setattr(continuation, "BATCH_MIN", 10**9)
        return linkage.solve(*args, **kwargs)


@pytest.mark.parametrize("count", [64, 1000, 4099])
def test_a_long_newton_sweep_solved_at_once_is_the_sweep_followed_instant_by_instant(monkeypatch, count):
    linkage = newton_fourbar()
    end = LIMIT - 1e-3
    theta = np.linspace(-end, end, count)  # a Grashof rocker's input range, nearly to both limits
    guess = {"theta3": 1.0, "x_B": 0.25, "y_B": -0.1}
    rates = ({"theta2": 10.0}, {"theta2": 5.0})
    batched = linkage.solve({"theta2": theta}, *rates, guess=guess)
    alone = one_by_one(monkeypatch, linkage, {"theta2": theta}, *rates, guess=guess)
    assert batched.converged.all() and alone.converged.all()
    for name in ("theta3", "x_B", "y_B"):
        assert np.abs(batched.position[name] - alone.position[name]).max() < 1e-12
        scale = 1.0 + np.abs(alone.velocity[name])
        assert (np.abs(batched.velocity[name] - alone.velocity[name]) / scale).max() < 1e-9
    assert batched.message == alone.message
    # against the circles: B on the circle about O4 and at l3 from A, on the guess's side
    A = 0.15 * np.stack([np.cos(theta), np.sin(theta)], -1)
    B = np.stack([batched.position["x_B"], batched.position["y_B"]], -1)
    assert np.abs(np.hypot(*(B - A).T) - 0.10).max() < 1e-12
    assert np.abs(np.hypot(*(B - [0.2, 0.0]).T) - 0.12).max() < 1e-12


def test_a_long_newton_sweep_through_a_change_point_keeps_the_smooth_motion_and_names_it(monkeypatch):
    theta = np.linspace(2.0, 4.5, 500)
    guess = {"theta3": 0.0, "x_B": 0.2 + 0.1 * np.cos(2.0), "y_B": 0.1 * np.sin(2.0)}
    batched = parallelogram().solve({"theta2": theta}, guess=guess)
    assert np.abs(np.angle(np.exp(1j * batched.position["theta3"]))).max() < 1e-9  # the parallelogram
    assert batched.message.count("change point") == 1 and "theta2=3.14" in batched.message
    assert batched.message == one_by_one(monkeypatch, parallelogram(), {"theta2": theta}, guess=guess).message


def test_a_long_newton_sweep_with_a_stretch_out_of_reach_gives_what_one_by_one_gives(monkeypatch):
    linkage = newton_fourbar()
    theta = np.linspace(-1.0, 1.6, 70)  # past the limit at θ2 = LIMIT ≈ 1.42: the rest cannot be reached
    guess = {"theta3": 1.0, "x_B": 0.25, "y_B": -0.1}
    batched = linkage.solve({"theta2": theta}, guess=guess, on_failure="nan")
    alone = one_by_one(monkeypatch, linkage, {"theta2": theta}, guess=guess, on_failure="nan")
    assert np.array_equal(batched.converged, alone.converged) and not batched.converged[-1]
    found = np.asarray(batched.converged)
    assert np.abs(batched.position["x_B"][found] - alone.position["x_B"][found]).max() < 1e-12
