"""Build the course website, ``_build/html/``, from the committed notebooks: nothing is executed.

Usage: python tools/build_site.py            (= make site)

Steps:

1. **Stage** ``_build/source/``: ``site/_config.yml`` (every page's footer names the version,
   ``[project] version`` of pyproject.toml); a landing page ``index.md`` that is the README's lesson
   map (its title, the version, its introduction and its *Lessons* section, exercises included); a
   ``_toc.yml`` listing every lesson (``notebooks/NN_*.ipynb``) and every student exercise copy
   (``notebooks/exercises/exNN_*.ipynb``; never the solutions); and a display copy of each notebook.
   The display copy differs from the committed file only where a page would otherwise load from
   outside the site: widget views are dropped (no widget manager is served; an explorer shows the
   static picture saved beside its view) and the player of a matplotlib animation loses the link to
   a CDN's icon font (the site's own Font Awesome draws the buttons).  Files are rewritten only when
   their content changes, so Sphinx rebuilds only what changed.
2. **Build** with Jupyter Book 1 (Sphinx, ``execute_notebooks: off``), MathJax copied into
   ``_static/mathjax`` from a pinned package.
3. **Publish the notebooks as committed**: each page's download link (``_sources/…ipynb``) serves
   the committed file, not the display copy.  MathJax keeps its one entry point (``mathjax_path``
   in the config) and everything that loads lazily (extensions, fonts, menu, accessibility, SVG
   output); the package's other combined entry points, never loaded, are left out.
4. **Check** that no page, stylesheet or script tag of the site loads anything from outside it.
5. **Print the whole course** as one PDF, ``_build/html/course.pdf``: Jupyter Book's single-page build
   of the same staged tree (``_build/singlehtml``), typeset and printed by Debian's chromium through
   playwright, served from 127.0.0.1 with every other request refused; its first page opens with the
   title and the version, and every page's foot names both.  Without /usr/bin/chromium
   (or with ``COURSE_SITE_PDF=off``) the PDF and the landing page's link to it are left out, with a warning.

Each page also offers its notebook as a percent-format Python script (``_sources/…/name.py``, cells
marked ``# %%`` as jupytext and VS Code read them), each figure has an alt text (its titles, or the
heading it illustrates), and code stays within the text column (long lines wrap): ``site/_ext``.

The repository's address (``[project.urls] Repository`` in pyproject.toml, ``COURSE_REPOSITORY_URL``
overriding it; tools/repository.py) adds launch buttons (Binder, Colab, and an nbgitpuller link when
a JupyterHub is set too) and repository, source and issue links; without it the site has none of them.
``COURSE_SITE_OUTPUT`` builds into another folder's ``_build/`` (the tests build both ways).
"""

from __future__ import annotations

import ast
import contextlib
import copy
import functools
import http.server
import json
import os
import pathlib
import re
import shutil
import subprocess
import sys
import threading
import time
import tomllib
import urllib.parse
from html import escape as escape_html  # (display_copy has a variable named html)

import nbformat
import yaml

ROOT = pathlib.Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tools"))
import repository  # noqa: E402

SITE_CONFIG = ROOT / "site" / "_config.yml"
SITE_EXTENSION = ROOT / "site" / "_ext"
BUILD = pathlib.Path(os.environ.get("COURSE_SITE_OUTPUT") or ROOT).resolve() / "_build"
STAGE = BUILD / "source"
HTML = BUILD / "html"
SINGLE = BUILD / "singlehtml"
PDF = HTML / "course.pdf"
OVERFLOW = HTML / "course-pdf-overflow.json"  # what prints wider than the PDF's page (tests/test_site.py)
CHROMIUM = pathlib.Path("/usr/bin/chromium")
CHROMIUM_ARGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
# the collection's version, one place: pyproject.toml's [project] version (= course_lib.__version__,
# tests/test_release.py); the landing page, every page's footer and the PDF's pages show it
VERSION = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]["version"]
# a figure whose text/plain is only matplotlib's repr says nothing about it
GENERIC_FIGURE = re.compile(r"^<Figure size [^>]*>$")

