"""Pictures for the lessons: linkages with labelled links and numbered joints, Newton convergence plots,
and animations rendered to HTML (no ffmpeg needed) with a still picture wherever JavaScript does not run.
Only the functions that make a new figure import pyplot, so importing this module stays cheap.
"""

from __future__ import annotations

import base64
import hashlib
import io
import itertools
import math
import sys
from collections.abc import Callable, Mapping, Sequence

import numpy as np
from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image

from .errors import (
    CourseLibError,
    InvalidArgumentError,
    InvalidGeometryError,
    _numbers,
    require_choice,
    require_finite,
)
from .newton import NewtonResult

__all__ = ["draw", "animate", "draw_linkage", "LinkageArtist", "animate_linkage",
           "plot_convergence", "animation_html",
           "AnimationHTML", "LINK_COLORS"]

#: One colour per link, in the order the links are given.
LINK_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown")
#: The shade of a rigid plate (a coupler with its point P): opaque, so a still's palette holds it exactly.
PLATE_COLOR = "#dcdcdc"


def _ground_symbol(ax: Axes, point: np.ndarray, size: float) -> None:
    """A small hatched triangle under a fixed pivot (the bancada)."""
    x, y = point
    triangle = np.array([[x, y], [x - size, y - 1.6 * size], [x + size, y - 1.6 * size]])
    ax.fill(triangle[:, 0], triangle[:, 1], facecolor="none", edgecolor="0.3", hatch="///", lw=1)


def draw_linkage(points: Sequence[Sequence[float]], links: Sequence[tuple[int, int, str]],
                 ax: Axes | None = None, *, joint_labels: Sequence[str] | None = None,
                 ground: Sequence[int] = (), title: str | None = None, grid: bool = True,
                 linestyle: str = "-", alpha: float = 1.0) -> Axes:
    """The older, index-based spelling of :func:`draw`: the joints' ``points`` (x, y) (m) with
    ``joint_labels`` (default "1", "2", …), ``links`` (i, j, label), the ``ground`` joints by index — drawn
    by :func:`draw` as the links "link 1", "link 2", … between the joints "P1", "P2", …, each written with
    its label (the link's line carries its name as ``gid``).

    >>> import matplotlib; matplotlib.use("Agg")
    >>> ax = draw_linkage([(0, 0), (0.03, 0.04), (0.1, 0.05), (0.1, 0)],
    ...                   [(0, 1, "l2"), (1, 2, "l3"), (2, 3, "l4"), (3, 0, "l1")], ground=[0, 3], title="4")
    >>> ax.get_title(), sorted(text.get_text() for text in ax.texts)
    ('4', ['1', '2', '3', '4', 'l1', 'l2', 'l3', 'l4'])
    """
    xy = require_finite("points", points, unit="metres")
    if xy.ndim != 2 or xy.shape[1] != 2 or not len(xy):
        raise InvalidGeometryError(f"points must be a list of (x, y) pairs; got shape {xy.shape}")
    links = [_link(k, link, len(xy)) for k, link in enumerate(_sequence("links", links))]
    ground = [_index("ground", index, len(xy)) for index in _sequence("ground", ground)]
    labels = joint_labels if joint_labels is not None else [str(k + 1) for k in range(len(xy))]
    _one_each("joint_labels", labels, len(xy), "text per joint")
    require_choice("linestyle", linestyle, ("-", "--", "-.", ":"))
    keys = [f"P{k + 1}" for k in range(len(xy))]
    names = [f"link {k + 1}" for k in range(len(links))]
    ax = draw({name: (keys[i], keys[j]) for name, (i, j, _) in zip(names, links, strict=True)},
              dict(zip(keys, xy, strict=True)), ax, ground=[keys[index] for index in ground],
              labels={key: str(label) for key, label in zip(keys, labels, strict=True)},
              link_labels={name: label for name, (_, _, label) in zip(names, links, strict=True)},
              styles={name: {"linestyle": linestyle} for name in names}, title=title, alpha=alpha)
    if not grid:
        ax.grid(False)
    return ax


def _sequence(name: str, value) -> list:
    if isinstance(value, str) or not isinstance(value, Sequence | np.ndarray):
        raise InvalidGeometryError(f"{name} must be a list; got {value!r}")
    return list(value)


def _one_each(name: str, value, count: int, what: str) -> None:
    """``value`` must be a list of ``count`` entries, one ``what`` (e.g. "name per variable")."""
    if isinstance(value, str) or len(_sequence(name, value)) != count:
        raise InvalidGeometryError(f"{name} must give one {what} ({count}); got {value!r}")


def _axes(ax) -> None:
    if not isinstance(ax, Axes):
        raise InvalidArgumentError(f"ax must be a matplotlib Axes; got {ax!r}")


def _index(name: str, value, count: int) -> int:
    whole = isinstance(value, int | np.integer) and not isinstance(value, bool | np.bool_)
    if not whole or not 0 <= value < count:
        raise InvalidGeometryError(f"{name} must hold joint numbers from 0 to {count - 1}; got {value!r}")
    return int(value)


def _link(k: int, link, count: int) -> tuple[int, int, str]:
    if isinstance(link, str) or not isinstance(link, Sequence) or len(link) != 3:
        raise InvalidGeometryError(f"links[{k}] must be (i, j, label); got {link!r}")
    return _index(f"links[{k}]", link[0], count), _index(f"links[{k}]", link[1], count), str(link[2])


