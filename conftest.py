"""Doctests of course_lib's rooms (course_lib/mechanism/*.py) build a ``Mechanism`` — all the rooms together,
which no room imports — from sympy symbols, as the rest of course_lib's doctests do: pytest gives every
doctest ``Mechanism``, ``np`` and ``sp``."""

import numpy as np
import pytest
import sympy as sp


@pytest.fixture(autouse=True)
def _mechanism_in_doctests(doctest_namespace):
    from course_lib.mechanism import Mechanism

    doctest_namespace.update(Mechanism=Mechanism, np=np, sp=sp)


@pytest.fixture(autouse=True)
def _figures_closed():
    """Every test and doctest starts and ends with no pyplot figure open: one that draws with pyplot and
    leaves its figures open would otherwise make a later one, on the same worker, meet matplotlib's
    "more than 20 figures" warning (an error under the test settings), depending on the order tests run."""
    yield
    import sys

    if "matplotlib.pyplot" in sys.modules:
        sys.modules["matplotlib.pyplot"].close("all")
