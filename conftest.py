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
