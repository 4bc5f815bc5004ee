"""The course website (`make site`): built offline from the committed outputs, and read in a real browser.

The site is built once per test session by tools/build_site.py, unless ``_build/html`` is already newer
than everything it is made from (README, site config, the build tool, every notebook), as after
``make site`` in .ci/run.  The browser part serves it on 127.0.0.1 and opens pages in Debian's chromium
through playwright with every request to anywhere else blocked and recorded; it is skipped, with the
reason, when /usr/bin/chromium is missing (CI installs it: see .ci/run).  Screenshots are written to a
temporary folder whose path is printed.
"""

import functools
import http.server
import json
import pathlib
import re
import subprocess
import sys
import tempfile
import threading
import time
import urllib.parse

import nbformat
import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import build_site  # noqa: E402

HTML = build_site.HTML
FORMULA_PAGE = "notebooks/04_fourbar_velocity_acceleration"
EXPLORER_PAGE = "notebooks/11_explorers"
EXERCISE_PAGE = "notebooks/exercises/ex03_fourbar"
ANIMATION_PAGE = "notebooks/03_fourbar_position"


def _inputs() -> list[pathlib.Path]:
    return [ROOT / "README.md", build_site.SITE_CONFIG, pathlib.Path(build_site.__file__),
            *build_site.page_paths()]


def _fresh() -> bool:
    index = HTML / "index.html"
    return index.exists() and index.stat().st_mtime > max(path.stat().st_mtime for path in _inputs())


@pytest.fixture(scope="module")
def site() -> pathlib.Path:
    if not _fresh():
        started = time.monotonic()
        result = subprocess.run([sys.executable, str(ROOT / "tools" / "build_site.py")], cwd=ROOT,
                                capture_output=True, text=True, timeout=900)
        assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
        print(f"site built in {time.monotonic() - started:.1f} s: {result.stdout.strip().splitlines()[-1]}")
    return HTML


def _page(path: pathlib.Path) -> str:
    """``notebooks/…/name`` for a notebook path."""
    return path.relative_to(ROOT).with_suffix("").as_posix()


# ---------------------------------------------------------------- the built files


def test_every_lesson_and_exercise_has_a_page_and_no_solution_does(site):
    for path in build_site.page_paths():
        assert (site / f"{_page(path)}.html").is_file(), f"no page for {path.name}"
    assert not (site / "notebooks" / "solutions").exists()
    assert len(build_site.lesson_paths()) >= 12 and len(build_site.exercise_paths()) >= 5


def test_landing_page_is_the_lesson_map_and_links_every_page(site):
    index = (site / "index.html").read_text(encoding="utf-8")
    article = index[index.index("<article"): index.index("</article>")]  # the page, not the side bar
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert readme.splitlines()[0].lstrip("# ") in article
    for path in build_site.page_paths():
        assert f'href="{_page(path)}.html"' in article, f"the lesson map does not link {path.name}"
    assert 'href="notebooks/solutions' not in index


def test_each_page_offers_its_committed_notebook_for_download(site):
    for path in build_site.page_paths():
        page = (site / f"{_page(path)}.html").read_text(encoding="utf-8")
        depth = "../" * (len(path.relative_to(ROOT).parts) - 1)
        link = f'{depth}_sources/{path.relative_to(ROOT).as_posix()}'
        assert f'href="{link}"' in page, f"{path.name}: no download link {link}"
        assert (site / "_sources" / path.relative_to(ROOT)).read_bytes() == path.read_bytes()


def test_search_and_a_local_mathjax_are_part_of_the_site(site):
    assert (site / "search.html").is_file() and (site / "searchindex.js").is_file()
    assert "Grashof" in (site / "searchindex.js").read_text(encoding="utf-8")
    assert (site / "_static" / "mathjax" / "tex-chtml.js").is_file()
    page = (site / f"{FORMULA_PAGE}.html").read_text(encoding="utf-8")
    assert re.search(r'<script[^>]* src="\.\./_static/mathjax/tex-chtml\.js[?"]', page)


def test_nothing_in_the_site_loads_from_outside_it(site):
    assert build_site.outside_loads(site) == []


