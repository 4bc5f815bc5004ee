"""Checkers for the exercise notebooks and the lessons' "Try it" cells: take a student's answer,
return friendly feedback.

Each checker returns a :class:`Feedback` (``ok`` and a ``message``) for any answer, never raising.
The message names what looks wrong — the other branch, degrees, a sign, missing ω² terms, mm — and
never the reference value.  Equivalent answers pass: angles modulo 2π, equal sympy expressions, an
equation times a constant, either order where order does not matter.  SI units and radians.

One module per exercise set (``ex01`` … ``ex06``) and one for the lessons, on the shared ``engine``.

>>> check_mobility({"links": 6, "full_joints": 7, "half_joints": 0, "mobility": 1}).ok
True
>>> print(check_mobility((5, 7, 0, -2)))
✘ Not yet: count the ground (the frame, bancada) as one of the links.
"""
# ruff: noqa: F403 — each module lists its checkers in its __all__

from . import ex01, ex02, ex03, ex04, ex05, ex06, lessons
from .engine import ANGLE_TOL, RELATIVE_TOL, Feedback
from .ex01 import *
from .ex02 import *
from .ex03 import *
from .ex04 import *
from .ex05 import *
from .ex06 import *
from .lessons import *

__all__ = ["ANGLE_TOL", "RELATIVE_TOL", "Feedback"]
for _module in (ex01, ex02, ex03, ex04, ex05, ex06, lessons):
    __all__ += _module.__all__
