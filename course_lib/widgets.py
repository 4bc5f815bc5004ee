"""Interactive explorers (ipywidgets): move a slider, watch the mechanism move.

Each builder returns an :class:`Explorer`: controls, one Agg figure redrawn in cached layers into a PNG
image, a readout, and ``update(**state)``, which never raises for a value (a state the mechanism cannot
take is explained); a builder argument outside its slider's range raises ``InvalidGeometryError``.
Without a widget manager (GitHub, ``nbconvert``) an explorer shows a PNG of figure and readout.
Units: metres and seconds; sliders show angles in degrees (the state keys say so: ``theta2_deg``).
Every explorer here is an :class:`ExplorerSpec` (controls, panels, linkage, draw step) on one builder,
:func:`build_explorer`; ``mechanism_explorer`` makes one for any declared mechanism or machine.

>>> explorer = fourbar_explorer()
>>> explorer.update(theta2_deg=90.0).status, explorer.update(assembly="sideways").status
('ok', 'invalid')
"""

from __future__ import annotations

import base64
import html
import io
import math
import numbers
import textwrap
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field

import ipywidgets as widgets
import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.colors import to_rgba_array
from matplotlib.figure import Figure
from matplotlib.patches import Circle, Polygon
from PIL import Image as PILImage

from .errors import CourseLibError, InvalidArgumentError, InvalidGeometryError
from .fourbar import BRANCHES, FourBar
from .planar import wrap_angle
from .plotting import (
    LINK_COLORS,
    LinkageArtist,
    _figure_size,
    _ground_symbol,
    _motion_background,
    _Quantizer,
    _sliders,
)
from .thresholds import APPROACH, COINCIDENT, TRANSMISSION_MIN_DEG

__all__ = ["Explorer", "ExplorerSpec", "ExplorerStage", "Readout", "build_explorer", "fourbar_explorer",
           "saw_explorer", "fivebar_explorer", "mechanism_explorer", "explore"]

_STYLE = {"description_width": "120px"}  # shared by every slider and toggle, so the columns line up
_COLUMN_PX = 360  # the controls' column, left of the picture
_WIDE = "course-explorer-wide"  # a slider laid out over the explorer's whole width (the angles)
_ERROR_COLOR = "#b00020"


@dataclass(frozen=True)
class Readout:
    """One update step's ``status`` ("ok", or why the picture is not the requested state: "unreachable",
    "singular", "invalid" for a refused input, "error") and readout ``lines``.

    >>> Readout("ok", ("a < b", "c")).text
    'a < b\\nc'
    >>> Readout("ok", ("a < b",)).html()
    '<div class="course-explorer-readout-text" style="line-height:1.4">a &lt; b</div>'
    """

    status: str
    lines: tuple[str, ...] = ()

    text = property(lambda self: "\n".join(self.lines), doc="The readout as plain text, one line per entry.")

    def html(self) -> str:
        """The readout as HTML (escaped), red when the status is not "ok"."""
        body = "<br>".join(html.escape(line) for line in self.lines)
        color = "" if self.status == "ok" else f"color:{_ERROR_COLOR};"
        return f'<div class="course-explorer-readout-text" style="{color}line-height:1.4">{body}</div>'


@dataclass(eq=False)
class Explorer:
    """Controls + one reused figure + readout, tied together by a plain update step.

    ``controls``: input widgets by state key; ``draw(state, geometry_changed) -> Readout`` moves the
    ``artists`` (``animated`` ones drawn at every event); ``geometry_keys``: the state keys that alter
    the ``geometry_artists`` (a cached layer); ``extra``: more widgets.

    >>> explorer = fourbar_explorer()
    >>> explorer.status, sorted(explorer.state)[:3], "Grashof" in explorer.message
    ('ok', ['assembly', 'coupler', 'crank'], True)
    >>> explorer.render()[:4] == explorer.picture()[:4] == b"\\x89PNG"
    True
    """

    name: str
    controls: dict[str, widgets.ValueWidget]
    figure: Figure
    artists: dict[str, object]
    draw: Callable[[Mapping[str, object], bool], Readout]
    geometry_keys: tuple[str, ...] = ()
    extra: tuple[widgets.Widget, ...] = ()
    geometry_artists: tuple[str, ...] = ()
    last: Readout = field(default=Readout("ok"), init=False)

    def __post_init__(self) -> None:
        self.canvas = FigureCanvasAgg(self.figure)
        self._geometry_layer = [self.artists[name] for name in self.geometry_artists]
        for artist in self._geometry_layer:
            artist.set_animated(True)  # drawn into the cached background, not the base
        moving = [artist for name, artist in self.artists.items()
                  if name not in self.geometry_artists and artist.get_animated()]
        self._moving = sorted(moving, key=lambda artist: artist.get_zorder())  # stable: ties keep their order
        self._base = self._background = self._base_limits = self._background_visible = None
        self._palette = self._drawn_geometry = None
        self._holding = False
        width = self.figure.bbox.width
        self.image = widgets.Image(format="png", layout={"width": f"{width:.0f}px"}).add_class(
            "course-explorer-image")
        self.readout = widgets.HTML(layout={"width": f"{width:.0f}px"}).add_class("course-explorer-readout")
        for control in self.controls.values():
            control.observe(self._on_change, names="value")
        # the angle sliders span the explorer (or the output, where narrower), above the picture, whose
        # readout changes height with the state, so nothing above them moves: a turn in over 360 pixels
        wide = [control for control in self.controls.values() if _WIDE in control._dom_classes]
        for control in wide:
            control.layout.width, control.layout.max_width = "100%", f"{_COLUMN_PX + width:.0f}px"
        column = widgets.VBox([control for control in self.controls.values() if control not in wide]
                              + list(self.extra), layout={"width": f"{_COLUMN_PX}px"})
        view = widgets.VBox([self.image, self.readout])
        self.widget = widgets.VBox([*wide, widgets.HBox([column, view])]).add_class("course-explorer")
        self.refresh()

    state = property(lambda self: {key: control.value for key, control in self.controls.items()},
                     doc="The current input values by key (a copy).")
    status = property(lambda self: self.last.status, doc='"ok" or why the last state could not be drawn.')
    message = property(lambda self: self.last.text, doc="The readout of the last update as plain text.")

    def update(self, **state) -> Readout:
        """Set some inputs (by state key) and redraw once.  A toggle takes one of its options (text in any
        case), a slider a finite number, clamped (angles wrapped) to its range; any other value is kept,
        status "invalid", the readout says why.  Only an unknown key raises ``InvalidGeometryError``.

        >>> readout = fourbar_explorer().update(theta2_deg=float("nan"))
        >>> readout.status, readout.lines[0]
        ('invalid', 'θ2 (°): refused NaN, not a number; kept 60')
        """
        unknown = sorted(set(state) - set(self.controls))
        if unknown:
            raise InvalidArgumentError(f"unknown explorer input {unknown[0]!r}; "
                                       f"valid inputs: {', '.join(self.controls)}")
        checked = [(key, *_control_value(key, self.controls[key], value)) for key, value in state.items()]
        self._holding = True
        try:
            for key, accepted, _ in checked:
                if accepted is not _REFUSED:
                    self.controls[key].value = accepted
        finally:
            self._holding = False
        return self.refresh(notes=[note for *_, note in checked if note],
                            refused=any(accepted is _REFUSED for _, accepted, _ in checked))

    def refresh(self, notes=(), refused: bool = False) -> Readout:
        """Redraw from the widget values; ``notes`` lead the readout, ``refused`` makes it "invalid"."""
        state = self.state
        geometry = {key: state[key] for key in self.geometry_keys}
        changed = self._drawn_geometry is None or geometry != self._drawn_geometry
        try:
            readout = self.draw(state, changed)
            if not isinstance(readout, Readout):
                raise InvalidArgumentError(f"draw must return a Readout (its status and lines); got "
                                           f"{readout!r}"[:300])
            self._drawn_geometry = geometry
        except (CourseLibError, ArithmeticError, ValueError, TypeError, IndexError) as err:
            self._drawn_geometry = None
            readout = Readout("error", (f"this state cannot be drawn: {err}", "Change an input to continue."))
        if notes or refused:
            readout = Readout("invalid" if refused else readout.status, (*notes, *readout.lines))
        self.last = readout
        self.image.value = self._render(full=False, geometry_changed=changed)
        self.readout.value = self.last.html()
        return self.last

    def render(self, full: bool = True) -> bytes:
        """The figure as PNG bytes; ``full=True`` redraws every layer, ``full=False`` only what changed."""
        return self._render(full=full, geometry_changed=False)

    def _render(self, full: bool, geometry_changed: bool) -> bytes:
        limits = [(axes.get_xlim(), axes.get_ylim()) for axes in self.figure.axes]
        new_limits = self._base is None or limits != self._base_limits  # then a new PNG palette too
        if full or new_limits:
            self.canvas.draw()  # without the animated artists: the geometry layer and the moving ones
            self._base, self._base_limits = self.canvas.copy_from_bbox(self.figure.bbox), limits
            self._background = None
        visible = tuple(artist.get_visible() for artist in self._geometry_layer)
        if self._background is None or geometry_changed or visible != self._background_visible:
            self.canvas.restore_region(self._base)
            self._draw_artists(self._geometry_layer)
            self._background, self._background_visible = self.canvas.copy_from_bbox(self.figure.bbox), visible
        else:
            self.canvas.restore_region(self._background)
        self._draw_artists(self._moving)
        # the palette, with every colour the artists can take, is made for new axis limits
        pixels = np.asarray(self.canvas.buffer_rgba())
        if new_limits or self._palette is None:
            self._palette = _Quantizer(pixels, _solid_colours(self.artists.values()))
        return self._palette.png(pixels, compress_level=1, trim=False)

    def _draw_artists(self, artists) -> None:
        for artist in artists:
            if artist.get_visible():
                (artist.axes or self.figure).draw_artist(artist)

    def _on_change(self, change) -> None:
        if not self._holding:
            self.refresh()

    def _repr_mimebundle_(self, include=None, exclude=None, **kwargs) -> dict:
        """The widget view, the still :meth:`picture` and the readout as text."""
        widget_bundle = getattr(self.widget, "_repr_mimebundle_", None)  # None once the widget is closed
        bundle = dict(widget_bundle(**kwargs) or {}) if callable(widget_bundle) else {}
        bundle["image/png"] = base64.b64encode(self.picture()).decode("ascii")
        bundle["text/plain"] = "\n".join((f"{self.name} explorer ({self.status})", *self.last.lines))
        return bundle

    def picture(self) -> bytes:
        """The current figure with the readout written under it, as PNG bytes (the still picture)."""
        figure = np.asarray(PILImage.open(io.BytesIO(self.image.value)).convert("RGB"))
        width = figure.shape[1]
        # the readout's lines wrapped to fit, as in the widget: 9 points at 80 dpi, about 6 px per character
        lines = [part for line in self.last.lines for part in textwrap.wrap(line, max(20, int(width / 6.4)))]
        height = int(np.ceil(len(lines) * (9.0 * 1.45 / 72 * 80) + 10))
        canvas = FigureCanvasAgg(Figure(figsize=(width / 80, height / 80), dpi=80))
        canvas.figure.text(8 / width, 1 - 5 / height, "\n".join(lines), fontsize=9.0, va="top", ha="left",
                  color="black" if self.status == "ok" else _ERROR_COLOR, linespacing=1.45)
        canvas.draw()
        readout = np.asarray(canvas.buffer_rgba())[..., :3][:, :width]  # padded where rounding lost a pixel:
        readout = np.pad(readout, ((0, 0), (0, width - readout.shape[1]), (0, 0)), constant_values=255)
        picture = np.concatenate([figure, readout])
        return _Quantizer(picture).png(picture, compress_level=9)