WIDGET_VIEW = "application/vnd.jupyter.widget-view+json"
# matplotlib's to_jshtml() player links Font Awesome 4 from a CDN for its buttons
CDN_ICON_LINK = re.compile(r'<link rel="stylesheet"\s+href="https?://[^"]*font-awesome[^"]*"\s*/?>\s*')
# what makes a browser fetch a resource (links <a href> to elsewhere are fine: they load nothing)
OUTSIDE_LOADS = [
    re.compile(r"<script\b[^>]*\bsrc=[\"'](?:https?:)?//", re.I),
    re.compile(r"<link\b(?=[^>]*\brel=[\"']?(?:stylesheet|preload|modulepreload|icon|prefetch))"
               r"[^>]*\bhref=[\"'](?:https?:)?//", re.I),
    re.compile(r"<(?:img|iframe|audio|video|source|embed)\b[^>]*\bsrc=[\"'](?:https?:)?//", re.I),
    re.compile(r"@import\s+(?:url\()?[\"']?(?:https?:)?//", re.I),
    re.compile(r"url\([\"']?(?:https?:)?//", re.I),
]


class SiteError(RuntimeError):
    """The site cannot be built as promised (message says what and where)."""


def lesson_paths() -> list[pathlib.Path]:
    return sorted((ROOT / "notebooks").glob("[0-9][0-9]_*.ipynb"))


def exercise_paths() -> list[pathlib.Path]:
    return sorted((ROOT / "notebooks" / "exercises").glob("ex[0-9][0-9]_*.ipynb"))


def page_paths() -> list[pathlib.Path]:
    """Every notebook that becomes a page, lessons first."""
    return lesson_paths() + exercise_paths()


def _relative(path: pathlib.Path) -> str:
    return path.relative_to(ROOT).as_posix()


def _anchor(url: str, text: str) -> str:
    """An HTML link to ``url``, its address and text escaped for HTML."""
    return f'<a href="{escape_html(url, quote=True)}">{escape_html(text)}</a>'


def landing_page(readme: str, url: str | None = None, pdf: bool = False) -> str:
    """The site's index page: the README's title, the version, its first paragraph and its *Lessons* section.

    The README's links (``notebooks/….ipynb``) are kept as they are: the staged tree has the same
    layout, so they become links to the pages.  ``url`` (the repository's address) adds a line of
    links to run the lessons elsewhere; ``pdf`` a link to the whole course as one PDF.
    """
    lines = readme.splitlines()
    if not lines or not lines[0].startswith("# "):
        raise SiteError("README.md must start with its '# ' title")
    title = lines[0]
    paragraphs, block, fenced = [], [], False
    for line in lines[1:]:
        if line.startswith("```"):
            fenced = not fenced
            continue
        if fenced:
            continue
        if line.startswith("#"):
            break
        if line.strip():
            block.append(line)
        elif block:
            paragraphs.append(" ".join(block))
            block = []
    if not paragraphs:
        raise SiteError("README.md has no introductory paragraph before its first section")
    start = next((i for i, line in enumerate(lines) if line.strip() == "## Lessons"), None)
    if start is None:
        raise SiteError("README.md has no '## Lessons' section (the site's lesson map)")
    stop = next((i for i in range(start + 1, len(lines)) if lines[i].startswith("## ")), len(lines))
    lesson_map = "\n".join(lines[start:stop]).rstrip()
    missing = [_relative(path) for path in page_paths() if f"({_relative(path)})" not in lesson_map]
    if missing:  # the pages are built all the same (the table of contents lists every notebook)
        print(f"warning: README.md's lesson map does not link {', '.join(missing)}")
    how_to = (
        "Every page is a notebook shown with the outputs it was committed with. The download button "
        "at the top of a page (↓) gives you the notebook itself (`.ipynb`) or the same cells as a Python "
        "script (`.py`), which runs top to bottom with `python`. Either needs `course_lib` and the packages "
        "of `environment.txt` (see *Start here*); where `course_lib` is missing, as on Colab, a lesson's "
        "first cell says so."
    )
    parts = [title, f"*Version {VERSION}*", paragraphs[0], how_to]
    if pdf:
        parts.append("The whole course, every lesson and exercise set, is also one PDF: "
                     f'<a href="{PDF.name}" class="course-pdf">{PDF.name}</a>.')
    if url:
        made = repository.links(url)  # the address checked (tools/repository.py); escaped all the same
        elsewhere = [_anchor(made.repository, "the repository"), _anchor(made.issues, "its issues")]
        if made.binder:
            binder = _anchor(made.binder, "Binder")
            elsewhere.append(f"{binder} (JupyterLab at lesson 00, nothing to install)")
        parts.append("Run the lessons elsewhere, or report a problem: " + ", ".join(elsewhere) + ".")
    licence = (
        "## Licence\n\nThe lesson text and figures are licensed CC-BY-4.0 (`LICENSE-content`); the code — "
        "`course_lib`, the tools and the tests — BSD-3-Clause (`LICENSE`)."
    )
    return "\n\n".join([*parts, lesson_map, licence]) + "\n"


