"""course_lib — the small library behind "Mechanism Kinematics, step by step".

Units are SI (metres, seconds); angles are radians from +x, counter-clockwise.  One module per concept:
errors, newton, planar, symbolic, mobility, plotting (and, per mechanism, fourbar, slider_crank, profile,
saw, fivebar, widgets, checks).
"""

from .errors import (
           ConvergenceError,
           CourseLibError,
           InvalidGeometryError,
           SingularJacobianError,
           UnreachableError,
)
from .mobility import gruebler
from .newton import BatchNewtonResult, NewtonResult, newton, newton_batch

__all__ = ["CourseLibError", "UnreachableError", "ConvergenceError", "SingularJacobianError",
           "InvalidGeometryError", "gruebler", "newton", "newton_batch", "NewtonResult", "BatchNewtonResult"]

__version__ = "0.1.0"
