"""The course website's own Sphinx extension (site/_config.yml: local_extensions).

* A ``.py`` download next to the ``.ipynb`` one on every notebook page: the notebook as a
  percent-format script, which tools/build_site.py writes beside the notebook in ``_sources/``.
* The landing page's browser title says the collection's title once; printed, its title is followed by
  the version.
* ``course.css``: code and outputs stay within the text column (long lines wrap; a wide output
  scrolls inside its cell; pictures shrink to fit), on screen and in print.
"""

import html
import pathlib

STATIC = pathlib.Path(__file__).resolve().parent / "static"


def add_script_download(app, pagename, templatename, context, doctree):
    """After sphinx-book-theme's own buttons (priority 501): the ``.py`` link after the ``.ipynb`` one."""
    source = context.get("sourcename") or ""
    if not source.endswith(".ipynb"):
        return
    for group in context.get("header_buttons", []):
        if group.get("label") != "download-buttons":
            continue
        buttons = group["buttons"]
        where = next((k + 1 for k, button in enumerate(buttons) if button.get("text") == ".ipynb"), 1)
        buttons.insert(where, {
            "type": "link",
            "url": f"{context['pathto']('_sources', 1)}/{source[: -len('.ipynb')]}.py",
            "text": ".py",
            "tooltip": "Download as a Python script (cells marked # %%)",
            "icon": "fas fa-file-code",
            "label": "download-script-button",
        })


def single_title_on_the_landing_page(app, pagename, templatename, context, doctree):
    """The landing page's title is the collection's title: its browser title says it once, not
    "title — title" (Sphinx adds " — " and the collection's title to every page's); the navigation bar
    keeps showing the collection's title."""
    docstitle = context.get("docstitle")
    if pagename != app.config.root_doc or not docstitle or context.get("title") != docstitle:
        return
    context["theme_logo"] = {**(context.get("theme_logo") or {}), "text": docstitle}
    context["docstitle"] = None  # no suffix (basic/layout.html adds one only where docstitle is set)


def version_under_the_printed_title(app, pagename, templatename, context, doctree):
    """The landing page as printed (the PDF's first page): the version (``release``, which
    tools/build_site.py sets from pyproject.toml) under the title.  After sphinx-book-theme's handler,
    which sets ``pagetitle``, the print-only heading's text."""
    if pagename != app.config.root_doc or not app.config.release or not context.get("pagetitle"):
        return
    context["pagetitle"] = (f'{html.escape(context["pagetitle"])}<br><span class="course-version">'
                            f'Version {html.escape(app.config.release)}</span>')


def add_static(app):
    app.config.html_static_path.append(str(STATIC))


def setup(app):
    app.connect("builder-inited", add_static)
    app.add_css_file("course.css")
    app.connect("html-page-context", add_script_download, priority=502)
    app.connect("html-page-context", single_title_on_the_landing_page)
    app.connect("html-page-context", version_under_the_printed_title, priority=600)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
