"""`make lab` installs the project's JupyterLab settings: the Jupyter news pop-up never shows."""

import json
import os
import pathlib
import shutil
import signal
import socket
import subprocess
import time
import urllib.request

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
NOTIFICATION = "@jupyterlab/apputils-extension:notification"


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def test_overrides_name_settings_that_jupyterlab_knows():
    overrides = json.loads((ROOT / "tools" / "lab-settings" / "overrides.json").read_text())
    schemas = ROOT / ".venv" / "share" / "jupyter" / "lab" / "schemas"
    if not schemas.is_dir():
        pytest.skip("JupyterLab is not installed in .venv")
    for plugin, values in overrides.items():
        package, name = plugin.split(":")
        schema = json.loads((schemas / package / f"{name}.json").read_text())
        for key, value in values.items():
            spec = schema["properties"][key]
            allowed = [choice["const"] for choice in spec.get("oneOf", [])]
            assert value in allowed if allowed else isinstance(value, bool), (plugin, key, value)
    assert overrides[NOTIFICATION]["fetchNews"] == "false"  # "Never": no question, no request


@pytest.mark.skipif(shutil.which("make") is None, reason="make is not installed")
def test_make_lab_serves_fetch_news_never():
    port, token = _free_port(), "course-settings-token"
    args = f"--no-browser --ServerApp.ip=127.0.0.1 --ServerApp.port={port} --IdentityProvider.token={token}"
    server = subprocess.Popen(
        ["make", "--no-print-directory", "lab", f"LAB_ARGS={args}"],
        cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True,
    )
    try:
        settings, deadline = None, time.monotonic() + 60
        while settings is None and time.monotonic() < deadline and server.poll() is None:
            request = urllib.request.Request(f"http://127.0.0.1:{port}/lab/api/settings/{NOTIFICATION}",
                                             headers={"Authorization": f"token {token}"})
            try:
                with urllib.request.urlopen(request, timeout=2) as response:
                    settings = json.load(response)
            except OSError:
                time.sleep(0.5)
        assert settings is not None, "JupyterLab did not answer within 60 s"
        # overrides.json changes the defaults the frontend reads (unless a user changed the setting)
        assert settings["schema"]["properties"]["fetchNews"]["default"] == "false"
    finally:
        os.killpg(server.pid, signal.SIGTERM)
        server.wait(timeout=30)
