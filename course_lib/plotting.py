"""Pictures for the lessons: linkages with labelled links and numbered joints,
Newton convergence plots, and animations rendered to HTML (no ffmpeg needed).

>>> import matplotlib
>>> matplotlib.use("Agg")
>>> ax = draw_linkage([(0, 0), (0.03, 0.04), (0.1, 0.05), (0.1, 0)],
...                   [(0, 1, "l2"), (1, 2, "l3"), (2, 3, "l4"), (3, 0, "l1")], ground=[0, 3])
>>> [text.get_text() for text in ax.texts][:5]
['l2', 'l3', 'l4', 'l1', '1']
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import matplotlib.pyplot as plt
import numpy as np
from matplotlib.animation import FuncAnimation
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from .errors import InvalidGeometryError
from .newton import NewtonResult

__all__ = ["draw_linkage", "plot_convergence", "animation_html", "LINK_COLORS"]

#: One colour per link, in the order the links are given.
LINK_COLORS = ("tab:blue", "tab:orange", "tab:green", "tab:red", "tab:purple", "tab:brown")


def _ground_symbol(ax: Axes, point: np.ndarray, size: float) -> None:
    """A small hatched triangle under a fixed pivot (the bancada)."""
    x, y = point
    triangle = np.array([[x, y], [x - size, y - 1.6 * size], [x + size, y - 1.6 * size]])
    ax.fill(triangle[:, 0], triangle[:, 1], facecolor="none", edgecolor="0.3", hatch="///", lw=1)


def draw_linkage(
    points: Sequence[Sequence[float]],
    links: Sequence[tuple[int, int, str]],
    ax: Axes | None = None,
    *,
    joint_labels: Sequence[str] | None = None,
    ground: Sequence[int] = (),
    title: str | None = None,
    grid: bool = True,
    linestyle: str = "-",
    alpha: float = 1.0,
) -> Axes:
    """Draw a planar linkage.

    Parameters
    ----------
    points : joint coordinates (x, y) in metres, one row per joint.
    links : (i, j, label) per link: a bar from joint i to joint j, labelled at its midpoint.
    joint_labels : text beside each joint (default "1", "2", …).
    ground : indices of fixed pivots, drawn with a hatched ground symbol.
    title, grid, linestyle, alpha : cosmetics; ``grid`` draws a dashed grid.

    Returns the axes (created if ``ax`` is None), with equal aspect ratio.

    >>> import matplotlib; matplotlib.use("Agg")
    >>> ax = draw_linkage([(0, 0), (1, 0)], [(0, 1, "l1")], title="one bar")
    >>> ax.get_title()
    'one bar'
    """
    xy = np.asarray(points, dtype=float)
    if xy.ndim != 2 or xy.shape[1] != 2:
        raise InvalidGeometryError(f"points must be a list of (x, y) pairs; got shape {xy.shape}")
    if not np.all(np.isfinite(xy)):
        raise InvalidGeometryError("points must be finite: the linkage is not assembled here")
    if ax is None:
        ax = plt.figure(figsize=(5, 4)).add_subplot()
    span = float(np.ptp(xy, axis=0).max()) or 1.0
    for k, (i, j, label) in enumerate(links):
        if not (0 <= i < len(xy) and 0 <= j < len(xy)):
            raise InvalidGeometryError(
                f"link {label!r} joins joints {i}, {j}; only {len(xy)} given"
            )
        color = LINK_COLORS[k % len(LINK_COLORS)]
        segment = xy[[i, j]]
        ax.plot(
            segment[:, 0],
            segment[:, 1],
            linestyle,
            color=color,
            lw=3,
            alpha=alpha,
            solid_capstyle="round",
        )
        middle = segment.mean(axis=0)
        direction = segment[1] - segment[0]
        normal = np.array([-direction[1], direction[0]]) / (np.hypot(*direction) or 1.0)
        ax.text(
            *(middle + 0.04 * span * normal),
            label,
            color=color,
            ha="center",
            va="center",
            fontsize=10,
            fontweight="bold",
            alpha=alpha,
        )
    for index in ground:
        _ground_symbol(ax, xy[index], 0.03 * span)
    ax.plot(xy[:, 0], xy[:, 1], "o", ms=7, mfc="white", mec="black", zorder=3, alpha=alpha)
    labels = joint_labels if joint_labels is not None else [str(k + 1) for k in range(len(xy))]
    for (x, y), label in zip(xy, labels, strict=True):
        ax.annotate(
            label, (x, y), xytext=(6, 6), textcoords="offset points", fontsize=9, alpha=alpha
        )
    ax.set_aspect("equal", adjustable="datalim")
    ax.margins(0.08)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    if grid:
        ax.grid(True, linestyle="--", alpha=0.5)
    if title is not None:
        ax.set_title(title)
    return ax


def plot_convergence(
    result: NewtonResult,
    exact: Sequence[float] | float | None = None,
    names: Sequence[str] | None = None,
    title: str | None = None,
) -> Figure:
    """Three panels for one Newton run: iterates per variable, per-variable
    error, and the error norm on a log axis.

    The error is measured against ``exact`` when given; otherwise against the
    last iterate (so the last point is dropped from the log plots).

    >>> import matplotlib; matplotlib.use("Agg")
    >>> from course_lib.newton import newton
    >>> fig = plot_convergence(newton(lambda x: x**2 - 2, 1.0), exact=2**0.5, names=["x"])
    >>> len(fig.axes)
    3
    """
    history = np.asarray(result.history, dtype=float).reshape(len(result.history), -1)
    n = history.shape[1]
    names = list(names) if names is not None else [f"x{k + 1}" for k in range(n)]
    if len(names) != n:
        raise InvalidGeometryError(f"names must have {n} entries; got {len(names)}")
    reference = history[-1] if exact is None else np.asarray(exact, float).reshape(n)
    errors = np.abs(history - reference)
    if exact is None:
        errors = errors[:-1]
    steps = np.arange(len(history))
    fig, axes = plt.subplots(1, 3, figsize=(12, 3.4), layout="constrained")
    for k in range(n):
        axes[0].plot(steps, history[:, k], "o-", label=names[k])
        axes[1].semilogy(
            steps[: len(errors)], np.maximum(errors[:, k], 1e-17), "o-", label=names[k]
        )
    axes[2].semilogy(steps[: len(errors)], np.maximum(np.linalg.norm(errors, axis=1), 1e-17), "o-k")
    axes[0].set_title("iterates")
    axes[1].set_title("error per variable")
    axes[2].set_title("error norm")
    for ax in axes:
        ax.set_xlabel("iteration n")
        ax.grid(True, linestyle="--", alpha=0.5)
    axes[0].legend(fontsize=8)
    axes[1].legend(fontsize=8)
    if title:
        fig.suptitle(title)
    return fig


def animation_html(
    fig: Figure, update: Callable[[int], object], frames: int, interval_ms: float = 40
) -> str:
    """Animate ``fig`` by calling ``update(frame)`` for each frame and return
    a self-contained HTML/JavaScript player (no ffmpeg needed).

    The figure is closed afterwards so the notebook shows only the player;
    display it with ``IPython.display.HTML``.

    >>> import matplotlib; matplotlib.use("Agg")
    >>> fig, ax = plt.subplots()
    >>> line, = ax.plot([0, 1], [0, 0])
    >>> html = animation_html(fig, lambda k: line.set_ydata([0, k]), frames=2)
    >>> html.lstrip().startswith("<link") or "<script" in html
    True
    """
    if int(frames) != frames or frames < 1:
        raise InvalidGeometryError(f"frames must be a positive integer; got {frames!r}")
    animation = FuncAnimation(fig, update, frames=int(frames), interval=interval_ms, blit=False)
    html = animation.to_jshtml(default_mode="loop")
    plt.close(fig)
    return html
