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


def course_inverse_angles(x3, y3, lengths, sigma1, sigma2):
    """θ1, θ4 of the five-bar's inverse kinematics in working mode (σ1, σ2) from the course's half-angle
    coefficients, typed from the course material: θ = 2·atan((−b + σ√(b² − 4ac)) / 2a)."""
    l1, l2, l3, l4, l5 = lengths
    a1 = l1**2 - l2**2 - l1 * l5 + l5**2 / 4 + 2 * l1 * x3 - l5 * x3 + x3**2 + y3**2
    b1, b2 = -4 * l1 * y3, -4 * l4 * y3
    c1 = l1**2 - l2**2 + l1 * l5 + l5**2 / 4 - 2 * l1 * x3 - l5 * x3 + x3**2 + y3**2
    a2 = -(l3**2) + l4**2 + l4 * l5 + l5**2 / 4 + 2 * l4 * x3 + l5 * x3 + x3**2 + y3**2
    c2 = -(l3**2) + l4**2 - l4 * l5 + l5**2 / 4 - 2 * l4 * x3 + l5 * x3 + x3**2 + y3**2

    def angle(a, b, c, sigma):
        return 2 * np.arctan((-b + sigma * np.sqrt(b * b - 4 * a * c)) / (2 * a))

    return angle(a1, b1, c1, sigma1), angle(a2, b2, c2, sigma2)
