"""Five-bar inverse kinematics over a 1000 × 1000 grid, all four working modes.

Vectorized: one call of ``FiveBar.inverse`` per working mode on the whole grid.
Per-point loops (timed on a random sample of grid points, then scaled to the full grid):
  * the same library function called with scalars, one point and one mode at a time;
  * a plain ``math``-module loop of the course's formula (no input checks), for reference.
The last line printed is a JSON object with "grid_seconds" and "vs_loop" (vectorized vs the
library loop).
"""

from __future__ import annotations

import json
import math

import numpy as np
from timing import best_of

from course_lib.fivebar import WORKING_MODES, FiveBar

ROBOT = FiveBar(l1=0.10, l2=0.15, l3=0.15, l4=0.10, l5=0.08)
SIDE = 1000
SAMPLE = 2000
REPEATS = 3


def vectorized(X: np.ndarray, Y: np.ndarray) -> list:
    return [ROBOT.inverse(X, Y, modes=modes, on_failure="nan") for modes in WORKING_MODES]


def library_loop(xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    out = np.empty((len(WORKING_MODES), len(xs), 2))
    for m, modes in enumerate(WORKING_MODES):
        for i in range(len(xs)):
            result = ROBOT.inverse(float(xs[i]), float(ys[i]), modes=modes, on_failure="nan")
            out[m, i] = result.theta1, result.theta4
    return out


def math_loop(xs: np.ndarray, ys: np.ndarray) -> np.ndarray:
    l1, l2, l3, l4, l5 = ROBOT.l1, ROBOT.l2, ROBOT.l3, ROBOT.l4, ROBOT.l5
    out = np.empty((len(WORKING_MODES), len(xs), 2))
    for m, (s1, s2) in enumerate(WORKING_MODES):
        for i in range(len(xs)):
            x, y = float(xs[i]), float(ys[i])
            common = x * x + y * y + l5 * l5 / 4
            a1 = l1 * l1 - l2 * l2 - l1 * l5 + 2 * l1 * x - l5 * x + common
            c1 = l1 * l1 - l2 * l2 + l1 * l5 - 2 * l1 * x - l5 * x + common
            a2 = -l3 * l3 + l4 * l4 + l4 * l5 + 2 * l4 * x + l5 * x + common
            c2 = -l3 * l3 + l4 * l4 - l4 * l5 - 2 * l4 * x + l5 * x + common
            b1, b2 = -4 * l1 * y, -4 * l4 * y
            d1, d2 = b1 * b1 - 4 * a1 * c1, b2 * b2 - 4 * a2 * c2
            if d1 < 0 or d2 < 0:
                out[m, i] = math.nan, math.nan
                continue
            out[m, i] = (2 * math.atan2(-b1 + s1 * math.sqrt(d1), 2 * a1),
                         2 * math.atan2(-b2 + s2 * math.sqrt(d2), 2 * a2))
    return out



def main() -> None:
    axis = np.linspace(-0.3, 0.3, SIDE)
    X, Y = np.meshgrid(axis, axis)
    grid_seconds, solutions = best_of(REPEATS, vectorized, X, Y)

    rng = np.random.default_rng(0)
    pick = rng.choice(X.size, SAMPLE, replace=False)
    xs, ys = X.ravel()[pick], Y.ravel()[pick]
    library_seconds, looped = best_of(REPEATS, library_loop, xs, ys)
    math_seconds, plain = best_of(REPEATS, math_loop, xs, ys)

    expected = np.stack([np.stack([s.theta1.ravel()[pick], s.theta4.ravel()[pick]], -1) for s in solutions])
    assert np.allclose(looped, expected, atol=1e-12, equal_nan=True)
    wrap = (plain - expected + np.pi) % (2 * np.pi) - np.pi
    assert np.nanmax(np.abs(wrap)) < 1e-9 and np.array_equal(np.isnan(plain), np.isnan(expected))

    scale = X.size / SAMPLE
    library_full, math_full = library_seconds * scale, math_seconds * scale
    reachable = float(np.mean(solutions[0].reachable))
    rows = [
        ("vectorized FiveBar.inverse, 4 modes", grid_seconds, "measured"),
        ("per-point loop, FiveBar.inverse", library_full, f"{SAMPLE} points timed, x{scale:.0f}"),
        ("per-point loop, plain math formula", math_full, f"{SAMPLE} points timed, x{scale:.0f}"),
    ]
    modes = len(WORKING_MODES)
    print(f"Five-bar inverse kinematics on a {SIDE} x {SIDE} grid ({X.size:,} points, "
          f"{reachable:.1%} reachable),")
    print(f"all {modes} working modes = {modes * X.size:,} solutions; best of {REPEATS}.")
    print()
    print(f"{'method':<40} {'seconds':>10} {'vs vectorized':>14}   note")
    for name, seconds, note in rows:
        print(f"{name:<40} {seconds:>10.3f} {seconds / grid_seconds:>13.0f}x   {note}")
    print()
    print("Loops are timed on a random sample of grid points and scaled to the full grid;")
    print("vs_loop compares with the library called point by point (its input checks included).")
    print(json.dumps({
        "grid_seconds": round(grid_seconds, 4),
        "vs_loop": round(library_full / grid_seconds, 1),
        "vs_math_loop": round(math_full / grid_seconds, 1),
    }))


if __name__ == "__main__":
    main()
