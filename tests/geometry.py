"""Independent geometry for the tests: two circles meet where the chord construction says.

>>> left, right = circle_intersections([0.0, 0.0], 5.0, [8.0, 0.0], 5.0)
>>> left.tolist(), right.tolist()
([4.0, 3.0], [4.0, -3.0])
"""

import numpy as np


def circle_intersections(a, ra, b, rb):
    """The points at distance ``ra`` from ``a`` and ``rb`` from ``b``: (left of a→b, right of a→b).

    ``a`` and ``b`` may be stacks (..., 2).  Tangent circles (rounding just past touching) give
    the touching point twice.
    """
    a, b = np.asarray(a, float), np.asarray(b, float)
    d_vec = b - a
    d = np.linalg.norm(d_vec, axis=-1, keepdims=True)
    along = (ra**2 - rb**2 + d**2) / (2 * d)
    across = np.sqrt(np.maximum(ra**2 - along**2, 0.0))
    unit = d_vec / d
    normal = np.stack([-unit[..., 1], unit[..., 0]], axis=-1)
    foot = a + along * unit
    return foot + across * normal, foot - across * normal


def fourbar_pins(l1, l2, l3, l4, theta2, branch):
    """Crank pin A and rocker pin B of a four-bar (O2 at the origin, O4 = (l1, 0)) from circles:
    |AB| = l3, |O4B| = l4; the "open" branch has B left of A → O4, "crossed" right of it."""
    theta2 = np.asarray(theta2, float)
    A = l2 * np.stack([np.cos(theta2), np.sin(theta2)], axis=-1)
    left, right = circle_intersections(A, l3, np.array([l1, 0.0]), l4)
    return A, (left if branch == "open" else right)
