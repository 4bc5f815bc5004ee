"""The one drawing path: LinkageArtist (every explorer and animation moves its links through it),
animate_linkage, and the explorer of any declared Mechanism; and a named error, naming the
argument and showing its value, for every misuse of the plotting functions."""

from __future__ import annotations

import math

import matplotlib
import numpy as np
import pytest
import sympy as sp
from matplotlib.figure import Figure

from course_lib.errors import CourseLibError, InvalidArgumentError
from course_lib.fivebar import FiveBar
from course_lib.fourbar import FourBar
from course_lib.mechanism import Mechanism
from course_lib.newton import newton
from course_lib.plotting import (
    LinkageArtist,
    animate_linkage,
    animation_html,
    draw,
    draw_linkage,
    plot_convergence,
)
from course_lib.saw import Saw
from course_lib.slider_crank import OffsetSliderCrank
from course_lib.widgets import mechanism_explorer

matplotlib.use("Agg")

TH, X = sp.symbols("theta x", real=True)
CRANK, ROD = 0.05, 0.12
#: an in-line slider-crank declared on the core: the slider's travel x is the unknown (a length)
SLIDER_CRANK = Mechanism(
    loops=[sp.Matrix([CRANK * sp.cos(TH) + ROD * sp.cos(sp.Symbol("phi")) - X,
                      CRANK * sp.sin(TH) + ROD * sp.sin(sp.Symbol("phi"))])],
    unknowns=[sp.Symbol("phi"), X], inputs=[TH],
    points={"O": sp.Matrix([0, 0]), "A": sp.Matrix([CRANK * sp.cos(TH), CRANK * sp.sin(TH)]),
            "B": sp.Matrix([X, 0])},
    links=[("O", "A"), ("A", "B")])
TURN = SLIDER_CRANK.solve({TH: np.radians(np.arange(0, 360, 10))}, guess={"phi": 0.0, X: CRANK + ROD})
S, Y = sp.symbols("s y")
#: a sweep of another mechanism (input s, unknown y), the wrong motion for SLIDER_CRANK's explorer
OTHER_TURN = Mechanism([Y - sp.cos(S)], [Y], [S]).solve({S: np.linspace(0.0, 1.0, 5)}, guess={Y: 1.0})


def slider_x(theta):
    """Slider position by the law of cosines (an independent route)."""
    return CRANK * math.cos(theta) + math.sqrt(ROD**2 - (CRANK * math.sin(theta)) ** 2)


def test_the_artist_puts_each_link_between_its_points_and_hides_what_is_unknown():
    ax = Figure().add_subplot()
    artist = LinkageArtist(ax, {"crank": ("O", "A"), "rod": ("A", "B")}, blocks=["B"], labels={"A": "A"},
                           label_offset=0.01)
    points = {"O": (0.0, 0.0), "A": (0.03, 0.04), "B": (0.15, 0.0)}
    artist.move(points)
    assert artist.lines["rod"].get_xydata().tolist() == [[0.03, 0.04], [0.15, 0.0]]
    assert artist.lines["blocks"].get_xydata().tolist() == [[0.15, 0.0]]
    assert artist.texts["A"].get_position() == pytest.approx((0.04, 0.05))
    artist.move({**points, "B": (math.nan, 0.0)})
    assert artist.lines["crank"].get_visible() and not artist.lines["rod"].get_visible()
    assert artist.lines["joints"].get_xydata().tolist() == [[0.0, 0.0], [0.03, 0.04]]
    artist.move(np.array([[0.0, 0.0], [1.0, 1.0]]))  # keys are indices into an array: no link matches
    assert not artist.lines["crank"].get_visible()


def test_an_animation_has_one_frame_per_instant_up_to_its_cap_and_a_still():
    paths = SLIDER_CRANK.joints(TURN)
    html = animate_linkage(SLIDER_CRANK.links, paths, ground=["O"], trace=["A"], blocks=["B"],
                           caption=lambda k: f"frame {k}", title="slider-crank")
    assert html.frame_count == len(TURN.inputs["theta"]) and html.still_png[:4] == b"\x89PNG"
    assert animate_linkage(SLIDER_CRANK.links, paths, max_frames=12).frame_count == 12


def test_one_instant_is_drawn_in_one_call():
    # once refused with "points must give every point one (x, y) per frame; got shapes {(2,)}"
    instant = {"O": (0.0, 0.0), "A": (0.03, 0.04), "B": (slider_x(0.927295218), 0.0)}
    ax = draw({"crank": ("O", "A"), "rod": ("A", "B")}, instant, ground=["O"], blocks=["B"])
    assert ax.lines[1].get_xydata().tolist() == [[0.03, 0.04], [instant["B"][0], 0.0]]
    assert animate_linkage([("O", "A"), ("A", "B")], instant).frame_count == 1
    assert animate_linkage([(0, 1)], np.array([[0.0, 0.0], [1.0, 1.0]])).frame_count == 1  # (P, 2)
    sweep = draw(SLIDER_CRANK, TURN, frame=9, trace=["A"])  # a declaration and a Motion: frame 9 is 90°
    assert sweep.lines[-2].get_xydata()[1] == pytest.approx([0.0, CRANK], abs=1e-15)
    with pytest.raises(CourseLibError, match=r"frame must be a whole number from 0 to 35; got 36"):
        draw(SLIDER_CRANK, TURN, frame=36)


