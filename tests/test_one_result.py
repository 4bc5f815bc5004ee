"""One result and one drawing vocabulary: every machine's solve returns a ``Motion`` of its declaration
(values by the course's names as well as by the declaration's), and the declaration names its ground
pivots, sliders, plates and styles, so ``draw``, ``animate`` and ``explore`` need only the machine and a
motion.  References are independent: circle intersections, the law of cosines, finite differences."""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest
import sympy as sp

from course_lib.errors import CourseLibError
from course_lib.fivebar import FiveBar
from course_lib.fourbar import FourBar
from course_lib.mechanism import Mechanism
from course_lib.motion import Motion
from course_lib.plotting import animate, draw
from course_lib.saw import Saw, solve_consecutive, solve_simultaneous, sweep
from course_lib.slider_crank import OffsetSliderCrank
from course_lib.widgets import explore

matplotlib.use("Agg")

WIPER = FourBar(crank=0.06, coupler=0.18, rocker=0.12, ground=0.20)
ROBOT = FiveBar(l1=0.10, l2=0.15, l3=0.15, l4=0.10, l5=0.08)
SAW = Saw()
SLIDER = OffsetSliderCrank(crank=0.05, rod=0.20, offset=0.01)

RESULTS = {
    "four-bar": lambda: WIPER.solve(np.radians([0.0, 60.0, 200.0]), omega2=10.0),
    "slider-crank": lambda: SLIDER.solve(np.radians([0.0, 60.0, 200.0]), omega2=10.0),
    "saw closed form": lambda: SAW.motion(np.radians([0.0, 60.0, 200.0]), omega2=6.0),
    "saw consecutive": lambda: solve_consecutive(0.3, 6.0, 0.0),
    "saw simultaneous": lambda: solve_simultaneous(0.3, 6.0, 0.0),
    "saw sweep": lambda: sweep(20, method="batched"),
    "five-bar forward": lambda: ROBOT.forward(np.radians([50.0, 60.0]), np.radians([115.0, 120.0])),
    "five-bar motion": lambda: ROBOT.motion(np.radians(50.0), np.radians(115.0), omega1=1.0),
    "five-bar inverse": lambda: ROBOT.inverse([0.03, 0.0], [0.17, 0.2], modes=(-1, 1)),
}


ANGLES = np.radians([0.0, 60.0, 200.0])
#: The course's names for the rates, written from its notation (ω = dθ/dt, v = dx/dt, v_r = dr1/dt): machine →
#: (its solve at the input angles with rate 1, the name → the position it is the time derivative of).
COURSE_RATES = {
    "four-bar": (lambda theta, rate: WIPER.solve(theta, omega2=rate),
                 {"omega3": "theta3", "omega4": "theta4"}),
    "slider-crank": (lambda theta, rate: SLIDER.solve(theta, omega2=rate),
                     {"omega3": "theta3", "v_xC": "xC"}),
    "saw": (lambda theta, rate: SAW.motion(theta, omega2=rate), {"omega1": "theta1", "omega3": "theta3",
                                                                 "v_r": "r1"}),
}


@pytest.mark.parametrize("name", COURSE_RATES)
def test_the_course_names_of_the_rates_are_the_derivatives_of_the_positions(name):
    """ω3, v, v_r … read by their course names equal central differences of the positions (h = 1e-6)."""
    solve, names = COURSE_RATES[name]
    at, h = solve(ANGLES, 1.0), 1e-6
    ahead, behind = solve(ANGLES + h, 0.0), solve(ANGLES - h, 0.0)
    for attribute, position in names.items():
        difference = (np.asarray(getattr(ahead, position)) - np.asarray(getattr(behind, position))) / (2 * h)
        np.testing.assert_allclose(getattr(at, attribute), difference, rtol=1e-6, atol=1e-8,
                                   err_msg=attribute)


@pytest.mark.parametrize("name", RESULTS)
def test_every_machine_solve_returns_a_motion_whose_course_names_are_its_values(name):
    result = RESULTS[name]()
    assert isinstance(result, Motion)
    parts = {"position": result.position, "inputs": result.inputs, "velocity": result.velocity or {},
             "acceleration": result.acceleration or {}}
    for part in ("position", "inputs"):  # every unknown and input also by its own name
        for key, value in parts[part].items():
            assert np.array_equal(getattr(result, key), value, equal_nan=True), key
    values = list(result)  # unpacks as the course's values, and converts to one array of them
    assert np.array(result).shape == (len(values), *np.shape(values[0]))
    assert np.all(result.converged) and not np.any(result.singular)


