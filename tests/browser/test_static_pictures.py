"""What a reader sees of explorers and animations where nothing runs, and the animation player where
JavaScript runs: chromium (Debian's, via playwright) on nbconvert's HTML of a notebook whose outputs
are the explorers' and an animation's display bundles.  Skipped, with the reason, when
/usr/bin/chromium or playwright is missing (CI installs chromium: see .ci/run).
"""


import matplotlib
import nbformat
import pytest
from matplotlib.figure import Figure

from course_lib.plotting import animation_html
from course_lib.widgets import fivebar_explorer, fourbar_explorer, saw_explorer

matplotlib.use("Agg")



def _animation():
    fig = Figure(figsize=(3.0, 2.4), dpi=60)
    ax = fig.add_subplot()
    ax.set(xlim=(-1.2, 1.2), ylim=(-1.2, 1.2), aspect="equal")
    bar, = ax.plot([], [], "o-", lw=3)

    def update(k):
        bar.set_data([0, [1, 0, -1, 0][k % 4]], [0, [0, 1, 0, -1][k % 4]])

    return animation_html(fig, update, frames=8, interval_ms=50)


@pytest.fixture(scope="module")
def page_html(tmp_path_factory):
    """nbconvert's HTML (lab template) of a notebook showing three explorers and an animation."""
    from nbconvert import HTMLExporter

    notebook = nbformat.v4.new_notebook()
    for k, shown in enumerate((fourbar_explorer(), saw_explorer(), fivebar_explorer(), _animation())):
        cell = nbformat.v4.new_code_cell(f"shown_{k}", execution_count=k + 1)
        cell.outputs = [nbformat.v4.new_output("execute_result", data=shown._repr_mimebundle_(),
                                               execution_count=k + 1)]
        notebook.cells.append(cell)
    html, _ = HTMLExporter().from_notebook_node(notebook)
    path = tmp_path_factory.mktemp("static") / "pictures.html"
    path.write_text(html, encoding="utf-8")
    return path


def _shown_images(page) -> list[int]:
    """Natural widths of the output images the page actually shows (0: broken)."""
    return page.evaluate("() => [...document.querySelectorAll('.jp-OutputArea-output img')]"
                         ".filter(i => i.offsetWidth > 0).map(i => i.naturalWidth)")


def test_without_javascript_every_explorer_and_animation_shows_a_picture(page_html, chromium):
    page = chromium.new_page(viewport={"width": 1300, "height": 1000}, java_script_enabled=False)
    page.goto(page_html.as_uri())
    widths = _shown_images(page)
    assert len(widths) == 4 and all(width > 300 for width in widths), widths  # 3 explorers + the filmstrip
    text = page.locator("body").inner_text()
    assert "HBox(" not in text and "Loading widget" not in text
    page.close()


def test_with_javascript_the_animation_plays(page_html, chromium):
    page = chromium.new_page(viewport={"width": 1300, "height": 1000})
    errors = []
    page.on("pageerror", lambda error: errors.append(str(error)))
    page.goto(page_html.as_uri())
    player = page.locator(".course-animation").first
    player.locator("canvas").wait_for()
    assert player.locator("img").count() == 0  # the still gave way to the player

    def painted() -> str:
        return page.evaluate("() => document.querySelector('.course-animation canvas').toDataURL()")

    first = painted()
    player.locator("button[title='next frame']").click()
    assert painted() != first and "frame 2 / 8" in player.inner_text()
    player.locator("button[title='first frame']").click()
    assert painted() == first and "frame 1 / 8" in player.inner_text()
    player.locator("button[title^='play']").click()
    counter = "document.querySelector('.course-animation').innerText"
    page.wait_for_function(f"() => !{counter}.includes('frame 1 /')")
    assert errors == []
    page.close()
