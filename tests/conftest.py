"""Shared pytest set-up: deterministic hypothesis runs, headless matplotlib."""

import matplotlib
from hypothesis import settings

matplotlib.use("Agg")

settings.register_profile("course", derandomize=True, deadline=None, max_examples=200, database=None)
settings.load_profile("course")