def _callback(name: str, function: Callable, frame: int):
    """``function(frame)``; what it raises becomes a named error (the original is chained)."""
    try:
        return function(frame)
    except CourseLibError:
        raise
    except Exception as err:
        raise InvalidArgumentError(f"{name}({frame}) raised {type(err).__name__}: {err}") from err


class LinkageArtist:
    """A moving linkage on an axes: a line per link in the course's colours, white joint circles, slider
    ``blocks`` and point ``labels``; :meth:`move` puts them at one configuration, hiding a link with an
    end point missing or not finite.  ``links`` maps link names to their end points' keys (a
    declaration's ``Mechanism.links`` keeps its names; a plain list of pairs is "link 1", "link 2", …);
    ``styles`` overrides line properties by link name; ``plates`` (name → three or more keys) are shaded
    polygons, rigid bodies such as a coupler with its point P; ``animated=True`` keeps the artists out of a
    plain ``canvas.draw``.

    >>> artist = LinkageArtist(Figure().add_subplot(), {"crank": ("O2", "A"), "rod": ("A", "B")})
    >>> artist.move({"O2": (0, 0), "A": (0.03, 0.04), "B": (float("nan"), 0.0)})
    >>> artist.lines["crank"].get_xydata().tolist(), artist.lines["rod"].get_visible()
    ([[0.0, 0.0], [0.03, 0.04]], False)
    """

    def __init__(self, ax: Axes, links, *, styles: Mapping[str, Mapping] | None = None, blocks: Sequence = (),
                 labels: Mapping | None = None, plates: Mapping[str, Sequence] | None = None,
                 animated: bool = False, label_offset: float = 0.0):
        _axes(ax)
        if isinstance(links, Mapping):
            pairs = dict(links)
        elif callable(getattr(links, "named", None)):  # a declaration's Links: its own names
            pairs = links.named()
        else:
            pairs = {f"link {k + 1}": link for k, link in enumerate(_sequence("links", links))}
        self.links: dict[str, tuple] = {}
        for name, link in pairs.items():
            if isinstance(link, str) or not isinstance(link, Sequence) or len(link) != 2:
                raise InvalidGeometryError(f"links[{name!r}] must be a pair of point keys; got {link!r}")
            self.links[str(name)] = tuple(link)
        styles = dict(styles or {})
        unknown = sorted(set(styles) - set(self.links))
        if unknown:
            raise InvalidGeometryError(f"styles names {unknown[0]!r}, not a link; links: {list(self.links)}")
        self._ends = list(dict.fromkeys(key for link in self.links.values() for key in link))
        self.blocks = tuple(_sequence("blocks", blocks))
        self.labels = dict(labels or {})
        self.label_offset = float(label_offset)
        self.lines: dict[str, object] = {}
        for k, name in enumerate(self.links):
            (self.lines[name],) = ax.plot([], [], color=LINK_COLORS[k % len(LINK_COLORS)], lw=3,
                                          solid_capstyle="round", animated=animated, gid=name)
            try:
                self.lines[name].set(**styles.get(name, {}))
            except (AttributeError, TypeError, ValueError) as err:
                raise InvalidGeometryError(f"styles[{name!r}] is not a set of line properties: {err}"
                                           ) from None
        (self.lines["joints"],) = ax.plot([], [], "o", ms=7, mfc="white", mec="black", zorder=4,
                                          animated=animated)
        if self.blocks:
            (self.lines["blocks"],) = ax.plot([], [], "s", ms=14, mfc="0.85", mec="black", zorder=3,
                                               animated=animated)
        self.texts = {key: ax.text(0, 0, str(text), fontsize=9, animated=animated, zorder=5)
                      for key, text in self.labels.items()}
        self.plates: dict[str, tuple] = {}
        if plates is not None and not isinstance(plates, Mapping):
            raise InvalidGeometryError(f"plates must map names to three or more point keys; got {plates!r}")
        for name, corners in dict(plates or {}).items():
            if isinstance(corners, str) or not isinstance(corners, Sequence) or len(corners) < 3:
                raise InvalidGeometryError(f"plates[{name!r}] must be three or more point keys; "
                                           f"got {corners!r}")
            self.plates[str(name)] = tuple(corners)
            self._ends += [key for key in corners if key not in self._ends]  # a plate's corner is a joint too
            (self.lines[f"plate {name}"],) = ax.fill([], [], color=PLATE_COLOR, lw=0, zorder=1.5,
                                                     animated=animated, gid=f"plate {name}")

    @property
    def artists(self) -> dict[str, object]:
        """Every matplotlib artist it moves, by name: the links, "joints", "blocks", "label <key>"."""
        return {**self.lines, **{f"label {key}": text for key, text in self.texts.items()}}

    def move(self, points) -> None:
        """Put the linkage at one configuration: ``points`` by key (mapping or (P, 2) array, m)."""
        known = _known_points(points)
        for name, (start, end) in self.links.items():
            line = self.lines[name]
            line.set_visible(start in known and end in known)
            if line.get_visible():
                line.set_data([known[start][0], known[end][0]], [known[start][1], known[end][1]])
        joints = np.array([known[key] for key in self._ends if key in known]).reshape(-1, 2)
        self.lines["joints"].set_data(joints[:, 0], joints[:, 1])
        if self.blocks:
            at = np.array([known[key] for key in self.blocks if key in known]).reshape(-1, 2)
            self.lines["blocks"].set_data(at[:, 0], at[:, 1])
        for name, corners in self.plates.items():
            plate = self.lines[f"plate {name}"]
            plate.set_visible(all(key in known for key in corners))
            if plate.get_visible():
                plate.set_xy([known[key] for key in corners])
        for key, text in self.texts.items():
            text.set_visible(key in known)
            if key in known:
                text.set_position(known[key] + self.label_offset)


