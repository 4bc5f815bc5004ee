"""Every number that decides a verdict, in one place (plain numbers: importing this loads nothing else).

The core's rules use them (:mod:`course_lib.mechanism.singular` for the singularity rule,
:mod:`course_lib.mechanism.closed_forms` for rounding and closure); the machines' registered kernels and the
explorers read them from here, so no machine keeps a threshold of its own.

>>> SINGULAR < NEAR_SINGULAR < APPROACH
True
"""

__all__ = ["APPROACH", "CHANGE_LEVEL", "COINCIDENT", "FLIP_NEAR", "FLIP_SMOOTH", "LEVEL", "MAX_CONDITION",
           "NEAR_SINGULAR", "RESIDUAL", "SINGULAR", "TRANSMISSION_MIN_DEG", "UNIT_RANGE"]

#: J is singular where σ_min(J̃) < SINGULAR (J̃: J with rows and columns scaled by their typical sizes).
SINGULAR = 1e-6
#: Motion.near_singular marks σ_min(J̃) < NEAR_SINGULAR: the rates are large and sensitive there — on before
#: they exceed about 100 times their size at a regular pose (they grow like 1 / σ_min(J̃)).
NEAR_SINGULAR = 1e-2
#: A discriminant below −LEVEL·(its scale) has no real root; above, it is rounding and counts as 0.
LEVEL = 1e-12
#: A closed-form block's two assemblies meet (a change point, where σ swaps) between two instants of a sweep
#: only where the lowest level of its quadratic between them, located, is at most CHANGE_LEVEL; above it they
#: come near and part again (a near miss) and σ is kept.
CHANGE_LEVEL = 1e-9
#: On Newton's route a step over which J's orientation changes is a change point crossed only where the
#: corrector moved its end by at most FLIP_SMOOTH of the step from the tangent's prediction (the path smooth
#: there) and σ_min(J̃) at its two ends adds up to at most FLIP_NEAR of the step (J singular within it: along
#: a path through a change point σ_min(J̃) grows like the distance from it); else the step may have reached
#: the other assembly where the two come near (a near miss) and is taken again in halves.
FLIP_SMOOTH = 0.05
FLIP_NEAR = 0.3
#: A closed-form or continued position is accepted where |F_i| / (typical size of row i) stays below this.
RESIDUAL = 1e-8
#: Two lengths (or a point and a pivot) closer than COINCIDENT × the longest length are equal: rounding.
COINCIDENT = 1e-14
#: The explorers warn "near a singularity" where one of the course's singularity measures (a sine of the
#: angle between two links, 0 at the singularity) falls below APPROACH: the approach a student should see
#: coming, well before the core's rule (σ_min(J̃) < SINGULAR) calls the rates undefined.
APPROACH = 0.05
#: Newton's step test (not the mechanism's singularity rule): a Jacobian whose |det| is below
#: 1 / MAX_CONDITION × the product of its row lengths gives no trustworthy step.
MAX_CONDITION = 1e12
#: The course's design value for a four-bar's transmission angle μ (acute, Norton's): below it (degrees) the
#: force transmission is poor, and the four-bar explorer says so and draws the line.
TRANSMISSION_MIN_DEG = 40.0
#: A declaration whose loops are homogeneous in its lengths is solved with its lengths in units of a power of
#: two near their typical size where that typical size (the median of its nonzero length parameters) lies
#: outside [1 / UNIT_RANGE, UNIT_RANGE] (m): there Newton's absolute ``tol`` would be below the rounding of
#: the lengths (or above the lengths themselves) and the closed forms' fourth powers of the lengths would
#: overflow or underflow (see :mod:`course_lib.mechanism.scaling`).
UNIT_RANGE = 1024.0
