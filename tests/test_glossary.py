"""docs/glossary.md: every public name of course_lib is on it, and its σ statements (section 3) hold.

The σ statements are re-computed here from the geometry: the assembly each machine names (four-bar branch,
slider-crank branch, five-bar arms up/down and working modes) against σ = −sign(det J_b) as
``Motion.assembly`` reports it and as ``Mechanism.solve(assembly=...)`` chooses it, with the cross products
taken from the declared points (``Mechanism.joints``).
"""

from __future__ import annotations

import importlib
import re
from pathlib import Path

import numpy as np
import pytest
import sympy as sp

import course_lib
from course_lib.fivebar import FiveBar
from course_lib.fourbar import FourBar
from course_lib.mechanism import Mechanism
from course_lib.saw import Saw
from course_lib.slider_crank import OffsetSliderCrank

ROOT = Path(__file__).resolve().parents[1]
GLOSSARY = ROOT / "docs" / "glossary.md"

FOURBARS = [(0.06, 0.18, 0.12, 0.20),   # Grashof crank-rocker (the course's wiper)
            (0.12, 0.06, 0.18, 0.20),   # limited crank: two intervals
            (0.15, 0.10, 0.12, 0.20),   # non-Grashof triple-rocker
            (0.12, 0.18, 0.20, 0.06)]   # double-crank
FIVEBARS = [(0.10, 0.15, 0.15, 0.10, 0.08), (0.10, 0.15, 0.15, 0.10, 0.0), (0.12, 0.20, 0.17, 0.09, 0.15)]


def cross(a, b):
    """z of a × b for arrays (..., 2)."""
    a, b = np.asarray(a), np.asarray(b)
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def unit(angle):
    return np.stack([np.cos(angle), np.sin(angle)], axis=-1)


def same_angle(a, b):
    return np.abs(np.angle(np.exp(1j * (np.asarray(a) - np.asarray(b)))))


# ---------------------------------------------------------------- (a) every public name is on the page

def _code_identifiers(text: str) -> set[str]:
    """Every identifier written inside a code span of ``text``."""
    return {word for span in re.findall(r"`([^`]+)`", text) for word in re.findall(r"[A-Za-z_]\w*", span)}


