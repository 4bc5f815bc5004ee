"""plotting.animation_html: the player's frames are the figure's frames, drawn cheaply, with a still."""

import base64
import io
import re

import matplotlib.pyplot as plt
import numpy as np
import pytest
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from PIL import Image

from course_lib.errors import InvalidGeometryError
from course_lib.plotting import AnimationHTML, animation_html

FRAME = re.compile(r'frames\[(\d+)\] = \[(\d+), (\d+), (\d+), (?:"([A-Za-z0-9+/=]+)"|null)\];')


def _image(data: bytes) -> np.ndarray:
    return np.asarray(Image.open(io.BytesIO(data)).convert("RGB")).astype(int)


def _player_frames(html: str) -> list[np.ndarray]:
    """What the player paints for each frame: its background, with its patch at (left, top)."""
    listed = re.search(r"var backgrounds = \[(.*?)\];", html).group(1)
    backgrounds = [_image(base64.b64decode(uri)) for uri in re.findall(r'"([^"]+)"', listed)]
    frames = []
    for index, background, left, top, patch in FRAME.findall(html):
        assert int(index) == len(frames)
        picture = backgrounds[int(background)].copy()
        if patch:
            pixels = _image(base64.b64decode(patch))
            picture[int(top):int(top) + pixels.shape[0], int(left):int(left) + pixels.shape[1]] = pixels
        frames.append(picture)
    return frames


def _pendulum(layout=None):
    """A figure with axes, ticks, a fixed curve, a moving bar and bob, and a moving label."""
    fig = Figure(figsize=(3.0, 2.4), dpi=50, layout=layout)
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    angles = np.linspace(-0.8, 0.8, 12)
    ax.plot(np.sin(angles), -np.cos(angles), color="0.6", lw=1)
    bar, = ax.plot([], [], "o-", color="tab:blue", lw=3, mfc="white", mec="black")
    label = ax.text(0.03, 0.95, "", transform=ax.transAxes, va="top")
    ax.set(xlim=(-1.1, 1.1), ylim=(-1.2, 0.2), aspect="equal")

    def update(k):
        bar.set_data([0, np.sin(angles[k])], [0, -np.cos(angles[k])])
        label.set_text(f"frame {k}")

    return fig, update, len(angles)


def _full_redraws(fig, update, frames) -> list[np.ndarray]:
    """The independent route: every frame drawn in full, as FuncAnimation would."""
    pictures = []
    for k in frames:
        update(k)
        fig.canvas.draw()
        pictures.append(np.asarray(fig.canvas.buffer_rgba())[..., :3].astype(int))
    return pictures


@pytest.mark.parametrize("layout", [None, "constrained"])
def test_player_frames_are_the_figures_frames(layout):
    fig, update, count = _pendulum(layout)
    html = animation_html(fig, update, frames=count)
    assert isinstance(html, AnimationHTML) and html.frame_count == count
    painted = _player_frames(html)
    fig.set_layout_engine("none")  # the layout of the first frame, as the player keeps it
    for picture, expected in zip(painted, _full_redraws(fig, update, range(count)), strict=True):
        assert picture.shape == expected.shape
        # 256 colours: anti-aliased edges may move to a neighbouring colour, nothing else
        assert np.mean(np.abs(picture - expected)) < 1.0
        assert np.mean(np.any(np.abs(picture - expected) > 48, axis=2)) < 0.002


def test_update_called_once_per_frame_and_the_figure_is_drawn_in_full_once():
    fig, update, count = _pendulum()
    calls, draws = [], []
    original = fig.canvas.draw
    fig.canvas.draw = lambda: draws.append(1) or original()
    animation_html(fig, lambda k: calls.append(k) or update(k), frames=count)
    assert calls[-count:] == list(range(count)) and len(calls) == count + 2  # + the layout and the probe
    assert len(draws) == 2  # the layout, then the background without the moving artists