def table_of_contents() -> str:
    """Jupyter Book's ``_toc.yml``: the landing page, then the lessons, then the exercises."""
    def chapters(paths):
        return "".join(f"      - file: {_relative(path)[: -len('.ipynb')]}\n" for path in paths)

    return (
        "# generated by tools/build_site.py from the notebooks present\n"
        "format: jb-book\nroot: index\nparts:\n"
        "  - caption: Lessons\n    chapters:\n" + chapters(lesson_paths())
        + "  - caption: Exercises\n    chapters:\n" + chapters(exercise_paths())
    )


def site_config(url: str | None, hub: str | None = None) -> str:
    """``_config.yml`` as staged: ``site/_config.yml`` with the repository's links when there is an address.

    Without one, every repository and launch setting stays empty or off, so no button shows.
    """
    config = yaml.safe_load(SITE_CONFIG.read_text(encoding="utf-8"))
    options = config["sphinx"]["config"].setdefault("html_theme_options", {})
    config["sphinx"]["config"]["release"] = VERSION  # the print title's version (site/_ext)
    config["html"]["extra_footer"] = (f'<p class="course-version">Version {escape_html(VERSION)}.</p>'
                                      + config["html"].get("extra_footer", ""))
    if url:
        made = repository.links(url)
        config["repository"] = {"url": made.repository, "path_to_book": "", "branch": made.branch}
        config["launch_buttons"] = {
            "notebook_interface": "jupyterlab", "thebe": False,
            "binderhub_url": "https://mybinder.org" if made.binder else "",
            "colab_url": "https://colab.research.google.com" if made.colab else "",
            "jupyterhub_url": repository.checked_hub(hub) if hub else "",
        }
        config["html"].update(use_repository_button=True, use_issues_button=True)
        options.update(use_repository_button=True, use_issues_button=True, use_source_button=True)
    else:
        config["repository"] = {"url": ""}
        config["launch_buttons"] = {"notebook_interface": "jupyterlab", "thebe": False,
                                    "binderhub_url": "", "colab_url": "", "jupyterhub_url": ""}
        config["html"].update(use_repository_button=False, use_issues_button=False)
        options.update(use_repository_button=False, use_issues_button=False, use_source_button=False)
    header = "# staged by tools/build_site.py from site/_config.yml and the repository's address\n"
    return header + yaml.safe_dump(config, sort_keys=False, allow_unicode=True, width=110)


def _literal_strings(node: ast.AST) -> list[str]:
    """The text of a string literal or f-string (its literal parts), else nothing."""
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return [node.value]
    if isinstance(node, ast.JoinedStr):  # a formatted value reads "…"
        text = "".join(part.value if isinstance(part, ast.Constant) else "…" for part in node.values)
        return [text] if text.strip("… ") else []
    return []