def _known_points(points) -> dict:
    """Finite points by key, from a mapping key → (x, y) or an array (P, 2)."""
    if not isinstance(points, Mapping):
        array = _numbers("points", points, "(x, y) pairs of numbers")
        if array.ndim != 2 or array.shape[1] != 2:
            raise InvalidGeometryError(f"points must be (x, y) pairs, shape (P, 2); got shape {array.shape}")
        points = dict(enumerate(array))
    known = {}
    for key, xy in points.items():
        xy = _numbers(f"points[{key!r}]", xy, "an (x, y) pair of numbers").reshape(-1)
        if xy.shape != (2,):
            raise InvalidGeometryError(f"points[{key!r}] must be one (x, y) pair; got {xy.tolist()!r}")
        if np.all(np.isfinite(xy)):
            known[key] = xy
    return known


def _paths(points) -> dict:
    """Each point's path over the frames, key → (n, 2), from a mapping or an (n, P, 2) array; one instant
    (key → (x, y), or a (P, 2) array) is one frame."""
    if isinstance(points, Mapping):
        paths = {key: _numbers(f"points[{key!r}]", path, "an array of (x, y)")
                 for key, path in points.items()}
        if paths and all(path.shape == (2,) for path in paths.values()):  # one instant
            paths = {key: path[None, :] for key, path in paths.items()}
    else:
        array = _numbers("points", points, "an array of (x, y) per frame and point")
        if array.ndim == 2 and array.shape[1] == 2:  # one instant
            array = array[None]
        if array.ndim != 3 or array.shape[2] != 2:
            raise InvalidGeometryError(f"points must have shape (frames, P, 2) or (P, 2); got shape "
                                       f"{array.shape}")
        paths = dict(enumerate(np.moveaxis(array, 1, 0)))
    shapes = {path.shape for path in paths.values()}
    if not paths or len(shapes) != 1 or next(iter(shapes))[1:] != (2,) or next(iter(shapes))[0] < 1:
        raise InvalidGeometryError(f"points must give every point one (x, y) per frame; got shapes {shapes}")
    return paths


def _sliders(sliders, blocks) -> list:
    """The points drawn as slider blocks: ``sliders=`` (the declaration's word), or ``blocks=``, its older
    name; not two different lists."""
    sliders, blocks = _sequence("sliders", sliders), _sequence("blocks", blocks)
    if sliders and blocks and sliders != blocks:
        raise InvalidArgumentError(f"give sliders= (blocks= is its older name), not both; got "
                                   f"sliders={sliders!r} and blocks={blocks!r}")
    return sliders or blocks


def _declared(links, points, options: dict):
    """``links``, ``points`` and the drawing ``options`` (ground, blocks, plates, styles) as drawn: a
    declaration (a ``Mechanism``, or a machine with one as its ``.mechanism``) with a ``Motion`` of it
    gives its named links, ``joints(motion)`` and, for each option not given, its own (ground pivots,
    sliders, plates, styles); anything else is passed on as it is."""
    mechanism = getattr(links, "mechanism", links)
    if all(hasattr(mechanism, name) for name in ("joints", "links", "points", "unknowns")):
        if hasattr(points, "position") and hasattr(points, "inputs"):  # a Motion
            points = mechanism.joints(points)
        declared = {"ground": mechanism.ground, "blocks": mechanism.sliders, "plates": mechanism.plates,
                    "styles": mechanism.styles}
        return mechanism.links, points, {key: value if value else declared[key]
                                         for key, value in options.items()}
    return links, points, options


def animate_linkage(links, points, *, ground: Sequence = (), trace: Sequence = (), sliders: Sequence = (),
                    blocks: Sequence = (), labels: Mapping | bool | None = None,
                    styles: Mapping[str, Mapping] | None = None,
                    plates: Mapping[str, Sequence] | None = None,
                    caption: Callable[[int], str] | None = None,
                    background: Callable[[Axes], object] | None = None, title: str | None = None,
                    size: tuple[float, float] = (4.2, 3.0), dpi: float = 60, interval_ms: float = 80,
                    max_frames: int = 48) -> AnimationHTML:
    """A linkage (as :class:`LinkageArtist`) moving through the frames of ``points`` (key → (frames, 2),
    as ``Mechanism.joints(motion)``, or (frames, P, 2); one instant is one frame), as an
    :func:`animation_html` player; ``trace`` points get their dotted path, ``caption(frame)`` a corner
    line, ``background(ax)`` draws what stays; ``sliders`` points get a slider block (``blocks=``, its
    older name).  ``links`` may be a declaration (a ``Mechanism``, or a machine such as ``FourBar``) and
    ``points`` a ``Motion`` of it: ``animate_linkage(wiper, wiper.motion(theta2))`` draws its named links
    at its declared points.

    >>> html = animate_linkage({"crank": ("O", "A")},
    ...                        {"O": np.zeros((3, 2)), "A": [[1, 0], [0, 1], [-1, 0]]}, ground=["O"])
    >>> html.frame_count
    3
    """
    links, points, options = _declared(links, points, {"ground": ground, "blocks": _sliders(sliders, blocks),
                                                       "plates": plates, "styles": styles})
    paths = _paths(points)
    for argument, function in (("caption", caption), ("background", background)):
        if function is not None and not callable(function):
            raise InvalidArgumentError(f"{argument} must be a function or None; got {function!r}")
    figure = Figure(figsize=_figure_size(size), dpi=_dpi(dpi), layout="constrained")
    ax = figure.add_subplot()
    artist = _stage(ax, links, paths, trace, labels, **options)
    if title is not None:
        ax.set_title(title)
    if background is not None:
        _callback("background", lambda _: background(ax), 0)
    text = ax.text(0.02, 0.97, "", transform=ax.transAxes, va="top", fontsize=8) if caption else None

    def update(frame: int) -> None:
        artist.move({key: path[frame] for key, path in paths.items()})
        if text is not None:
            text.set_text(str(_callback("caption", caption, frame)))

    return animation_html(figure, update, frames=len(next(iter(paths.values()))),
                          interval_ms=interval_ms, max_frames=max_frames)


