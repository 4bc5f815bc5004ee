"""The explorers in a real browser: JupyterLab + Debian's chromium driven by playwright.

Starts JupyterLab on 127.0.0.1 (free port, no token) rooted at a temporary copy of the lessons, opens
11_explorers, runs all cells from the Run menu, moves the four-bar's θ2 slider with the keyboard and
checks that the readout and the picture follow, with no error output anywhere.  Skipped, with the
reason, when /usr/bin/chromium or playwright is missing (CI installs chromium: see .ci/run).
"""

import json
import os
import pathlib
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request

import nbformat
import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
CHROMIUM = pathlib.Path("/usr/bin/chromium")
NOTEBOOK = "11_explorers.ipynb"
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
ERROR_OUTPUTS = ('.jp-OutputArea-output[data-mime-type="application/vnd.jupyter.stderr"], '
                 '.jp-OutputArea-output[data-mime-type="application/vnd.jupyter.error"]')


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def _get_json(url: str):
    with urllib.request.urlopen(url, timeout=5) as response:
        return json.load(response)


def _prepare_root(root: pathlib.Path) -> None:
    """Copies of the lessons, outputs cleared (so whatever the page shows comes from this run)."""
    for path in sorted((ROOT / "notebooks").glob("*.ipynb")):
        notebook = nbformat.read(path, as_version=4)
        for cell in notebook.cells:
            if cell.cell_type == "code":
                cell.outputs, cell.execution_count = [], None
        notebook.metadata.pop("widgets", None)
        nbformat.write(notebook, root / path.name)


def _isolated_jupyter_env(home: pathlib.Path) -> dict[str, str]:
    """User config/data/runtime dirs in a temporary home; the news pop-up disabled."""
    env = dict(os.environ)
    for name in ("JUPYTER_CONFIG_DIR", "JUPYTER_DATA_DIR", "JUPYTER_RUNTIME_DIR", "IPYTHONDIR"):
        env[name] = str(home / name.lower())
        (home / name.lower()).mkdir()
    labconfig = home / "jupyter_config_dir" / "labconfig"
    labconfig.mkdir()
    disabled = {"@jupyterlab/apputils-extension:announcements": True}
    (labconfig / "page_config.json").write_text(json.dumps({"disabledExtensions": disabled}))
    # render every cell (no windowing), so explorers scrolled out of view still have their text
    tracker = home / "lab_settings" / "@jupyterlab" / "notebook-extension"
    tracker.mkdir(parents=True)
    (tracker / "tracker.jupyterlab-settings").write_text(json.dumps({"windowingMode": "none"}))
    env["PYDEVD_DISABLE_FILE_VALIDATION"] = "1"
    return env


def _start_lab(root: pathlib.Path, home: pathlib.Path, port: int) -> subprocess.Popen:
    command = [
        sys.executable, "-m", "jupyterlab", "--no-browser", "--allow-root",
        "--ServerApp.ip=127.0.0.1", f"--ServerApp.port={port}", "--ServerApp.port_retries=0",
        "--IdentityProvider.token=", "--ServerApp.password=", "--ServerApp.disable_check_xsrf=True",
        f"--ServerApp.root_dir={root}",
        f"--LabApp.user_settings_dir={home / 'lab_settings'}", "--LabApp.news_url=None",
        "--LabApp.check_for_updates_class=jupyterlab.NeverCheckForUpdate",
    ]
    log = open(home / "jupyterlab.log", "wb")  # noqa: SIM115 (closed with the process)
    return subprocess.Popen(command, cwd=root, env=_isolated_jupyter_env(home), stdout=log,
                            stderr=subprocess.STDOUT, start_new_session=True)


def _wait_for_server(server: subprocess.Popen, port: int, timeout: float = 40.0) -> None:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if server.poll() is not None:
            raise AssertionError(f"JupyterLab exited with code {server.returncode}")
        try:
            if "started" in _get_json(f"http://127.0.0.1:{port}/api/status"):
                return
        except OSError:
            time.sleep(0.3)
    raise AssertionError(f"JupyterLab did not answer on port {port} within {timeout:.0f} s")


def _stop_server(server: subprocess.Popen, port: int) -> None:
    """Shut the kernels down through the REST API, then SIGTERM the server's process group and wait."""
    try:
        for kernel in _get_json(f"http://127.0.0.1:{port}/api/kernels"):
            request = urllib.request.Request(f"http://127.0.0.1:{port}/api/kernels/{kernel['id']}",
                                             method="DELETE")
            urllib.request.urlopen(request, timeout=10).close()
    except OSError:
        pass
    for sig, wait in ((signal.SIGTERM, 20), (signal.SIGKILL, 10)):
        try:
            os.killpg(server.pid, sig)
        except ProcessLookupError:
            break
        try:
            server.wait(timeout=wait)
            break
        except subprocess.TimeoutExpired:
            continue
    deadline = time.monotonic() + 10
    while time.monotonic() < deadline:  # the kernel, a child in the same group, may take a moment
        try:
            os.killpg(server.pid, 0)
        except ProcessLookupError:
            return
        time.sleep(0.2)
    os.killpg(server.pid, signal.SIGKILL)


