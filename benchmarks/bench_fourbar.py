"""Four-bar position + velocity + acceleration for 10⁶ crank angles, three ways.

1. ``FourBar.solve``: the core's solve of the four-bar's declaration, its block solved by the course's
   vectorized closed form (the half-angle quadratic, registered as the block's kernel), the rates by the
   core's linear solves of the declared loop.
2. ``newton_batch`` on the two loop equations for all points at once (seed: the middle of the open
   branch's range), F and J from one evaluation of the declared loop with θ2's cos and sin computed
   once (``Mechanism.newton_function``), each step a 2×2 Cramer solve; then the rates in one linear
   solve each with the same Jacobian (``Mechanism.rates``).
3. A Python loop calling ``scipy.optimize.root`` per crank angle (plus two 2×2 solves per point):
   too slow for 10⁶ points, so it is timed on an evenly spread sample and scaled per point.
4. The generic core: the loop declared once on ``course_lib.mechanism.Mechanism`` (sympy, lambdified),
   ``solve`` sweeping every crank angle with continuation from the same seed, then the rates.

Then the closed forms against the trig floor, the transcendental work a closed form cannot avoid
(sin, cos, two arctan2 and a square root of N doubles, nothing else), timed in turn with it:
``FourBar.solve`` on the N crank angles, and the five-bar's ``FiveBar.inverse`` and
``FiveBar.workspace`` on a grid of about N points; with each one's memory, the peak that
``tracemalloc`` sees during the call divided by the number of points (the inputs made before; the
four-bar's also at 10⁷ points).

The wiper linkage of lessons 03–04 (l1..l4 = 0.20, 0.06, 0.18, 0.12 m), ω2 = 10 rad/s, α2 = 5 rad/s².
Prints a table, then one JSON line whose "vs_scipy_loop" is (scipy-loop time per point) /
(closed-form time per point) and "vs_trig_floor" is (FourBar.solve time) / (trig floor time).
Usage: python benchmarks/bench_fourbar.py [N] [SAMPLE]
"""

from __future__ import annotations

import json
import math
import sys
import tracemalloc

import numpy as np
import scipy.optimize
import sympy as sp
from timing import best_of, best_of_each

from course_lib.fivebar import FiveBar
from course_lib.fourbar import FourBar
from course_lib.mechanism import Mechanism
from course_lib.newton import newton_batch

LINKAGE = FourBar(crank=0.06, coupler=0.18, rocker=0.12, ground=0.20)
OMEGA2, ALPHA2 = 10.0, 5.0
SEED = np.array([0.6, 2.0])  # (θ3, θ4) near the middle of the open branch: 17°–57°, 86°–146°
ROBOT = FiveBar(l1=0.10, l2=0.15, l3=0.15, l4=0.10, l5=0.08)  # the five-bar of bench_fivebar.py
MEMORY_SIZES = (1_000_000, 10_000_000)  # points at which the four-bar's bytes per point are measured

TH2, TH3, TH4 = sp.symbols("theta2 theta3 theta4")
L1, L2, L3, L4 = sp.symbols("l1:5", positive=True)
CORE = Mechanism(
    loops=[sp.Matrix([L2 * sp.cos(TH2) + L3 * sp.cos(TH3) - L4 * sp.cos(TH4) - L1,
                      L2 * sp.sin(TH2) + L3 * sp.sin(TH3) - L4 * sp.sin(TH4)])],
    unknowns=[TH3, TH4], inputs=[TH2], parameters={L1: 0.20, L2: 0.06, L3: 0.18, L4: 0.12})



def closed_form(theta2):
    solution = LINKAGE.solve(theta2, OMEGA2, ALPHA2)
    return np.stack([solution.theta3, solution.theta4, solution.omega3, solution.omega4,
                     solution.alpha3, solution.alpha4], axis=-1)


def rates(theta2, angles, omega2, alpha2):
    """ω3, ω4, α3, α4 from J·x = b on stacked 2×2 systems (numpy.linalg.solve, no inverse)."""
    l2, l3, l4 = LINKAGE.l2, LINKAGE.l3, LINKAGE.l4
    theta3, theta4 = angles[..., 0], angles[..., 1]
    J = LINKAGE.loop_jacobian(theta3, theta4)
    s2, c2, s3, c3, s4, c4 = (f(a) for a in (theta2, theta3, theta4) for f in (np.sin, np.cos))
    b = np.stack([omega2 * l2 * s2, -omega2 * l2 * c2], axis=-1)
    omega = np.linalg.solve(J, b[..., None])[..., 0]
    w3, w4 = omega[..., 0], omega[..., 1]
    b_acc = np.stack([alpha2 * l2 * s2 + omega2**2 * l2 * c2 + w3**2 * l3 * c3 - w4**2 * l4 * c4,
                      -alpha2 * l2 * c2 + omega2**2 * l2 * s2 + w3**2 * l3 * s3 - w4**2 * l4 * s4], axis=-1)
    alpha = np.linalg.solve(J, b_acc[..., None])[..., 0]
    return np.concatenate([omega, alpha], axis=-1)