@dataclass(eq=False)
class ExplorerStage:
    """What an explorer's draw step moves: the linkage's ``axes``, its ``linkage`` artist and all the named
    ``artists`` (the panels', the linkage's and "failure", the red text that says why nothing is drawn)."""

    axes: object
    linkage: LinkageArtist
    artists: dict[str, object]

    def failed(self, points, text: str, status: str, lines, circles=()) -> Readout:
        """A failed step: the linkage at the known ``points``, the red ``text``, the reach ``circles``
        (artist name, centre, radius) shown."""
        self.linkage.move(points)
        self.artists["failure"].set_text(text)
        for name, center, radius in circles:
            self.artists[name].set(center=tuple(center), radius=radius, visible=True)
        return Readout(status, tuple(lines))

    def solved(self, points, lines, **shown) -> Readout:
        """A solved step: the linkage at ``points``, the ``shown`` line artists at their (x, y) data."""
        self.artists["failure"].set_text("")
        self.linkage.move(points)
        for name, data in shown.items():
            self.artists[name].set(data=data, visible=True)
        return Readout("ok", tuple(lines))


@dataclass(frozen=True)
class ExplorerSpec:
    """One explorer as a specification for :func:`build_explorer`.

    ``controls``: the input widgets by state key; ``size``: the figure (inches, at 80 dpi);
    ``panels(figure) -> (axes, before, after)`` lays the figure out, draws what never moves and returns
    the linkage's axes and the named artists drawn before and after the linkage (an "after" artist
    "failure" places the red failure text, else it goes last, top left); ``linkage``: the
    :class:`~course_lib.plotting.LinkageArtist` arguments (``links``, ``styles``, ``blocks``, ``labels``,
    ``label_offset``); ``draw(stage, state, geometry_changed) -> Readout`` moves the
    :class:`ExplorerStage`.  ``geometry_keys``, ``geometry_artists`` and ``extra`` as in :class:`Explorer`.
    """

    name: str
    controls: Mapping[str, widgets.ValueWidget]
    size: tuple[float, float]
    panels: Callable[[Figure], tuple[object, Mapping[str, object], Mapping[str, object]]]
    linkage: Mapping[str, object]
    draw: Callable[[ExplorerStage, Mapping[str, object], bool], Readout]
    geometry_keys: tuple[str, ...] = ()
    geometry_artists: tuple[str, ...] = ()
    extra: tuple[widgets.Widget, ...] = ()


def build_explorer(spec: ExplorerSpec) -> Explorer:
    """The :class:`Explorer` of a specification: its figure, panels, animated linkage and draw step.

    >>> import sympy as sp
    >>> from course_lib.mechanism import Mechanism
    >>> th = sp.Symbol("theta")
    >>> spec = ExplorerSpec("crank", {"theta_deg": _slider("θ (°)", 30.0, -180.0, 180.0, 1.0)}, (3.0, 3.0),
    ...     panels=lambda figure: (_grid(figure.add_subplot(), xlim=(-1, 1), ylim=(-1, 1)), {}, {}),
    ...     linkage={"links": {"crank": ("O", "A")}},
    ...     draw=lambda stage, state, changed: stage.solved(
    ...         {"O": (0.0, 0.0), "A": (np.cos(np.radians(state["theta_deg"])), 0.0)}, ["turned"]))
    >>> crank = build_explorer(spec)
    >>> crank.update(theta_deg=60.0).lines, crank.artists["crank"].get_xydata()[1].round(3).tolist()
    (('turned',), [0.5, 0.0])
    """
    size = _checked_spec(spec)
    figure = Figure(figsize=size, dpi=80)
    laid_out = spec.panels(figure)
    if not (isinstance(laid_out, tuple | list) and len(laid_out) == 3 and isinstance(laid_out[0], Axes)
            and laid_out[0].figure is figure and all(isinstance(part, Mapping) for part in laid_out[1:])):
        raise InvalidArgumentError(f"panels must return (axes of the figure it is given, the artists drawn "
                                   f"before, the artists drawn after), two dicts; got {laid_out!r}"[:400])
    axes, before, after = laid_out
    linkage = LinkageArtist(axes, animated=True, **spec.linkage)
    artists = {**before, **linkage.artists, **after}
    if "failure" not in artists:
        artists["failure"] = _failure_text(axes)
    unknown = [name for name in spec.geometry_artists if name not in artists]
    if unknown:
        raise InvalidArgumentError(f"geometry_artists must name artists of the explorer "
                                   f"({', '.join(artists)}); got {unknown[0]!r}")
    stage = ExplorerStage(axes, linkage, artists)
    return Explorer(spec.name, dict(spec.controls), figure, artists,
                    lambda state, geometry_changed: spec.draw(stage, state, geometry_changed),
                    spec.geometry_keys, spec.extra, spec.geometry_artists)