def test_a_change_outside_the_moving_artists_starts_a_new_background():
    fig, update, count = _pendulum()
    ax = fig.axes[0]

    def zooming(k):
        update(k)
        if k == 6:
            ax.set_xlim(-2.0, 2.0)  # the limits change once: the ticks must follow
        if k == 9:
            ax.set_title("slower")  # a static artist changes once

    html = animation_html(fig, zooming, frames=count)
    assert len(re.search(r"var backgrounds = \[(.*?)\];", html).group(1).split(",")) == 3
    painted = _player_frames(html)
    ax.set_xlim(-1.1, 1.1)
    ax.set_title("")
    fig.set_layout_engine("none")
    for picture, expected in zip(painted, _full_redraws(fig, zooming, range(count)), strict=True):
        assert np.mean(np.abs(picture - expected)) < 1.0


def test_more_frames_than_max_are_thinned_keeping_the_duration():
    fig, ax = plt.subplots(figsize=(2, 1.5), dpi=40)
    line, = ax.plot([0, 1], [0, 0])
    calls = []
    html = animation_html(fig, lambda k: calls.append(k) or line.set_ydata([0, k / 100]), frames=100,
                          interval_ms=40, max_frames=25)
    assert html.frame_count == 25 and html.interval_ms == pytest.approx(160)
    assert calls[-25:] == list(range(0, 100, 4))
    assert "delay = 160," in html
    assert not plt.fignum_exists(fig.number)  # closed: the notebook shows only the player


def test_display_bundle_has_player_filmstrip_and_text():
    fig, update, count = _pendulum()
    html = animation_html(fig, update, frames=count, interval_ms=80)
    bundle = html._repr_mimebundle_()
    assert bundle["text/html"] == str(html) and bundle["text/plain"] == "animation: 12 frames, 80 ms each"
    still = _image(base64.b64decode(bundle["image/png"]))
    width, height = 150, 120  # 3.0 × 2.4 in at 50 dpi: four frames in a row, 4 px apart
    assert still.shape == (height, 4 * width + 3 * 4, 3)
    painted = _player_frames(html)
    for k, frame in enumerate((0, 3, 6, 9)):
        tile = still[:, k * (width + 4):k * (width + 4) + width]
        assert np.mean(np.abs(tile - painted[frame])) < 1.0
    # without JavaScript the HTML shows the same still
    still = r'<div class="course-animation" id="[\w-]+"><img src="data:image/png;base64,([^"]+)"'
    first = re.match(still, html)
    assert base64.b64decode(first.group(1)) == html.still_png


def test_ipython_displays_the_three_representations_not_the_html_as_text():
    from IPython.core.formatters import DisplayFormatter

    fig, update, count = _pendulum()
    html = animation_html(fig, update, frames=count, interval_ms=80)
    data, _ = DisplayFormatter().format(html)
    assert data == html._repr_mimebundle_()


def test_a_wide_animation_gets_a_two_by_two_still():
    fig = Figure(figsize=(6, 2), dpi=50)
    FigureCanvasAgg(fig)
    line, = fig.add_subplot().plot([0, 1], [0, 0])
    html = animation_html(fig, lambda k: line.set_ydata([0, k]), frames=8)
    assert _image(html.still_png).shape == (2 * 100 + 4, 2 * 300 + 4, 3)


@pytest.mark.parametrize(("arguments", "name"), [
    (dict(frames=0), "frames"), (dict(frames=-1), "frames"), (dict(frames=2.5), "frames"),
    (dict(frames=True), "frames"), (dict(frames="3"), "frames"),
    (dict(frames=3, interval_ms=0), "interval_ms"), (dict(frames=3, interval_ms=float("nan")), "interval_ms"),
    (dict(frames=3, interval_ms="40"), "interval_ms"), (dict(frames=3, max_frames=0), "max_frames"),
    (dict(frames=3, dpi=-72), "dpi"),
])
def test_bad_arguments_are_named(arguments, name):
    fig, update, _ = _pendulum()
    with pytest.raises(InvalidGeometryError, match=f"^{name} "):
        animation_html(fig, update, **arguments)


def test_bad_figure_or_update_are_named():
    with pytest.raises(InvalidGeometryError, match="^fig "):
        animation_html("figure", lambda k: None, frames=2)
    with pytest.raises(InvalidGeometryError, match="^update "):
        animation_html(Figure(), None, frames=2)
