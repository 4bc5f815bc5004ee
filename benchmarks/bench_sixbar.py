"""A Stephenson III six-bar swept over 10^5 crank angles (positions, velocities, accelerations): the core
(`Mechanism.solve`, its closed forms derived from the declaration) against a hand-vectorised numpy closed
form, measured in the same process; prints the ratio (goal: at most 3), the median of five runs.

    .venv/bin/python benchmarks/bench_sixbar.py
"""

import statistics
import time

import numpy as np
import sympy as sp

from course_lib.mechanism import Mechanism

L1, L2, L3, L4, P, DELTA, L5, L6, GX, GY = 0.20, 0.06, 0.18, 0.12, 0.10, 0.4, 0.20, 0.15, 0.05, 0.22
GUESS = {"theta3": 0.7, "theta4": -4.7, "theta5": 2.8, "theta6": -2.7}  # the open four-bar, dyad σ = +1


def stephenson() -> Mechanism:
    """Four-bar O2-A-B-O4 whose coupler carries P (at p, δ from AB); the dyad P-C-O6 hangs on P."""
    th2, th3, th4, th5, th6 = sp.symbols("theta2:7")
    l1, l2, l3, l4, p, delta, l5, l6, gx, gy = sp.symbols("l1 l2 l3 l4 p delta l5 l6 gx gy")

    def R(length, angle):
        return sp.Matrix([length * sp.cos(angle), length * sp.sin(angle)])

    A = R(l2, th2)
    loops = [
        A + R(l3, th3) - R(l4, th4) - sp.Matrix([l1, 0]),
        A + R(p, th3 + delta) + R(l5, th5) - sp.Matrix([gx, gy]) - R(l6, th6),
    ]
    values = {l1: L1, l2: L2, l3: L3, l4: L4, p: P, delta: DELTA, l5: L5, l6: L6, gx: GX, gy: GY}
    return Mechanism(loops, [th3, th4, th5, th6], [th2], values)