def batched_newton(theta2):
    column, loop = theta2[:, None], LINKAGE.mechanism
    result = newton_batch(loop.newton_function(column), np.tile(SEED, (theta2.size, 1)), jac=True, tol=1e-12,
                          max_iter=30)
    velocity, acceleration, _ = loop.rates(result.x, column, [OMEGA2], [ALPHA2])
    return np.concatenate([result.x, velocity, acceleration], axis=-1), result


def core_sweep(theta2):
    """The declared loop through Mechanism.solve: position, velocity and acceleration."""
    motion = CORE.solve({TH2: theta2}, {TH2: OMEGA2}, {TH2: ALPHA2}, guess={TH3: SEED[0], TH4: SEED[1]},
                        tol=1e-12, max_iter=30)
    columns = [getattr(motion, kind)[name] for kind in ("position", "velocity", "acceleration")
               for name in ("theta3", "theta4")]
    return np.stack(columns, axis=-1), motion


def scipy_loop(theta2):
    out = np.empty((theta2.size, 6))
    for k, angle in enumerate(theta2):
        solution = scipy.optimize.root(
            lambda x, a=angle: LINKAGE.loop_residual(a, x[0], x[1]), SEED,
            jac=lambda x: LINKAGE.loop_jacobian(x[0], x[1]), method="hybr", tol=1e-13,
        )
        out[k, :2] = solution.x
        out[k, 2:] = rates(angle, solution.x, OMEGA2, ALPHA2)
    return out


def largest_difference(a, b):
    """Largest gap between two (N, 6) results; angles compared modulo 2π."""
    angle_gap = np.abs(np.angle(np.exp(1j * (a[:, :2] - b[:, :2])))).max()
    rate_gap = np.abs(a[:, 2:] - b[:, 2:]).max() / np.abs(b[:, 2:]).max()
    return float(angle_gap), float(rate_gap)


def trig_floor(theta2):
    """sin, cos, two arctan2 and a square root of every angle (θ2 ≥ 0 here), and nothing else."""
    sine, cosine = np.sin(theta2), np.cos(theta2)
    return np.arctan2(sine, cosine), np.arctan2(cosine, sine), np.sqrt(theta2)


def bytes_per_point(function, n_points: int) -> float:
    """Peak memory traced during ``function()`` (inputs made before it), per point."""
    tracemalloc.start()
    try:
        result = function()
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    del result
    return peak / n_points


def against_floor(theta2) -> dict:
    """Times (best of 5, the trig floor timed in turn with them) and bytes per point of the closed
    forms: FourBar.solve on ``theta2``, FiveBar.inverse and .workspace on a square grid of about as
    many points."""
    side = math.isqrt(theta2.size)
    axis = np.linspace(-0.3, 0.3, side)
    X, Y = np.meshgrid(axis, axis)
    floor_s, solve_s, inverse_s, workspace_s = best_of_each(
        5, lambda: trig_floor(theta2), lambda: LINKAGE.solve(theta2, OMEGA2, ALPHA2),
        lambda: ROBOT.inverse(X, Y, on_failure="nan"), lambda: ROBOT.workspace(axis, axis))
    memory = {}
    for size in MEMORY_SIZES:
        angles = theta2 if size == theta2.size else np.linspace(0, 2 * np.pi, size, endpoint=False)
        memory[size] = bytes_per_point(lambda a=angles: LINKAGE.solve(a, OMEGA2, ALPHA2), size)
        del angles
    return {
        "floor_s": floor_s, "solve_s": solve_s, "inverse_s": inverse_s, "workspace_s": workspace_s,
        "grid_points": X.size, "solve_memory": memory,
        "inverse_memory": bytes_per_point(lambda: ROBOT.inverse(X, Y, on_failure="nan"), X.size),
        "workspace_memory": bytes_per_point(lambda: ROBOT.workspace(axis, axis), X.size),
    }


