"""`make lab` installs the student set and starts a JupyterLab server rooted at notebooks/ that answers on
/api/status, with the project's settings installed (the Jupyter news pop-up never shows); `make test` installs
the whole set; `make clean` removes what the targets make."""

import json
import os
import pathlib
import re
import shlex
import shutil
import signal
import socket
import subprocess
import sys
import time
import urllib.request

import pytest

ROOT = pathlib.Path(__file__).resolve().parent.parent


def free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


@pytest.mark.skipif(shutil.which("make") is None, reason="make is not installed")
def _listing(port: int, token: str) -> set[str]:
    request = urllib.request.Request(f"http://127.0.0.1:{port}/api/contents/",
                                     headers={"Authorization": f"token {token}"})
    with urllib.request.urlopen(request, timeout=5) as response:
        return {entry["name"] for entry in json.load(response)["content"]}


@pytest.mark.parametrize("target", ["lab", "lab-instructor"])
def test_make_lab_serves_the_lessons(target):
    # make lab, the students' route, lists lessons and exercise copies; make lab-instructor the solutions too
    port, token = free_port(), "course-test-token"
    args = f"--no-browser --ServerApp.ip=127.0.0.1 --ServerApp.port={port} --IdentityProvider.token={token}"
    server = subprocess.Popen(
        ["make", "--no-print-directory", target, f"LAB_ARGS={args}"],
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
        listed = _listing(port, token)
        assert {"00_start_here.ipynb", "exercises"} <= listed
        assert ("solutions" in listed) == (target == "lab-instructor")
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


def _run_in_kernel(port: int, token: str, kernel: str, code: str) -> str:
    """What ``code`` prints, run in the server's kernel through its websocket (as JupyterLab does)."""
    import asyncio
    import uuid

    from tornado.httpclient import HTTPRequest
    from tornado.websocket import websocket_connect

    async def run() -> str:
        socket_ = await websocket_connect(HTTPRequest(f"ws://127.0.0.1:{port}/api/kernels/{kernel}/channels",
                                                      headers={"Authorization": f"token {token}"}))
        header = {"msg_id": uuid.uuid4().hex, "msg_type": "execute_request", "username": "",
                  "session": uuid.uuid4().hex, "version": "5.3", "date": ""}
        socket_.write_message(json.dumps({"header": header, "parent_header": {}, "metadata": {},
                                          "buffers": [], "channel": "shell",
                                          "content": {"code": code, "silent": False}}))
        while True:
            message = json.loads(await asyncio.wait_for(socket_.read_message(), 60))
            if message["msg_type"] == "stream" and message["parent_header"].get("msg_id") == header["msg_id"]:
                socket_.close()
                return message["content"]["text"]

    return asyncio.run(run())


@pytest.mark.skipif(shutil.which("make") is None, reason="make is not installed")
def test_make_labs_kernels_run_with_encrypted_sockets_and_print_no_tcp_warning(tmp_path):
    """The server `make lab` starts (its command line as `make -n` plans it, run with this Python's
    JupyterLab): a kernel runs code, and the server's log holds no "running over TCP without encryption"."""
    planned = subprocess.run(["make", "-n", "--no-print-directory", "lab", f"VENV={tmp_path / 'venv'}"],
                             cwd=ROOT, capture_output=True, text=True, check=True).stdout
    command = shlex.split(planned.splitlines()[-1].split("&& ")[-1])
    assert command[:2] == [str(tmp_path / "venv" / "bin" / "jupyter"), "lab"]
    assert "--config=tools/lab-settings/jupyter_server_config.py" in command
    port, token = free_port(), "course-test-token"
    env = {**os.environ, **{name: str(tmp_path / name.lower()) for name in
                            ("JUPYTER_CONFIG_DIR", "JUPYTER_DATA_DIR", "JUPYTER_RUNTIME_DIR", "IPYTHONDIR")}}
    log = tmp_path / "server.log"
    with open(log, "wb") as output:
        server = subprocess.Popen(
            [sys.executable, "-m", "jupyterlab", *command[2:], "--no-browser", "--ServerApp.ip=127.0.0.1",
             f"--ServerApp.port={port}", f"--IdentityProvider.token={token}"],
            cwd=ROOT, env=env, stdout=output, stderr=subprocess.STDOUT, start_new_session=True)
    authorized = {"Authorization": f"token {token}"}
    try:
        deadline = time.monotonic() + 60
        while time.monotonic() < deadline and server.poll() is None:
            try:
                urllib.request.urlopen(urllib.request.Request(f"http://127.0.0.1:{port}/api/status",
                                                              headers=authorized), timeout=2).close()
                break
            except OSError:
                time.sleep(0.5)
        request = urllib.request.Request(f"http://127.0.0.1:{port}/api/kernels", data=b"{}", method="POST",
                                         headers=authorized)
        with urllib.request.urlopen(request, timeout=60) as response:
            kernel = json.load(response)["id"]
        assert _run_in_kernel(port, token, kernel, "print(6 * 7)") == "42\n"
    finally:
        os.killpg(server.pid, signal.SIGTERM)
        server.wait(timeout=30)
    text = log.read_text(encoding="utf-8", errors="replace")
    assert "Kernel started" in text  # the log is the server's and its kernel's
    assert "without encryption" not in text, text[-2000:]


@pytest.mark.skipif(shutil.which("make") is None, reason="make is not installed")
def test_make_lab_installs_the_student_set_and_make_test_the_whole_set(tmp_path):
    """Into a venv that does not exist yet (make -n prints the commands without running them)."""
    def planned(target: str) -> str:
        return subprocess.run(["make", "-n", "--no-print-directory", target, f"VENV={tmp_path / 'venv'}"],
                              cwd=ROOT, capture_output=True, text=True, check=True).stdout

    lab, test = planned("lab"), planned("test")
    assert "-r environment.txt" in lab and "environment-dev.txt" not in lab
    check = subprocess.run(["make", "-n", "--no-print-directory", "check", f"VENV={tmp_path / 'venv'}",
                            "NOTEBOOK=notebooks/exercises/ex01_vector_loops_and_mobility.ipynb"],
                           cwd=ROOT, capture_output=True, text=True, check=True).stdout
    assert "-r environment.txt" in check and "environment-dev.txt" not in check  # the student set alone
    assert "--nbval-lax" in check and "ex01_vector_loops_and_mobility.ipynb" in check
    assert "-r environment-dev.txt" in test and ".installed-dev" in test
    for plan in (lab, check, test):  # every install takes the locked versions
        assert "-c environment.lock -r environment" in plan
    unlocked = subprocess.run(["make", "-n", "--no-print-directory", "test", "LOCK=",
                               f"VENV={tmp_path / 'venv'}"], cwd=ROOT, capture_output=True, text=True,
                              check=True).stdout
    assert "-r environment-dev.txt" in unlocked and "environment.lock" not in unlocked  # after a pin changes
    dev = (ROOT / "environment-dev.txt").read_text(encoding="utf-8").splitlines()
    assert "-r environment.txt" in dev  # the whole set is the student set plus the tools
    student = (ROOT / "environment.txt").read_text(encoding="utf-8")
    for tool in ("hypothesis", "ruff", "playwright", "jupyter-book", "nbgrader"):
        assert f"\n{tool}==" not in student and any(line.startswith(f"{tool}==") for line in dev), tool
    for tool in ("pytest", "nbval"):  # a student checks their own notebook runs clean: make check
        assert f"\n{tool}==" in student and not any(line.startswith(f"{tool}==") for line in dev), tool


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


# The Python check and the rebuild of .venv, in a copy of the Makefile with fake interpreters: shell scripts
# that answer the Makefile's `-c` query with their version, make a fake venv (python, jupyter, ruff: copies of
# themselves) for `-m venv` and log every call. The PATH holds only them and the few tools the recipes use, so
# no real Python is found, nothing is installed and every make run takes milliseconds.
FAKE_PYTHON = """#!/bin/sh
printf '%s\\n' "$0 $*" >> {log}
case "$1" in
  -c) echo "{version} /opt/python{version}/bin/python{version}" ;;
  -m) if [ "$2" = venv ]; then
        mkdir -p "$3/bin"; for tool in python jupyter ruff; do cp "$0" "$3/bin/$tool"; done
        echo "home = /opt/python{version}/bin" > "$3/pyvenv.cfg"
      fi ;;
esac
"""
MAKEFILE = (ROOT / "Makefile").read_text(encoding="utf-8")
SUPPORTED = re.search(r"^SUPPORTED_PYTHONS := (.+)$", MAKEFILE, re.M)
# the targets that make .venv: those that need an installed set
VENV_TARGETS = re.findall(r"^([a-z][\w-]*):.*\$\((?:STUDENT|DEV)_STAMP\)", MAKEFILE, re.M)


class Sandbox:
    def __init__(self, root: pathlib.Path):
        self.repo, self.bin, self.log = root / "repo", root / "bin", root / "calls.log"
        for name in ("Makefile", "environment.txt", "environment-dev.txt", "environment.lock",
                     "pyproject.toml", "tools/lab-settings/overrides.json"):
            (self.repo / name).parent.mkdir(parents=True, exist_ok=True)
            shutil.copy2(ROOT / name, self.repo / name)
        tools = root / "tools"
        for directory in (self.bin, tools):
            directory.mkdir()
        for tool in ("sh", "cat", "mkdir", "cp", "touch", "rm", "id", "uname"):
            (tools / tool).symlink_to(shutil.which(tool))
        self.env = {key: value for key, value in os.environ.items()
                    if key not in ("PYTHON", "MAKEFLAGS", "MFLAGS", "MAKELEVEL")}
        self.env["PATH"] = f"{self.bin}{os.pathsep}{tools}"
        self.venv = self.repo / ".venv"

    def python(self, name: str, version: str) -> pathlib.Path:
        path = self.bin / name
        path.write_text(FAKE_PYTHON.format(log=self.log, version=version), encoding="utf-8")
        path.chmod(0o755)
        return path

    def make(self, *arguments: str) -> subprocess.CompletedProcess:
        self.log.unlink(missing_ok=True)
        return subprocess.run([shutil.which("make"), "--no-print-directory", *arguments], cwd=self.repo,
                              env=self.env, capture_output=True, text=True, timeout=60)

    def calls(self) -> list[str]:
        """What the fakes were asked to do besides answering the version query."""
        if not self.log.exists():
            return []
        lines = self.log.read_text(encoding="utf-8").splitlines()
        return [line for line in lines if " -m " in line or "/jupyter " in line or "/ruff " in line]

    def stamp(self) -> str:
        return (self.venv / ".python").read_text(encoding="utf-8").strip()


needs_make = pytest.mark.skipif(shutil.which("make") is None, reason="make is not installed")


@pytest.fixture
def sandbox(tmp_path):
    return Sandbox(tmp_path)


def test_the_supported_pythons_are_listed_once_and_match_the_readme():
    targets = {"lab", "test", "test-portable", "execute", "exercises", "bench", "site", "nbgrader"}
    assert targets <= set(VENV_TARGETS), targets - set(VENV_TARGETS)
    assert SUPPORTED, "the Makefile lists the supported Pythons in SUPPORTED_PYTHONS"
    versions = SUPPORTED.group(1).split()
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    assert f"Needs Python {', '.join(versions[:-1])} or {versions[-1]}" in readme
    makefile = MAKEFILE
    # make test-pythons tests all of them unless told fewer (tests/test_release.py pins that line as it is)
    assert re.search(rf"^PYTHONS \?= {re.escape(SUPPORTED.group(1))}$", makefile, re.M)
    code = "\n".join(line for line in makefile.splitlines() if not line.lstrip().startswith("#"))
    for version in versions:  # and nowhere else: the check and its message take them from SUPPORTED_PYTHONS
        assert code.count(version) == 2, version


@needs_make
@pytest.mark.parametrize("target", VENV_TARGETS)
def test_an_unsupported_python_stops_each_target_making_the_venv_before_it_creates_anything(sandbox, target):
    old = sandbox.python("python3.10", "3.10")
    sandbox.python("python3.12", "3.12")  # a supported one on the PATH: the message names it
    result = sandbox.make(target, "PYTHON=python3.10")
    assert result.returncode != 0
    ours = [line for line in result.stderr.splitlines() if not line.startswith("make")]
    assert ours == [f"needs Python 3.11–3.13; found 3.10 at {old} — run `make {target} PYTHON=python3.12`"]
    assert not sandbox.venv.exists() and sandbox.calls() == []
    assert "pip" not in result.stdout


@needs_make
def test_a_missing_python_says_so_and_names_one_to_install(sandbox):
    result = sandbox.make("lab", "PYTHON=python3.14")
    assert result.returncode != 0
    assert result.stderr.splitlines()[0] == ("needs Python 3.11–3.13; python3.14 was not found — install one "
                                             "and run `make lab PYTHON=python3.13`")
    result = sandbox.make("test")  # PYTHON not named: python3, which is not there either
    assert result.returncode != 0 and "python3 was not found" in result.stderr
    (sandbox.bin / "python3").write_text("#!/bin/sh\nexit 1\n", encoding="utf-8")  # there but broken
    (sandbox.bin / "python3").chmod(0o755)
    result = sandbox.make("lab")
    assert result.returncode != 0 and f"python3 at {sandbox.bin / 'python3'} does not run" in result.stderr
    assert not sandbox.venv.exists()


@needs_make
def test_the_venv_is_made_again_when_another_python_made_it(sandbox):
    sandbox.python("python3.12", "3.12")
    result = sandbox.make("lab", "PYTHON=python3.12")
    assert result.returncode == 0, result.stderr
    assert sandbox.calls()[:2] == [f"{sandbox.bin}/python3.12 -m venv .venv",
                                   ".venv/bin/python -m pip install --quiet --disable-pip-version-check "
                                   "-c environment.lock -r environment.txt"]
    assert sandbox.stamp() == "3.12 /opt/python3.12/bin/python3.12"
    (sandbox.venv / "pythons" / "3.13").mkdir(parents=True)  # make test-pythons' venvs stay
    (sandbox.venv / "pythons" / "3.13" / "pyvenv.cfg").touch()

    # nothing changed: nothing made, nothing installed
    assert sandbox.make("lab", "PYTHON=python3.12").returncode == 0
    assert [call for call in sandbox.calls() if "jupyter" not in call] == []

    # .venv/.python says another version made it (as a 3.10 venv that the Python was swapped under)
    (sandbox.venv / ".python").write_text("3.10 /usr/bin/python3.10\n", encoding="utf-8")
    result = sandbox.make("lab", "PYTHON=python3.12")
    assert result.returncode == 0, result.stderr
    assert "making .venv again: it was made with Python 3.10, its python is now 3.12" in result.stdout
    assert f"{sandbox.bin}/python3.12 -m venv .venv" in sandbox.calls()
    assert any("-r environment.txt" in call for call in sandbox.calls())
    assert sandbox.stamp() == "3.12 /opt/python3.12/bin/python3.12"
    assert (sandbox.venv / "pythons" / "3.13" / "pyvenv.cfg").exists()

    # another Python named: made again by it, and `make test` installs the whole set into it
    sandbox.python("python3.13", "3.13")
    result = sandbox.make("test", "PYTHON=python3.13")
    assert result.returncode == 0, result.stderr
    assert ("making .venv again: it was made by /opt/python3.12/bin/python3.12 (3.12), PYTHON=python3.13 is "
            "/opt/python3.13/bin/python3.13 (3.13)") in result.stdout
    assert f"{sandbox.bin}/python3.13 -m venv .venv" in sandbox.calls()
    assert any("-r environment-dev.txt" in call for call in sandbox.calls())
    assert sandbox.stamp() == "3.13 /opt/python3.13/bin/python3.13"

    # no Python named: the working 3.13 venv stays although python3 is 3.10
    sandbox.python("python3", "3.10")
    result = sandbox.make("lab")
    assert result.returncode == 0, result.stderr
    assert not any(" -m " in call for call in sandbox.calls())
    # an unsupported Python named: refused, and the venv is left as it is
    result = sandbox.make("lab", "PYTHON=python3")
    assert result.returncode != 0 and "found 3.10 at" in result.stderr
    assert sandbox.stamp() == "3.13 /opt/python3.13/bin/python3.13"


@needs_make
def test_a_venv_whose_python_is_broken_or_unsupported_is_made_again(sandbox):
    sandbox.python("python3", "3.12")
    assert sandbox.make("lab").returncode == 0
    (sandbox.venv / "bin" / "python").unlink()  # its interpreter uninstalled: a dangling link
    (sandbox.venv / "bin" / "python").symlink_to(sandbox.repo / "gone" / "python3.12")
    result = sandbox.make("lab")
    assert result.returncode == 0, result.stderr
    assert "making .venv again: its python does not run" in result.stdout
    assert f"{sandbox.bin}/python3 -m venv .venv" in sandbox.calls()

    # a 3.10 .venv made before the check (no .venv/.python): made again with a supported Python
    sandbox.python("python3.10", "3.10").rename(sandbox.venv / "bin" / "python")
    (sandbox.venv / ".python").unlink()
    result = sandbox.make("lab")
    assert result.returncode == 0, result.stderr
    assert "making .venv again: it was made with Python 3.10" in result.stdout
    assert sandbox.stamp() == "3.12 /opt/python3.12/bin/python3.12"

    # a .venv that is not a venv at all is not emptied
    (sandbox.venv / "pyvenv.cfg").unlink()
    (sandbox.venv / "bin" / "python").write_text("#!/bin/sh\nexit 1\n", encoding="utf-8")
    result = sandbox.make("lab")
    assert result.returncode != 0 and "(no pyvenv.cfg): remove it" in result.stderr
    assert (sandbox.venv / "bin" / "jupyter").exists()


@needs_make
def test_a_venv_that_failed_half_way_is_removed(sandbox):
    # Debian's python3.X without python3.X-venv: the venv's python is made, then ensurepip fails
    failing = sandbox.python("python3", "3.12")
    failing.write_text(failing.read_text(encoding="utf-8").replace(
        'echo "home', 'echo "ensurepip is not available" >&2; exit 1; echo "home'), encoding="utf-8")
    result = sandbox.make("lab")
    assert result.returncode != 0 and "ensurepip is not available" in result.stderr
    assert not any(sandbox.venv.iterdir())
    assert not any("pip" in call for call in sandbox.calls())
    sandbox.python("python3", "3.12")  # python3.12-venv installed: made now
    result = sandbox.make("lab")
    assert result.returncode == 0, result.stderr
    assert f"{sandbox.bin}/python3 -m venv .venv" in sandbox.calls()


@needs_make
def test_a_working_venv_made_before_the_check_is_kept_without_installing_again(sandbox):
    sandbox.python("python3.12", "3.12")
    assert sandbox.make("lab", "PYTHON=python3.12").returncode == 0
    (sandbox.venv / ".python").unlink()
    result = sandbox.make("lab", "PYTHON=python3.12")
    assert result.returncode == 0, result.stderr
    assert [call for call in sandbox.calls() if "jupyter" not in call] == []
    assert sandbox.stamp() == "3.12 /opt/python3.12/bin/python3.12"
    # the requirements changed: installed again into the same venv
    os.utime(sandbox.repo / "environment.txt")
    assert sandbox.make("lab", "PYTHON=python3.12").returncode == 0
    assert [call for call in sandbox.calls() if "jupyter" not in call] == [
        ".venv/bin/python -m pip install --quiet --disable-pip-version-check "
        "-c environment.lock -r environment.txt"]
