"""The power-saw motor's jerk-limited start-up profile (course report, section 4; seconds, radians).

From rest, during the first revolution (T seconds) α2 rises linearly from 0 to ``alpha_max`` over T/3,
holds it for T/3, falls back to 0 over T/3 and stays 0, so the crank then turns at ω2 = 2·alpha_max·T/3;
θ2(T) = 2π fixes T = √(6π / alpha_max).  The course's 5 rad/s² gives T ≈ 1.9416 s and a final speed of
10T/3 ≈ 6.472 rad/s (≈ 61.8 rpm).
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np

from .errors import InvalidGeometryError, require_finite

__all__ = ["ALPHA_MAX", "MotorProfile", "first_turn_time", "motor_profile"]

#: Peak angular acceleration of the course's motor, rad/s².
ALPHA_MAX = 5.0


class MotorProfile(NamedTuple):
    """Crank angle (rad), angular speed (rad/s) and angular acceleration (rad/s²), shaped like ``t``."""

    theta2: np.ndarray
    omega2: np.ndarray
    alpha2: np.ndarray


def _check_alpha_max(alpha_max: float) -> float:
    array = require_finite("alpha_max", alpha_max, "rad/s²")
    value = float(array) if array.ndim == 0 else np.nan
    if not (np.isfinite(value) and value > 0):
        raise InvalidGeometryError(f"alpha_max must be a positive, finite rad/s²; got {alpha_max!r}")
    return value


def first_turn_time(alpha_max: float = ALPHA_MAX) -> float:
    """Duration T (s) of the start-up: θ2(T) = ω2(T)·T/2 = alpha_max·T²/3 = 2π (the speed rises
    symmetrically about T/2 to ω2(T) = 2·alpha_max·T/3), so T = √(6π / alpha_max).

    >>> round(first_turn_time(), 4)
    1.9416
    """
    return float(np.sqrt(6.0 * np.pi / _check_alpha_max(alpha_max)))


#: The latest time (s) motor_profile accepts: θ2 ∝ t³ stays finite far beyond it (30 000 years).
MAX_TIME = 1e12


def motor_profile(t, alpha_max: float = ALPHA_MAX) -> MotorProfile:
    """θ2 (rad), ω2 (rad/s), α2 (rad/s²) of the crank at time(s) ``t`` ≥ 0 (s), vectorized, piece by piece;
    ``InvalidGeometryError`` for a negative or non-finite time.

    >>> profile = motor_profile([0.0, first_turn_time()])
    >>> [round(v, 6) for v in profile.theta2.tolist()]
    [0.0, 6.283185]
    """
    A = _check_alpha_max(alpha_max)
    s = require_finite("t", t, unit="seconds")
    for bad, rule in ((s < 0, "t must be >= 0 s (the motor starts at t = 0)"),
                      (s > MAX_TIME, f"t must be <= {MAX_TIME:.0e} s")):
        if np.any(bad):
            raise InvalidGeometryError(f"{rule}; got {s.ravel()[np.flatnonzero(bad)[0]]}")
    T = first_turn_time(A)
    phase = np.select([s < T / 3, s < 2 * T / 3, s < T], [0, 1, 2], default=3)
    pieces = [  # (α2, ω2, θ2) with A = alpha_max on [0, T/3), [T/3, 2T/3), [2T/3, T) and [T, ∞)
        (3 * A * s / T, 3 * A * s**2 / (2 * T), A * s**3 / (2 * T)),
        (np.full_like(s, A), A * s - A * T / 6, A * s**2 / 2 - A * T * s / 6 + A * T**2 / 54),
        (3 * A - 3 * A * s / T, 3 * A * s - 3 * A * s**2 / (2 * T) - 5 * A * T / 6,
         A * T**2 / 6 - 5 * A * T * s / 6 + 3 * A * s**2 / 2 - A * s**3 / (2 * T)),
        (np.zeros_like(s), np.full_like(s, 2 * A * T / 3), 2 * A * T * s / 3 - A * T**2 / 3),
    ]
    alpha2, omega2, theta2 = (np.choose(phase, column) for column in zip(*pieces, strict=True))
    return MotorProfile(theta2=theta2, omega2=omega2, alpha2=alpha2)