def main(n_points: int = 1_000_000, sample: int = 2000) -> dict:
    theta2 = np.linspace(0, 2 * np.pi, n_points, endpoint=False)
    sample_index = np.linspace(0, n_points - 1, sample).astype(int)

    closed_time, reference = best_of(3, lambda: closed_form(theta2))
    newton_time, (newton_out, newton_result) = best_of(2, lambda: batched_newton(theta2))
    core_sweep(theta2[:10])  # derive and lambdify once, outside the timing
    core_time, (core_out, core_motion) = best_of(2, lambda: core_sweep(theta2))
    scipy_time, scipy_out = best_of(1, lambda: scipy_loop(theta2[sample_index]))
    floor = against_floor(theta2)

    per_point = {"closed": closed_time / n_points, "newton": newton_time / n_points,
                 "core": core_time / n_points, "scipy": scipy_time / sample}
    newton_gap = largest_difference(newton_out, reference)
    core_gap = largest_difference(core_out, reference)
    scipy_gap = largest_difference(scipy_out, reference[sample_index])

    print(f"Four-bar (l1..l4 = 0.20, 0.06, 0.18, 0.12 m), position + velocity + acceleration, "
          f"{n_points:,} crank angles")
    print(f"{'method':44} {'total (s)':>11} {'per point (µs)':>15} {'× closed form':>14}")
    rows = [
        ("closed form, vectorized (FourBar.solve)", closed_time, per_point["closed"]),
        ("Newton, batched (newton_batch + 2x2 solves)", newton_time, per_point["newton"]),
        ("Mechanism core (declared loop, continuation)", core_time, per_point["core"]),
        (f"scipy.optimize.root loop (timed on {sample}, scaled)", per_point["scipy"] * n_points,
         per_point["scipy"]),
    ]
    for name, total, each in rows:
        print(f"{name:44} {total:11.3f} {each * 1e6:15.3f} {each / per_point['closed']:14.1f}")
    print(f"batched Newton: {int(newton_result.converged.sum()):,} of {n_points:,} converged, "
          f"mean {newton_result.iterations.mean():.2f} iterations; vs closed form: "
          f"angles {newton_gap[0]:.1e} rad, rates {newton_gap[1]:.1e} (relative)")
    print(f"Mechanism core: {int(core_motion.converged.sum()):,} of {n_points:,} converged; vs closed form: "
          f"angles {core_gap[0]:.1e} rad, rates {core_gap[1]:.1e} (relative)")
    print(f"scipy loop vs closed form on the sample: angles {scipy_gap[0]:.1e} rad, rates {scipy_gap[1]:.1e}")
    print()
    grid, memory = floor["grid_points"], floor["solve_memory"]
    print(f"Closed forms against the trig floor (sin, cos, 2 arctan2, sqrt of {n_points:,} doubles), "
          f"best of 5 in turn")
    print(f"{'closed form':44} {'points':>11} {'total (s)':>11} {'× trig floor':>13} {'bytes/point':>12}")
    floor_rows = [
        ("trig floor", n_points, floor["floor_s"], ""),
        ("FourBar.solve (θ, ω, α of coupler, rocker)", n_points, floor["solve_s"],
         " / ".join(f"{memory[size]:.0f}" for size in MEMORY_SIZES)),
        ("FiveBar.inverse (grid, on_failure=nan)", grid, floor["inverse_s"],
         f"{floor['inverse_memory']:.0f}"),
        ("FiveBar.workspace (grid)", grid, floor["workspace_s"], f"{floor['workspace_memory']:.0f}"),
    ]
    for name, points, total, bytes_text in floor_rows:
        ratio = total / floor["floor_s"] * n_points / points  # per point, against the floor's
        print(f"{name:44} {points:11,} {total:11.4f} {ratio:13.2f} {bytes_text:>12}")
    print(f"FourBar.solve bytes/point at {' and '.join(f'{size:,}' for size in MEMORY_SIZES)} points; "
          "the results alone take 50 (six float64 and two bool arrays)")
    per_floor_point = floor["floor_s"] / n_points

    return {
        "n_points": n_points,
        "scipy_sample": sample,
        "closed_form_s": round(closed_time, 4),
        "newton_batch_s": round(newton_time, 4),
        "scipy_loop_s_scaled": round(per_point["scipy"] * n_points, 2),
        "closed_form_us_per_point": round(per_point["closed"] * 1e6, 4),
        "scipy_loop_us_per_point": round(per_point["scipy"] * 1e6, 2),
        "vs_scipy_loop": round(per_point["scipy"] / per_point["closed"], 1),
        "vs_newton_batch": round(per_point["newton"] / per_point["closed"], 2),
        "newton_converged_fraction": float(newton_result.converged.mean()),
        "mechanism_core_s": round(core_time, 4),
        "vs_mechanism_core": round(per_point["core"] / per_point["closed"], 2),
        "core_vs_newton_batch": round(core_time / newton_time, 2),
        "core_converged_fraction": float(core_motion.converged.mean()),
        "core_max_angle_diff_rad": core_gap[0],
        "newton_max_angle_diff_rad": newton_gap[0],
        "scipy_max_angle_diff_rad": scipy_gap[0],
        "trig_floor_s": round(floor["floor_s"], 4),
        "fourbar_solve_s": round(floor["solve_s"], 4),
        "vs_trig_floor": round(floor["solve_s"] / floor["floor_s"], 2),
        "bytes_per_point": {f"{size:.0e}".replace("+0", ""): round(memory[size], 1) for size in MEMORY_SIZES},
        "fivebar_grid_points": grid,
        "fivebar_inverse_s": round(floor["inverse_s"], 4),
        "fivebar_inverse_vs_trig_floor": round(floor["inverse_s"] / grid / per_floor_point, 2),
        "fivebar_inverse_bytes_per_point": round(floor["inverse_memory"], 1),
        "fivebar_workspace_s": round(floor["workspace_s"], 4),
        "fivebar_workspace_vs_trig_floor": round(floor["workspace_s"] / grid / per_floor_point, 2),
        "fivebar_workspace_bytes_per_point": round(floor["workspace_memory"], 1),
    }


if __name__ == "__main__":
    arguments = [int(a) for a in sys.argv[1:3]]
    print(json.dumps(main(*arguments)))