#: The name the declarations' vocabulary uses: ``animate(mechanism, motion)``, as ``draw(mechanism, motion)``.
animate = animate_linkage


def _stage(ax, links, paths, trace, labels, *, ground, blocks, plates, styles) -> LinkageArtist:
    """The linkage's artist on ``ax``, its links checked against the points, the ground and the traces
    drawn, and the axes fitted to the whole motion."""
    if labels is True:  # every point by its own name
        labels = {key: str(key) for key in paths}
    elif labels is not None and not isinstance(labels, Mapping):
        raise InvalidArgumentError(f"labels must map point keys to texts, or be True (their names); "
                                   f"got {labels!r}")
    artist = LinkageArtist(ax, links, styles=styles, blocks=blocks, labels=labels, plates=plates)
    for kind, parts in (("links", artist.links), ("plates", artist.plates)):
        for name, ends in parts.items():
            if not set(ends) <= set(paths):
                raise InvalidGeometryError(f"{kind}: {name} joins {ends}, not all points; "
                                           f"points: {list(paths)}")
    (xmin, xmax, ymin, ymax), span = _motion_background(ax, paths, ground, trace)
    ax.set(xlim=(xmin, xmax), ylim=(ymin, ymax), aspect="equal", xlabel="x (m)", ylabel="y (m)")
    artist.label_offset = 0.03 * span
    return artist


def draw(links, points, ax: Axes | None = None, *, frame: int = 0, ground: Sequence = (),
         trace: Sequence = (), sliders: Sequence = (), blocks: Sequence = (),
         labels: Mapping | bool | None = None,
         link_labels: Mapping | bool | None = None,
         styles: Mapping[str, Mapping] | None = None, plates: Mapping[str, Sequence] | None = None,
         title: str | None = None, alpha: float = 1.0,
         size: tuple[float, float] = (4.2, 3.0)) -> Axes:
    """A still of one instant in one call, on ``ax`` (default: a new figure's), returned: the linkage (as
    :class:`LinkageArtist`, in the vocabulary of :func:`animate_linkage`) at ``points`` — key → (x, y),
    or a sweep (key → (frames, 2), or (frames, P, 2)) at its ``frame``, whose ``trace`` points get their
    dotted path.  ``links`` may be a declaration (a ``Mechanism``, or a machine such as ``FourBar``) and
    ``points`` a ``Motion`` of it: ``draw(wiper, wiper.solve(0.7))``, with the declaration's ground
    pivots, sliders, plates and styles unless given; ``sliders``: the points drawn as slider blocks
    (``blocks=`` is its older name).  ``labels``: point key → text, or True for every
    point's own name; ``link_labels``: link name → text, or True for every link's own name, written beside
    the link's middle (its ``gid`` is "label " + the link's name); ``alpha`` (0 to 1) fades the whole
    drawing, e.g. a seed drawn under a solution.  Each link's line carries its name as ``gid``.

    >>> import matplotlib; matplotlib.use("Agg")
    >>> ax = draw({"crank": ("O", "A")}, {"O": (0, 0), "A": (0.03, 0.04)}, ground=["O"], title="one",
    ...           link_labels=True)
    >>> ax.lines[0].get_xydata().tolist(), ax.get_title(), [t.get_text() for t in ax.texts]
    ([[0.0, 0.0], [0.03, 0.04]], 'one', ['crank'])
    """
    links, points, options = _declared(links, points, {"ground": ground, "blocks": _sliders(sliders, blocks),
                                                       "plates": plates, "styles": styles})
    paths = _paths(points)
    count = len(next(iter(paths.values())))
    whole = isinstance(frame, int | np.integer) and not isinstance(frame, bool | np.bool_)
    if not whole or not -count <= frame < count:
        raise InvalidArgumentError(f"frame must be a whole number from 0 to {count - 1}; got {frame!r}")
    number = _numbers("alpha", alpha, "a number from 0 to 1")
    if number.ndim or not 0 <= number <= 1:
        raise InvalidArgumentError(f"alpha must be a number from 0 to 1; got {alpha!r}")
    if ax is None:
        import matplotlib.pyplot as plt

        ax = plt.figure(figsize=_figure_size(size), layout="constrained").add_subplot()
    _axes(ax)
    before = set(ax.get_children())
    artist = _stage(ax, links, paths, trace, labels, **options)
    at = {key: path[frame] for key, path in paths.items()}
    artist.move(at)
    _name_links(ax, artist, at, link_labels)
    if number < 1:  # only what this call drew
        for child in set(ax.get_children()) - before:
            child.set_alpha(float(number))
    if title is not None:
        ax.set_title(title)
    return ax