def _readme_modules() -> list[str]:
    """The modules of the README's library reference table (its first column)."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme.split("## Library reference", 1)[1].split("\n## ", 1)[0]
    return re.findall(r"^\| `([a-z_]+)` \|", section, flags=re.MULTILINE)


def test_readme_lists_the_modules():
    modules = _readme_modules()
    expected = {"mechanism", "motion", "fourbar", "fivebar", "saw", "errors"}
    assert len(modules) >= 10 and expected <= set(modules), modules


def _public_names() -> dict[str, list[str]]:
    names = {"course_lib": list(course_lib.__all__)}
    for module in _readme_modules():
        names[f"course_lib.{module}"] = list(importlib.import_module(f"course_lib.{module}").__all__)
    # the README's checks row names its engine too: its parsers and verdicts are public names as well
    names["course_lib.checks.engine"] = list(importlib.import_module("course_lib.checks.engine").__all__)
    return names


@pytest.mark.parametrize("module", ["course_lib", *(f"course_lib.{m}" for m in _readme_modules()),
                                    "course_lib.checks.engine"])
def test_every_public_name_is_in_the_glossary(module):
    written = _code_identifiers(GLOSSARY.read_text(encoding="utf-8"))
    missing = [name for name in _public_names()[module] if name not in written]
    assert not missing, f"{module}: not on docs/glossary.md (as code): {missing}"


def test_the_thresholds_are_the_ones_written():
    from course_lib.mechanism import singular

    text = GLOSSARY.read_text(encoding="utf-8")
    assert (singular.SINGULAR, singular.NEAR_SINGULAR) == (1e-6, 1e-2)
    assert "`SINGULAR` = 1e-6" in text and "`NEAR_SINGULAR` = 1e-2" in text


# ---------------------------------------------------------------- (c) the σ statements of section 3

@pytest.mark.parametrize("lengths", FOURBARS)
@pytest.mark.parametrize(("branch", "sigma"), [("open", 1), ("crossed", -1)])
def test_fourbar_branch_is_sigma(lengths, branch, sigma):
    """open: B left of the directed line A → O4, e(θ3) × e(θ4) > 0, σ = +1; crossed the opposite."""
    linkage = FourBar(*lengths)
    theta2 = np.linspace(-np.pi, np.pi, 73)
    solution = linkage.solve(theta2, branch=branch, on_failure="nan")
    points = linkage.mechanism.joints(solution)
    side = cross(points["O4"] - points["A"], points["B"] - points["A"])
    turn = cross(unit(solution.theta3), unit(solution.theta4))
    found = np.asarray(solution.reachable) & (np.abs(turn) > 1e-9)
    assert found.sum() >= 20
    assert np.all(np.sign(side[found]) == sigma)
    assert np.all(np.sign(turn[found]) == sigma)
    for unknown in ("theta3", "theta4"):   # Motion.assembly gives σ for every unknown of the block
        assert np.all(np.asarray(solution.assembly[unknown])[found] == sigma)
    # the core, asked for σ by either unknown, gives the machine's branch
    for unknown in ("theta3", "theta4"):
        core = linkage.mechanism.solve({"theta2": theta2[found]}, assembly={unknown: sigma}, on_failure="nan")
        assert same_angle(core.position["theta3"], np.asarray(solution.theta3)[found]).max() < 1e-9
        assert same_angle(core.position["theta4"], np.asarray(solution.theta4)[found]).max() < 1e-9


def test_fourbar_one_instant_as_the_glossary_writes_it():
    linkage = FourBar(0.06, 0.18, 0.12, 0.20)
    for theta2 in (0.0, 0.7, 2.0, -2.5):
        for branch, sigma in (("open", 1), ("crossed", -1)):
            core = linkage.mechanism.solve({"theta2": theta2}, assembly={"theta3": sigma})
            machine = linkage.solve(theta2, branch=branch)
            assert same_angle(core.position["theta4"], machine.theta4) < 1e-12
            assert dict(core.assembly) == dict(machine.assembly) == {"theta3": sigma, "theta4": sigma}


def _dyad(chain: bool) -> Mechanism:
    """A four-bar's output dyad at B written two ways: both link vectors from their far end (A, O4) to the pin
    B, or as a chain A → B → O4 (the second vector reversed)."""
    theta2, ta, tb = sp.symbols("theta2 theta_a theta_b")
    A, O4 = sp.Matrix([0.06 * sp.cos(theta2), 0.06 * sp.sin(theta2)]), sp.Matrix([0.20, 0])
    first, second = 0.18 * sp.Matrix([sp.cos(ta), sp.sin(ta)]), 0.12 * sp.Matrix([sp.cos(tb), sp.sin(tb)])
    loop = A + first + second - O4 if chain else A + first - O4 - second
    return Mechanism([loop], [ta, tb], [theta2], {}, points={"A": A, "O4": O4, "B": A + first})


@pytest.mark.parametrize("chain", [False, True])
@pytest.mark.parametrize("sigma", [1, -1])
def test_dyad_rule(chain, sigma):
    """σ = +1: the pin left of the directed line from the first unknown's far end to the second's (either
    writing); e(θ_a) × e(θ_b) > 0 with both vectors drawn from their far end to the pin, < 0 for a chain."""
    dyad = _dyad(chain)
    motion = dyad.solve({"theta2": np.linspace(-3.0, 3.0, 31)}, assembly={"theta_a": sigma})
    points = dyad.joints(motion)
    side = cross(points["O4"] - points["A"], points["B"] - points["A"])
    turn = cross(unit(motion.position["theta_a"]), unit(motion.position["theta_b"]))
    assert np.all(np.sign(side) == sigma)
    assert np.all(np.sign(turn) == (-sigma if chain else sigma))
    assert np.all(np.asarray(motion.assembly["theta_b"]) == sigma)


@pytest.mark.parametrize("offset", [0.045, 0.0, -0.03])
@pytest.mark.parametrize(("branch", "sigma"), [("left", 1), ("right", -1)])
def test_slider_crank_branch_is_sigma(offset, branch, sigma):
    machine = OffsetSliderCrank(0.075, 0.170, offset)
    theta2 = np.linspace(-np.pi, np.pi, 37)
    motion = machine.solve(theta2, branch=branch)
    assert np.all(np.sign(np.cos(motion.theta3)) == -sigma)   # det J_b = rod·cos θ3, σ = −sign(det J_b)
    assert np.all(np.asarray(motion.assembly["theta3"]) == sigma)
    assert np.all(np.asarray(motion.assembly["xC"]) == sigma)
    core = machine.mechanism.solve({"theta2": theta2}, assembly={"xC": sigma})
    assert np.abs(core.position["xC"] - motion.xC).max() < 1e-12


@pytest.mark.parametrize("side", ["left", "right"])
def test_saw_has_no_closed_form_block_and_its_sides_are_the_slider_cranks(side):
    saw = Saw()
    theta2 = np.linspace(0.0, 2 * np.pi, 25)
    motion = saw.motion(theta2, assembly=side)
    sigma = {"left": 1, "right": -1}[side]
    assert saw.mechanism.closed_forms == [None]  # Newton's block: the course's closed form is its kernel
    assert {name: set(np.ravel(value)) for name, value in motion.assembly.items()} == {
        "r1": {sigma}, "theta1": {sigma}, "theta3": {sigma}}
    same = OffsetSliderCrank(saw.r2, saw.r3, saw.r1y).solve(theta2, branch=side)
    assert same_angle(motion.theta3, same.theta3).max() < 1e-12
    assert np.abs(motion.r1 * np.cos(motion.theta1) - same.xC).max() < 1e-12
    assert np.all(np.asarray(same.assembly["theta3"]) == sigma)
    # σ = −sign(det J_b), det J_b = −r1·r3·cos θ3 here (sympy), and the kernel keeps r1 < 0
    r1, th1, th3, r1y, r2, r3, th2 = sp.symbols("r1 theta1 theta3 r1y r2 r3 theta2")
    loops = sp.Matrix([-r1 * sp.cos(th1) + r2 * sp.cos(th2) + r3 * sp.cos(th3),
                       r1 * sp.sin(th1) - r2 * sp.sin(th2) - r3 * sp.sin(th3), r1 * sp.sin(th1) - r1y])
    det = sp.lambdify((r1, th1, th3, r3), sp.simplify(loops.jacobian([r1, th1, th3]).det()))
    assert np.all(motion.r1 < 0)
    # one instant alone keeps the core's angle rule, [−π, π]; a sweep from θ2 = 0 stays near π (the glossary)
    assert round(saw.motion(0.0, assembly="right").theta1, 3) == -2.955  # outside (−π/2, π/2]: r1 < 0 kept
    alone, swept = saw.motion(1.0).theta3, saw.motion([0.0, 1.0]).theta3[1]
    assert round(alone, 3) == -3.035 and round(swept, 3) == 3.248 and abs(swept - alone - 2 * np.pi) < 1e-12
    assert np.all(-np.sign(det(motion.r1, motion.theta1, motion.theta3, saw.r3)) == sigma)


@pytest.mark.parametrize("lengths", FIVEBARS)
def test_fivebar_forward_arms_up_is_sigma(lengths):
    """Arms up (P3 left of P4 → P2, (P2 − P4) × (P3 − P4) > 0) is σ = +1; the course's mode=+1 is the larger
    Y3: the geometric σ while D > 0, the opposite where D < 0."""
    robot = FiveBar(*lengths)
    rng = np.random.default_rng(7)
    theta1, theta4 = rng.uniform(-np.pi, np.pi, (2, 800))
    D = robot.forward_coefficients(theta1, theta4)["D"]
    results = {}
    for mode in (1, -1):
        result = robot.forward(theta1, theta4, mode, on_failure="nan")
        points = robot.mechanism.joints(result)
        side = cross(points["P2"] - points["P4"], points["P3"] - points["P4"])
        found = np.asarray(result.reachable) & (np.abs(side) > 1e-9)
        assert (found & (D > 0)).sum() >= 50 and (found & (D < 0)).sum() >= 20
        geometric = np.sign(side[found])
        assert np.all(np.asarray(result.assembly["x3"])[found] == geometric)
        assert np.all(np.asarray(result.assembly["y3"])[found] == geometric)
        assert np.all(geometric[D[found] > 0] == mode)
        assert np.all(geometric[D[found] < 0] == -mode)
        results[mode] = result
    both = np.asarray(results[1].reachable)
    assert np.all(np.asarray(results[1].y3)[both] >= np.asarray(results[-1].y3)[both])
    # the core, asked for arms up / down by σ, puts P3 on that side
    for sigma in (1, -1):
        core = robot.mechanism.solve({"theta1": theta1[:100], "theta4": theta4[:100]}, assembly={"y3": sigma},
                                     on_failure="nan")
        points = robot.mechanism.joints(core)
        side = cross(points["P2"] - points["P4"], points["P3"] - points["P4"])
        found = np.asarray(core.converged) & (np.abs(side) > 1e-9)
        assert found.sum() >= 30 and np.all(np.sign(side[found]) == sigma)


@pytest.mark.parametrize("lengths", FIVEBARS)
@pytest.mark.parametrize("modes", [(1, 1), (-1, 1), (1, -1), (-1, -1)])
def test_fivebar_inverse_modes_are_minus_sigma(lengths, modes):
    """σ(theta1) = −σ1, σ(theta4) = −σ2; the core's σ is +1 where the leg turns counter-clockwise at its
    elbow, and the course's σi = +1 puts the elbow left of the line from its motor to P3."""
    robot = FiveBar(*lengths)
    rng = np.random.default_rng(11)
    x3, y3 = rng.uniform(-0.35, 0.35, (2, 1500))
    result = robot.inverse(x3, y3, modes, on_failure="nan")
    points = robot.mechanism.joints(robot.mechanism.motion_of(
        {"x3": x3, "y3": y3}, {"theta1": result.theta1, "theta4": result.theta4}))
    P1, P2, P3, P4, P5 = (points[f"P{k}"] for k in range(1, 6))
    leg1, leg4 = cross(P2 - P1, P3 - P2), cross(P4 - P5, P3 - P4)
    elbow1, elbow4 = cross(P3 - P1, P2 - P1), cross(P3 - P5, P4 - P5)   # elbow left of motor → P3
    found = np.asarray(result.reachable) & (np.abs(leg1) > 1e-9) & (np.abs(leg4) > 1e-9)
    assert found.sum() >= 200
    sigma1 = np.asarray(result.assembly["theta1"])[found]
    sigma4 = np.asarray(result.assembly["theta4"])[found]
    assert np.all(sigma1 == -modes[0]) and np.all(sigma4 == -modes[1])
    assert np.all(np.sign(leg1[found]) == sigma1) and np.all(np.sign(leg4[found]) == sigma4)
    assert np.all(np.sign(elbow1[found]) == modes[0]) and np.all(np.sign(elbow4[found]) == modes[1])
