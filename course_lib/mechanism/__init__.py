"""One core for every planar mechanism: write the vector loops once, get position, velocity, acceleration.

A mechanism is declared by its loop equations F(q, u) = 0 in sympy: unknowns q (angles or lengths),
inputs u and a number for every other symbol.  The core derives once, lambdified with cse: F,
J = ∂F/∂q, F_u = ∂F/∂u, the velocity system J·q̇ = −F_u·u̇, the acceleration system J·q̈ = −(the rest of
d²F/dt²) and the stacked 3n system.  It splits the loops into blocks solved in turn and, where a block
reduces to one quadratic by the course's half-angle route (:func:`~course_lib.symbolic.reduce_loop`),
solves it in closed form, each block's assembly fixed by its root σ = ±1; elsewhere by Newton–Raphson
with continuation.  SI units, radians.

The core is a package of rooms, one per job; :class:`Mechanism` is all of them together:

==================  =========================================================================================
``declaration``     the loops, unknowns, inputs, parameters and drawing (points, links, ground, sliders,
                    plates, styles), checked when made; the loops differentiated in time, in symbols
``compiled``        F, J, F_u, the acceleration right-hand side and the 3n system, derived once, lambdified
``singular``        the one singularity rule (σ_min of the scaled J) and its thresholds
``closed_forms``    the blocks, each block's closed form by the half-angle route, its σ along a sweep
``continuation``    Newton with continuation where no closed form solves a block
``rates``           q̇ and q̈ at known positions (linear solves, block by block)
``routes``          the course's consecutive and simultaneous Newton routes
``solving``         ``solve`` → :class:`~course_lib.motion.Motion`, the one result
``points``          the declared points along a motion: ``joints`` and ``point_motion``
``scaling``         a declaration homogeneous in its lengths, declared far from unit size (1e-90 … 1e90 m),
                    solved with its lengths in units of a power of two near their typical size
==================  =========================================================================================

The singularity rule: J is singular where the smallest singular value of J̃ — J with each row and column
divided by its typical size at the declaration's generic point — is below ``SINGULAR`` = 1e-6 (near one
below ``NEAR_SINGULAR`` = 1e-2, before the rates exceed about 100 times their size); there the rates are
undefined and asking for them raises.

>>> import numpy as np, sympy as sp
>>> th2, th3, th4 = sp.symbols("theta2 theta3 theta4")
>>> l1, l2, l3, l4 = sp.symbols("l1:5", positive=True)
>>> wiper = Mechanism(
...     loops=[sp.Matrix([l2*sp.cos(th2) + l3*sp.cos(th3) - l4*sp.cos(th4) - l1,
...                       l2*sp.sin(th2) + l3*sp.sin(th3) - l4*sp.sin(th4)])],
...     unknowns=[th3, th4], inputs=[th2],
...     parameters={l1: 0.20, l2: 0.06, l3: 0.18, l4: 0.12})
>>> motion = wiper.solve({th2: np.pi / 2}, rates={th2: 10.0}, guess={th3: 0.4, th4: 1.6})
>>> round(motion.position["theta4"], 6), round(motion.velocity["theta4"], 6), motion.newton.iterations
(1.815502, 4.761066, 5)
>>> sweep = wiper.solve({th2: np.linspace(0, 2 * np.pi, 7)}, guess={th3: 0.4, th4: 1.6})
>>> sweep.position["theta3"].shape, bool(sweep.converged.all()), sweep.velocity, sweep.message
((7,), True, None, '')
"""

from ..motion import Motion
from .closed_forms import ClosedForms
from .compiled import Compiled
from .continuation import Continuation
from .declaration import Declaration, Links
from .points import Points
from .rates import Rates
from .routes import Routes
from .scaling import Scaling
from .singular import NEAR_SINGULAR, SINGULAR, Singularity
from .solving import Solving

__all__ = ["Mechanism", "Motion", "Links", "SINGULAR", "NEAR_SINGULAR"]


class Mechanism(Solving, Points, Routes, Rates, Continuation, ClosedForms, Singularity, Compiled, Scaling,
                Declaration):
    """A planar mechanism declared by its loop equations (each expression = 0, or an ``Eq``).

    ``loops``: 2×1 sympy matrices (x and y components of a vector loop), scalar expressions or ``Eq`` s, as
    many equations in all as ``unknowns``; loops may share unknowns.  ``inputs``: the driven variables.
    ``parameters``: a number (or a sympy constant such as ``sp.pi / 6``) for every other symbol, keyed by
    the symbol or its name (:meth:`with_parameters` gives the same declaration with other numbers, sharing
    everything derived).  Optional ``points`` (name → 2×1 matrix of x, y) and ``links`` (pairs of point
    names, or a dict link name → pair: :class:`Links`) describe the drawing, with the ``ground`` pivots
    and ``sliders`` (point names), ``plates`` (name → three or more point names: a rigid plate, shaded)
    and ``styles`` (link name → line properties) that ``draw``, ``animate`` and ``explore`` use.  A
    declaration is checked when made: rows that are not smooth and real, involve no unknown, repeat or
    depend on each other (J of rank < n at a generic point) are refused by name.

    >>> import numpy as np, sympy as sp
    >>> x, th = sp.symbols("x theta")
    >>> follower = Mechanism([sp.Eq(x, sp.cos(th))], unknowns=[x], inputs=[th])
    >>> follower.solve({th: np.pi / 2}, rates={th: 2.0}, guess={x: 0.5}).velocity["x"]
    -2.0
    """

