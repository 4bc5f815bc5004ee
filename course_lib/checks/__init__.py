"""Checkers for the exercise notebooks and the lessons' "Try it" cells: a :class:`Feedback` (``ok``, a
``message`` naming what looks wrong, never the reference value) for any answer, never raising.  The task
arguments (the linkage, angles, branch or mode the notebook passes) are checked first: a bad one, or a task
that has no answer, is the instructor's to fix and raises ``InvalidArgumentError`` naming it.
Equivalent answers pass (angles modulo 2π, equal sympy expressions, scaled equations); SI units, radians.
One module per exercise set (``ex01`` … ``ex06``) and one for the lessons, on the shared ``engine``.

>>> print(check_mobility((5, 7, 0, -2)))
✘ Not yet: count the ground (the frame, bancada) as one of the links.
"""
# ruff: noqa: F403 — each module lists its checkers in its __all__

from . import ex01, ex02, ex03, ex04, ex05, ex06, lessons, worked
from .engine import (
    ANGLE_TOL,
    DECIMALS,
    FIGURES,
    RELATIVE_TOL,
    Feedback,
    Precision,
    as_expressions,
    same_equations,
)
from .ex01 import *
from .ex02 import *
from .ex03 import *
from .ex04 import *
from .ex05 import *
from .ex06 import *
from .lessons import *
from .worked import *

__all__ = ["ANGLE_TOL", "RELATIVE_TOL", "Feedback", "Precision", "FIGURES", "DECIMALS", "as_expressions",
           "same_equations"]
for _module in (ex01, ex02, ex03, ex04, ex05, ex06, lessons, worked):
    __all__ += _module.__all__