def by_hand(theta2, omega2, alpha2):
    """The same motion in closed form, written out with numpy: Norton's quadratic for θ4 (the core's
    assembly σ = −1 of its t-quadratic is the open one here), θ3 from the loop, the dyad by its own
    half-angle quadratic, the rates by Cramer's rule loop by loop."""
    c2, s2 = np.cos(theta2), np.sin(theta2)
    k3 = L2**2 - L3**2 + L4**2 + L1**2
    A = 2 * L2 * L4 * c2 - 2 * L1 * L4 - 2 * L1 * L2 * c2 + k3
    B = -4 * L2 * L4 * s2
    C = -2 * (L1 * L2 + L2 * L4) * c2 + 2 * L1 * L4 + k3
    theta4 = 2 * np.arctan2(-B - np.sqrt(B * B - 4 * A * C), 2 * A)
    c4, s4 = np.cos(theta4), np.sin(theta4)
    theta3 = np.arctan2(L4 * s4 - L2 * s2, L1 + L4 * c4 - L2 * c2)
    c3, s3 = np.cos(theta3), np.sin(theta3)
    cp, sp_ = np.cos(theta3 + DELTA), np.sin(theta3 + DELTA)
    dx, dy = L2 * c2 + P * cp - GX, L2 * s2 + P * sp_ - GY  # P − O6
    # |D + l5 e5| = l6: 2 l5 (dx cos θ5 + dy sin θ5) + dx² + dy² + l5² − l6² = 0
    a5, b5, k5 = 2 * L5 * dx, 2 * L5 * dy, dx * dx + dy * dy + L5**2 - L6**2
    qa, qb, qc = k5 - a5, 2 * b5, k5 + a5
    theta5 = 2 * np.arctan2(-qb + np.sqrt(qb * qb - 4 * qa * qc), 2 * qa)
    c5, s5 = np.cos(theta5), np.sin(theta5)
    theta6 = np.arctan2(dy + L5 * s5, dx + L5 * c5)
    c6, s6 = np.cos(theta6), np.sin(theta6)
    # loop 1: [−l3 s3, l4 s4; l3 c3, −l4 c4]·(ω3, ω4) = (l2 s2 ω2, −l2 c2 ω2)
    det1 = L3 * L4 * (s3 * c4 - c3 * s4)
    r1, r2 = L2 * s2 * omega2, -L2 * c2 * omega2
    omega3 = (-L4 * c4 * r1 - L4 * s4 * r2) / det1
    omega4 = (-L3 * c3 * r1 - L3 * s3 * r2) / det1
    ax = L2 * c2 * omega2**2 + L2 * s2 * alpha2 + L3 * c3 * omega3**2 - L4 * c4 * omega4**2
    ay = L2 * s2 * omega2**2 - L2 * c2 * alpha2 + L3 * s3 * omega3**2 - L4 * s4 * omega4**2
    alpha3 = (-L4 * c4 * ax - L4 * s4 * ay) / det1
    alpha4 = (-L3 * c3 * ax - L3 * s3 * ay) / det1
    # loop 2: [−l5 s5, l6 s6; l5 c5, −l6 c6]·(ω5, ω6) = (vx, vy), P's velocity moved over
    det2 = L5 * L6 * (s5 * c6 - c5 * s6)
    vx = L2 * s2 * omega2 + P * sp_ * omega3
    vy = -L2 * c2 * omega2 - P * cp * omega3
    omega5 = (-L6 * c6 * vx - L6 * s6 * vy) / det2
    omega6 = (-L5 * c5 * vx - L5 * s5 * vy) / det2
    bx = (
        L2 * c2 * omega2**2
        + L2 * s2 * alpha2
        + P * cp * omega3**2
        + P * sp_ * alpha3
        + L5 * c5 * omega5**2
        - L6 * c6 * omega6**2
    )
    by = (
        L2 * s2 * omega2**2
        - L2 * c2 * alpha2
        + P * sp_ * omega3**2
        - P * cp * alpha3
        + L5 * s5 * omega5**2
        - L6 * s6 * omega6**2
    )
    alpha5 = (-L6 * c6 * bx - L6 * s6 * by) / det2
    alpha6 = (-L5 * c5 * bx - L5 * s5 * by) / det2
    return (
        np.stack([theta3, theta4, theta5, theta6]),
        np.stack([omega3, omega4, omega5, omega6]),
        np.stack([alpha3, alpha4, alpha5, alpha6]),
    )


def main(count: int = 100_000, runs: int = 5) -> None:
    mechanism = stephenson()
    theta2 = np.linspace(0.0, 2 * np.pi, count)
    omega2, alpha2 = 10.0 + np.sin(theta2), 3.0

    def core():
        return mechanism.solve({"theta2": theta2}, {"theta2": omega2}, {"theta2": alpha2}, guess=GUESS)

    motion, hand = core(), by_hand(theta2, omega2, alpha2)  # warm: derivations compiled once
    names = ("theta3", "theta4", "theta5", "theta6")
    gaps = [
        max(
            np.abs(np.angle(np.exp(1j * (motion.position[n] - hand[0][k])))).max()
            for k, n in enumerate(names)
        ),
        max(np.abs(motion.velocity[n] - hand[1][k]).max() for k, n in enumerate(names)),
        max(np.abs(motion.acceleration[n] - hand[2][k]).max() for k, n in enumerate(names)),
    ]
    ratios = []
    for _ in range(runs):
        start = time.perf_counter()
        core()
        middle = time.perf_counter()
        by_hand(theta2, omega2, alpha2)
        end = time.perf_counter()
        ratios.append((middle - start) / (end - middle))
    print(f"Stephenson III six-bar, {count:,} crank angles, positions + velocities + accelerations")
    print(
        f"core vs numpy closed form: largest gaps {gaps[0]:.1e} rad, {gaps[1]:.1e} rad/s, "
        f"{gaps[2]:.1e} rad/s^2"
    )
    print(
        f"time ratio core / numpy: median {statistics.median(ratios):.2f} of {runs} runs (goal ≤ 3) "
        f"({', '.join(f'{r:.2f}' for r in ratios)})"
    )


if __name__ == "__main__":
    main()
