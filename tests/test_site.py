"""The course website (`make site`): built offline from the committed outputs, and read in a real browser.

The site is built once per test session by tools/build_site.py, unless ``_build/html`` is already newer
than everything it is made from (README, site config, the build tool, every notebook), as after
``make site`` in .ci/run.  The browser part serves it on 127.0.0.1 and opens pages in Debian's chromium
through playwright with every request to anywhere else blocked and recorded; it is skipped, with the
reason, when /usr/bin/chromium is missing (CI installs it: see .ci/run).  Screenshots are written to a
temporary folder whose path is printed.
"""

import ast
import html
import json
import os
import pathlib
import re
import subprocess
import sys
import tempfile
import time
import tomllib
import urllib.parse

import nbformat
import pytest
import yaml

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import build_site  # noqa: E402

HTML = build_site.HTML
FORMULA_PAGE = "notebooks/04_fourbar_velocity_acceleration"
EXPLORER_PAGE = "notebooks/11_explorers"
EXERCISE_PAGE = "notebooks/exercises/ex03_fourbar"
ANIMATION_PAGE = "notebooks/03_fourbar_position"


def _inputs() -> list[pathlib.Path]:
    return [ROOT / "README.md", ROOT / "pyproject.toml", build_site.SITE_CONFIG,
            pathlib.Path(build_site.__file__), ROOT / "tools" / "repository.py",
            *build_site.SITE_EXTENSION.rglob("*.*"), *build_site.page_paths()]


def _fresh() -> bool:
    index = HTML / "index.html"
    return index.exists() and index.stat().st_mtime > max(path.stat().st_mtime for path in _inputs())


@pytest.fixture(scope="module")
def site() -> pathlib.Path:
    if build_site.repository.repository_url() is not None:
        pytest.skip("these tests read the site built without a repository address (COURSE_REPOSITORY_URL)")
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


def test_each_page_offers_its_notebook_as_a_percent_script(site):
    for path in build_site.page_paths():
        page = (site / f"{_page(path)}.html").read_text(encoding="utf-8")
        depth = "../" * (len(path.relative_to(ROOT).parts) - 1)
        link = f'{depth}_sources/{path.relative_to(ROOT).with_suffix(".py").as_posix()}'
        assert f'href="{link}"' in page, f"{path.name}: no .py download {link}"
        script = (site / "_sources" / path.relative_to(ROOT).with_suffix(".py")).read_text(encoding="utf-8")
        notebook = nbformat.read(path, as_version=4)
        assert script.count("\n# %%") == len(notebook.cells)
        ast.parse(script)  # magics are commented out: the script is plain Python
        for cell in notebook.cells:
            if cell.cell_type == "code" and not cell.source.lstrip().startswith("%"):
                assert cell.source.splitlines()[-1] in script


def test_every_figure_has_an_alt_text_from_its_titles_or_its_section(site):
    pictures = 0
    for path in build_site.page_paths():
        page = (site / f"{_page(path)}.html").read_text(encoding="utf-8")
        article = page[page.index("<article"): page.index("</article>")]
        for alt in re.findall(r'<img\b[^>]*\balt="([^"]*)"', article):
            pictures += 1
            assert alt.strip() and "_images/" not in alt and not alt.endswith(".png"), f"{path.name}: {alt!r}"
        assert len(re.findall(r"<img\b", article)) == len(re.findall(r'<img\b[^>]*\balt="', article))
    assert pictures >= 60
    page = (site / f"{ANIMATION_PAGE}.html").read_text(encoding="utf-8")
    assert 'alt="Figure: The wiper four-bar at θ2 = 60°"' in page


def test_the_figure_alt_text_prefers_titles_then_the_output_then_the_heading():
    figure = nbformat.v4.new_output("display_data", {"image/png": "iVBOR",
                                                     "text/plain": "<Figure size 6x4 with 1 Axes>"})
    cell = nbformat.v4.new_code_cell('ax.set_title("Coupler curve")\nfig.suptitle(f"{name} at rest")',
                                     outputs=[figure])
    assert build_site.figure_alt(cell, "3. Curves", "Lesson") == "Figure: Coupler curve; … at rest"
    cell.source = "plot()"
    assert build_site.figure_alt(cell, "3. Curves", "Lesson") == "Figure of the section “3. Curves”"
    cell.outputs[0]["data"]["text/plain"] = "four-bar explorer (ok)\nθ2 = 60.0°\nmore"
    assert build_site.figure_alt(cell, None, "Lesson") == "four-bar explorer (ok): θ2 = 60.0° (in “Lesson”)"