def _name_links(ax, artist, at, link_labels) -> None:
    """Each link's text (``link_labels``: link name → text, or True for its own name) beside its middle,
    offset square to the link by the artist's label offset."""
    if link_labels is None or link_labels is False:
        return
    if link_labels is True:
        link_labels = {name: name for name in artist.links}
    if not isinstance(link_labels, Mapping) or not set(link_labels) <= set(artist.links):
        raise InvalidArgumentError(f"link_labels must map link names {list(artist.links)} to texts, or be "
                                   f"True (their names); got {link_labels!r}")
    for name, text in link_labels.items():
        start, end = (np.asarray(at[key], dtype=float) for key in artist.links[name])
        along = end - start
        length = float(np.hypot(*along))
        normal = np.array([-along[1], along[0]]) / length if length > 0 else np.array([0.0, 1.0])
        x, y = (start + end) / 2 + artist.label_offset * normal
        # the text's near edge towards the link: it never lies across it
        ha = "left" if normal[0] > 0.3 else "right" if normal[0] < -0.3 else "center"
        va = "bottom" if normal[1] > 0.3 else "top" if normal[1] < -0.3 else "center"
        ax.text(x, y, str(text), ha=ha, va=va, fontsize=8, color="0.25", gid=f"label {name}")


def _figure_size(size) -> tuple[float, float]:
    """``size`` as (width, height) in inches: two positive numbers of at most 20, else a named error."""
    if isinstance(size, str) or not isinstance(size, Sequence | np.ndarray) or len(size) != 2:
        raise InvalidArgumentError(f"size must be a (width, height) pair in inches; got {size!r}")
    width, height = (_positive_number(f"size[{k}]", value) for k, value in enumerate(size))
    if width > 20 or height > 20:
        raise InvalidArgumentError(f"size must be at most 20 × 20 inches; got {size!r}")
    return width, height


def _motion_background(ax: Axes, paths: Mapping, ground: Sequence = (), trace: Sequence = ()):
    """Draw the ``trace`` points' dotted paths and the ``ground`` points' fixed-pivot symbol; returns the
    box (xmin, xmax, ymin, ymax) of the finite ``paths`` with a margin, and the motion's span (m)."""
    for argument, keys in (("ground", ground), ("trace", trace)):
        for key in _sequence(argument, keys):
            if key not in paths:
                raise InvalidGeometryError(f"{argument} names {key!r}, not a point; points: {list(paths)}")
    everything = np.concatenate([np.reshape(path, (-1, 2)) for path in paths.values()])
    everything = everything[np.isfinite(everything).all(axis=1)]
    if not len(everything):
        raise InvalidGeometryError("points must have a finite (x, y) in some frame; all are nan or inf")
    (xmin, ymin), (xmax, ymax) = everything.min(axis=0), everything.max(axis=0)
    span = float(max(xmax - xmin, ymax - ymin)) or 1.0
    for key in trace:
        ax.plot(*np.reshape(paths[key], (-1, 2)).T, ":", color="0.55", lw=1)
    for key in ground:
        _ground_symbol(ax, np.reshape(paths[key], (-1, 2))[0], 0.03 * span)
    margin = 0.08 * span
    return (xmin - margin, xmax + margin, ymin - 2 * margin, ymax + margin), span


def plot_convergence(result: NewtonResult, exact: Sequence[float] | float | None = None,
                     names: Sequence[str] | None = None, title: str | None = None) -> Figure:
    """Three panels for one Newton run: iterates per variable, per-variable error and the error norm
    (log axes).  The error is measured against ``exact``, else against the last iterate (then dropped).

    >>> import matplotlib; matplotlib.use("Agg")
    >>> from course_lib.newton import newton
    >>> fig = plot_convergence(newton(lambda x: x**2 - 2, 1.0), exact=2**0.5, names=["x"])
    >>> len(fig.axes)
    3
    """
    if not isinstance(result, NewtonResult) or len(result.history) == 0:
        raise InvalidGeometryError(f"result must be a NewtonResult with its history (from newton); "
                                   f"got {result!r}")
    history = np.asarray(result.history, dtype=float).reshape(len(result.history), -1)
    n = history.shape[1]
    names = [f"x{k + 1}" for k in range(n)] if names is None else names
    _one_each("names", names, n, "name per variable")
    reference = history[-1] if exact is None else require_finite("exact", exact)
    if exact is not None and reference.size != n:
        raise InvalidGeometryError(f"exact must give one value per variable ({n}); got {exact!r}")
    errors = np.abs(history - reference.reshape(n))
    if exact is None:
        errors = errors[:-1]
    steps = np.arange(len(history))
    import matplotlib.pyplot as plt
    from matplotlib.ticker import LogLocator

    # fixed margins and at most six labelled decades: a layout engine and a label per decade would
    # render every 10⁻ⁿ label several times, the most of this figure's cost
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.4))
    fig.subplots_adjust(left=0.055, right=0.99, bottom=0.15, top=0.83 if title else 0.9, wspace=0.26)
    for k in range(n):
        axes[0].plot(steps, history[:, k], "o-", label=names[k])
        axes[1].semilogy(steps[: len(errors)], np.maximum(errors[:, k], 1e-17), "o-", label=names[k])
    axes[2].semilogy(steps[: len(errors)], np.maximum(np.linalg.norm(errors, axis=1), 1e-17), "o-k")
    for k, (ax, panel) in enumerate(zip(axes, ("iterates", "error per variable", "error norm"), strict=True)):
        ax.set(title=panel, xlabel="iteration n")
        ax.grid(True, linestyle="--", alpha=0.5)
        if k:
            ax.yaxis.set_major_locator(LogLocator(numticks=6))
        if k < 2:
            ax.legend(fontsize=8)
    if title:
        fig.suptitle(title)
    return fig