def figure_titles(source: str) -> list[str]:
    """The titles a code cell gives its figures (``set_title("…")``, ``suptitle``, ``title=``), in order."""
    try:
        tree = ast.parse(source)
    except SyntaxError:
        return []
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        name = node.func.attr if isinstance(node.func, ast.Attribute) else getattr(node.func, "id", "")
        if name in {"set_title", "suptitle", "title"} and node.args:
            found += _literal_strings(node.args[0])
        found += [text for keyword in node.keywords if keyword.arg == "title"
                  for text in _literal_strings(keyword.value)]
    titles = []
    for title in found:
        title = " ".join(title.split())
        if title and title not in titles:
            titles.append(title)
    return titles


def _heading(markdown: str) -> str | None:
    for line in markdown.splitlines():
        if line.startswith("#"):
            return re.sub(r"[*_`$\\]", "", line.lstrip("#")).strip()
    return None


def figure_alt(cell: nbformat.NotebookNode, heading: str | None, page_title: str) -> str | None:
    """The alt text of a code cell's pictures: its figures' titles, else what the output says it
    shows (an explorer's readout, an animation's frame count), else the heading it sits under."""
    pictures = [output for output in cell.get("outputs", []) if "image/png" in output.get("data", {})]
    if not pictures:
        return None
    titles = figure_titles(cell.source)
    if titles:
        return "Figure: " + "; ".join(titles)
    text = pictures[0]["data"].get("text/plain", "")
    text = ("".join(text) if isinstance(text, list) else text).strip()
    where = heading or page_title
    if text and not GENERIC_FIGURE.match(text):  # e.g. an explorer's name, status and first readout
        return ": ".join(line.strip() for line in text.splitlines()[:2]) + f" (in “{where}”)"
    return f"Figure of the section “{where}”"


def display_copy(notebook: nbformat.NotebookNode) -> nbformat.NotebookNode:
    """The notebook as the site shows it: nothing in it loads from outside the site.

    Widget views go (an output keeps its other representations, such as the explorer's
    ``image/png``; an output left with only the widget's text repr goes altogether), and the
    CDN icon-font link of matplotlib animation players goes.  Each cell with a picture gets its alt
    text (``figure_alt``) as MyST-NB's ``mystnb.image.alt`` cell option.
    """
    shown = copy.deepcopy(notebook)
    shown.metadata.pop("widgets", None)
    page_title = next((_heading(cell.source) for cell in shown.cells if cell.cell_type == "markdown"
                       and _heading(cell.source)), "this page")
    heading = None
    for cell in shown.cells:
        if cell.cell_type == "markdown":
            heading = _heading(cell.source) or heading
            continue
        if cell.cell_type != "code":
            continue
        outputs = []
        for output in cell.outputs:
            data = output.get("data")
            if data is not None and WIDGET_VIEW in data:
                data.pop(WIDGET_VIEW)
                if set(data) <= {"text/plain"}:
                    continue
            if data is not None and "text/html" in data:
                html = data["text/html"]
                html = "".join(html) if isinstance(html, list) else html
                data["text/html"] = CDN_ICON_LINK.sub("", html)
            outputs.append(output)
        cell.outputs = outputs
        alt = figure_alt(cell, heading, page_title)
        if alt:
            cell.metadata.setdefault("mystnb", {}).setdefault("image", {})["alt"] = alt
    return shown


def percent_script(notebook: nbformat.NotebookNode) -> str:
    """The notebook as a percent-format Python script: ``# %%`` before each code cell, ``# %% [markdown]``
    before each text cell (its lines commented), as jupytext writes it; IPython magics are commented
    out, so the script runs with plain Python."""
    kernel = notebook.metadata.get("kernelspec", {})
    lines = ["# ---", "# jupyter:", "#   kernelspec:",
             f"#     display_name: {kernel.get('display_name', 'Python 3')}",
             f"#     language: {kernel.get('language', 'python')}",
             f"#     name: {kernel.get('name', 'python3')}", "# ---"]
    for cell in notebook.cells:
        lines.append("")
        if cell.cell_type == "code":
            lines.append("# %%")
            lines += [f"# {line}" if line.lstrip().startswith(("%", "!")) else line
                      for line in cell.source.splitlines()]
        else:
            lines.append("# %% [markdown]" if cell.cell_type == "markdown" else "# %% [raw]")
            lines += [f"# {line}".rstrip() for line in cell.source.splitlines()]
    return "\n".join(lines) + "\n"