def test_machine_names_that_are_not_values_raise_attribute_error():
    with pytest.raises(AttributeError, match="theta9"):
        _ = WIPER.solve(0.3).theta9


def test_a_four_bar_solution_is_the_loop_closed_by_circle_intersection():
    theta2 = np.radians(60.0)
    solution = WIPER.solve(theta2, branch="open")
    A = WIPER.l2 * np.array([math.cos(theta2), math.sin(theta2)])
    O4 = np.array([WIPER.l1, 0.0])
    B = WIPER.mechanism.joints(solution)["B"]  # the declaration's point at the solution
    assert abs(np.linalg.norm(B - A) - WIPER.l3) < 1e-12 and abs(np.linalg.norm(B - O4) - WIPER.l4) < 1e-12


def test_near_singular_marks_the_four_bar_close_to_its_toggle_and_nowhere_else():
    # a triple rocker: θ2 stops where coupler and rocker are collinear, |O2B| = l3 + l4 (law of cosines)
    triple = FourBar(crank=0.15, coupler=0.10, rocker=0.12, ground=0.20)
    reach = triple.l3 + triple.l4
    limit = math.acos((triple.l2**2 + triple.l1**2 - reach**2) / (2 * triple.l2 * triple.l1))
    near = triple.solve([limit - 1e-9, limit - 0.3], on_failure="nan").near_singular
    assert near.tolist() == [True, False]


def test_an_inverse_result_draws_the_robot_with_its_pen_on_the_target():
    target = (0.03, 0.17)
    result = ROBOT.inverse(*target, modes=(-1, 1))
    joints = ROBOT.mechanism.joints(result)
    assert np.allclose(joints["P3"], target, atol=1e-15)
    assert abs(np.linalg.norm(joints["P3"] - joints["P2"]) - ROBOT.l2) < 1e-12
    assert abs(np.linalg.norm(joints["P3"] - joints["P4"]) - ROBOT.l3) < 1e-12
    ax = draw(ROBOT, result)
    assert {line.get_gid() for line in ax.lines} >= {"l1", "l2", "l3", "l4", "l5"}


def test_an_inverse_result_is_singular_where_a_leg_is_stretched():
    # at (0, h) both legs reach straight out: |P1P3| = l1 + l2, where ∂(loops)/∂θ loses rank
    h = math.sqrt((ROBOT.l1 + ROBOT.l2) ** 2 - (ROBOT.l5 / 2) ** 2)
    result = ROBOT.inverse([0.0, 0.0], [h - 1e-9, 0.15])
    assert result.near_singular.tolist() == [True, False]


def test_the_declaration_names_its_ground_and_sliders_and_the_drawing_uses_them():
    assert WIPER.mechanism.ground == ("O2", "O4") and ROBOT.mechanism.ground == ("P1", "P5")
    assert SAW.mechanism.sliders == ("C",) and SLIDER.mechanism.sliders == ("C",)
    ax = draw(SAW, SAW.motion(0.3))
    blocks = [line for line in ax.lines if line.get_marker() == "s"]
    assert len(blocks) == 1
    assert np.allclose(blocks[0].get_xydata(), SAW.mechanism.joints(SAW.motion(0.3))["C"])
    # the ground symbols: one hatched triangle per declared pivot, its apex on the pivot
    apexes = [patch.get_xy()[0] for patch in ax.patches if patch.get_hatch() == "///"]
    assert np.allclose(apexes, [[0.0, 0.0]])
    hatched = [patch.get_xy()[0] for patch in draw(WIPER, WIPER.solve(0.3)).patches if patch.get_hatch()]
    assert np.allclose(hatched, [[0.0, 0.0], [WIPER.l1, 0.0]])