@pytest.mark.parametrize("machine, motion, names", [
    (FourBar(0.06, 0.18, 0.12, 0.20), lambda m: m.motion(np.radians(np.arange(0, 360, 30)), 10.0),
     ("crank", "coupler", "rocker", "ground")),
    (OffsetSliderCrank(0.075, 0.170, 0.045), lambda m: m.motion(np.linspace(0, 6, 12), branch="left"),
     ("crank", "rod")),
    (Saw(), lambda m: m.motion(np.linspace(0, 6, 12), 6.0), ("crank", "rod")),
    (FiveBar(0.10, 0.15, 0.15, 0.10, 0.08), lambda m: m.motion(np.linspace(1.0, 1.4, 5), 2.0), tuple(
        f"l{k}" for k in range(1, 6))),
])
def test_the_machines_are_drawn_animated_and_explored_from_their_declaration(machine, motion, names):
    sweep = motion(machine)
    ax = draw(machine, sweep, frame=3)
    # links named on the declaration, each drawn between its declared points at that instant
    points = machine.mechanism.joints(sweep)
    for name, (start, end) in machine.mechanism.links.named().items():
        line = [line for line in ax.lines if line.get_gid() == name]  # (gid: the link's name)
        xy = np.array([points[start][3], points[end][3]])
        assert len(line) == 1 and np.array_equal(line[0].get_xydata(), xy), name
    assert machine.mechanism.links.names == names
    assert animate_linkage(machine, sweep, max_frames=4).frame_count == 4
    if len(machine.mechanism.inputs) == 1:  # the explorer takes one input
        explorer = mechanism_explorer(machine.mechanism, sweep)
        assert explorer.update(**{next(iter(explorer.controls)): 30.0}).status == "ok"


def test_the_mechanism_explorer_draws_the_slider_where_the_law_of_cosines_puts_it():
    explorer = mechanism_explorer(SLIDER_CRANK, TURN, ground=["O"], blocks=["B"], rates={TH: 10.0})
    for degrees in (-150.0, -20.0, 35.0, 90.0, 170.0):
        readout = explorer.update(theta_deg=degrees)
        assert readout.status == "ok"
        (x, y), = explorer.artists["blocks"].get_xydata()
        assert abs(x - slider_x(math.radians(degrees))) < 1e-12 and y == 0.0
    assert explorer.update(theta_deg=float("nan")).status == "invalid"


def test_the_mechanism_explorer_reports_a_value_where_the_loop_cannot_close():
    short = SLIDER_CRANK.with_parameters({})  # the same declaration ...
    long_crank = Mechanism(short.equations.subs(CRANK, 0.2), short.unknowns, short.inputs,
                           points={"O": sp.Matrix([0, 0]), "A": 0.2 * sp.Matrix([sp.cos(TH), sp.sin(TH)]),
                                   "B": sp.Matrix([X, 0])}, links=[("O", "A")], sliders=["B"])
    turn = long_crank.solve({TH: np.radians(np.arange(-30, 31, 5))}, guess={"phi": 0.0, X: 0.32})
    explorer = mechanism_explorer(long_crank, turn)
    readout = explorer.update(theta_deg=90.0)  # 0.2 m crank, 0.12 m rod: the rod cannot reach the line
    assert readout.status == "unreachable" and "theta = 90" in readout.lines[0]
    assert not explorer.artists["link 1"].get_visible()
    assert explorer.update(theta_deg=0.0).status == "ok"