class AnimationHTML(str):
    """An animation player's HTML (a ``str``) shown as ``text/html`` (the player, with the still until
    JavaScript replaces it), ``image/png`` (the still: a filmstrip, also ``still_png``) and ``text/plain``.

    >>> fig = Figure(figsize=(2, 1.5), dpi=40)
    >>> line, = fig.add_subplot().plot([0, 1], [0, 0])
    >>> bundle = animation_html(fig, lambda k: line.set_ydata([0, k]), frames=5)._repr_mimebundle_()
    >>> sorted(bundle), bundle["text/plain"]
    (['image/png', 'text/html', 'text/plain'], 'animation: 5 frames, 40 ms each')
    """

    still_png: bytes
    frame_count: int
    interval_ms: float

    def _repr_html_(self) -> str:
        return str(self)

    def _text(self) -> str:
        return f"animation: {self.frame_count} frames, {self.interval_ms:g} ms each"

    def _repr_pretty_(self, printer, cycle) -> None:
        """IPython's plain text (which would otherwise print the HTML, as for any ``str``)."""
        printer.text(self._text())

    def _repr_mimebundle_(self, include=None, exclude=None, **kwargs) -> dict:
        return {"text/html": str(self), "image/png": _b64(self.still_png), "text/plain": self._text()}


#: Frames in a filmstrip (the still of an animation); a row when narrow enough, else a 2 × 2 grid.
_STILL_FRAMES = 4
_STILL_MAX_ROW_PX = 1100
_players = itertools.count(1)  # numbers the players of one session, so two equal animations differ

_PLAYER_JS = """(function () {
  var root = document.getElementById("%(id)s");
  if (!root || root.getAttribute("data-ready")) return;
  root.setAttribute("data-ready", "1");
  var width = %(width)d, height = %(height)d, delay = %(interval)s, k = 0, timer = null, waiting = 0;
  // each frame: [background, left, top, patch]; the patch (what moves) is drawn over its background
  var backgrounds = [%(backgrounds)s];
  var frames = new Array(%(count)d);
%(frames)s
  function picture(uri) {
    var image = new Image();
    waiting += 1;
    image.onload = function () { waiting -= 1; if (!waiting) show(k); };
    image.src = "data:image/png;base64," + uri;
    return image;
  }
  backgrounds = backgrounds.map(picture);
  frames = frames.map(function (f) { return [f[0], f[1], f[2], f[3] ? picture(f[3]) : null]; });
  var canvas = document.createElement("canvas");
  canvas.width = width; canvas.height = height;
  canvas.style.cssText = "display:block;max-width:100%%";
  canvas.setAttribute("aria-label", "animation of %(count)d frames");
  var context = canvas.getContext("2d");
  var bar = document.createElement("div");
  bar.style.cssText = "font:13px sans-serif;margin-top:2px";
  function button(label, title, action) {
    var b = document.createElement("button");
    b.textContent = label; b.title = title; b.onclick = action;
    b.style.cssText = "min-width:2.4em;margin-right:3px";
    bar.appendChild(b);
    return b;
  }
  var slider = document.createElement("input"), count = document.createElement("span");
  function show(j) {
    k = (j + frames.length) %% frames.length;
    slider.value = k;
    count.textContent = " frame " + (k + 1) + " / " + frames.length;
    if (waiting) return;
    var f = frames[k];
    context.drawImage(backgrounds[f[0]], 0, 0);
    if (f[3]) context.drawImage(f[3], f[1], f[2]);
  }
  function stop() { if (timer) { clearInterval(timer); timer = null; } play.textContent = "\u25B6"; }
  function tick() { if (!document.body.contains(canvas)) { stop(); return; } show(k + 1); }
  button("|\u25C0", "first frame", function () { stop(); show(0); });
  button("\u25C0", "previous frame", function () { stop(); show(k - 1); });
  var play = button("\u25B6", "play / pause (loops)", function () {
    if (timer) { stop(); } else { timer = setInterval(tick, delay); play.textContent = "||"; }
  });
  button("\u25B6|", "next frame", function () { stop(); show(k + 1); });
  slider.type = "range"; slider.min = 0; slider.max = frames.length - 1; slider.value = 0;
  slider.style.cssText = "vertical-align:middle;width:12em";
  slider.oninput = function () { stop(); show(parseInt(slider.value, 10)); };
  bar.appendChild(slider); bar.appendChild(count);
  while (root.firstChild) root.removeChild(root.firstChild);
  root.appendChild(canvas); root.appendChild(bar);
  show(0);
})();"""