def test_the_display_copy_drops_widget_views_and_cdn_icon_links():
    view = {"model_id": "x", "version_major": 2, "version_minor": 0}
    notebook = nbformat.v4.new_notebook(cells=[nbformat.v4.new_code_cell("explorer", outputs=[
        nbformat.v4.new_output("display_data", {build_site.WIDGET_VIEW: view, "text/plain": "HBox(…)"}),
        nbformat.v4.new_output("display_data", {build_site.WIDGET_VIEW: view, "image/png": "iVBOR",
                                                "text/plain": "HBox(…)"}),
        nbformat.v4.new_output("display_data", {"text/html": '<link rel="stylesheet"\n'
                               'href="https://cdn.example/font-awesome/4.4.0/css/font-awesome.min.css">\n<div/>'}),
    ])])
    notebook.metadata["widgets"] = {"state": {}}
    shown = build_site.display_copy(notebook)
    outputs = shown.cells[0].outputs
    assert "widgets" not in shown.metadata and "widgets" in notebook.metadata
    assert [sorted(output["data"]) for output in outputs] == [["image/png", "text/plain"], ["text/html"]]
    assert outputs[1]["data"]["text/html"] == "<div/>"


# ---------------------------------------------------------------- in a browser


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@pytest.fixture(scope="module")
def served(site):
    handler = functools.partial(_QuietHandler, directory=str(site))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


SHOTS = pathlib.Path(tempfile.mkdtemp(prefix="course-site-"))


class Visit:
    """One page in a fresh browser context: outside requests blocked and recorded, errors collected."""

    def __init__(self, browser, base: str, page: str):
        self.blocked, self.errors, self.failed = [], [], []
        self.context = browser.new_context(viewport={"width": 1280, "height": 900})
        self.context.route("**/*", self._route)
        self.page = self.context.new_page()
        self.page.set_default_timeout(30_000)
        self.page.on("console", lambda msg: self.errors.append(msg.text) if msg.type == "error" else None)
        self.page.on("pageerror", lambda error: self.errors.append(str(error)))
        self.page.on("requestfailed", lambda request: self.failed.append(request.url))
        self.page.on("response", lambda response: self.failed.append(f"{response.status} {response.url}")
                     if response.status >= 400 else None)
        self.page.goto(f"{base}/{page}", wait_until="load")

    def _route(self, route):
        host = urllib.parse.urlsplit(route.request.url).hostname
        if route.request.url.startswith(("data:", "blob:")) or host == "127.0.0.1":
            route.continue_()
        else:
            self.blocked.append(route.request.url)
            route.abort()

    def wait_for_mathjax(self) -> None:
        self.page.wait_for_function("() => window.MathJax && MathJax.startup && MathJax.startup.promise")
        self.page.evaluate("() => MathJax.startup.promise")

    def load_all_images(self) -> list[dict]:
        """Scroll through the page (lazy images load when seen), then report every image."""
        self.page.evaluate("""async () => {
            for (let y = 0; y < document.body.scrollHeight; y += 600) {
                window.scrollTo(0, y); await new Promise(r => setTimeout(r, 30)); }
            window.scrollTo(0, 0);
            await Promise.all([...document.images].map(img => img.decode().catch(() => null)));
        }""")
        return self.page.evaluate("""() => [...document.images].map(img => ({
            src: img.currentSrc.slice(0, 80), complete: img.complete, width: img.naturalWidth}))""")

    def screenshot(self, name: str, full_page: bool = False) -> pathlib.Path:
        path = SHOTS / f"{name}.png"
        self.page.screenshot(path=str(path), full_page=full_page)
        print(f"screenshot: {path}")
        return path

    def assert_clean(self) -> None:
        assert self.blocked == [], f"requests outside the site: {self.blocked}"
        assert self.errors == [], f"console errors: {self.errors}"
        assert self.failed == [], f"failed requests: {self.failed}"

    def close(self) -> None:
        self.context.close()


@pytest.fixture
def visit(chromium, served):
    opened = []

    def open_page(page: str) -> Visit:
        opened.append(Visit(chromium, served, page))
        return opened[-1]

    yield open_page
    for page in opened:
        page.close()


