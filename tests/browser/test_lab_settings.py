"""The project's JupyterLab settings name settings JupyterLab knows (tests/test_make_lab.py checks that
`make lab` serves them)."""

import json
import pathlib

import pytest

ROOT = pathlib.Path(__file__).resolve().parents[2]
NOTIFICATION = "@jupyterlab/apputils-extension:notification"


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