def _write_if_changed(path: pathlib.Path, text: str) -> None:
    path.parent.mkdir(parents=True, exist_ok=True)
    if not path.exists() or path.read_text(encoding="utf-8") != text:
        path.write_text(text, encoding="utf-8")


def stage(url: str | None = None, hub: str | None = None, pdf: bool = False) -> list[pathlib.Path]:
    """Write ``_build/source/``; returns the staged notebooks."""
    STAGE.mkdir(parents=True, exist_ok=True)
    _write_if_changed(STAGE / "_config.yml", site_config(url, hub))
    _write_if_changed(STAGE / "_toc.yml", table_of_contents())
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    _write_if_changed(STAGE / "index.md", landing_page(readme, url, pdf))
    for path in sorted(SITE_EXTENSION.rglob("*")):
        if path.is_file() and "__pycache__" not in path.parts:
            target = STAGE / "_ext" / path.relative_to(SITE_EXTENSION)
            _write_if_changed(target, path.read_text(encoding="utf-8"))
    staged = []
    for path in page_paths():
        target = STAGE / path.relative_to(ROOT)
        shown = display_copy(nbformat.read(path, as_version=4))
        _write_if_changed(target, nbformat.writes(shown) + "\n")
        staged.append(target)
    wanted = set(staged)
    for old in STAGE.glob("notebooks/**/*.ipynb"):  # a notebook renamed or removed since the last build
        if old not in wanted:
            old.unlink()
    return staged


def build(builder: str = "html") -> None:
    """Run Jupyter Book on the staged tree; the HTML lands in ``_build/html`` (or ``_build/singlehtml``)."""
    jupyter_book = pathlib.Path(sys.executable).parent / "jupyter-book"
    command = [str(jupyter_book), "build", str(STAGE), "--path-output", str(BUILD.parent),
               "--builder", builder]
    result = subprocess.run(command, cwd=ROOT, capture_output=True, text=True)
    log = result.stdout + result.stderr
    (BUILD / f"site-build-{builder}.log").write_text(log, encoding="utf-8")
    warnings = [line for line in log.splitlines() if "WARNING" in line]
    for line in warnings:
        print(line)
    output = HTML if builder == "html" else SINGLE
    if result.returncode != 0 or not (output / "index.html").exists():
        sys.stdout.write(log[-4000:])
        raise SiteError(f"jupyter-book build failed (exit code {result.returncode}): "
                        f"{BUILD / f'site-build-{builder}.log'}")


def publish_committed_notebooks() -> None:
    """Each page's downloads: the committed notebook (not its display copy) and its percent script."""
    for path in page_paths():
        target = HTML / "_sources" / path.relative_to(ROOT)
        if not target.exists():
            raise SiteError(f"the build has no download copy of {_relative(path)} ({target} missing)")
        shutil.copyfile(path, target)
        script = percent_script(nbformat.read(path, as_version=4))
        target.with_suffix(".py").write_text(script, encoding="utf-8")


def _title() -> str:
    """The collection's title, as ``site/_config.yml`` gives it."""
    return yaml.safe_load(SITE_CONFIG.read_text(encoding="utf-8"))["title"]


def mathjax_entry() -> str:
    """The MathJax component the pages load, as ``mathjax_path`` in ``site/_config.yml`` names it."""
    config = yaml.safe_load(SITE_CONFIG.read_text(encoding="utf-8"))
    path = config["sphinx"]["config"]["mathjax_path"]
    if "://" in path or not path.startswith("mathjax/"):
        raise SiteError(f"mathjax_path must name a file under _static/mathjax/, not {path!r}")
    return path.split("/", 1)[1]


def prune_mathjax(html_root: pathlib.Path = HTML) -> None:
    """Drop the combined MathJax components other than the one the pages load (none loads another)."""
    folder = html_root / "_static" / "mathjax"
    entry = folder / mathjax_entry()
    if not entry.is_file():
        raise SiteError(f"the site has no {entry.relative_to(html_root)}")
    for component in folder.glob("*.js"):
        if component.name.startswith(("tex-", "mml-", "node-main")) and component != entry:
            component.unlink()