def test_the_whole_course_is_one_pdf_linked_from_the_landing_page(site):
    if not build_site.can_print():
        pytest.skip("the PDF needs /usr/bin/chromium and playwright")
    pdf = (site / "course.pdf").read_bytes()
    pages = build_site.pdf_page_count(pdf)
    print(json.dumps({"course_pdf_pages": pages, "course_pdf_mb": round(len(pdf) / 1e6, 1)}))
    assert pdf.startswith(b"%PDF-") and pages >= 100
    assert 'href="course.pdf"' in (site / "index.html").read_text(encoding="utf-8")
    # nothing runs past the page's right margin: measured in the print layout the PDF is made from, at A4's
    # printable width (a formula wider than the page is shrunk to it, code wraps, pictures shrink)
    wide = json.loads((site / build_site.OVERFLOW.name).read_text(encoding="utf-8"))
    assert wide == [], wide
    single = html.unescape((build_site.SINGLE / "index.html").read_text(encoding="utf-8")).replace("’", "'")
    for path in build_site.page_paths():  # every page is in the printed single page
        cells = nbformat.read(path, as_version=4).cells
        title = next(build_site._heading(cell.source) for cell in cells
                     if cell.cell_type == "markdown" and build_site._heading(cell.source))
        assert title.split("·")[-1].strip()[:20] in single, path.name


def test_the_version_shows_on_the_landing_page_under_every_page_and_on_the_pdfs_first_page(site):
    version = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["version"]
    import course_lib

    assert course_lib.__version__ == version  # one version (tests/test_release.py), read, never typed here
    index = (site / "index.html").read_text(encoding="utf-8")
    article = index[index.index("<article"): index.index("</article>")]
    assert f"Version {version}" in article
    for path in [site / "index.html", *(site / f"{_page(path)}.html" for path in build_site.page_paths())]:
        page = path.read_text(encoding="utf-8")
        foot = page[page.index('<footer class="bd-footer-content'):]  # the footer under the text
        assert f'<p class="course-version">Version {version}.</p>' in foot, f"{path.name}: no version"
    if build_site.can_print():  # the PDF is printed from the single page: its first page, the printed title
        single = (build_site.SINGLE / "index.html").read_text(encoding="utf-8")
        cover = single[single.index('<div id="jb-print-docs-body"'):
                       single.index('<div id="print-main-content"')]
        assert re.search(r"<h1>Mechanism Kinematics, step by step<br><span class=\"course-version\">"
                         rf"Version {re.escape(version)}</span></h1>", cover), cover


def test_the_landing_pages_browser_title_names_the_collection_once(site):
    title = yaml.safe_load(build_site.SITE_CONFIG.read_text(encoding="utf-8"))["title"]
    shown = re.search(r"<title>(.*?)</title>", (site / "index.html").read_text(encoding="utf-8")).group(1)
    assert html.unescape(shown) == title  # not "title — title"
    lesson = (site / f"{ANIMATION_PAGE}.html").read_text(encoding="utf-8")
    assert html.unescape(re.search(r"<title>(.*?)</title>", lesson).group(1)).endswith(f" — {title}")
    for page in ("index.html", f"{ANIMATION_PAGE}.html"):  # the navigation bar keeps the collection's title
        shown = (site / page).read_text(encoding="utf-8")
        assert f'<p class="title logo__title">{html.escape(title)}</p>' in shown


PLACEHOLDERS = re.compile(r"OWNER/|example\.(?:org|com)|the repository's address|mybinder|colab\.research|"
                          r"git-pull|github\.com|gitlab\.com", re.I)


def test_without_a_repository_address_no_repository_link_or_placeholder_shows(site):
    for path in sorted(site.rglob("*.html")):
        if "_static" in path.parts:
            continue
        text = path.read_text(encoding="utf-8")
        body = text[text.index("<body"):]
        found = PLACEHOLDERS.search(body)
        assert not found, f"{path.relative_to(site)}: {found.group(0)}"
        for label in ("launch-buttons", "repository-button", "source-file-button", "issues-button"):
            assert label not in body, f"{path.relative_to(site)}: {label}"


def test_the_site_config_keeps_no_setting_jupyter_book_ignores():
    """Jupyter Book passes on only these keys of ``parse`` (myst_dmath_double_inline there did nothing)."""
    config = yaml.safe_load(build_site.SITE_CONFIG.read_text(encoding="utf-8"))
    assert set(config["parse"]) <= {"myst_enable_extensions", "myst_substitutions", "myst_url_schemes"}
    assert "html_show_sourcelink" not in config["sphinx"]["config"]  # no sourcelink in sphinx-book-theme


REPOSITORY = "https://github.com/example-org/mechanism-kinematics"
HUB = "https://hub.example.edu"