_LINKAGE_OPTIONS = ("links", "styles", "blocks", "labels", "plates", "label_offset")


def _checked_spec(spec) -> tuple[float, float]:
    """A specification's parts checked by name before anything is drawn; its figure size (inches)."""
    if not isinstance(spec, ExplorerSpec):
        raise InvalidArgumentError(f"spec must be an ExplorerSpec; got {spec!r}"[:300])
    if not isinstance(spec.name, str) or not spec.name.strip():
        raise InvalidArgumentError(f"name must be the explorer's name, some text; got {spec.name!r}")
    controls = spec.controls
    if not isinstance(controls, Mapping) or not all(
            isinstance(key, str) and isinstance(control, widgets.ValueWidget)
            for key, control in controls.items()):
        raise InvalidArgumentError(f"controls must map state keys (text) to input widgets (sliders, toggles, "
                                   f"…); got {controls!r}"[:300])
    for name in ("panels", "draw"):
        if not callable(getattr(spec, name)):
            raise InvalidArgumentError(f"{name} must be a function; got {getattr(spec, name)!r}")
    linkage = spec.linkage
    if not isinstance(linkage, Mapping) or "links" not in linkage or set(linkage) - set(_LINKAGE_OPTIONS):
        raise InvalidArgumentError(f"linkage must map 'links' (and any of {', '.join(_LINKAGE_OPTIONS[1:])}) "
                                   f"to the linkage's drawing; got {linkage!r}"[:300])
    keys = spec.geometry_keys
    if isinstance(keys, str) or not isinstance(keys, Sequence) or any(key not in controls for key in keys):
        raise InvalidArgumentError(f"geometry_keys must be state keys of the controls "
                                   f"({', '.join(controls)}); got {keys!r}")
    if isinstance(spec.geometry_artists, str) or not isinstance(spec.geometry_artists, Sequence):
        raise InvalidArgumentError(f"geometry_artists must be a sequence of artist names; got "
                                   f"{spec.geometry_artists!r}")
    if isinstance(spec.extra, str) or not isinstance(spec.extra, Sequence) or not all(
            isinstance(widget, widgets.Widget) for widget in spec.extra):
        raise InvalidArgumentError(f"extra must be a sequence of widgets; got {spec.extra!r}"[:300])
    return _figure_size(spec.size)


_REFUSED = object()  # marks a value update() does not set


def _plain_number(value):
    """``value`` as a float if it is a real number (not a bool, not a string), else None."""
    if isinstance(value, np.ndarray) and value.ndim == 0 and value.dtype.kind in "iuf":
        value = value.item()
    return None if isinstance(value, bool | np.bool_) or not isinstance(value, numbers.Real) else float(value)


def _wrap_degrees(degrees: float) -> float:
    """Degrees unchanged inside [−180, 180], else wrapped into [−180, 180)."""
    return degrees if -180.0 <= degrees <= 180.0 else (degrees + 180.0) % 360.0 - 180.0


def _option(value, labels, values):
    """The option ``value`` stands for (its value, or its label or value in any case), else _REFUSED."""
    if isinstance(value, str):
        wanted = value.strip().casefold()
        return next((option for label, option in zip(labels, values, strict=True)
                     if wanted in (str(label).casefold(), str(option).casefold())), _REFUSED)
    number = _plain_number(value)
    return next((option for option in values if number is not None and number == option), _REFUSED)


def _control_value(key: str, control, value) -> tuple[object, str]:
    """What ``update`` sets for ``value`` on ``control`` (or ``_REFUSED``) and a readout note, or ""."""
    name, number = control.description or key, _plain_number(value)
    echo = repr(value) if number is None else "NaN" if math.isnan(number) else f"{number:g}"
    if isinstance(control, widgets.ToggleButtons):
        option = _option(value, control._options_labels, control._options_values)
        listed = ", ".join(repr(option) for option in control._options_values)
        return option, (f"{name}: refused {echo}, not one of {listed}; kept {control.value!r}"
                        if option is _REFUSED else "")
    if number is None or not math.isfinite(number):
        why = "not a finite number" if number is not None and math.isinf(number) else "not a number"
        return _REFUSED, f"{name}: refused {echo}, {why}; kept {control.value:g}"
    if control.min <= number <= control.max:
        return number, ""
    if key.endswith("_deg"):
        wrapped = _wrap_degrees(number)
        return wrapped, f"{name} = {number:g} taken as {wrapped:g} (the same direction)"
    clamped = min(max(number, control.min), control.max)
    return clamped, (f"{name} = {number:g} is outside the slider's range "
                     f"[{control.min:g}, {control.max:g}]: set to {clamped:g}")


def _number_argument(name: str, value, unit: str, low: float = -math.inf, high: float = math.inf) -> float:
    """A builder argument: a finite number (within its slider's range ``low``…``high``), else raise."""
    number = _plain_number(value)
    if number is None or not math.isfinite(number):
        raise InvalidGeometryError(f"{name} must be a finite number ({unit}); got {value!r}")
    if not low <= number <= high:
        raise InvalidGeometryError(f"{name} must be between {low:g} and {high:g} {unit} "
                                   f"(its slider's range); got {value!r}")
    return number


def _slider(description: str, value: float, low: float, high: float, step: float, fmt: str = ".3f"):
    return widgets.FloatSlider(value=value, min=low, max=high, step=step, description=description,
                               readout_format=fmt, style=_STYLE, layout={"width": "340px"})


def _metres(name: str, value, description: str, low: float, high: float):
    """A slider in metres set to the builder argument ``name``, checked against the range."""
    return _slider(description, _number_argument(name, value, "m", low, high), low, high, 0.005)


def _angle_slider(description: str, degrees: float):
    """A slider in degrees over [−180°, 180°], in steps of 0.1° (readout, arrow keys), over the explorer's
    whole width."""
    return _slider(description, degrees, -180.0, 180.0, 0.1, ".1f").add_class(_WIDE)


def _degrees(name: str, value, description: str):
    """An angle slider set to the builder angle ``name`` (radians, wrapped)."""
    return _angle_slider(description, _wrap_degrees(math.degrees(_number_argument(name, value,
                                                                                  "an angle in radians"))))


def _toggle(description: str, options, name: str, value):
    """A toggle set to the builder argument ``name``, one of ``options`` (texts or (label, value) pairs)."""
    labels, values = zip(*((option, option) if isinstance(option, str) else option for option in options),
                         strict=True)
    chosen = _option(value, labels, values)
    if chosen is _REFUSED:
        listed = ", ".join(repr(option) for option in values)
        raise InvalidGeometryError(f"{name} must be one of {listed}; got {value!r}")
    # wide enough for the longest label: up to 8 px a character (13 px font) and the button's padding
    width = max(90, 8 * max(len(label) for label in labels) + 32)
    return widgets.ToggleButtons(options=options, value=chosen, description=description,
                                 style={**_STYLE, "button_width": f"{width}px"})


def _grid(ax, **properties):
    """The axes with ``properties`` set (labels, limits) and the explorers' dashed grid."""
    ax.set(**properties)
    ax.grid(True, linestyle="--", alpha=0.5)
    return ax


def _set_equal_limits(ax, xmin: float, xmax: float, ymin: float, ymax: float) -> None:
    """Limits covering the box with equal x and y scales, for the axes' fixed size on the figure."""
    box, (width_in, height_in) = ax.get_position(), ax.figure.get_size_inches()
    box_width, box_height = box.width * width_in, box.height * height_in
    scale = max((xmax - xmin) / box_width, (ymax - ymin) / box_height)
    x_mid, y_mid = (xmin + xmax) / 2, (ymin + ymax) / 2
    ax.set(xlim=(x_mid - scale * box_width / 2, x_mid + scale * box_width / 2),
           ylim=(y_mid - scale * box_height / 2, y_mid + scale * box_height / 2))


def _moving_line(ax, *args, **kwargs):
    return ax.plot(*args, animated=True, **kwargs)[0]