def test_plates_are_shaded_polygons_on_their_corners():
    th, x = sp.symbols("theta x")
    A = sp.Matrix([sp.cos(th), sp.sin(th)])
    P = A + 0.5 * sp.Matrix([-sp.sin(th), sp.cos(th)])  # on the crank, square to it: a rigid plate O, A, P
    crank = Mechanism([x - sp.cos(th)], [x], [th], points={"O": sp.zeros(2, 1), "A": A,
                      "B": sp.Matrix([x, 0]), "P": P},
                      links={"crank": ("O", "A"), "arm": ("A", "P")}, ground=["O"], sliders=["B"],
                      plates={"crank plate": ("O", "A", "P")}, styles={"arm": {"color": "black"}})
    motion = crank.solve({th: [0.0, 1.0]}, guess={x: 1.0})
    ax = draw(crank, motion, frame=1)
    (plate,) = [patch for patch in ax.patches if patch.get_gid() == "plate crank plate"]
    corners = np.asarray(plate.get_xy())[:3]
    tip = [math.cos(1) - 0.5 * math.sin(1), math.sin(1) + 0.5 * math.cos(1)]
    assert np.allclose(corners, [[0.0, 0.0], [math.cos(1), math.sin(1)], tip])
    assert [line.get_color() for line in ax.lines if line.get_gid() == "arm"] == ["black"]
    joints = [line for line in ax.lines if line.get_marker() == "o"][0].get_xydata()
    assert np.allclose(joints[-1], tip)  # P, a corner of the plate only
    assert animate(crank, motion).frame_count == 2
    assert explore(crank, motion).update(theta_deg=30.0).status == "ok"


@pytest.mark.parametrize("argument, value", [
    ("ground", ["Q"]), ("sliders", [3]), ("plates", {"p": ("O", "A")}), ("styles", {"no such": {}}),
    ("styles", {"crank": 3}),
])
def test_a_bad_drawing_declaration_is_refused_by_name(argument, value):
    th, x = sp.symbols("theta x")
    with pytest.raises(CourseLibError, match=argument):
        Mechanism([x - sp.cos(th)], [x], [th], points={"O": sp.zeros(2, 1), "A": sp.Matrix([x, 0])},
                  links={"crank": ("O", "A")}, **{argument: value})


def test_the_readme_example_declares_solves_and_draws_as_the_wiper_closes():
    import pathlib
    import re

    text = (pathlib.Path(__file__).resolve().parent.parent / "README.md").read_text(encoding="utf-8")
    (block,) = re.findall(r"```python\n(.*?)```", text, re.S)
    names: dict = {}
    exec(compile(block, "README.md", "exec"), names)  # noqa: S102 - the README's own example
    motion, angles = names["motion"], np.radians(np.arange(0, 360, 2))
    O4 = np.array([0.20, 0.0])
    A = 0.06 * np.stack([np.cos(angles), np.sin(angles)], axis=-1)
    B = names["wiper"].joints(motion)["B"]
    assert np.allclose(np.linalg.norm(B - A, axis=-1), 0.18, atol=1e-12)  # the coupler's length
    assert np.allclose(np.linalg.norm(B - O4, axis=-1), 0.12, atol=1e-12)  # the rocker's length


def test_labels_true_names_every_point_where_it_is():
    ax = draw(WIPER, WIPER.solve(np.radians(60.0)), labels=True)
    placed = {text.get_text(): np.array(text.get_position()) for text in ax.texts}
    assert sorted(placed) == ["A", "B", "O2", "O4"]
    A = 0.06 * np.array([math.cos(math.radians(60.0)), math.sin(math.radians(60.0))])
    assert np.linalg.norm(placed["A"] - A) < 0.02  # beside its point, offset by a few per cent of the span
    with pytest.raises(CourseLibError, match="labels"):
        draw(WIPER, WIPER.solve(0.3), labels="yes")


def test_draw_names_the_links_beside_their_middles():
    motion = WIPER.solve(np.radians(60.0))
    ax = draw(WIPER, motion, link_labels=True)
    A = 0.06 * np.array([math.cos(math.radians(60.0)), math.sin(math.radians(60.0))])
    texts = {text.get_gid(): text for text in ax.texts if (text.get_gid() or "").startswith("label ")}
    assert set(texts) == {"label crank", "label coupler", "label rocker", "label ground"}
    crank = texts["label crank"]
    assert crank.get_text() == "crank"
    middle = A / 2
    offset = np.array(crank.get_position()) - middle
    assert abs(offset @ A) < 1e-12 and np.linalg.norm(offset) > 0  # beside the middle, square to the link
    renamed = draw(WIPER, motion, link_labels={"coupler": "l3"})
    assert [t.get_text() for t in renamed.texts if t.get_gid() == "label coupler"] == ["l3"]
    with pytest.raises(CourseLibError, match="link_labels must map link names"):
        draw(WIPER, motion, link_labels={"no such": "x"})