def animation_html(fig: Figure, update: Callable[[int], object], frames: int, interval_ms: float = 40, *,
                   max_frames: int = 48, dpi: float | None = None) -> AnimationHTML:
    """Animate ``fig`` by ``update(frame)``: a self-contained HTML/JavaScript player, with a filmstrip
    where JavaScript does not run, drawing per frame only the artists ``update`` makes stale; more than
    ``max_frames`` frames are thinned (each shown longer).  A pyplot figure is closed afterwards.

    >>> fig = Figure(figsize=(2, 1.5), dpi=40)
    >>> line, = fig.add_subplot().plot([0, 1], [0, 0])
    >>> html = animation_html(fig, lambda k: line.set_ydata([0, k]), frames=2)
    >>> "<script" in html and "frames[1]" in html, html.frame_count
    (True, 2)
    """
    _count("frames", frames)
    if not isinstance(fig, Figure):
        raise InvalidArgumentError(f"fig must be a matplotlib Figure; got {type(fig).__name__}")
    if not callable(update):
        raise InvalidArgumentError(f"update must be a function of the frame number; got {update!r}")
    interval = _positive_number("interval_ms", interval_ms)
    _count("max_frames", max_frames)
    if dpi is not None:
        fig.set_dpi(_dpi(dpi))
    chosen = [int(k) for k in np.arange(min(frames, max_frames)) * frames // min(frames, max_frames)]
    width, height = fig.get_size_inches()
    pixels = width * height * fig.dpi**2 * len(chosen)
    if pixels > MOST_PIXELS:  # checked before any drawing: an animation answers within seconds
        raise InvalidArgumentError(
            f"an animation of {len(chosen)} frames of {width:g}×{height:g} in at {fig.dpi:g} dpi is "
            f"{pixels / 1e6:.0f} million pixels, more than the {MOST_PIXELS / 1e6:.0f} million drawn within "
            f"seconds: lower dpi, size or max_frames")
    frames_drawn, backgrounds = _render_frames(fig, update, chosen)
    if "matplotlib.pyplot" in sys.modules:  # (a figure pyplot does not manage needs no closing)
        sys.modules["matplotlib.pyplot"].close(fig)
    return _player(frames_drawn, backgrounds, interval * (frames / len(chosen)))


#: The most pixels an animation draws (all its frames together): 48 frames of 4.2×3 in at 200 dpi, ~3 s.
MOST_PIXELS = 25e6


def _count(name: str, value) -> None:
    if isinstance(value, bool) or not isinstance(value, int | np.integer) or value < 1:
        raise InvalidArgumentError(f"{name} must be a positive whole number; got {value!r}")


def _dpi(value) -> float:
    dpi = _positive_number("dpi", value)
    if dpi > 600:
        raise InvalidArgumentError(f"dpi must be at most 600 (dots per inch); got {value!r}")
    return dpi


def _positive_number(name: str, value) -> float:
    ok = not isinstance(value, bool) and isinstance(value, int | float | np.integer | np.floating)
    if not ok or not math.isfinite(value) or value <= 0:
        raise InvalidArgumentError(f"{name} must be a positive, finite number; got {value!r}")
    return float(value)


def _render_frames(fig: Figure, update: Callable[[int], object], chosen: list[int]):
    """Each chosen frame as (RGB array, index of its background: what does not move), and the backgrounds."""
    canvas = fig.canvas if isinstance(fig.canvas, FigureCanvasAgg) else FigureCanvasAgg(fig)
    _callback("update", update, chosen[0])
    canvas.draw()  # the one layout (constrained, tight, …), then the layout engine is switched off
    engine = fig.get_layout_engine()
    fig.set_layout_engine("none")
    # the artists update() makes stale are the moving ones (some, e.g. an empty text or a tick out of
    # view, stay stale after a draw; setting stale to False propagates to nothing)
    parts = [artist for artist in fig.findobj() if not isinstance(artist, Figure | Axes)]
    for artist in parts:
        artist.stale = False
    if len(chosen) > 1:
        _callback("update", update, chosen[1])
    moving = sorted((artist for artist in parts if artist.stale), key=lambda artist: artist.get_zorder())
    was_animated = [artist.get_animated() for artist in moving]
    for artist in moving:
        artist.set_animated(True)
    frames, backgrounds, watched, limits, saved = [], [], [], None, None
    try:
        for frame in chosen:
            _callback("update", update, frame)
            now = [(axes.get_xlim(), axes.get_ylim()) for axes in fig.axes]
            if saved is None or now != limits or any(artist.stale for artist in watched):
                canvas.draw()  # something besides the moving artists changed: a new background
                saved, limits = canvas.copy_from_bbox(fig.bbox), now
                backgrounds.append(_rgb(canvas))
                watched = [artist for artist in fig.findobj()
                           if artist not in moving and not isinstance(artist, Figure | Axes)]
                for artist in watched:
                    artist.stale = False  # from here on, stale means update() changed it
            else:
                canvas.restore_region(saved)
            for artist in moving:
                if artist.get_visible():
                    (artist.axes or fig).draw_artist(artist)
            frames.append((_rgb(canvas), len(backgrounds) - 1))
    finally:
        for artist, animated in zip(moving, was_animated, strict=True):
            artist.set_animated(animated)
        fig.set_layout_engine(engine)
    return frames, backgrounds


def _rgb(canvas: FigureCanvasAgg) -> np.ndarray:
    return np.asarray(canvas.buffer_rgba())[..., :3].copy()


class _Quantizer:
    """Pictures as PNGs in one palette of ≤ 255 colours from a first picture (its colours, or its 127 most
    frequent and 128 octree blends) and up to 64 ``extra`` RGB colours; pixels map through a 7-bit table
    (PIL's has 6 bits and turns white into 252)."""

    _UNSEEN = 255  # the table's value of a cell not met yet; the palette uses entries 0…254

    def __init__(self, picture: np.ndarray, extra=()):
        values, counts = np.unique(_pack(picture), return_counts=True)
        extra = np.setdiff1d(_pack(np.asarray(list(extra), np.uint32).reshape(-1, 3)[:64]), values)
        if len(values) + len(extra) > self._UNSEEN:
            common = values[np.argsort(counts, kind="stable")[::-1][:127 - len(extra)]]
            octree = Image.fromarray(np.ascontiguousarray(picture[..., :3])).quantize(
                128, method=Image.Quantize.FASTOCTREE)
            blends = _pack(np.asarray(octree.getpalette()[:384], np.uint32).reshape(-1, 3))
            values = np.concatenate([common, extra, blends])
        else:
            values = np.concatenate([values, extra])
        self.colours = ((values[:, None] >> np.array([16, 8, 0], np.uint32)) & 255).astype(np.int32)
        self.table = np.full(1 << 21, self._UNSEEN, np.uint8)

    def png(self, picture: np.ndarray, compress_level: int = 1, trim: bool = True) -> bytes:
        """An RGB or RGBA array as a PNG in this palette; ``trim`` keeps only the colours it uses."""
        word = _pack(picture, little_endian=True)
        # np.intp indices: np.take refuses uint32 ones where np.intp is 32 bits (a "safe" cast only)
        cells = (((word >> 1) & 0x7F) | ((word >> 2) & 0x3F80) | ((word >> 3) & 0x1FC000)).astype(np.intp)
        indices = np.take(self.table, cells)
        unseen = indices == self._UNSEEN
        if unseen.any():
            first_cells, first = np.unique(cells[unseen], return_index=True)
            colours = picture[unseen][first, :3].astype(np.int32)
            distances = ((colours[:, None, :] - self.colours[None, :, :]) ** 2).sum(axis=2)
            self.table[first_cells] = distances.argmin(axis=1)
            indices = np.take(self.table, cells)
        colours = self.colours
        if trim:
            used = np.flatnonzero(np.bincount(indices.ravel(), minlength=256))
            remap = np.zeros(256, np.uint8)
            remap[used] = np.arange(len(used))
            indices, colours = remap[indices], colours[used]
        image = Image.fromarray(indices)
        image.putpalette(colours.astype(np.uint8).ravel().tolist())  # ("L" + a palette: "P")
        buffer = io.BytesIO()
        image.save(buffer, format="PNG", compress_level=compress_level)
        return buffer.getvalue()


def _pack(picture: np.ndarray, little_endian: bool = False) -> np.ndarray:
    """Each pixel's RGB as one integer, 65536 R + 256 G + B, or R + 256 G + 65536 B (+ 2**24 alpha) if
    ``little_endian``: then a view of a contiguous RGBA buffer (matplotlib's), with no copy."""
    if (little_endian and picture.ndim == 3 and picture.shape[2] == 4 and picture.dtype == np.uint8
            and picture.flags.c_contiguous and sys.byteorder == "little"):
        return picture.view(np.uint32)[..., 0]
    red, green, blue = (picture[..., k].astype(np.uint32) for k in range(3))
    return (blue << 16) | (green << 8) | red if little_endian else (red << 16) | (green << 8) | blue


def _filmstrip(pictures: list[np.ndarray]) -> np.ndarray:
    """Up to four evenly spaced frames side by side (or 2 × 2 when a row would be too wide)."""
    count = min(_STILL_FRAMES, len(pictures))
    chosen = [pictures[k * len(pictures) // count] for k in range(count)]
    height, width, _ = chosen[0].shape
    gap = 4
    columns = count if count * width <= _STILL_MAX_ROW_PX or count < _STILL_FRAMES else 2
    rows = -(-count // columns)
    strip = np.full((rows * (height + gap) - gap, columns * (width + gap) - gap, 3), 200, np.uint8)
    for k, picture in enumerate(chosen):
        top, left = (k // columns) * (height + gap), (k % columns) * (width + gap)
        strip[top:top + height, left:left + width] = picture
    return strip


def _b64(data: bytes) -> str:
    return base64.b64encode(data).decode("ascii")


def _player(frames: list[tuple[np.ndarray, int]], backgrounds: list[np.ndarray], interval: float
            ) -> AnimationHTML:
    """The HTML/JS player: the backgrounds once and per frame only the (cropped) box where it differs
    from its background, painted on a canvas; and the filmstrip still."""
    quantizer = _Quantizer(frames[0][0])
    lines, patches = [], []
    for k, (picture, background) in enumerate(frames):
        rows, columns = np.nonzero(np.any(picture != backgrounds[background], axis=2))
        if rows.size:
            top, left, bottom, right = rows.min(), columns.min(), rows.max() + 1, columns.max() + 1
            patches.append(quantizer.png(picture[top:bottom, left:right], 6))
            lines.append(f'  frames[{k}] = [{background}, {left}, {top}, "{_b64(patches[-1])}"];')
        else:
            lines.append(f"  frames[{k}] = [{background}, 0, 0, null];")
    strip = _filmstrip([picture for picture, _ in frames])
    still = _Quantizer(strip).png(strip, 9)
    digest = hashlib.sha1(b"".join(patches) + still).hexdigest()[:12]
    element = f"course-animation-{digest}-{next(_players)}"
    height, width, _ = frames[0][0].shape
    script = _PLAYER_JS % {
        "id": element, "width": width, "height": height, "count": len(frames),
        "interval": f"{interval:.0f}",
        "backgrounds": ", ".join(f'"{_b64(quantizer.png(background, 6))}"' for background in backgrounds),
        "frames": "\n".join(lines),
    }
    strip_height, strip_width, _ = strip.shape
    html = (
        f'<div class="course-animation" id="{element}">'
        f'<img src="data:image/png;base64,{_b64(still)}" width="{strip_width}" height="{strip_height}" '
        f'alt="{len(frames)} frames of an animation; a still of {min(_STILL_FRAMES, len(frames))} of them">'
        f"</div>\n<script>\n{script}\n</script>\n"
    )
    result = AnimationHTML(html)
    result.still_png, result.frame_count, result.interval_ms = still, len(frames), round(interval, 3)
    return result