# ---------------------------------------------------------------- misuse, by function
AX = Figure().add_subplot()
POINTS, LINKS = [(0, 0), (1, 0), (1, 1)], [(0, 1, "a"), (1, 2, "b")]
RESULT = newton(lambda x: x**2 - 2, 1.0)
FIG = Figure()
FRAMES = np.zeros((3, 2, 2)) + [[0.0, 0.0], [1.0, 0.0]]
MISUSES = {
    "draw_linkage": (lambda **kw: draw_linkage(**{"points": POINTS, "links": LINKS, "ax": AX, **kw}), {
        "points": [None, "abc", [(0, 0), (1,)], [(0, math.nan), (1, 0), (1, 1)], np.zeros((0, 2)), [1, 2]],
        "links": [None, "ab", [(0, 1)], [("0", 1, "a")], [(0.5, 1, "a")], [(-1, 1, "a")], [(0, 9, "a")]],
        "ax": ["ax", 3],
        "joint_labels": [["a"], "abc", 5],
        "ground": [[5], "0", None, [True]],
        "linestyle": ["zz", None],
        "alpha": [2, math.nan, "0.5", -0.1],
    }),
    "plot_convergence": (lambda **kw: plot_convergence(**{"result": RESULT, **kw}), {
        "result": [None, "abc", 1.4],
        "exact": [[1, 2], "1.4", math.nan],
        "names": ["x", 5, ["x", "y"]],
    }),
    "animation_html": (lambda **kw: animation_html(**{"fig": FIG, "update": print, "frames": 3, **kw}), {
        "fig": [None, "fig"],
        "update": [None, 3, lambda: None, lambda k: 1 / 0],
        "frames": [0, -1, 2.5, True, "3"],
        "interval_ms": [math.nan, 0, "80"],
        "dpi": [0, 1e6, math.inf],
        "max_frames": [0, 1.5],
    }),
    "LinkageArtist": (lambda **kw: LinkageArtist(**{"ax": AX, "links": [(0, 1)], **kw}), {
        "ax": [None, "ax"],
        "links": [None, [(0,)], ["ab"], 7],
        "styles": [{"link 1": {"zz": 1}}, {"link 9": {}}],
        "blocks": ["B", 3],
    }),
    "LinkageArtist.move": (lambda points: LinkageArtist(AX, [(0, 1)]).move(points), {
        "points": [None, "ab", {0: (1,), 1: (0, 0)}, {0: "ab"}, np.zeros((2, 3))],
    }),
    "animate_linkage": (lambda **kw: animate_linkage(**{"links": [(0, 1)], "points": FRAMES, **kw}), {
        "links": [None, [(0, 5)]],
        "points": [None, np.zeros((3, 3)), np.full((3, 2, 2), math.nan),
                   {0: np.zeros((3, 2)), 1: np.zeros((4, 2))}],
        "ground": [[7], "0"],
        "trace": [[7]],
        "caption": ["t", lambda k: 1 / 0],
        "background": [5],
        "size": [(0, 1), "big", (1, 2, 3), (100, 3)],
        "dpi": [-1, 1e5],
    }),
    "mechanism_explorer": (lambda **kw: mechanism_explorer(**{"mechanism": SLIDER_CRANK, "motion": TURN,
                                                              **kw}), {
        "mechanism": [None, "crank", TURN],
        "motion": [None, SLIDER_CRANK, SLIDER_CRANK.solve({TH: 0.5}, guess={"phi": 0.0, X: 0.17}),
                   OTHER_TURN],
        "ground": [["Q"], "O"],
        "trace": [["Q"]],
        "blocks": ["B"],
        "styles": [{"link 9": {}}, {"link 1": {"zz": 1}}],
        "rates": [{TH: "10"}, {TH: math.nan}, {"psi": 1.0}],
        "readout": ["text", 3],
        "size": [(0, 1), "big", (math.inf, 2)],
    }),
}
CASES = [(function, argument, value) for function, (_, table) in MISUSES.items()
         for argument, values in table.items() for value in values]


@pytest.mark.parametrize(("function", "argument", "value"), CASES,
                         ids=[f"{f}-{a}-{k}" for k, (f, a, _) in enumerate(CASES)])
def test_every_misuse_of_the_plotting_functions_gets_a_named_error(function, argument, value):
    call, _ = MISUSES[function]
    with pytest.raises(CourseLibError) as caught:
        call(value) if function == "LinkageArtist.move" else call(**{argument: value})
    message = str(caught.value)
    assert argument in message, message
    assert any(text in message for text in shown(value)), message


def shown(value) -> list[str]:
    """Texts of which one must appear in the message: the value, an entry of it, or what it is."""
    texts = [repr(value), str(value), type(value).__name__, "nan", "shape", "division by zero",
             "positional argument", "zz"]
    if isinstance(value, dict):
        value = [*value, *value.values()]
    if isinstance(value, list | tuple):
        texts += [text for entry in value for text in shown(entry)]
    return texts


def test_sliders_is_the_declarations_word_and_blocks_its_older_name():
    links, points = {"rod": ("A", "C")}, {"A": (0.0, 0.0), "C": (0.2, 0.05)}
    for given in ({"sliders": ["C"]}, {"blocks": ["C"]}, {"sliders": ["C"], "blocks": ["C"]}):
        ax = draw(links, points, **given)
        block = next(line for line in ax.lines if line.get_marker() == "s")   # the slider block, a square
        assert block.get_xydata().tolist() == [[0.2, 0.05]], given
        matplotlib.pyplot.close(ax.figure)
    with pytest.raises(InvalidArgumentError, match=r"sliders=\['C'\] and blocks=\['A'\]"):
        draw(links, points, sliders=["C"], blocks=["A"])