@pytest.fixture(scope="module")
def site_with_repository(tmp_path_factory):
    """The same site built with a repository address and a JupyterHub set (no PDF: it is the same)."""
    output = tmp_path_factory.mktemp("site-with-repository")
    env = dict(os.environ, COURSE_SITE_OUTPUT=str(output), COURSE_REPOSITORY_URL=REPOSITORY,
               COURSE_JUPYTERHUB_URL=HUB, COURSE_SITE_PDF="off")
    result = subprocess.run([sys.executable, str(ROOT / "tools" / "build_site.py")], cwd=ROOT, env=env,
                            capture_output=True, text=True, timeout=900)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    return output / "_build" / "html"


def test_with_a_repository_address_the_site_shows_launch_and_repository_links(site_with_repository):
    built = site_with_repository
    page = (built / f"{ANIMATION_PAGE}.html").read_text(encoding="utf-8")
    notebook = f"{ANIMATION_PAGE}.ipynb"
    binder = "https://mybinder.org/v2/gh/example-org/mechanism-kinematics/main"
    assert f"{binder}?urlpath=lab/tree/{notebook}" in page
    colab = "https://colab.research.google.com/github/example-org/mechanism-kinematics/blob/main/"
    assert f"{colab}{notebook}" in page
    assert f"{HUB}/hub/user-redirect/git-pull?repo={urllib.parse.quote(REPOSITORY)}" in page
    assert f'href="{REPOSITORY}"' in page and f"{REPOSITORY}/issues" in page
    assert f"{REPOSITORY}/blob/main/{notebook}" in page  # the page's source
    index = (built / "index.html").read_text(encoding="utf-8")
    assert f"{REPOSITORY}/issues" in index and "mybinder.org" in index
    assert not (built / "course.pdf").exists() and 'href="course.pdf"' not in index
    assert build_site.outside_loads(built) == []


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


@pytest.fixture(scope="module")
def served(site):
    with build_site.serve(site) as address:
        yield address


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
    outputs = " ".join(view.page.locator("article .cell_output").all_inner_texts())  # (code may name errors)
    assert outputs and "Error" not in outputs
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


def test_code_and_outputs_stay_within_the_text_column(visit):
    for page in (FORMULA_PAGE, "notebooks/07_saw_full_motion", EXERCISE_PAGE):
        view = visit(f"{page}.html")
        view.load_all_images()
        outside = view.page.evaluate("""() => {
            const column = document.querySelector('article').getBoundingClientRect();
            const found = [];
            document.querySelectorAll('article div.cell, article div.cell_output img').forEach(element => {
                const box = element.getBoundingClientRect();
                if (box.right > column.right + 1) found.push(element.className + ' ends at ' + box.right);
            });
            const pres = document.querySelectorAll('article div.cell_input pre, article div.cell_output pre');
            pres.forEach(pre => {
                if (pre.scrollWidth > pre.clientWidth + 1) found.push(pre.textContent.slice(0, 60));
            });
            return found; }""")
        assert outside == [], f"{page}: {outside}"
        view.assert_clean()


def test_the_download_menu_offers_the_notebook_and_its_script(visit):
    view = visit(f"{ANIMATION_PAGE}.html")
    view.page.locator(".dropdown-download-buttons button").first.click()
    script = view.page.locator("a.btn-download-script-button")
    script.wait_for(state="visible")
    assert script.inner_text().strip() == ".py"
    assert view.page.locator("a.btn-download-source-button").inner_text().strip() == ".ipynb"
    response = view.page.request.get(script.evaluate("link => link.href"))
    assert response.ok and response.text().startswith("# ---\n# jupyter:")
    alts = view.page.evaluate("() => [...document.querySelectorAll('article img')].map(img => img.alt)")
    assert alts and all(alt and "_images/" not in alt for alt in alts), alts
    view.screenshot("03_download_menu")
    view.assert_clean()


@pytest.fixture(scope="module")
def served_with_repository(site_with_repository):
    with build_site.serve(site_with_repository) as base:
        yield base


def test_the_launch_and_repository_buttons_show_and_load_nothing(chromium, served_with_repository):
    view = Visit(chromium, served_with_repository, f"{ANIMATION_PAGE}.html")
    try:
        launch = view.page.locator(".dropdown-launch-buttons button").first
        launch.click()
        hrefs = "links => links.map(a => a.href)"
        targets = view.page.locator(".dropdown-launch-buttons a").evaluate_all(hrefs)
        assert any("mybinder.org" in url for url in targets) and any("colab" in url for url in targets)
        assert any("git-pull" in url for url in targets), targets
        source = view.page.locator(".dropdown-source-buttons a").evaluate_all(hrefs)
        assert any(url.startswith(REPOSITORY) for url in source), source
        view.screenshot("03_launch_buttons")
        view.assert_clean()
    finally:
        view.close()
