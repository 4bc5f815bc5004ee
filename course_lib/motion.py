"""What solving a mechanism gives: :class:`Motion`, the one result of every declaration and machine.
Light on purpose (numpy only).  Its ``singular`` and ``near_singular`` masks follow the one singularity
rule of :mod:`course_lib.mechanism.singular` (``SINGULAR``, ``NEAR_SINGULAR``).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields
from types import MappingProxyType
from typing import TYPE_CHECKING, ClassVar

import numpy as np

if TYPE_CHECKING:
    from .newton import NewtonResult

__all__ = ["Motion", "Deferred", "machine_joints"]


class Deferred:
    """A value computed when first read: a :class:`Motion` field given as ``Deferred(function)`` (a
    machine's ``singular`` and ``near_singular``, which only some callers read) is replaced by
    ``function()`` the first time it is asked for.

    >>> motion = Motion(position={"x": 1.0}, velocity=None, acceleration=None, converged=True,
    ...                 singular=Deferred(lambda: False), iterations=0, inputs={"s": 0.0})
    >>> motion.singular
    False
    """

    __slots__ = ("function",)

    def __init__(self, function):
        self.function = function


@dataclass(frozen=True)
class Motion:
    """What :meth:`~course_lib.mechanism.Mechanism.solve` found, shaped like the broadcast inputs (Python
    numbers for scalars); every machine's solve returns one too (``FourBar.solve`` a
    :class:`~course_lib.fourbar.FourBarSolution`, …), which also names its values as the course does
    (``solution.theta4`` is ``solution.position["theta4"]``, ``solution.omega4`` its velocity).

    position, velocity, acceleration : unknown's name → q, q̇, q̈ (SI); the rates None unless asked.
    converged, singular : masks, True where the position was found / J is singular (see ``SINGULAR``).
    iterations : Newton updates per instant (0 where the closed form alone gave it).
    inputs : input's name → its broadcast values.  newton : one instant's ``NewtonResult``; None for a sweep.
    near_singular : True where σ_min(J̃) < NEAR_SINGULAR (rates large and sensitive).  message : the toggles,
    limits and change points met, in words ("" when none).  assembly : each unknown of a closed-form
    block → its block's σ (±1) per instant, σ = −sign(det J_b) (see :mod:`course_lib.mechanism.closed_forms`;
    0 where J_b is singular or nothing was found); None where Newton alone solved.
    """

    position: Mapping[str, float | np.ndarray]
    velocity: Mapping[str, float | np.ndarray] | None
    acceleration: Mapping[str, float | np.ndarray] | None
    converged: bool | np.ndarray
    singular: bool | np.ndarray
    iterations: int | np.ndarray
    inputs: Mapping[str, float | np.ndarray]
    newton: NewtonResult | None = None
    near_singular: bool | np.ndarray = False
    message: str = ""
    assembly: Mapping[str, int | np.ndarray] | None = None
    #: A machine's own names for rates: attribute → (part, key), e.g. ``"omega4": ("velocity", "theta4")``.
    _names: ClassVar[Mapping[str, tuple[str, str]]] = MappingProxyType({})

    def __getattribute__(self, name: str):
        value = object.__getattribute__(self, name)
        if type(value) is Deferred:  # computed once, when first read
            value = value.function()
            object.__setattr__(self, name, value)
        return value

    def __getattr__(self, name: str):
        """A value by name: an unknown's or input's own (``motion.theta4``), or a machine's name for a rate
        (``solution.omega4``, see ``_names``)."""
        if not name.startswith("__"):
            part, key = type(self)._names.get(name, (None, name))
            for where in (part,) if part else ("position", "inputs"):
                values = object.__getattribute__(self, where)
                if values is None or key in values:
                    return None if values is None else values[key]
        raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")

    __iter__ = None  # values by name, not by position (a machine's result unpacks as its own values)

    def __getitem__(self, key):
        """A value by its name or sympy Symbol: ``motion["theta4"]`` is ``motion.theta4`` (an unknown's or
        input's value, or a machine's name for a rate); another name is refused, listing the names.

        >>> motion = Motion(position={"x": 1.0}, velocity=None, acceleration=None, converged=True,
        ...                 singular=False, iterations=0, inputs={"s": 0.5})
        >>> motion["x"], motion["s"]
        (1.0, 0.5)
        """
        name = getattr(key, "name", key)
        if isinstance(name, str):
            try:
                return getattr(self, name)
            except AttributeError:
                pass
        from .errors import InvalidArgumentError

        names = [*self.position, *self.inputs, *type(self)._names]
        raise InvalidArgumentError(f"no value named {key!r} in this motion; its names are {names}")

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        """The position as one array, (unknowns, ...) in the declared order; a machine's result converts
        to its own values instead (``np.array(solution)``).

        >>> motion = Motion(position={"theta3": [0.1, 0.2], "theta4": 1.5}, velocity=None, acceleration=None,
        ...                 converged=True, singular=False, iterations=0, inputs={"theta2": [0.0, 1.0]})
        >>> np.array(motion).tolist()
        [[0.1, 0.2], [1.5, 1.5]]
        """
        return np.array(np.broadcast_arrays(*(np.asarray(v) for v in self.position.values())), dtype=dtype)


def recast(motion: Motion, kind: type[Motion], *, at_rest: bool = False, **extra) -> Motion:
    """``motion`` as a machine's own :class:`Motion` (``kind``, a subclass), the same values with the
    machine's ``extra`` fields; ``at_rest``: ``motion`` was solved without rates, which are then 0 where the
    position was found (NaN elsewhere).

    >>> motion = Motion(position={"x": 1.0}, velocity=None, acceleration=None, converged=True,
    ...                 singular=False, iterations=0, inputs={"s": 0.5})
    >>> recast(motion, Motion, at_rest=True).velocity["x"]
    0.0
    """
    values = {field.name: object.__getattribute__(motion, field.name) for field in fields(Motion)}
    if at_rest:  # one read-only array of 0 (NaN where not found), shared by every rate
        still = np.where(values["converged"], 0.0, np.nan)
        still = float(still) if still.ndim == 0 else still
        if not isinstance(still, float):
            still.flags.writeable = False
        rest = MappingProxyType({name: still for name in motion.position})
        values["velocity"] = values["acceleration"] = rest
    return kind(**values, **extra)


def machine_joints(machine, given, older):
    """A machine's ``joints``: of a :class:`Motion` (``machine.joints(machine.solve(...))``), the declared
    points by name, as ``machine.mechanism.joints(motion)`` (the one meaning of joints); of the machine's
    inputs (the older spelling, ``FourBar.joints(theta2, branch)``), ``older()``: the same points stacked
    in declared order, shape (..., P, 2).

    >>> from course_lib.fourbar import FourBar
    >>> bar = FourBar(1.0, 1.0, 1.0, 1.0)
    >>> bar.joints(bar.solve(np.pi / 2))["B"].round(12).tolist(), bar.joints(np.pi / 2).shape
    ([1.0, 1.0], (4, 2))
    """
    if isinstance(given, Motion):
        return machine.mechanism.joints(given)
    points = older()
    return np.stack(np.broadcast_arrays(*points.values()), axis=-2)
