"""One vocabulary in every lesson and exercise set: no code line uses an older spelling the glossary keeps
only for compatibility (docs/glossary.md, "Older spellings").  Counted per notebook: zero everywhere."""

import json
import re
from pathlib import Path

import pytest

ROOT = Path(__file__).parents[1]
NOTEBOOKS = sorted((ROOT / "notebooks").glob("*.ipynb")) + sorted((ROOT / "notebooks").glob("*/*.ipynb"))

#: older spelling → the one the lessons use (both as the glossary lists them)
OLDER = {
    r"\bbranch\s*=": "assembly=",
    r"\bon_unreachable\b|\bon_singular\b": "on_failure=",
    r"\.mask\b": ".unreachable",
    r"\bdraw_linkage\b": "draw",
    r"\bblocks\s*=": "sliders= (the declaration's word)",
    r"\bjoint_positions\b": "mechanism.joints(motion)",
    r"\bnewton\.is_singular\b|\bfrom course_lib\.newton import[^\n]*\bis_singular\b":
        "newton.ill_conditioned",
    r"\b(\w+)(?:\[[^\]]*\])?\.reachable\b": ".converged (a Motion's; `reachable` is a WorkspaceMap's grid)",
    r"\bsaw\.(?:velocity|acceleration)_jacobian\b"
    r"|\bfrom course_lib\.saw import[^\n]*\b(?:velocity|acceleration)_jacobian\b":
        "saw.velocity_residual_jacobian, saw.acceleration_residual_jacobian",
    r"\banimate_linkage\b": "animate",
    r"\bmechanism_explorer\b": "explore",
}


def code_lines(path: Path) -> list[str]:
    cells = json.loads(path.read_text())["cells"]
    return [line for cell in cells if cell["cell_type"] == "code"
            for line in "".join(cell["source"]).splitlines()]


def bound_names(lines: list[str], call: str = r"\w+\.workspace\(") -> set[str]:
    """Names bound in the notebook to what ``call`` returns (``x = robot.workspace(...)``, a dict of them,
    or an item of that dict); by default WorkspaceMaps, whose ``reachable`` is the map's own field."""
    names = {m.group(1) for line in lines
             for m in re.finditer(r"(\w+)\s*=\s*(?:\{[^}]*:\s*)?" + call, line)}
    item = re.compile(r"(\w+)\s*=\s*(\w+)\[[^\]]*\]\s*(?:#.*)?$")
    return names | {m.group(1) for line in lines for m in item.finditer(line) if m.group(2) in names}


workspace_names = bound_names

#: older names of a result's values, counted only on names bound to that kind of result: (pattern, the one)
OLDER_MAP_VALUES = (r"\b(\w+)(?:\[[^\]]*\])?\.(?:x|y)\b", "WorkspaceMap.x3, .y3")
OLDER_SLIDER_VALUES = (r"\b(\w+)\.(?:x|v|a)\b", "SliderCrankMotion.xC, .v_xC, .a_xC")
OLDER_NEWTON_VALUES = (r"\b(\w+)(?:\[[^\]]*\])?\.singular\b",
                       "NewtonResult.ill_conditioned (Motion.singular is the mechanism's rule)")
#: what returns a Newton run's result: a call of newton / newton_batch (also as newton.newton or
#: course_lib.newton), a Motion's .newton, a SawSolution's stages
NEWTON_CALL = r"(?:(?:\w+\.)*newton(?:_batch)?\(|\w+\.newton\b|\w+\.stages\[)"


def newton_names(lines: list[str]) -> set[str]:
    """Names bound to a Newton run's result (``NewtonResult``, ``BatchNewtonResult``), whose ``singular`` is
    the older name of ``ill_conditioned``; a Motion's ``singular`` is not counted."""
    return bound_names(lines, NEWTON_CALL)


def slider_names(lines: list[str]) -> set[str]:
    """Names bound to a slider-crank's solve: ``OffsetSliderCrank(...).solve(...)``, or ``m.solve(...)`` of a
    name bound to ``OffsetSliderCrank(...)``."""
    machines = {m.group(1) for line in lines
                for m in re.finditer(r"(\w+)\s*=\s*OffsetSliderCrank\(", line)}
    either = "".join(f"|{name}" for name in machines)
    call = r"(?:OffsetSliderCrank\([^)]*\)" + either + r")\.(?:solve|motion)\("
    return bound_names(lines, call)


