"""One locked environment: ``environment.lock`` pins every package this environment runs with, the two sets'
own pins agree with it, and Binder's requirements are the student set's closure at those versions (what
``tools/lock.py`` writes; run it after changing a pin and ``make test``)."""

import importlib.metadata as metadata
import pathlib
import re
import sys

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tools"))
import lock  # noqa: E402

PIN = re.compile(r"^([A-Za-z0-9][A-Za-z0-9._-]*)==(\S+)$")


def pinned(path: pathlib.Path) -> dict[str, str]:
    """canonical name → version of each ``name==version`` line of a requirements file."""
    found = {}
    for line in path.read_text(encoding="utf-8").splitlines():
        line = line.split("#", 1)[0].strip()
        if match := PIN.match(line):
            found[lock.canonical(match.group(1))] = match.group(2)
    return found


LOCKED = pinned(ROOT / "environment.lock")


def test_every_package_this_environment_runs_with_is_locked_at_its_version():
    here = {lock.canonical(d.metadata["Name"]): d.version for d in metadata.distributions()
            if d.metadata["Name"]}
    own = {lock.canonical(lock.OWN), "pip", "setuptools"}
    unlocked = sorted(name for name in here if name not in own and name not in LOCKED)
    other = sorted(f"{name} {here[name]} (locked {LOCKED[name]})" for name in here
                   if name in LOCKED and LOCKED[name] != here[name])
    assert not unlocked and not other, (f"not in environment.lock: {unlocked}; at another version: {other}; "
                                        "run `python tools/lock.py` after `make test` installed the sets")
    assert len(LOCKED) > 100  # the whole set and what it pulls in, not only the direct pins


@pytest.mark.parametrize("requirements", ["environment.txt", "environment-dev.txt"])
def test_the_sets_own_pins_are_the_locked_versions(requirements):
    own = pinned(ROOT / requirements)
    assert own and all(LOCKED.get(name) == version for name, version in own.items()), own


def test_the_lock_and_binder_are_what_the_tool_writes_from_this_environment():
    # the closure is taken under this Python's markers: Binder's is binder/runtime.txt's, so compare Binder's
    # file whole under that Python, and elsewhere its pins against the lock
    # the lock whole under the Python it was written with (3.12 and 3.13 install a few packages fewer: the
    # first test holds there, every package they install is locked at its version)
    written, text = lock.texts(), (ROOT / "environment.lock").read_text(encoding="utf-8")
    here = lock.WRITTEN_UNDER.format(*sys.version_info[:2])
    assert re.search(r"^# Written under Python 3\.1\d\.$", text, re.M)
    if here in text:
        assert text == written[lock.LOCK]
    binder = pinned(lock.BINDER)
    runtime = (ROOT / "binder" / "runtime.txt").read_text(encoding="utf-8").strip()
    if runtime == f"python-{sys.version_info[0]}.{sys.version_info[1]}":
        assert lock.BINDER.read_text(encoding="utf-8") == written[lock.BINDER]
    assert binder and all(LOCKED.get(name) == version for name, version in binder.items())
    for name in pinned(ROOT / "environment.txt"):  # each direct pin and what it requires here
        assert name in binder
    # requirements of an extra another package asks for: nbconvert's bleach[css], jupyter-events'
    # jsonschema[format-nongpl]
    assert {"tinycss2", "fqdn", "uri-template", "webcolors"} <= set(binder)


def test_the_lock_tool_names_what_is_stale(tmp_path, monkeypatch, capsys):
    stale = tmp_path / "environment.lock"  # the lock with numpy's line from an older term
    numpy = f"numpy=={metadata.version('numpy')}"
    stale.write_text((ROOT / "environment.lock").read_text(encoding="utf-8").replace(numpy, "numpy==1.0"),
                     encoding="utf-8")
    monkeypatch.setattr(lock, "LOCK", stale)
    monkeypatch.setattr(lock, "BINDER", tmp_path / "requirements.txt")
    assert lock.main(["--check"]) == 1
    said = capsys.readouterr().out
    assert "- numpy==1.0" in said and f"+ {numpy}" in said
    assert lock.main([]) == 0 and lock.main(["--check"]) == 0