def _expected_images(page: str) -> int:
    notebook = nbformat.read(ROOT / f"{page}.ipynb", as_version=4)
    return sum("image/png" in output.get("data", {}) for cell in notebook.cells if cell.cell_type == "code"
               for output in cell.outputs)


def _assert_images_loaded(images: list[dict], at_least: int) -> None:
    broken = [image for image in images if not image["complete"] or image["width"] == 0]
    assert broken == [], f"images that did not load: {broken}"
    assert len(images) >= at_least


def test_formulas_are_typeset_by_the_sites_own_mathjax(visit):
    view = visit(f"{FORMULA_PAGE}.html")
    view.wait_for_mathjax()
    typeset = view.page.locator("mjx-container").count()
    assert typeset > 10, f"only {typeset} typeset formulas"
    text = view.page.locator("article").inner_text()
    assert "$$" not in text and "\\begin{" not in text and "\\frac" not in text
    _assert_images_loaded(view.load_all_images(), _expected_images(FORMULA_PAGE))
    view.screenshot("04_top")
    view.page.locator("mjx-container").nth(12).scroll_into_view_if_needed()
    view.screenshot("04_formulas")
    view.assert_clean()


def test_an_exercise_page_shows_tasks_hints_and_pictures(visit):
    view = visit(f"{EXERCISE_PAGE}.html")
    text = view.page.locator("article").inner_text()
    assert "Task 1" in text and "hint" in text.lower() and "$$" not in text
    assert "BEGIN SOLUTION" not in text
    _assert_images_loaded(view.load_all_images(), _expected_images(EXERCISE_PAGE))
    view.page.locator("article h2").first.scroll_into_view_if_needed()
    view.screenshot("ex03")
    view.assert_clean()


def test_the_explorers_page_shows_its_saved_pictures(visit):
    view = visit(f"{EXPLORER_PAGE}.html")
    images = view.load_all_images()
    _assert_images_loaded(images, _expected_images(EXPLORER_PAGE))
    assert "Error" not in view.page.locator("article").inner_text()
    view.screenshot("11_explorers", full_page=True)
    view.assert_clean()


def test_an_animation_plays_with_its_buttons_drawn(visit):
    """The lesson's animation player (course_lib's, or matplotlib's to_jshtml in older outputs) runs."""
    view = visit(f"{ANIMATION_PAGE}.html")
    player = view.page.locator(".course-animation, .animation").first
    player.scroll_into_view_if_needed()
    slider = player.locator('input[type="range"]')
    view.page.wait_for_function("el => el.max > 1", arg=slider.element_handle())
    play = player.locator('button[title="Play"], button[title^="play"]').first
    icon = play.locator("i, svg")
    if icon.count():  # matplotlib's player: the site's Font Awesome draws the icon (an inline SVG once run)
        width = icon.first.evaluate("icon => icon.getBoundingClientRect().width")
        assert width > 4, "the play button's icon is not drawn (icon font missing)"
    else:
        assert play.inner_text().strip(), "the play button has no label"
    play.click()
    view.page.wait_for_function("el => parseInt(el.value) > 3", arg=slider.element_handle(), timeout=10_000)
    play.click() if not icon.count() else player.locator('button[title="Pause"]').click()
    _assert_images_loaded(view.load_all_images(), 1)
    player.scroll_into_view_if_needed()
    view.screenshot("03_animation")
    view.assert_clean()


def test_the_landing_page_and_search_work(visit):
    view = visit("index.html")
    for path in build_site.page_paths():
        assert view.page.locator(f'article a[href="{_page(path)}.html"]').count() >= 1
    view.screenshot("index")
    view.assert_clean()
    search = visit("search.html?q=Grashof")
    search.page.wait_for_selector("#search-results li a", timeout=20_000)
    hits = search.page.locator("#search-results li a").evaluate_all("links => links.map(a => a.href)")
    assert any("03_fourbar_position" in hit for hit in hits), hits
    search.assert_clean()
    print(json.dumps({"search_hits_for_Grashof": len(hits)}))