def outside_loads(html_root: pathlib.Path = HTML) -> list[str]:
    """``file: snippet`` for every tag or stylesheet rule of the site that loads from outside it."""
    found = []
    for path in sorted(html_root.rglob("*")):
        if path.suffix not in {".html", ".css"} or not path.is_file():
            continue
        text = path.read_text(encoding="utf-8", errors="replace")
        for pattern in OUTSIDE_LOADS:
            for match in pattern.finditer(text):
                found.append(f"{path.relative_to(html_root)}: {text[match.start(): match.start() + 120]}")
    return found


def site_size(html_root: pathlib.Path = HTML) -> int:
    return sum(path.stat().st_size for path in html_root.rglob("*") if path.is_file())


def pdf_page_count(pdf: bytes) -> int:
    """The pages of a PDF as chromium writes it (one ``/Type /Page`` object each)."""
    return len(re.findall(rb"/Type\s*/Page(?![a-zA-Z])", pdf))


def can_print() -> bool:
    """Whether the PDF is printed: chromium and playwright present, ``COURSE_SITE_PDF`` not ``off``."""
    if os.environ.get("COURSE_SITE_PDF", "").lower() in {"off", "0", "no"}:
        return False
    if not CHROMIUM.exists():
        return False
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return False
    return True


class _QuietHandler(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *args):
        pass


@contextlib.contextmanager
def serve(folder: pathlib.Path):
    """``folder`` served on 127.0.0.1 (a free port) while the block runs; yields the base address."""
    handler = functools.partial(_QuietHandler, directory=str(folder))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    try:
        yield f"http://127.0.0.1:{server.server_address[1]}"
    finally:
        server.shutdown()
        server.server_close()


def print_pdf(single: pathlib.Path = SINGLE, target: pathlib.Path = PDF) -> int:
    """The single-page build printed to ``target`` by chromium (A4, formulas typeset, every picture
    loaded); returns the page count.  Any request outside 127.0.0.1 is refused and fails the print."""
    from playwright.sync_api import sync_playwright

    refused = []

    def route(request_route):
        url = request_route.request.url
        if url.startswith(("data:", "blob:")) or urllib.parse.urlsplit(url).hostname == "127.0.0.1":
            request_route.continue_()
        else:
            refused.append(url)
            request_route.abort()

    with serve(single) as base, sync_playwright() as playwright:
        browser = playwright.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
        try:
            page = browser.new_page(viewport={"width": 1000, "height": 1400})
            page.route("**/*", route)
            page.set_default_timeout(180_000)
            page.goto(f"{base}/index.html", wait_until="load")
            page.wait_for_function("() => window.MathJax && MathJax.startup && MathJax.startup.promise")
            page.evaluate("() => MathJax.startup.promise")
            page.evaluate("""async () => {
                document.querySelectorAll('img[loading="lazy"]').forEach(img => img.loading = 'eager');
                await Promise.all([...document.images].map(img => img.decode().catch(() => null)));
            }""")
            page.emulate_media(media="print")
            page.set_viewport_size({"width": PRINT_WIDTH, "height": 1400})  # A4's 210 mm less the margins
            page.add_style_tag(content=PRINT_CSS)
            page.evaluate(FIT_FORMULAS)
            wide = page.evaluate(WIDER_THAN_THE_PAGE)
            pdf = page.pdf(format="A4", print_background=True, display_header_footer=True,
                           header_template="<span></span>",
                           footer_template='<div style="font-size:8px;width:100%;text-align:center">'
                                           f'{escape_html(_title())} {escape_html(VERSION)} · '
                                           '<span class="pageNumber"></span> / '
                                           '<span class="totalPages"></span></div>',
                           margin={"top": "14mm", "bottom": "16mm", "left": "12mm", "right": "12mm"})
        finally:
            browser.close()
    if refused:
        raise SiteError("the single-page build asked for files from outside the site:\n  "
                        + "\n  ".join(refused))
    target.write_bytes(pdf)
    OVERFLOW.write_text(json.dumps(wide, indent=1, ensure_ascii=False) + "\n", encoding="utf-8")
    if wide:
        shown = "; ".join(f"{w['where']}: {w['what'][:60]}" for w in wide[:5])
        print(f"warning: {len(wide)} formulas, code or pictures are wider than the PDF's page (see "
              f"{OVERFLOW.relative_to(ROOT)}): {shown}")
    return pdf_page_count(pdf)


