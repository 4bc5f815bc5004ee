"""Planar vectors as the course writes them, R = l(cos θ î + sin θ ĵ): numpy arrays whose last axis holds
(x, y); every function broadcasts, so θ may be an array of angles.  Lengths in metres, angles in radians.
"""

from __future__ import annotations

import numpy as np

from .errors import InvalidGeometryError, require_finite

__all__ = ["polar", "cross_k", "loop_residual", "wrap_angle", "to_complex", "from_complex", "scalar_or_array",
           "Unpacks"]


def polar(length, angle) -> np.ndarray:
    """The vector of ``length`` at ``angle`` (rad, from +x, counter-clockwise), shape (..., 2);
    ``InvalidGeometryError`` naming ``length`` or ``angle`` when it is not finite numbers.

    >>> polar([1.0, 1.0], [0.0, np.pi]).round(12).tolist()
    [[1.0, 0.0], [-1.0, 0.0]]
    """
    length = require_finite("length", length, "m")
    angle = require_finite("angle", angle, "rad")
    return np.stack(np.broadcast_arrays(length * np.cos(angle), length * np.sin(angle)), axis=-1)


def cross_k(vector) -> np.ndarray:
    """k̂ × r: the vector r turned +90°; ω k̂ × r is the velocity of a point rotating about the origin.

    >>> cross_k([0.0, 2.0]).tolist()
    [-2.0, 0.0]
    """
    vector = require_finite("vector", vector, "m", allow_nan=True)
    if vector.ndim == 0 or vector.shape[-1] != 2:
        raise InvalidGeometryError(f"vector must hold (x, y) on its last axis; got {vector.tolist()!r} "
                                   f"of shape {vector.shape}")
    return np.stack([-vector[..., 1], vector[..., 0]], axis=-1)


def loop_residual(lengths, angles, signs) -> np.ndarray:
    """Σ sᵢ lᵢ (cos θᵢ, sin θᵢ): zero when the vector loop closes (the four-bar's R2 + R3 − R4 − R1 = 0:
    signs (+1, +1, −1, −1)).

    >>> loop_residual([2.0, 1.0, 1.0, 2.0], [0.0, 0.0, 0.0, 0.0], [1, 1, -1, -1]).tolist()
    [0.0, 0.0]
    """
    terms = [s * polar(l, a) for l, a, s in zip(lengths, angles, signs, strict=True)]
    return np.sum(np.broadcast_arrays(*terms), axis=0)


def scalar_or_array(value):
    """A 0-d result becomes a Python number (or bool), so scalar inputs give scalar outputs; arrays stay.

    >>> scalar_or_array(np.float64(2.5)), scalar_or_array(np.array([1.0, 2.0])).shape
    (2.5, (2,))
    """
    array = np.asarray(value)
    return array.item() if array.ndim == 0 else array


def wrap_angle(angle, nan_ok: bool = False) -> np.ndarray:
    """Angle(s) wrapped into (−π, π]; ``InvalidGeometryError`` naming ``angle`` when it is not finite
    numbers, but with ``nan_ok=True`` NaN entries (an unreachable input's angle) stay NaN.

    >>> bool(float(wrap_angle(3 * np.pi / 2)) == -np.pi / 2)
    True
    """
    angle = np.asarray(angle, dtype=float) if nan_ok else require_finite("angle", angle, "rad")
    shifted = angle + np.pi
    if shifted.size and -np.pi <= shifted.min() and shifted.max() <= 3 * np.pi:
        # np.mod(shifted, 2π) without its division: one exact step of 2π on [−π, 3π] (NaN takes np.mod)
        shifted = shifted - (shifted >= 2 * np.pi) * (2 * np.pi)
        shifted += (shifted < 0.0) * (2 * np.pi)
    else:
        shifted = np.mod(shifted, 2 * np.pi)
    wrapped = shifted - np.pi
    return np.where(wrapped == -np.pi, np.pi, wrapped)


def to_complex(vector) -> np.ndarray:
    """(x, y) → x + iy, the complex-number form l·e^{iθ} of a planar vector.

    >>> complex(to_complex([3.0, 4.0]))
    (3+4j)
    """
    vector = np.asarray(vector, dtype=float)
    return vector[..., 0] + 1j * vector[..., 1]


def from_complex(z) -> np.ndarray:
    """x + iy → (x, y).

    >>> from_complex(1j).tolist()
    [0.0, 1.0]
    """
    z = np.asarray(z, dtype=complex)
    return np.stack([z.real, z.imag], axis=-1)


class Unpacks:
    """What the library's result objects share: they unpack as their ``_values`` (x3, y3 = result), index
    like a tuple and convert with ``np.array(result)``, shape (len(_values), ...).  Their boolean masks
    are named for what they mark and True where it holds (``reachable``, ``converged``, ``singular``).

    >>> from dataclasses import dataclass
    >>> @dataclass(frozen=True)
    ... class Point(Unpacks):
    ...     x: float
    ...     y: float
    ...     _values = ("x", "y")
    >>> x, y = Point(1.0, 2.0); np.array(Point(1.0, 2.0)).tolist(), len(Point(1.0, 2.0))
    ([1.0, 2.0], 2)
    """

    _values: tuple[str, ...] = ()

    def __iter__(self):
        return (getattr(self, name) for name in self._values)

    def __len__(self) -> int:
        return len(self._values)

    def __getitem__(self, index):
        """A value by position (``result[1]``) or by its name (``result["theta4"]``, or its sympy Symbol)."""
        name = getattr(index, "name", index)
        if isinstance(name, str):
            try:
                return getattr(self, name)
            except AttributeError:
                from .errors import InvalidArgumentError

                raise InvalidArgumentError(f"no value named {name!r} here; the values are "
                                           f"{list(self._values)}") from None
        return tuple(self)[index]

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        return np.array(np.broadcast_arrays(*(np.asarray(value) for value in self)), dtype=dtype)
