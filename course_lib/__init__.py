"""course_lib — the small library behind "Mechanism Kinematics, step by step".

Units are SI (metres, seconds); angles are radians from +x, counter-clockwise.  One module per concept:
errors, newton, planar, symbolic, mobility, mechanism, plotting (and, per mechanism, fourbar,
slider_crank, profile, saw, fivebar, widgets, checks).

``course_lib.newton`` is the module (``import course_lib.newton as m`` gives it), and calling it calls
its function :func:`course_lib.newton.newton`, so ``from course_lib import newton`` works both ways:

>>> import course_lib.newton as module
>>> from course_lib import newton
>>> module is newton, round(newton(lambda x: x * x - 4.0, 1.0).x, 12), callable(module.newton)
(True, 2.0, True)
"""

import types

from . import newton as _newton_module
from .errors import (
    ConvergenceError,
    CourseLibError,
    InvalidArgumentError,
    InvalidGeometryError,
    SingularJacobianError,
    UnreachableError,
)
from .mobility import gruebler
from .newton import BatchNewtonResult, NewtonResult, newton_batch


class _CallableModule(types.ModuleType):
    """The newton module, which calling runs its function ``newton`` (the package once re-exported the
    function under the module's own name)."""

    def __call__(self, *args, **kwargs):
        return self.newton(*args, **kwargs)


_newton_module.__class__ = _CallableModule
newton = _newton_module

__all__ = ["CourseLibError", "UnreachableError", "ConvergenceError", "SingularJacobianError",
           "InvalidGeometryError", "InvalidArgumentError", "gruebler", "newton", "newton_batch",
           "NewtonResult", "BatchNewtonResult"]

__version__ = "1.0.0"