#: The printable width of an A4 page with 12 mm margins, in CSS pixels (96 per inch): 186 mm.
PRINT_WIDTH = round((210 - 2 * 12) / 25.4 * 96)
#: On paper nothing scrolls: code and outputs wrap at the page's edge, pictures shrink to it.
PRINT_CSS = """
div.cell_input pre, div.cell_output pre { white-space: pre-wrap; overflow-wrap: anywhere; }
img { max-width: 100%; height: auto; }
"""
#: A display formula wider than its column (a matrix, a long derived equation) is shrunk to fit the page:
#: on screen it scrolls, on paper it would be cut at the margin.
FIT_FORMULAS = """() => {
    document.querySelectorAll('mjx-container[display="true"]').forEach(formula => {
        const room = formula.clientWidth, needed = formula.scrollWidth;
        if (room > 0 && needed > room + 1) formula.style.zoom = (room - 2) / needed;
    });
}"""
#: What the print layout shows wider than its page: display formulas, code and output blocks, pictures and
#: tables whose content runs past the text column (cut at the PDF's margin), each with the section it is in.
WIDER_THAN_THE_PAGE = """() => {
    const column = document.querySelector('article, main, body').getBoundingClientRect();
    const found = [];
    const section = element => {
        let node = element;
        while (node && node !== document.body) {
            const heading = node.querySelector ? node.querySelector(':scope > h1, :scope > h2') : null;
            if (heading) return heading.textContent.replace('#', '').trim();
            node = node.parentElement;
        }
        return '';
    };
    const selector = 'mjx-container[display="true"], div.cell_input pre, div.cell_output pre, img, table';
    document.querySelectorAll(selector).forEach(element => {
        const box = element.getBoundingClientRect();
        const clipped = element.scrollWidth > element.clientWidth + 1 && element.clientWidth > 0;
        if (box.width > 0 && (box.right > column.right + 1 || clipped)) {
            found.push({where: section(element), what: (element.getAttribute('alt')
                        || element.textContent || element.tagName).trim().slice(0, 120),
                        width: Math.round(Math.max(box.width, element.scrollWidth))});
        }
    });
    return found;
}"""


def main() -> int:
    started = time.monotonic()
    url, hub = repository.repository_url(), repository.jupyterhub_url()
    pdf = can_print()
    if not pdf:
        print(f"warning: the site is built without its PDF, {PDF.name} (no {CHROMIUM}, no playwright, "
              "or COURSE_SITE_PDF=off)")
        PDF.unlink(missing_ok=True)
    staged = stage(url, hub, pdf)
    build()
    publish_committed_notebooks()
    prune_mathjax()
    pages = None
    if pdf:
        build("singlehtml")
        prune_mathjax(SINGLE)
        pages = print_pdf()
    outside = outside_loads()
    if outside:
        raise SiteError("pages load from outside the site:\n  " + "\n  ".join(outside))
    html_pages = [path for path in HTML.rglob("*.html") if "_static" not in path.parts]
    summary = {
        "pages": len(html_pages), "notebook_pages": len(staged), "pdf_pages": pages,
        "repository": url, "size_mb": round(site_size() / 1e6, 1),
        "seconds": round(time.monotonic() - started, 1),
    }
    where = HTML.relative_to(ROOT) if HTML.is_relative_to(ROOT) else HTML
    print(f"site: {where}/index.html  {json.dumps(summary)}")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except (SiteError, repository.RepositoryError) as error:  # a bad setting: its message, no traceback
        print(f"build_site: {error}", file=sys.stderr)
        sys.exit(2)