def _reach_circle(ax, edgecolor: str):
    """A dashed circle, what a link end can reach, shown where a loop cannot close."""
    return ax.add_patch(Circle((0, 0), 1.0, fill=False, linestyle="--", edgecolor=edgecolor, lw=1,
                               animated=True))


def _failure_text(ax, y: float = 0.97):
    """The red text in the drawing's top left corner that says why the linkage is not drawn."""
    return ax.text(0.02, y, "", transform=ax.transAxes, va="top", color=_ERROR_COLOR, fontsize=10,
                   fontweight="bold", animated=True)


def _num(value: float, digits: int) -> str:
    """``value`` with ``digits`` decimals and no "-0.000" (rounded first); "undefined" if not finite."""
    number = float(value)
    return f"{round(number, digits) + 0.0:.{digits}f}" if math.isfinite(number) else "undefined"


def _solid_colours(artists) -> list[tuple[int, int, int]]:
    """The RGB colours (0…255, over white) of the artists' lines, faces, edges, markers and texts."""
    colours = []
    for artist in artists:
        for getter in ("get_color", "get_markerfacecolor", "get_markeredgecolor", "get_edgecolor",
                       "get_facecolor"):
            try:
                rgba = to_rgba_array(getattr(artist, getter)())
            except (AttributeError, TypeError, ValueError):
                continue
            alpha = rgba[:, 3:] * (artist.get_alpha() if artist.get_alpha() is not None else 1.0)
            blended = rgba[:, :3] * alpha + (1.0 - alpha)  # over the white figure
            colours += [tuple(int(round(255 * c)) for c in rgb) for rgb in blended]
    return colours


_TRIANGLE = np.array([[0.0, 0.0], [-1.0, -1.6], [1.0, -1.6]])  # the fixed-pivot symbol of unit size


def fourbar_explorer(
    crank: float = 0.06, coupler: float = 0.18, rocker: float = 0.12, ground: float = 0.20,
    theta2: float = np.pi / 3, assembly: str = "open", p: float | None = None,
    delta: float = np.radians(30.0), *, branch: str | None = None,
) -> Explorer:
    """Explorer of a four-bar linkage (:class:`course_lib.fourbar.FourBar`); arguments are the initial
    values (m, rad), lengths within the sliders' range 0.02…0.40 m.

    Sliders: lengths l1…l4, crank angle θ2, coupler point P at p from A turned δ from AB; toggle: the
    assembly ("open" or "crossed"; ``branch=`` its older name).
    Drawing: the linkage, the coupler curve of P, the transmission angle μ(θ2).  Readout: Grashof class,
    θ3, θ4, μ, input range, or why the loop cannot close (with the two circles that fail to meet).

    >>> explorer = fourbar_explorer(crank=0.15, coupler=0.10, rocker=0.12, ground=0.20)
    >>> explorer.update(theta2_deg=120.0).status, "outside the input range" in explorer.message
    ('unreachable', True)
    """
    named = {"ground": ground, "crank": crank, "coupler": coupler, "rocker": rocker}
    controls = {key: _metres(key, value, f"{key} l{k} (m)", 0.02, 0.40)
                for k, (key, value) in enumerate(named.items(), 1)}
    p = _metres("p", 0.5 * controls["coupler"].value if p is None else p, "point P: l_AP (m)", 0.0, 0.40)
    given = ("assembly", assembly) if branch is None else ("branch", branch)  # branch=: the older name
    toggle = _toggle("assembly", BRANCHES, *given)
    controls.update(theta2_deg=_degrees("theta2", theta2, "θ2 (°)"), assembly=toggle, p=p,
                    delta_deg=_degrees("delta", delta, "point P: δ (°)"))

    def panels(figure):  # the linkage with its coupler curve; μ(θ2) with its design line (40°)
        grid = figure.add_gridspec(1, 2, width_ratios=(1.45, 1.0), left=0.095, right=0.98, bottom=0.13,
                                   top=0.97, wspace=0.22)
        ax = _grid(figure.add_subplot(grid[0]), xlabel="x (m)", ylabel="y (m)")
        ax_mu = _grid(figure.add_subplot(grid[1]), xlabel="θ2 (°)", ylabel="transmission angle μ (°)",
                      xlim=(-180, 180), ylim=(0, 92), xticks=np.arange(-180, 181, 90))
        ax_mu.axhline(TRANSMISSION_MIN_DEG, color="0.5", linestyle=":", lw=1)
        ax_mu.text(-175, TRANSMISSION_MIN_DEG + 2, f"μ = {TRANSMISSION_MIN_DEG:g}°", color="0.4", fontsize=8)
        curve_line, = ax.plot([], [], color="tab:purple", lw=1.2, label="coupler curve of P")
        ax.legend(handles=[curve_line], loc="lower right", fontsize=8)
        return ax, {
            "coupler_curve": curve_line, "mu_curve": ax_mu.plot([], [], color="tab:purple", lw=1.5)[0],
            "ground": _moving_line(ax, [], [], "--", color=LINK_COLORS[3], lw=1.5),
        }, {
            "point_p": _moving_line(ax, [], [], "o", ms=6, color="tab:purple", zorder=5),
            "mu_cursor": _moving_line(ax_mu, [], [], "o", ms=7, color="black", zorder=5),
            "mu_cursor_line": ax_mu.axvline(0.0, color="black", lw=1, animated=True),
            "failure": _failure_text(ax),
            **{f"label_{key}": ax.text(0, 0, key, fontsize=9, animated=True) for key in ("O2", "O4")},
            **{f"ground_{key}": ax.add_patch(Polygon(_TRIANGLE * 0.01, closed=True, facecolor="none",
                                                     edgecolor="0.3", hatch="///", lw=1, animated=True))
               for key in ("O2", "O4")},
            **{key: _reach_circle(ax, "0.45") for key in ("reach_A", "reach_O4")},
        }

    def draw(stage, state, geometry_changed: bool) -> Readout:
        """Solve the four-bar at the state's θ2 and move the artists."""
        ax, artists = stage.axes, stage.artists
        theta2, assembly = np.radians(float(state["theta2_deg"])), state["assembly"]
        four = FourBar(**{key: state[key] for key in named})
        l1, l2, l3, l4 = four.l1, four.l2, four.l3, four.l4
        p, delta = float(state["p"]), np.radians(float(state["delta_deg"]))
        offset = stage.linkage.label_offset = 0.04 * max(l1, l2, l3, l4)
        if geometry_changed:
            sweep = np.linspace(-np.pi, np.pi, 361)
            curve = four.coupler_point(sweep, p, delta, assembly=assembly, on_failure="nan").position
            mu = four.transmission_angle(sweep, assembly=assembly, on_failure="nan")
            artists["coupler_curve"].set_data(curve[:, 0], curve[:, 1])
            artists["mu_curve"].set_data(np.degrees(sweep), np.degrees(mu))
            # the limits stay while crank circle, rocker circle and coupler curve fit and fill half of them
            xs = [-l2, l2, l1 - l4, l1 + l4, *np.nan_to_num(curve[:, 0], nan=0.0)]
            ys = [-l2, l2, -l4, l4, *np.nan_to_num(curve[:, 1], nan=0.0)]
            xmin, xmax, ymin, ymax = min(xs), max(xs), min(ys), max(ys)
            (x0, x1), (y0, y1) = ax.get_xlim(), ax.get_ylim()
            fits = x0 <= xmin and xmax <= x1 and y0 <= ymin and ymax <= y1
            if not (fits and max((xmax - xmin) / (x1 - x0), (ymax - ymin) / (y1 - y0)) >= 0.5):
                margin = 0.08 * max(xmax - xmin, ymax - ymin)
                _set_equal_limits(ax, xmin - margin, xmax + margin, ymin - margin, ymax + 2.5 * margin)
            artists["ground"].set_data([0.0, l1], [0.0, 0.0])
            for key, x in (("O2", 0.0), ("O4", l1)):
                artists[f"ground_{key}"].set_xy(_TRIANGLE * (0.035 * max(l1, l2, l4)) + [x, 0.0])
                artists[f"label_{key}"].set_position((x + offset, offset))
        grashof, reach = four.grashof(), four.input_range()
        relation = "<" if grashof.s_plus_l < grashof.p_plus_q else ">" if grashof.name[:3] == "non" else "="
        ranges = " and ".join(f"[{np.degrees(a):.1f}°, {np.degrees(b):.1f}°]" for a, b in reach.intervals)
        lines = (
            f"{grashof.name}: s + l = {grashof.s_plus_l:.3f} m {relation} p + q = {grashof.p_plus_q:.3f} m "
            f"(shortest: {grashof.shortest}, longest: {grashof.longest})",
            "input range: θ2 turns fully (0° to 360°)" if reach.full_rotation
            else f"input range: θ2 in {ranges} (toggle positions at the ends)" if reach.intervals
            else "input range: none — these lengths cannot be assembled at any θ2",
        )
        artists["mu_cursor_line"].set_xdata([np.degrees(theta2)] * 2)
        for name in ("reach_A", "reach_O4", "point_p", "mu_cursor"):
            artists[name].set_visible(False)
        try:
            solution = four.solve(theta2, assembly=assembly)
            mu = four.transmission_angle(theta2, assembly=assembly)
            joints = four.with_coupler_point(p, delta).joints(solution)  # O2, A, B, O4 and P, as declared
            point = joints["P"]
            finite = np.isfinite(np.hstack([solution.theta3, solution.theta4, mu, point])).all()
            failure = None if finite else "the closed form returns no number here"
        except CourseLibError as err:
            failure = err
        if failure is not None:  # the declared points the input alone places (B, unknown, is NaN)
            pins = four.joints(four.solve(theta2, assembly=assembly, on_failure="nan"))
            A, O4 = pins["A"], pins["O4"]
            at, distance = f"θ2 = {np.degrees(theta2):.0f}°", float(np.hypot(*(O4 - A)))
            known, says = {name: pins[name] for name in ("O2", "A", "O4")}, f"course_lib says: {failure}"
            if distance < COINCIDENT**0.5 * max(l1, l2):  # A on O4 (to √rounding): θ3 is undefined
                return stage.failed(known, f"A lands on O4 at {at}", "singular", (
                    f"{at}: the crank pin A lands on the pivot O4 (l2 = l1), "
                    "so the coupler's direction, θ3 and θ4 are undefined here.",
                    "Move θ2 a little, or change l1 or l2.", *lines, says))
            far, near = f"l3 + l4 = {l3 + l4:.3f} m", f"|l3 − l4| = {abs(l3 - l4):.3f} m"
            why = f"|AO4| = {distance:.3f} m " + (
                f"> {far}: coupler and rocker cannot reach" if distance > l3 + l4
                else f"< {near}: the longer link overshoots" if distance < abs(l3 - l4)
                else f"is at the limit {far} or {near}: a toggle position")
            return stage.failed(known, f"cannot assemble at {at}", "unreachable", (
                f"{at} is outside the input range: the loop cannot close.",
                why + " (the dashed circles about A and O4 do not meet).",
                "Move θ2 back into the input range, or change the lengths.", *lines, says),
                circles=(("reach_A", A, l3), ("reach_O4", O4, l4)))
        warning = (f"  ← below {TRANSMISSION_MIN_DEG:g}°: poor force transmission"
                   if np.degrees(mu) < TRANSMISSION_MIN_DEG else "")
        return stage.solved(joints, (
            f"θ2 = {np.degrees(theta2):.1f}°  →  θ3 = {np.degrees(solution.theta3):.2f}°, "
            f"θ4 = {np.degrees(solution.theta4):.2f}°  ({assembly} assembly)",
            f"transmission angle μ = {np.degrees(mu):.2f}°{warning}",
            f"coupler point P = ({point[0]:.4f}, {point[1]:.4f}) m", *lines),
            point_p=([point[0]], [point[1]]), mu_cursor=([np.degrees(theta2)], [np.degrees(mu)]))

    declared = FourBar(crank, coupler, rocker, ground).with_coupler_point(0.0, 0.0)  # its names: links, plate
    return build_explorer(ExplorerSpec(
        "four-bar", controls, (8.6, 3.8), panels, {  # the ground link is drawn dashed, as its lengths change
            "links": {name: ends for name, ends in declared.links.named().items() if name != "ground"},
            "plates": declared.plates, "labels": {"A": "A", "B": "B", "P": "P"}},
        draw, (*named, "assembly", "p", "delta_deg"),
        ("coupler_curve", "mu_curve", "ground", "ground_O2", "ground_O4", "label_O2", "label_O4")))