def _explorer_snapshot(page) -> tuple[str, str]:
    explorer = page.locator(".course-explorer").first
    readout = explorer.locator(".course-explorer-readout").inner_text()
    picture = explorer.locator(".course-explorer-image").get_attribute("src") or ""
    return readout, picture


def test_fourbar_explorer_follows_the_keyboard_in_jupyterlab():
    if not CHROMIUM.exists():
        pytest.skip("browser test needs Debian's chromium at /usr/bin/chromium (apt-get install -y chromium)")
    sync_api = pytest.importorskip("playwright.sync_api", reason="browser test needs python playwright")
    home = pathlib.Path(tempfile.mkdtemp(prefix="course-browser-"))
    root = home / "notebooks"
    root.mkdir()
    _prepare_root(root)
    port = _free_port()
    server = _start_lab(root, home, port)
    screenshot = home / "explorers.png"
    try:
        _wait_for_server(server, port)
        with sync_api.sync_playwright() as playwright:
            browser = playwright.chromium.launch(executable_path=str(CHROMIUM), args=CHROMIUM_ARGS)
            try:
                page = browser.new_page(viewport={"width": 1400, "height": 1000})
                page.set_default_timeout(30_000)
                page.goto(f"http://127.0.0.1:{port}/lab/tree/{NOTEBOOK}")
                idle = '.jp-StatusBar-TextItem:has-text("| Idle")'  # "Python 3 (ipykernel) | Idle"
                page.wait_for_selector(idle, timeout=45_000)  # kernel started, connected and idle
                page.locator(".jp-NotebookPanel .jp-Cell").first.click()
                page.locator(".lm-MenuBar-itemLabel", has_text="Run").first.click()
                page.locator(".lm-Menu-itemLabel", has_text="Run All Cells").first.click()
                page.wait_for_selector(".course-explorer .course-explorer-readout", timeout=45_000)
                page.wait_for_function(
                    "() => [...document.querySelectorAll('.jp-InputArea-prompt')]"
                    ".every(p => !p.textContent.includes('*'))", timeout=45_000)
                page.wait_for_selector(idle, timeout=45_000)
                page.locator(".course-explorer").first.scroll_into_view_if_needed()
                page.wait_for_function(
                    "() => document.querySelector('.course-explorer .course-explorer-readout')"
                    ".innerText.includes('θ2 = 60.0°')", timeout=20_000)
                before = _explorer_snapshot(page)
                assert "θ2 = 60.0°" in before[0]
                assert before[1].startswith("data:image/png") or before[1].startswith("blob:")
                slider = page.locator(".course-explorer").first.locator(".widget-slider", has_text="θ2 (°)")
                handle = slider.locator(".noUi-handle")
                # dragged, a pixel of the track is under 1° (a turn over more than 360 px); a key 0.1°
                track = slider.locator(".noUi-target").bounding_box()
                assert track["width"] > 360, f"θ2's track is {track['width']:.0f} px: over 1° per pixel"
                handle.focus()
                for _ in range(5):
                    handle.press("ArrowRight")
                page.wait_for_function(
                    "() => document.querySelector('.course-explorer .course-explorer-readout')"
                    ".innerText.includes('θ2 = 60.5°')", timeout=20_000)
                after = _explorer_snapshot(page)
                assert after[0] != before[0] and "θ2 = 60.5°" in after[0]
                assert slider.locator(".widget-readout").inner_text().strip() == "60.5"
                # every toggle's label fits its button (none is cut to "−1 (arms do…")
                cut = page.evaluate(
                    "() => [...document.querySelectorAll('.course-explorer .widget-toggle-button')]"
                    ".filter(b => b.scrollWidth > b.clientWidth).map(b => b.innerText)")
                assert page.locator(".course-explorer .widget-toggle-button").count() >= 10 and cut == [], cut
                assert after[1] != before[1], "the picture did not change after the slider moved"
                assert page.locator(ERROR_OUTPUTS).count() == 0
                assert "Traceback" not in page.locator(".jp-NotebookPanel").first.inner_text()
                assert "Error displaying widget" not in page.locator(".jp-NotebookPanel").first.inner_text()
                page.locator(".course-explorer").first.scroll_into_view_if_needed()
                page.screenshot(path=str(screenshot))
                print(f"screenshot: {screenshot}")
            finally:
                browser.close()
    finally:
        _stop_server(server, port)
        shutil.rmtree(root, ignore_errors=True)
