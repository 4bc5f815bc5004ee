"""Batched Newton vs a Python loop of scipy.optimize.root on 10,000 four-bar position problems.

Both solve the loop of lesson 02 (l1 = 0.20, l2 = 0.06, l3 = 0.18, l4 = 0.12 m) for θ3, θ4 at
10,000 crank angles over one revolution, from the same seed, to the same tolerance (1e-10 on
the step), in this one process.  Prints a table, then a JSON line with key ``vs_scipy_loop``
(loop time / batched time).
"""

import json

import numpy as np
import scipy.optimize
from timing import best_of

from course_lib.newton import newton_batch

L1, L2, L3, L4 = 0.20, 0.06, 0.18, 0.12
N = 10_000
TOL = 1e-10
SEED = (0.4, 1.6)  # near the open assembly


def residual(theta2, x):
    theta3, theta4 = x[..., 0], x[..., 1]
    return np.stack(
        [
            L2 * np.cos(theta2) + L3 * np.cos(theta3) - L4 * np.cos(theta4) - L1,
            L2 * np.sin(theta2) + L3 * np.sin(theta3) - L4 * np.sin(theta4),
        ],
        axis=-1,
    )


def jacobian(x):
    theta3, theta4 = x[..., 0], x[..., 1]
    row1 = np.stack([-L3 * np.sin(theta3), L4 * np.sin(theta4)], axis=-1)
    row2 = np.stack([L3 * np.cos(theta3), -L4 * np.cos(theta4)], axis=-1)
    return np.stack([row1, row2], axis=-2)



def main():
    theta2 = np.linspace(0.0, 2 * np.pi, N, endpoint=False)
    seeds = np.tile(SEED, (N, 1))

    def batched():
        return newton_batch(lambda x: residual(theta2, x), seeds, jac=jacobian, tol=TOL, max_iter=50)

    def scipy_loop():
        out = np.empty((N, 2))
        for k, angle in enumerate(theta2):
            solution = scipy.optimize.root(
                lambda x, a=angle: residual(a, x), SEED, jac=jacobian, method="hybr", tol=TOL
            )
            out[k] = solution.x
        return out

    batched_time, batch = best_of(5, batched)
    loop_time, loop = best_of(1, scipy_loop)
    both = batch.converged
    agree = np.abs(np.exp(1j * batch.x[both]) - np.exp(1j * loop[both])).max()

    print(f"{N} four-bar position problems, tolerance {TOL:g}, one process")
    print(f"{'method':34} {'total (s)':>10} {'per problem (µs)':>17}")
    print(f"{'newton_batch (vectorized)':34} {batched_time:10.4f} {1e6 * batched_time / N:17.2f}")
    print(f"{'scipy.optimize.root, Python loop':34} {loop_time:10.4f} {1e6 * loop_time / N:17.2f}")
    print(f"converged: {both.sum()} of {N}; max angle difference between methods {agree:.1e} rad")
    print(f"batched iterations: median {np.median(batch.iterations):.0f}, max {batch.iterations.max()}")
    print(json.dumps({"vs_scipy_loop": round(loop_time / batched_time, 1),
                      "batched_seconds": round(batched_time, 4), "loop_seconds": round(loop_time, 3)}))


if __name__ == "__main__":
    main()
