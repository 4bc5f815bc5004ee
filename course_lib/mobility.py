"""Mobility (degrees of freedom) of a planar mechanism: the Gruebler/Kutzbach count M = 3(L − 1) − 2·J1 − J2,
with L links counting the ground (bancada), J1 full joints (pins and sliders, one freedom each) and J2
half joints (pin-in-slot, rolling with slip: two freedoms each).
"""

from __future__ import annotations

import numbers

from .errors import InvalidGeometryError

__all__ = ["gruebler"]


def _count(name: str, value: int, minimum: int) -> int:
    whole = isinstance(value, numbers.Real) and not isinstance(value, bool) and float(value).is_integer()
    if not whole or value < minimum:
        raise InvalidGeometryError(f"{name} must be an integer >= {minimum}; got {value!r}")
    return int(value)


def gruebler(links: int, full_joints: int, half_joints: int = 0) -> int:
    """Degrees of freedom M = 3(L − 1) − 2·J1 − J2 of a planar linkage (``links`` counts the ground);
    0 means a structure, < 0 a preloaded (statically indeterminate) one.

    >>> gruebler(links=3, full_joints=3)   # a triangle: a structure
    0
    """
    L = _count("links", links, 1)
    J1 = _count("full_joints", full_joints, 0)
    J2 = _count("half_joints", half_joints, 0)
    return 3 * (L - 1) - 2 * J1 - J2
