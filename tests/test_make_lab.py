"""`make lab` installs the student set and starts a JupyterLab server rooted at notebooks/ that answers on
/api/status, with the project's settings installed (the Jupyter news pop-up never shows); `make test` installs
the whole set; `make clean` removes what the targets make."""

import json
import os
import pathlib
import re
import shutil
import signal
import socket
import subprocess
import time
import urllib.request

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


@pytest.mark.skipif(shutil.which("make") is None, reason="make is not installed")
def test_make_lab_serves_the_lessons():
    port, token = free_port(), "course-test-token"
    args = f"--no-browser --ServerApp.ip=127.0.0.1 --ServerApp.port={port} --IdentityProvider.token={token}"
    server = subprocess.Popen(
        ["make", "--no-print-directory", "lab", f"LAB_ARGS={args}"],
        cwd=ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True,
    )
    try:
        status, deadline = None, time.monotonic() + 60
        while status is None and time.monotonic() < deadline and server.poll() is None:
            request = urllib.request.Request(f"http://127.0.0.1:{port}/api/status",
                                             headers={"Authorization": f"token {token}"})
            try:
                with urllib.request.urlopen(request, timeout=2) as response:
                    status = json.load(response)
            except OSError:
                time.sleep(0.5)
        assert status is not None, "JupyterLab did not answer on /api/status within 60 s"
        assert "started" in status
        request = urllib.request.Request(f"http://127.0.0.1:{port}/api/contents/00_start_here.ipynb",
                                         headers={"Authorization": f"token {token}"})
        with urllib.request.urlopen(request, timeout=5) as response:
            assert json.load(response)["type"] == "notebook"  # served from notebooks/
        # tools/lab-settings/overrides.json changes the defaults the frontend reads: news "Never"
        request = urllib.request.Request(
            f"http://127.0.0.1:{port}/lab/api/settings/@jupyterlab/apputils-extension:notification",
            headers={"Authorization": f"token {token}"},
        )
        with urllib.request.urlopen(request, timeout=5) as response:
            assert json.load(response)["schema"]["properties"]["fetchNews"]["default"] == "false"
    finally:
        os.killpg(server.pid, signal.SIGTERM)
        server.wait(timeout=30)


@pytest.mark.skipif(shutil.which("make") is None, reason="make is not installed")
def test_make_lab_installs_the_student_set_and_make_test_the_whole_set(tmp_path):
    """Into a venv that does not exist yet (make -n prints the commands without running them)."""
    def planned(target: str) -> str:
        return subprocess.run(["make", "-n", "--no-print-directory", target, f"VENV={tmp_path / 'venv'}"],
                              cwd=ROOT, capture_output=True, text=True, check=True).stdout

    lab, test = planned("lab"), planned("test")
    assert "-r environment.txt" in lab and "environment-dev.txt" not in lab
    assert "-r environment-dev.txt" in test and ".installed-dev" in test
    dev = (ROOT / "environment-dev.txt").read_text(encoding="utf-8").splitlines()
    assert "-r environment.txt" in dev  # the whole set is the student set plus the tools
    student = (ROOT / "environment.txt").read_text(encoding="utf-8")
    for tool in ("pytest", "nbval", "hypothesis", "ruff", "playwright", "jupyter-book", "nbgrader"):
        assert f"\n{tool}==" not in student and any(line.startswith(f"{tool}==") for line in dev), tool


@pytest.mark.skipif(shutil.which("make") is None, reason="make is not installed")
def test_make_clean_removes_what_the_targets_make_and_keeps_the_nbgrader_settings():
    planned = subprocess.run(["make", "-n", "--no-print-directory", "clean"], cwd=ROOT, capture_output=True,
                             text=True, check=True).stdout
    removed = set(re.findall(r"[\w./-]+", " ".join(line for line in planned.splitlines()
                                                      if line.startswith("rm "))))
    made = {".venv", "_build", "dist", "nbgrader/source", "nbgrader/release", "nbgrader/submitted",
            "nbgrader/autograded", "nbgrader/feedback", "nbgrader/gradebook.db"}
    assert made <= removed, made - removed
    kept = {"nbgrader", ".", "nbgrader/nbgrader_config.py"}
    assert not any(path in kept or path.startswith("nbgrader/templates") for path in removed)