def test_draw_fades_only_what_it_drew():
    ax = draw({"crank": ("O", "A")}, {"O": (0.0, 0.0), "A": (0.03, 0.04)}, ground=["O"])
    first = set(ax.get_children())
    draw({"crank": ("O", "A")}, {"O": (0.0, 0.0), "A": (0.04, 0.03)}, ax, alpha=0.3)
    faded = [child for child in set(ax.get_children()) - first]
    assert faded and all(child.get_alpha() == 0.3 for child in faded)
    assert all(child.get_alpha() != 0.3 for child in first)
    with pytest.raises(CourseLibError, match="alpha must be a number from 0 to 1"):
        draw({"crank": ("O", "A")}, {"O": (0.0, 0.0), "A": (0.04, 0.03)}, alpha=2)


#: Every public function or method whose name says it solves or moves a machine: the ones that solve the loops
#: for their inputs return a Motion (RESULTS above, and the core's own solve); the others are named here with
#: what they return instead, so a new solve-like name cannot escape the table.
NOT_SOLVES = {
    "FourBar.joints": "the declared points of a Motion by name (older: of θ2, an array (..., 4, 2))",
    "OffsetSliderCrank.joints": "the declared points of a Motion by name (older: of θ2, an array)",
    "Saw.joints": "the declared points of a Motion by name (older: of θ2, an array)",
    "FiveBar.joints": "the declared points of a Motion by name (older: of a given configuration, an array)",
    "FourBar.with_coupler_point": "a FourBar with the coupler point declared",
    "FourBar.coupler_point": "one point's position and rates from a solve, as Mechanism.point_motion",
    "saw.analytic": "the course's eqs. 20–28 as written, an array (lesson 06's derivation, asserted "
                    "equal to Saw.motion)",
    "FiveBar.forward_coefficients": "the course's coefficients f, g, a, b, c, D",
    "FiveBar.inverse_coefficients": "the course's half-angle coefficients",
    "FiveBar.crank_rates": "the crank rates at a given configuration (no position solved)",
    "FiveBar.workspace": "a WorkspaceMap over a grid, built from FiveBar.inverse",
    "newton.newton": "Newton-Raphson on any F, a NewtonResult (lesson 02's method)",
    "newton.newton_batch": "Newton-Raphson on many F at once, a BatchNewtonResult",
    "newton.linear_solver": "a solver of linear systems",
    "fivebar.linear_solver": "newton.linear_solver, imported",
    "LinearStack.solve": "a linear solve",
}
SOLVE_NAMES = {"FourBar.solve": "four-bar", "FourBar.motion": "four-bar",
               "OffsetSliderCrank.solve": "slider-crank", "OffsetSliderCrank.motion": "slider-crank",
               "Saw.motion": "saw closed form", "saw.solve_consecutive": "saw consecutive",
               "saw.solve_simultaneous": "saw simultaneous", "saw.sweep": "saw sweep",
               "FiveBar.forward": "five-bar forward", "FiveBar.motion": "five-bar motion",
               "FiveBar.inverse": "five-bar inverse"}
SOLVE_LIKE = ("solve", "motion", "forward", "inverse", "sweep", "analytic", "workspace", "coupler_point",
              "newton", "consecutive", "simultaneous", "rates", "joints")


def test_every_public_solve_like_name_returns_a_motion_or_is_named_as_something_else():
    import importlib
    import inspect

    found = set()
    for module_name in ("fourbar", "slider_crank", "saw", "fivebar", "newton", "profile", "planar"):
        module = importlib.import_module(f"course_lib.{module_name}")
        for name, value in vars(module).items():
            if name.startswith("_"):
                continue
            if inspect.isfunction(value) and any(word in name for word in SOLVE_LIKE):
                found.add(f"{module_name}.{name}")
            if inspect.isclass(value) and value.__module__ == module.__name__:
                found |= {f"{name}.{attribute}" for attribute, member in vars(value).items()
                          if not attribute.startswith("_") and callable(member)
                          and any(word in attribute for word in SOLVE_LIKE)}
    assert found == set(SOLVE_NAMES) | set(NOT_SOLVES)
    for name, result in SOLVE_NAMES.items():
        assert isinstance(RESULTS[result](), Motion), name
    assert isinstance(FourBar(0.06, 0.18, 0.12, 0.20).motion(0.3), Motion)
    assert isinstance(OffsetSliderCrank(0.05, 0.20, 0.01).motion(0.3), Motion)
    th, x = sp.symbols("theta x")
    assert type(Mechanism([x**2 - th], [x], [th]).solve({th: 4.0}, guess={x: 2.0})) is Motion