@pytest.mark.parametrize("path", NOTEBOOKS, ids=lambda p: p.relative_to(ROOT / "notebooks").as_posix())
def test_no_code_line_in_an_older_spelling(path):
    lines = code_lines(path)
    maps, sliders, runs = workspace_names(lines), slider_names(lines), newton_names(lines)
    found = []
    for line in lines:
        for pattern, one in OLDER.items():
            for match in re.finditer(pattern, line):
                if match.groups() and match.group(1) in maps:
                    continue
                found.append(f"{line.strip()}  →  {one}")
        for names, (pattern, one) in ((maps, OLDER_MAP_VALUES), (sliders, OLDER_SLIDER_VALUES),
                                      (runs, OLDER_NEWTON_VALUES)):
            found += [f"{line.strip()}  →  {one}" for m in re.finditer(pattern, line) if m.group(1) in names]
    assert not found, "\n".join(found)


def test_the_glossary_lists_every_older_spelling_this_test_counts():
    glossary = (ROOT / "docs" / "glossary.md").read_text()
    older = glossary.split("### Older spellings", 1)[1].split("\n## ", 1)[0]
    for word in ("branch=", "on_unreachable=", "on_singular=", "mask", "draw_linkage", "joint_positions",
                 "blocks=", "is_singular", "reachable", "NewtonResult.singular", "BatchNewtonResult.singular",
                 "saw.velocity_jacobian", "saw.acceleration_jacobian", "animate_linkage",
                 "mechanism_explorer"):
        assert word in older, word


def test_the_pattern_counts_what_it_should():
    lines = ['m = wiper.solve(t, branch="open")', "print(attempt.mask)", "ok = back.reachable",
             "maps = {k: robot.workspace(g, g, k) for k in modes}", "one = maps[(1, 1)]",
             "ok = one.reachable", "ok = maps[k].reachable",
             'x = robot.inverse(0, 0.2, on_unreachable="nan")']
    maps = workspace_names(lines)
    hits = [line for line in lines for pattern in OLDER for m in re.finditer(pattern, line)
            if not (m.groups() and m.group(1) in maps)]
    assert maps == {"maps", "one"} and hits == [lines[0], lines[1], lines[2], lines[7]]


def test_the_older_value_names_are_counted_on_their_results_only():
    lines = ["w = robot.workspace(g, g)", "plt.contourf(w.x, w.y3, w.reachable)",
             "maps = {k: robot.workspace(g, g, k) for k in m}",
             "textbook = OffsetSliderCrank(crank=R2, rod=R3).solve(0.0)", "print(textbook.x, textbook.v_xC)",
             "slider = OffsetSliderCrank(0.1, 0.3)", "m = slider.motion(t)", "gap = m.a - other.a",
             "r = newton(f, j, 1.0)", "print(r.x, maps[(1, 1)].y)"]
    maps, sliders = workspace_names(lines), slider_names(lines)
    assert maps == {"w", "maps"} and sliders == {"textbook", "m"}
    hits = [(line, m.group(0)) for line in lines for names, (pattern, _) in
            ((maps, OLDER_MAP_VALUES), (sliders, OLDER_SLIDER_VALUES))
            for m in re.finditer(pattern, line) if m.group(1) in names]
    assert hits == [(lines[1], "w.x"), (lines[4], "textbook.x"), (lines[7], "m.a"),
                    (lines[9], "maps[(1, 1)].y")]



def test_the_older_newton_and_saw_names_are_counted_and_nothing_else():
    lines = ["again = newton_batch(F_batch, seeds, jac=J_batch, max_iter=50)",
             "stuck = ~again.converged & again.singular",
             "run = course_lib.newton(f, 1.0, jac=j)", "print(run.ill_conditioned, run.singular)",
             "first = motion.newton", "assert not first.singular",
             "stage = solution.stages['position']", "stage.singular",
             # a Motion's singular is the mechanism's rule: not counted
             "pose = robot.forward(1.2, 1.9, mode=1)", "assert not pose.singular",
             "sweep = linkage.solve({th2: angles})", "print(sweep.singular.any())",
             "J = saw.acceleration_jacobian(q_rest)", "from course_lib.saw import velocity_jacobian",
             "J = saw.acceleration_residual_jacobian(q_rest)",
             "V = robot.velocity_jacobian(1.2, 1.9, x3, y3)"]
    runs = newton_names(lines)
    assert runs == {"again", "run", "first", "stage"}
    pattern, _ = OLDER_NEWTON_VALUES
    hits = [m.group(0) for line in lines for m in re.finditer(pattern, line) if m.group(1) in runs]
    assert hits == ["again.singular", "run.singular", "first.singular", "stage.singular"]
    older = [line for line in lines for p in OLDER if re.search(p, line)]
    assert older == [lines[12], lines[13]]