#: (key in saw.UNKNOWNS, panel label with units)
_SAW_PANELS = (("r1", "r1 (m)"), ("theta1", "θ1 (rad)"), ("theta3", "θ3 (rad)"),
               ("v_r", "v_r (m/s)"), ("omega1", "ω1 (rad/s)"), ("omega3", "ω3 (rad/s)"),
               ("a_r", "a_r (m/s²)"), ("alpha1", "α1 (rad/s²)"), ("alpha3", "α3 (rad/s²)"))


def saw_explorer(
    frames: int = 120, t_end: float | None = None, t: float = 0.0, interval_ms: int = 100
) -> Explorer:
    """Explorer of the course's power saw (:mod:`course_lib.saw`) over the motor's start-up profile.

    A time slider t (s) over [0, ``t_end``] (default two crank turns, 2T ≈ 3.88 s) in ``frames`` steps,
    linked to an ``ipywidgets.Play`` button ``explorer.play`` (``interval_ms`` per frame).  Drawing: the
    saw at t, the motor profile θ2, ω2, α2 and the nine unknowns over time, each with a cursor at t.

    >>> explorer = saw_explorer()
    >>> explorer.play.value = 30  # the Play button's frame k moves the time slider to k·dt
    >>> explorer.status, bool(abs(explorer.state["t"] - 30 * explorer.controls["t"].step) < 1e-12)
    ('ok', True)
    """
    from .profile import first_turn_time, motor_profile
    from .saw import COURSE_SAW, analytic

    count = _plain_number(frames)
    if count is None or not 2 <= count <= 10_000 or count != int(count):
        raise InvalidArgumentError(f"frames must be a whole number from 2 to 10000; got {frames!r}")
    turn = first_turn_time()
    end = 2 * turn if t_end is None else _number_argument("t_end", t_end, "a time in seconds")
    if not 0 < end <= 100:
        raise InvalidArgumentError(f"t_end must be a time in seconds, > 0 and at most 100; got {t_end!r}")
    t = _number_argument("t", t, "s", 0.0, end)
    interval = _number_argument("interval_ms", interval_ms, "milliseconds per frame")
    if interval <= 0:
        raise InvalidArgumentError(f"interval_ms must be a positive time in ms; got {interval_ms!r}")
    dt = end / int(count)
    time_slider = _slider("time t (s)", t, 0.0, end, dt, ".3f")
    play = widgets.Play(min=0, max=int(count), step=1, interval=int(round(interval)), description="play")
    # t → the nearest frame (t itself is kept); frame k → t = k·dt
    widgets.link((time_slider, "value"), (play, "value"), transform=(lambda t: int(round(t / dt)),
                                                                     lambda k: k * dt))
    sweep_t = np.linspace(0.0, end, 481)
    profile = motor_profile(sweep_t)
    values = analytic(*profile, saw=COURSE_SAW)

    def panels(figure):  # the saw; the motor profile; the nine unknowns over time, each with a cursor
        grid = figure.add_gridspec(2, 1, height_ratios=(1.0, 1.25), left=0.08, right=0.985, bottom=0.06,
                                   top=0.97, hspace=0.2)
        top = grid[0].subgridspec(1, 2, width_ratios=(1.25, 1.0), wspace=0.25)
        bottom = grid[1].subgridspec(3, 3, hspace=0.55, wspace=0.38)
        ax, ax_profile = figure.add_subplot(top[0]), figure.add_subplot(top[1])
        r1y, r2, r3 = COURSE_SAW.r1y, COURSE_SAW.r2, COURSE_SAW.r3
        _grid(ax, xlabel="x (m)", ylabel="y (m)").xaxis.labelpad = ax.yaxis.labelpad = 1
        ax.axhline(r1y, color="0.55", lw=1, linestyle="-.")
        ax.text(-r2 - r3 - 0.015, r1y + 0.006, "slider line y = r1y", fontsize=7, color="0.4")
        crank_circle = np.linspace(0, 2 * np.pi, 100)
        ax.plot(r2 * np.cos(crank_circle), r2 * np.sin(crank_circle), color="0.75", lw=0.8)
        _ground_symbol(ax, (0.0, 0.0), 0.008)
        _set_equal_limits(ax, -r2 - r3 - 0.02, r2 + 0.02, -r2 - 0.015, max(r2, r1y) + 0.025)
        for curve, color, label in zip(profile, ("tab:blue", "tab:orange", "tab:green"),
                                       ("θ2 (rad)", "ω2 (rad/s)", "α2 (rad/s²)"), strict=True):
            ax_profile.plot(sweep_t, curve, color=color, label=label)
        ax_profile.axvline(turn, color="0.5", linestyle=":", lw=1)
        _grid(ax_profile, xlim=(0, end)).set_title("motor profile", fontsize=9, pad=3)
        ax_profile.set_xlabel("t (s)", labelpad=1)
        ax_profile.legend(fontsize=7, loc="upper left")
        artists = {
            "profile_cursor": ax_profile.axvline(0.0, color="black", lw=1, animated=True),
            "profile_points": _moving_line(ax_profile, [], [], "o", ms=5, color="black"),
            "failure": _failure_text(ax, 0.96),
            "title": ax.text(0.02, 0.96, "", transform=ax.transAxes, va="top", fontsize=9, animated=True),
        }
        for k, (key, label) in enumerate(_SAW_PANELS):
            panel = _grid(figure.add_subplot(bottom[k // 3, k % 3]), xlim=(0, end))
            panel.plot(sweep_t, values[:, k], color="tab:purple", lw=1.2)
            panel.set_title(label, fontsize=8, pad=2)
            panel.tick_params(labelsize=7, pad=1)
            if k >= 6:
                panel.set_xlabel("t (s)", fontsize=7, labelpad=0)
            artists[f"cursor_{key}"] = panel.axvline(0.0, color="black", lw=1, animated=True)
            artists[f"point_{key}"] = _moving_line(panel, [], [], "o", ms=4, color="black")
        return ax, {}, artists

    def draw(stage, state, geometry_changed: bool) -> Readout:
        """Solve the saw at time t of the motor profile and move the artists."""
        t, artists = float(state["t"]), stage.artists
        try:
            theta2, omega2, alpha2 = (float(v) for v in motor_profile(t))
            motion = COURSE_SAW.motion(theta2, omega2, alpha2)
        except CourseLibError as err:
            artists["profile_points"].set_visible(False)
            return stage.failed({}, f"no assembly at t = {t:.3f} s", "unreachable",
                                (f"t = {t:.3f} s: the saw cannot be solved here.", f"course_lib says: {err}"))
        values = motion.x
        # θ3 in the course's range (π/2, 3π/2), as eq. 20 and the curve below write it (the core's single
        # instant gives it in [−π, π])
        values[2] = np.pi + wrap_angle(values[2] - np.pi)
        artists["title"].set_text(f"t = {t:.3f} s")
        artists["profile_cursor"].set_xdata([t, t])
        for k, (key, _label) in enumerate(_SAW_PANELS):
            artists[f"cursor_{key}"].set_xdata([t, t])
            artists[f"point_{key}"].set_data([t], [values[k]])
        phase = ("start-up, " + ("α2 rising", "α2 constant", "α2 falling")[min(int(3 * t / turn), 2)]
                 if t < turn else "steady speed")
        shown = [label.replace(" (", f" = {_num(value, 5)} ")[:-1]  # "r1 (m)" → "r1 = -0.09967 m"
                 for (_, label), value in zip(_SAW_PANELS, values, strict=True)]
        return stage.solved(COURSE_SAW.mechanism.joints(motion), (
            f"t = {t:.3f} s ({phase}; first turn ends at T = {turn:.4f} s)",
            f"motor: θ2 = {_num(theta2, 4)} rad ({np.degrees(theta2):.1f}°), ω2 = {_num(omega2, 4)} rad/s, "
            f"α2 = {_num(alpha2, 4)} rad/s²",
            *(f"{kind}: {', '.join(shown[3 * k:3 * k + 3])}"
              for k, kind in enumerate(("position", "velocity", "acceleration")))),
            profile_points=([t, t, t], [theta2, omega2, alpha2]))

    explorer = build_explorer(ExplorerSpec(
        "power saw", {"t": time_slider}, (8.6, 6.6), panels, {
            # the declaration's links and slider, and the vector r1 to the slider pin C
            "links": {"r1": ("O2", "C"), **COURSE_SAW.mechanism.links.named()},
            "blocks": COURSE_SAW.mechanism.sliders,
            "styles": {"r1": {"color": "tab:purple", "lw": 1.2, "linestyle": "--"},
                       "crank": {"color": LINK_COLORS[0]}, "rod": {"color": LINK_COLORS[1]}}},
        draw, extra=(play,)))
    explorer.play = play  # the Play button (frame k ↔ t = k·dt), also in ``extra``
    return explorer


_SIGMA = (("+1 (arms up)", 1), ("−1 (arms down)", -1))  # σ of the forward kinematics (lesson 00)
_ROOT = (("+1 (+√Δ)", 1), ("−1 (−√Δ)", -1))  # σ1, σ2: the sign before √Δ in the root for θ1, θ4


def fivebar_explorer(
    l1: float = 0.10, l2: float = 0.15, l3: float = 0.15, l4: float = 0.10, l5: float = 0.08,
    kinematics: str = "forward", theta1: float = 1.2, theta4: float = 1.9, sigma: int = 1,
    x3: float = 0.0, y3: float = 0.2, sigma1: int = 1, sigma2: int = 1, *, mode: str | None = None,
) -> Explorer:
    """Explorer of the five-bar robot (:class:`course_lib.fivebar.FiveBar`); arguments are the initial
    values (m, rad).  ``kinematics`` "forward": sliders θ1, θ4 and the assembly σ (+1 arms up) give the end
    effector P3 = (X3, Y3); "inverse": sliders X3, Y3 and the working mode (σ1, σ2) give θ1, θ4 (``mode=``
    is the older name of ``kinematics=``: a five-bar's mode is the course's sign σ).  The workspace is
    shaded; in the inverse kinematics the working mode's parallel singularity curve is dotted.

    >>> explorer = fivebar_explorer()
    >>> explorer.update(kinematics="inverse", x3=0.0, y3=0.2).status, explorer.update(x3=0.3, y3=0.3).status
    ('ok', 'unreachable')
    """
    from .fivebar import FiveBar

    robot = FiveBar(l1, l2, l3, l4, l5)
    reach = max(robot.l1 + robot.l2, robot.l4 + robot.l3) + robot.l5 / 2
    limit = float(np.ceil(reach * 1.1 / 0.01) * 0.01)
    controls = {
        "kinematics": _toggle("kinematics", ("forward", "inverse"),
                              *(("kinematics", kinematics) if mode is None else ("mode", mode))),
        "theta1_deg": _degrees("theta1", theta1, "θ1 (°)"),
        "theta4_deg": _degrees("theta4", theta4, "θ4 (°)"),
        "sigma": _toggle("assembly σ", _SIGMA, "sigma", sigma),
        "x3": _metres("x3", x3, "X3 (m)", -limit, limit), "y3": _metres("y3", y3, "Y3 (m)", -limit, limit),
        "sigma1": _toggle("σ1 (θ1 root)", _ROOT, "sigma1", sigma1),
        "sigma2": _toggle("σ2 (θ4 root)", _ROOT, "sigma2", sigma2),
    }
    grid = np.linspace(-limit, limit, 161)
    pivots = robot.joints(robot.forward(theta1, theta4, on_failure="nan"))  # the declared P1, P5 (fixed)
    P1, P5 = pivots["P1"], pivots["P5"]

    def panels(figure):  # the workspace shaded, the ground pivots, the legend
        ax = _grid(figure.add_axes((0.12, 0.1, 0.85, 0.86)), xlabel="X (m)", ylabel="Y (m)")
        _set_equal_limits(ax, -limit, limit, -limit, limit)
        reachable = robot.workspace(grid, grid, modes=(1, 1)).reachable
        shade = np.zeros(reachable.shape + (4,))
        shade[reachable] = (0.12, 0.47, 0.71, 0.16)
        shading = ax.imshow(shade, extent=(-limit, limit, -limit, limit), origin="lower",
                            interpolation="nearest")
        for pivot in (P1, P5):
            _ground_symbol(ax, tuple(pivot), 0.012)
        singular_line, = ax.plot([], [], ".", color="tab:red", ms=2, label="parallel singularity of (σ1, σ2)")
        ax.plot([], [], "s", color=(0.12, 0.47, 0.71, 0.3), label="workspace (both legs reach)")
        ax.legend(loc="lower left", fontsize=8)
        return ax, {
            "workspace": shading, "singularity": singular_line,
            "base": _moving_line(ax, *np.transpose([P5, P1]), color=LINK_COLORS[4], lw=2),
        }, {
            "end_effector": _moving_line(ax, [], [], "o", ms=8, color="black", zorder=5),
            "target": _moving_line(ax, [], [], "x", ms=11, mew=2.5, color=_ERROR_COLOR),
            "failure": _failure_text(ax),
            **{key: _reach_circle(ax, "0.35") for key in ("reach_a", "reach_b")},
        }

    curves: dict[tuple[int, int], np.ndarray] = {}  # singularity curve per working mode, computed once

    def draw(stage, state, geometry_changed: bool) -> Readout:
        """Forward or inverse kinematics of the state and the artists moved."""
        artists = stage.artists
        inverse = state["kinematics"] == "inverse"
        modes = (int(state["sigma1"]), int(state["sigma2"]))
        if geometry_changed:  # the controls of the kinematics shown; in the inverse, the singularity curve
            for key in ("theta1_deg", "theta4_deg", "sigma", "x3", "y3", "sigma1", "sigma2"):
                controls[key].disabled = inverse == (key in ("theta1_deg", "theta4_deg", "sigma"))
            if inverse and modes not in curves:  # where the parallel measure changes sign between neighbours
                parallel, points = robot.workspace(grid, grid, modes=modes).parallel, []
                for down, a, b in ((True, parallel[:-1], parallel[1:]),
                                   (False, parallel[:, :-1], parallel[:, 1:])):
                    rows, cols = np.nonzero((np.sign(a) * np.sign(b) < 0) & np.isfinite(a) & np.isfinite(b))
                    step = (grid[1] - grid[0]) * (a[rows, cols] / (a[rows, cols] - b[rows, cols]))
                    points.append(np.stack([grid[cols] + (0.0 if down else step),
                                            grid[rows] + (step if down else 0.0)], axis=1))
                curves[modes] = np.concatenate(points)
            points = curves[modes] if inverse else np.empty((0, 2))
            artists["singularity"].set_data(points[:, 0], points[:, 1])
        for name in ("reach_a", "reach_b", "target", "end_effector"):
            artists[name].set_visible(False)
        try:
            if inverse:
                x3, y3 = float(state["x3"]), float(state["y3"])
                result = robot.inverse(x3, y3, modes=modes)
                theta1, theta4 = result
            else:
                theta1, theta4 = (np.radians(float(state[key])) for key in ("theta1_deg", "theta4_deg"))
                result = robot.forward(theta1, theta4, mode=int(state["sigma"]))
                x3, y3 = result
        except CourseLibError as err:  # explain it, and draw the reach circles that fail to meet
            says = f"course_lib says: {err}"
            if inverse:
                P3 = np.array([x3, y3])
                artists["target"].set(data=([P3[0]], [P3[1]]), visible=True)
                lines = [f"P3 = ({P3[0]:.4f}, {P3[1]:.4f}) m cannot be reached:"]
                for leg, pivot, crank, distal in (("leg 1 (l1, l2)", P1, robot.l1, robot.l2),
                                                  ("leg 4 (l4, l3)", P5, robot.l4, robot.l3)):
                    distance, far, near = float(np.hypot(*(P3 - pivot))), crank + distal, abs(crank - distal)
                    if distance > far:
                        lines.append(f"{leg}: distance {distance:.4f} m > {far:.4f} m, fully stretched")
                    elif distance < near:
                        lines.append(f"{leg}: distance {distance:.4f} m < {near:.4f} m, fully folded")
                return stage.failed({"P1": P1, "P5": P5},
                                    f"P3 = ({P3[0]:.3f}, {P3[1]:.3f}) m is out of reach", "unreachable",
                                    (*lines, "Bring the target back into the shaded workspace.", says))
            pins = robot.mechanism.joints(robot.forward(theta1, theta4, on_failure="nan"))  # P3 unknown: NaN
            P2, P4 = pins["P2"], pins["P4"]
            distance, l2, l3 = float(np.hypot(*(P2 - P4))), robot.l2, robot.l3
            why = (f"|P2P4| = {distance:.4f} m > l2 + l3 = {l2 + l3:.4f} m" if distance > l2 + l3
                   else f"|P2P4| = {distance:.4f} m < |l2 − l3| = {abs(l2 - l3):.4f} m")
            at = f"θ1 = {state['theta1_deg']:.0f}°, θ4 = {state['theta4_deg']:.0f}°"
            return stage.failed({"P1": P1, "P2": P2, "P4": P4, "P5": P5},
                                "the distal links cannot meet", "unreachable", (
                                    f"{at}: the robot cannot be assembled.",
                                    why + " (the dashed circles about P2 and P4 do not meet).",
                                    "Move θ1 or θ4 until the circles meet again.", says),
                                circles=(("reach_a", P2, l2), ("reach_b", P4, l3)))
        if not np.isfinite(np.hstack([theta1, theta4, x3, y3])).all():
            return stage.failed({"P1": P1, "P5": P5}, "no position here", "singular", (
                "The robot's position is undefined for these inputs (the closed form returns no number).",
                "Move a slider a little."))
        measures = robot.singularity_measures(theta1, theta4, x3, y3)
        parallel = float(measures.parallel)
        serial = min(abs(float(measures.serial_leg1)), abs(float(measures.serial_leg4)))
        head = (f"inverse, modes (σ1, σ2) = ({modes[0]:+d}, {modes[1]:+d}): "
                f"P3 = ({_num(x3, 4)}, {_num(y3, 4)}) m  →  θ1 = {_num(np.degrees(theta1), 2)}°, "
                f"θ4 = {_num(np.degrees(theta4), 2)}°" if inverse
                else f"forward, σ = {int(state['sigma']):+d}: θ1 = {np.degrees(theta1):.1f}°, "
                f"θ4 = {np.degrees(theta4):.1f}°  →  P3 = ({_num(x3, 4)}, {_num(y3, 4)}) m")
        return stage.solved(robot.mechanism.joints(result), (
            head,
            f"singularity measures (0 = singular): leg 1 {_num(measures.serial_leg1, 3)}, "
            f"leg 4 {_num(measures.serial_leg4, 3)}, parallel {_num(parallel, 3)}",
            *["near a parallel (type-2) singularity: l2 and l3 almost aligned"] * (abs(parallel) < APPROACH),
            *["near a serial (type-1) singularity: a leg almost stretched or folded"] * (serial < APPROACH)),
            end_effector=([x3], [y3]))

    return build_explorer(ExplorerSpec(
        "five-bar", controls, (6.2, 5.0), panels, {
            # the declaration's links but the base l5, drawn with the workspace
            "links": {name: ends for name, ends in robot.mechanism.links.named().items() if name != "l5"},
            "labels": {"P3": "P3"}, "label_offset": 0.03 * limit},
        draw, ("kinematics", "sigma1", "sigma2"), ("singularity",)))


def mechanism_explorer(
    mechanism, motion, *, ground=(), trace=(), sliders=(), blocks=(), styles: Mapping | None = None,
    rates: Mapping | None = None, readout: Callable[[object], Sequence[str]] | None = None,
    title: str = "mechanism", size: tuple[float, float] = (4.0, 3.6),
) -> Explorer:
    """Explorer of any declared :class:`~course_lib.mechanism.Mechanism`, one slider per input, or of a
    machine that declares one (``FourBar``, ``Saw``, ``OffsetSliderCrank``, ``FiveBar``: anything with
    ``.mechanism``).

    ``motion``, solved by ``mechanism.solve`` (a sweep of one input, or values of several inputs, such as
    a grid of the five-bar's two cranks), sets each slider's range (degrees for an input named "theta…",
    all round the turn; else the values the motion covers), the limits and the ``trace`` paths, and seeds
    each solve from its nearest solved instant (the motion's assembly).  ``ground`` points get the
    fixed-pivot symbol, ``sliders`` a slider block (``blocks=`` its older name), ``styles`` go by link name
    ("link 1", …): each, when not given, the declaration's own (its ``ground``, ``sliders``, ``styles``, and
    its ``plates``); ``rates``
    (input → rate) go to each solve, so ``readout(instant) -> lines`` can show velocities; by default each
    unknown is listed.

    >>> import sympy as sp
    >>> from course_lib.mechanism import Mechanism
    >>> th, x = sp.symbols("theta x")
    >>> crank = Mechanism([x - sp.cos(th)], [x], [th], points={"O": sp.Matrix([0, 0]),
    ...                   "A": sp.Matrix([sp.cos(th), sp.sin(th)]), "B": sp.Matrix([x, 0])},
    ...                   links=[("O", "A")])  # a Scotch yoke: A slides in B's vertical slot, no link
    >>> turn = crank.solve({th: np.radians(np.arange(0, 360, 10))}, guess={x: 1.0})
    >>> mechanism_explorer(crank, turn, ground=["O"], sliders=["B"]).update(theta_deg=60.0).lines[0]
    'x = 0.5'
    >>> from course_lib.fourbar import FourBar
    >>> linkage = FourBar(0.06, 0.18, 0.12, 0.20)
    >>> mechanism_explorer(linkage, linkage.motion(np.radians(np.arange(-180, 180, 10)))).update(
    ...     theta2_deg=60.0).status
    'ok'
    >>> from course_lib.fivebar import FiveBar
    >>> robot = FiveBar(0.10, 0.15, 0.15, 0.10, 0.08)
    >>> cranks = np.meshgrid(np.radians(np.arange(0, 180, 15)), np.radians(np.arange(0, 180, 15)))
    >>> arms = mechanism_explorer(robot, robot.forward(*cranks, mode=+1, on_failure="nan"))
    >>> sorted(arms.controls), arms.update(theta1_deg=50.0, theta4_deg=120.0).lines[:2]
    (['theta1_deg', 'theta4_deg'], ('x3 = 0.01301', 'y3 = 0.1956'))
    """
    from .errors import ConvergenceError, SingularJacobianError, UnreachableError
    from .mechanism import Mechanism, Motion

    declared = getattr(mechanism, "mechanism", None)  # a machine (FourBar, Saw, …): its declaration
    if not isinstance(mechanism, Mechanism) and isinstance(declared, Mechanism):
        mechanism = declared
    if not isinstance(mechanism, Mechanism):
        raise InvalidGeometryError(f"mechanism must be a course_lib Mechanism or a machine with one "
                                   f"(its .mechanism); got {mechanism!r}")
    ground, blocks = ground or mechanism.ground, _sliders(sliders, blocks) or mechanism.sliders
    styles = styles or mechanism.styles
    if not isinstance(motion, Motion) or np.ndim(next(iter(motion.inputs.values()))) < 1:
        raise InvalidGeometryError(f"motion must be solved by mechanism.solve at several instants (an "
                                   f"array of each input); got {type(motion).__name__}")
    if not np.any(motion.converged):
        raise InvalidGeometryError("motion must have a solved instant to start from; none converged")
    if readout is not None and not callable(readout):
        raise InvalidArgumentError(f"readout must be a function of the instant, or None; got {readout!r}")
    if not isinstance(title, str):
        raise InvalidArgumentError(f"title must be text; got {title!r}")
    width, height = _figure_size(size)
    if not mechanism.links:
        raise InvalidGeometryError(f"mechanism must have declared links to draw; got links "
                                   f"{list(mechanism.links)}")
    names, unknowns = [s.name for s in mechanism.inputs], [s.name for s in mechanism.unknowns]
    if list(motion.inputs) != names or list(motion.position) != unknowns:
        raise InvalidGeometryError(f"motion must be solved by this mechanism (inputs {names}, unknowns "
                                   f"{unknowns}); got a Motion of inputs {list(motion.inputs)} and unknowns "
                                   f"{list(motion.position)}")
    converged = np.flatnonzero(np.asarray(motion.converged, dtype=bool).ravel())
    sweeps, controls, keys, spans = {}, {}, {}, {}
    for name in names:
        sweep = np.asarray(motion.inputs[name], dtype=float).ravel()
        angle = name.startswith("theta")
        key = f"{name}_deg" if angle else name
        at = sweep[converged[0]]
        first = _wrap_degrees(math.degrees(at)) if angle else float(at)
        low, high = (-180.0, 180.0) if angle else (float(sweep.min()), float(sweep.max()))
        label = f"{name.replace('theta', 'θ')} ({'°' if angle else 'm'})"
        controls[key] = (_angle_slider(label, first) if angle else
                         _slider(label, first, low, high, (high - low) / 200 or 1.0, ".4f"))
        sweeps[name], keys[name] = sweep[converged], key
        spans[name] = 2 * np.pi if angle else (high - low) or 1.0

    def guess(k: int) -> dict:
        return {unknown: float(np.ravel(values)[k]) for unknown, values in motion.position.items()}

    def value_of(name, state) -> float:
        return math.radians(state[keys[name]]) if name.startswith("theta") else float(state[keys[name]])

    # a bad ``rates`` is refused here, by name, rather than at the first event
    mechanism.solve({name: sweeps[name][0] for name in names}, rates=rates, guess=guess(converged[0]))

    def panels(figure):  # margins in inches, for the labels and the title; the ground and the traces
        ax = _grid(figure.add_axes((0.75 / width, 0.5 / height, 1 - 0.9 / width, 1 - 0.8 / height)),
                   xlabel="x (m)", ylabel="y (m)", title=title)
        box, _ = _motion_background(ax, mechanism.joints(motion), ground, trace)
        _set_equal_limits(ax, *box)
        return ax, {}, {}

    def draw(stage, state, geometry_changed: bool) -> Readout:
        values = {name: value_of(name, state) for name in names}
        gaps = np.zeros(len(converged))  # the nearest solved instant, each input measured in its span
        for name, value in values.items():
            gap = sweeps[name] - value
            if name.startswith("theta"):
                gap = (gap + np.pi) % (2 * np.pi) - np.pi
            gaps += (gap / spans[name]) ** 2
        nearest = converged[int(np.argmin(gaps))]
        where = ", ".join(f"{name} = {state[keys[name]]:g}{'°' if name.startswith('theta') else ''}"
                          for name in names)
        try:
            now = mechanism.solve(values, rates=rates, guess=guess(nearest))
        except (ConvergenceError, UnreachableError, SingularJacobianError) as err:
            return stage.failed({}, f"no assembly at {where}", "unreachable", (
                f"{where}: the loops cannot be closed here from the nearest solved instant.",
                f"course_lib says: {err}"))
        stage.solved(mechanism.joints(now), ())  # first: a readout may raise
        if readout is None:
            return Readout("ok", tuple(f"{unknown} = {value:.4g}" for unknown, value in now.position.items()))
        return Readout("ok", _readout_lines(readout(now)))

    return build_explorer(ExplorerSpec(title, controls, (width, height), panels,
                                       {"links": mechanism.links, "blocks": blocks, "styles": styles,
                                        "plates": mechanism.plates}, draw))


def _readout_lines(lines) -> tuple[str, ...]:
    """What a readout function returned as the readout's lines: one text is one line; else a sequence of
    texts, or the named error (shown as the readout of a state that cannot be drawn)."""
    if isinstance(lines, str):
        return (lines,)
    if isinstance(lines, Sequence) and all(isinstance(line, str) for line in lines):
        return tuple(lines)
    raise InvalidArgumentError(f"readout must return a line of text or a list of lines; got {lines!r}"[:300])


#: The name the declarations' vocabulary uses: ``explore(mechanism, motion)``, as ``draw`` and ``animate``.
explore = mechanism_explorer
