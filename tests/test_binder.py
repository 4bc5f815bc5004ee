"""Binder (mybinder.org, jupyter-repo2docker): the student set, cached across commits, landing on lesson 00.

* ``binder/requirements.txt`` is environment.txt's pins without ``-e .``: nothing in it refers to the
  repository, so repo2docker installs it before copying the repository (the layer Binder reuses);
  ``binder/postBuild`` installs course_lib and the server configuration.
* repo2docker's own Dockerfile (``jupyter-repo2docker --no-build --debug``, no docker needed) shows that
  order, when repo2docker is installed (environment-dev.txt has it).
* ``jupyter lab`` and ``jupyter notebook``, started with the configuration postBuild installs, redirect
  ``/`` to lesson 00.
"""

import json
import os
import pathlib
import re
import shutil
import signal
import socket
import subprocess
import sys
import time
import tomllib
import urllib.parse
import urllib.request

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent
BINDER = ROOT / "binder"
BIN = pathlib.Path(sys.executable).parent
LESSON = "notebooks/00_start_here.ipynb"


def _requirements(path: pathlib.Path) -> list[str]:
    return [line.strip() for line in path.read_text(encoding="utf-8").splitlines()
            if line.strip() and not line.lstrip().startswith("#")]


def test_binder_installs_the_student_pins_and_nothing_from_the_repository():
    # the student set's own pins, and what they pull in at the locked versions (tests/test_lock.py checks
    # that these are the student set's whole closure); every line a plain pin, none a path of the repository
    student = _requirements(ROOT / "environment.txt")
    assert "-e ." in student
    binder = _requirements(BINDER / "requirements.txt")
    assert set(line for line in student if line != "-e .") <= set(binder)
    assert set(binder) <= set(_requirements(ROOT / "environment.lock"))
    assert all(re.fullmatch(r"[A-Za-z0-9_.\-\[\]]+==[0-9][\w.+!]*", line) for line in binder), binder


def test_binder_python_is_one_the_collection_supports():
    runtime = (BINDER / "runtime.txt").read_text(encoding="utf-8").strip()
    match = re.fullmatch(r"python-(3)\.(\d+)", runtime)
    assert match, runtime
    project = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]
    assert project["requires-python"] == ">=3.11" and int(match.group(2)) >= 11
    assert f"Programming Language :: Python :: 3.{match.group(2)}" in project["classifiers"]


def test_post_build_installs_course_lib_and_the_landing_configuration():
    mode = subprocess.run(["git", "ls-files", "-s", "binder/postBuild"], cwd=ROOT, capture_output=True,
                          text=True).stdout.split()
    assert mode and mode[0] == "100755", "binder/postBuild must be committed executable"
    script = (BINDER / "postBuild").read_text(encoding="utf-8")
    assert script.startswith("#!/bin/bash\n") and "set -euo pipefail" in script
    assert re.search(r"pip install --no-deps .*-e \.$", script, re.M)
    assert 'cp binder/jupyter_server_config.json "${HOME}/.jupyter/jupyter_server_config.json"' in script
    config = json.loads((BINDER / "jupyter_server_config.json").read_text(encoding="utf-8"))
    assert config["LabApp"]["default_url"] == f"/lab/tree/{LESSON}"
    assert config["JupyterNotebookApp"]["default_url"] == f"/notebooks/{LESSON}"
    assert (ROOT / LESSON).is_file()


def test_repo2docker_installs_the_pins_before_copying_the_repository():
    repo2docker = BIN / "jupyter-repo2docker"
    if not repo2docker.exists():
        pytest.skip("jupyter-repo2docker is not installed (pip install -r environment-dev.txt)")
    result = subprocess.run([str(repo2docker), "--no-build", "--debug", str(ROOT)], cwd=ROOT,
                            capture_output=True, text=True, timeout=120)
    dockerfile = result.stdout + result.stderr
    assert result.returncode == 0, dockerfile[-3000:]
    install = dockerfile.index('pip install --no-cache-dir -r "binder/requirements.txt"')
    copy_repository = re.search(r"^COPY .*\bsrc/ \$\{REPO_DIR\}/$", dockerfile, re.M)
    post_build = dockerfile.index("RUN ./binder/postBuild")
    assert copy_repository, "no COPY of the repository in repo2docker's Dockerfile"
    assert install < copy_repository.start() < post_build, "the pins' layer would not be cached"
    assert "Building conda environment for python=3.11" in dockerfile
    assert 'CMD ["jupyter", "notebook"' in dockerfile  # repo2docker's own start: the Notebook 7 server


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


@pytest.mark.parametrize("app, landing", [("lab", f"/lab/tree/{LESSON}"),
                                          ("notebook", f"/notebooks/{LESSON}")])
def test_the_server_opens_lesson_00(app, landing, tmp_path):
    """Started with the configuration postBuild copies into ~/.jupyter, `/` lands on lesson 00."""
    if not (BIN / "jupyter").exists():
        pytest.skip("jupyter is not installed")
    config_dir = tmp_path / "jupyter-config"
    config_dir.mkdir()
    shutil.copy(BINDER / "jupyter_server_config.json", config_dir / "jupyter_server_config.json")
    port, token = _free_port(), "binder-test-token"
    env = dict(os.environ, JUPYTER_CONFIG_DIR=str(config_dir), JUPYTER_RUNTIME_DIR=str(tmp_path / "runtime"))
    command = [str(BIN / "jupyter"), app, "--no-browser", "--ServerApp.ip=127.0.0.1",
               f"--ServerApp.port={port}", f"--IdentityProvider.token={token}",
               f"--ServerApp.root_dir={ROOT}"]
    if os.geteuid() == 0:
        command.append("--allow-root")
    server = subprocess.Popen(command, cwd=ROOT, env=env, stdout=subprocess.DEVNULL,
                              stderr=subprocess.DEVNULL, start_new_session=True)
    try:
        final, page, deadline = None, "", time.monotonic() + 90
        while final is None and time.monotonic() < deadline and server.poll() is None:
            request = urllib.request.Request(f"http://127.0.0.1:{port}/",
                                             headers={"Authorization": f"token {token}"})
            try:
                with urllib.request.urlopen(request, timeout=5) as response:
                    final, page = urllib.parse.urlsplit(response.url).path, response.read().decode()
            except OSError:
                time.sleep(0.5)
        assert final is not None, f"jupyter {app} did not answer within 90 s"
        print(f"binder landing page, jupyter {app}: {final}")
        assert final == landing
        assert "<title>" in page and ("JupyterLab" in page or "Jupyter Notebook" in page)
        request = urllib.request.Request(f"http://127.0.0.1:{port}/api/contents/{LESSON}?content=0",
                                         headers={"Authorization": f"token {token}"})
        with urllib.request.urlopen(request, timeout=10) as response:
            assert json.load(response)["type"] == "notebook"
    finally:
        os.killpg(server.pid, signal.SIGTERM)
        server.wait(timeout=30)