# ----------------------------------------------------------------- single letters with one meaning each

#: a letter in a second meaning, as a pattern over a notebook's whole text (markdown and code) → its name now
SECOND_MEANINGS = {
    # t is time: the half-angle tangent is v (lesson 03's v, lesson 09's v1, v2), as course_lib's LoopForm
    r"\bt_?\{?\d?\}?\s*=\s*\\?tan\s*\\?\(": "v = tan(θ/2)",
    r"half_angle\([^()\n]*,\s*t\d?\s*\)": "half_angle(…, v)",
    r"sp\.symbols?\(\"t\d?(?: t\d)?\"": "v, v1, v2 for tan(θ/2)",
    # A, B, C are points: the half-angle quadratic's coefficients are a, b, c (Norton's A, B, C)
    r"\bB_?\s*(?:\^|\*\*)\s*2\s*-\s*4\s*\*?\s*A_?\s*\*?\s*C_?\b": "b² − 4ac",
    r"\bA_?\s*\*?\s*[tv]\s*(?:\^|\*\*)\s*2\s*\+\s*B": "a v² + b v + c",
    r"sp\.symbols\(\"A B C\"\)": "a, b, c",
}
#: the coupler point's distance from A beside Grashof's p, q: in a notebook that writes s + l … p + q, the
#: distance is l_AP (the library's argument p, stated where the lesson uses it)
COUPLER_P = r"at distance \$p\$|\$p = 0\.10|^\s*p\s*,\s*delta\s*=|\bA, p, delta\s*="


def notebook_text(path: Path) -> str:
    return "\n".join("".join(cell["source"]) for cell in json.loads(path.read_text())["cells"])


def second_meanings(text: str) -> list[str]:
    found = [f"{m.group(0)!r}  →  {one}" for pattern, one in SECOND_MEANINGS.items()
             for m in re.finditer(pattern, text)]
    if "p + q" in text:
        found += [f"{m.group(0)!r}  →  l_AP" for m in re.finditer(COUPLER_P, text, re.M)]
    return found


#: notebooks that still use a letter in its second meaning, and where: the test fails once they no longer do
NOT_YET: dict[str, str] = {}


@pytest.mark.parametrize("path", [
    pytest.param(path, marks=pytest.mark.xfail(strict=True, reason=NOT_YET[path.name]))
    if path.name in NOT_YET else path for path in NOTEBOOKS],
    ids=lambda p: p.relative_to(ROOT / "notebooks").as_posix())
def test_no_letter_in_a_second_meaning(path):
    found = second_meanings(notebook_text(path))
    assert not found, "\n".join(found)


def test_the_second_meanings_are_found_where_they_are():
    older = ["With $t = \\tan(\\theta_4/2)$, the quadratic $A t^2 + B t + C = 0$",
             'polynomial = half_angle(freudenstein, th4, t)', 't1, t2 = sp.symbols("t1 t2", real=True)',
             'print(f"B^2 - 4AC = {d}")', "theta4 = 2 * np.arctan2(-B_ + np.sqrt(B_**2 - 4 * A_ * C_), 2)",
             'A, B, C = sp.symbols("A B C")', "$t_1 = \\tan(\\theta_1/2)$"]
    assert all(second_meanings(line) for line in older), [line for line in older if not second_meanings(line)]
    now = ["With $v = \\tan(\\theta_4/2)$, the quadratic $a v^2 + b v + c = 0$", "b**2 - 4 * a * c",
           'half_angle(leg1, theta1, v1)', "the time t, θ2(t)", "A, B, C = O2 + R(r2, theta2), R(l4, t4), P"]
    assert not any(second_meanings(line) for line in now)
    grashof = "$s + l < p + q$"
    assert second_meanings(grashof + "\nthe point $P$ at distance $p$ from $A$")
    assert second_meanings(grashof + "\np, delta = 0.10, np.radians(40)")
    assert not second_meanings(grashof + "\nl_AP, delta = 0.10, np.radians(40)")
    assert not second_meanings("p, delta = 0.10, np.radians(40)")      # no Grashof p beside it
