"""A Stephenson II six-bar on Newton's route against a hand closed form, 10^5 crank angles over a turn.

The linkage: Stephenson's chain (two ternary links kept apart by binary links: two single binaries and a
path of two) grounded on a binary link of the path of two, the Stephenson II inversion (Stephenson III,
benchmarks/bench_sixbar.py, grounds a ternary; Stephenson I, one of the single binaries).  The
dimensions are this benchmark's own, chosen so that the crank turns fully with J far from singular all the
way round:

* ground (link 1): pivots O2 = (0, 0) and O6 = (gx, gy) = (0.15, 0.52) m;
* ternary crank (link 2), the input θ2: O2A = l2 = 0.04 m, O2B = b2 = 0.04 m, angle A-O2-B β = π/2;
* coupler AC (link 3) l3 = 0.26 m, angle θ3; coupler BD (link 4) l4 = 0.39 m, angle θ4;
* ternary floating link CDE (link 5): CD = p = 0.30 m at angle θ5, CE = q = 0.29 m at θ5 + δ, δ = 1.5 rad;
* rocker O6E (link 6) l6 = 0.24 m, angle θ6.

The loops: the four-bar loop of the two ternaries, A + l3 e3 + p e5 − l4 e4 − B = 0, and the loop through
the ground, A + l3 e3 + q e(θ5 + δ) − l6 e6 − O6 = 0.  Driven from the crank, the floating ternary hangs
on three binary links (a triad): no block reduces to a dyad, so ``Mechanism.closed_forms`` is ``[None]``
and ``solve`` follows the sweep on Newton's route (the path followed from anchor to anchor, then every
instant solved at once by Newton from the path's tangent).  The assembly: the one of ``GUESS`` at θ2 = 0.

The hand closed form (:func:`by_hand`, numpy only) reduces the loops to one equation in the floating
ternary's angle θ5: C where the circles about A (radius l3) and about B − p e5 (radius l4: D's circle
moved by −CD) meet, to the right of the line from A to B − p e5 (the two couplers never line up here, so
C never changes side), E = C + q e(θ5 + δ), and f(θ5) = |E − O6|² − l6² = 0.  Its root is bracketed in
``WINDOW`` (f changes sign once there on this assembly; checked at every instant) and found at every
instant at once by the secant method from two angles amid θ5's range, each root checked to lie in the
window.  Then θ3, θ4, θ6 from the points, and the rates by projecting the differentiated loops on e4 and
e6 (a 2×2 system in ω3, ω5 by Cramer's rule, then ω4 and ω6 one at a time), the accelerations alike.

Prints both times (best of several runs taken in turn in this process), the ratio (goal: at most 10) and
the largest differences of positions and rates, then one JSON line.
Usage: python benchmarks/bench_stephenson.py [N] [RUNS]   (defaults 100000 and 5)
"""

from __future__ import annotations

import json
import sys

import numpy as np
import sympy as sp
from timing import best_of_each

from course_lib.mechanism import Mechanism

L2, B2, BETA, L3, L4, P, Q, DELTA, L6 = 0.04, 0.04, np.pi / 2, 0.26, 0.39, 0.30, 0.29, 1.5, 0.24
GX, GY = 0.15, 0.52
GUESS = {"theta3": 1.07, "theta4": -0.03, "theta5": -0.73, "theta6": -0.38}  # the assembly at θ2 = 0
WINDOW = (-1.5, -0.2)  # θ5 (rad): f changes sign once there, at every crank angle, on this assembly
START = (-0.8, -0.6)  # θ5 (rad): the secant method's two first angles, amid θ5's range
RIGHT = -1.0  # C lies to the right of the line from A to B − p e5 on this assembly
COS_DELTA, SIN_DELTA = np.cos(DELTA), np.sin(DELTA)
OMEGA2, ALPHA2 = 10.0, 5.0
NAMES = ("theta3", "theta4", "theta5", "theta6")


def stephenson_ii() -> Mechanism:
    """The declaration on the core: two loops in θ3, θ4, θ5, θ6, driven by θ2, with its drawing."""
    th2, th3, th4, th5, th6 = sp.symbols("theta2:7")
    l2, b2, beta, l3, l4, p, q, delta, l6, gx, gy = sp.symbols("l2 b2 beta l3 l4 p q delta l6 gx gy")

    def R(length, angle):
        return sp.Matrix([length * sp.cos(angle), length * sp.sin(angle)])

    A, B, O6 = R(l2, th2), R(b2, th2 + beta), sp.Matrix([gx, gy])
    C = A + R(l3, th3)
    D, E = C + R(p, th5), C + R(q, th5 + delta)
    loops = [D - R(l4, th4) - B, E - R(l6, th6) - O6]
    values = {l2: L2, b2: B2, beta: BETA, l3: L3, l4: L4, p: P, q: Q, delta: DELTA, l6: L6, gx: GX, gy: GY}
    points = {"O2": sp.Matrix([0, 0]), "A": A, "B": B, "C": C, "D": D, "E": E, "O6": O6}
    links = {"O2A": ("O2", "A"), "O2B": ("O2", "B"), "AB": ("A", "B"), "AC": ("A", "C"), "BD": ("B", "D"),
             "CD": ("C", "D"), "CE": ("C", "E"), "DE": ("D", "E"), "O6E": ("O6", "E")}
    return Mechanism(loops, [th3, th4, th5, th6], [th2], values, points=points, links=links,
                     ground=["O2", "O6"], plates={"crank": ["O2", "A", "B"], "CDE": ["C", "D", "E"]})


def _closure(theta5, ax, ay, bx, by, side=RIGHT):
    """For the floating ternary at θ5 (the crank's A and B given): C where the circles about A (radius l3)
    and about B − p e5 (radius l4, D's circle moved by −CD) meet, on the ``side`` of the line from A to
    B − p e5 (+1 left, −1 right), and f = |E − O6|² − l6², elementwise."""
    c5, s5 = np.cos(theta5), np.sin(theta5)
    dx, dy = bx - P * c5 - ax, by - P * s5 - ay
    r2 = dx * dx + dy * dy
    along = (L3 * L3 - L4 * L4 + r2) / (2 * r2)  # the foot of C on that line, as a fraction of its length
    across = side * np.sqrt(L3 * L3 / r2 - along * along)  # C's offset from it, as a fraction too
    cx, cy = ax + along * dx - across * dy, ay + along * dy + across * dx
    ex = cx + Q * (c5 * COS_DELTA - s5 * SIN_DELTA) - GX  # E − O6, E = C + q e(θ5 + δ)
    ey = cy + Q * (s5 * COS_DELTA + c5 * SIN_DELTA) - GY
    return (cx, cy), (c5, s5), (ex, ey), ex * ex + ey * ey - L6 * L6


def positions(theta2, tol=1e-14, max_iter=50):
    """θ3, θ4, θ5, θ6 at every crank angle: f(θ5) = 0, its root bracketed in ``WINDOW`` (checked at every
    crank angle), by the secant method from ``START`` until no step exceeds ``tol`` (rad); every root is
    then checked to lie in the window, where f has no other."""
    theta2 = np.asarray(theta2, dtype=float)
    ax, ay = L2 * np.cos(theta2), L2 * np.sin(theta2)
    bx, by = B2 * np.cos(theta2 + BETA), B2 * np.sin(theta2 + BETA)
    ends = [_closure(np.full(theta2.shape, end), ax, ay, bx, by)[3] for end in WINDOW]
    if not (ends[0] * ends[1] < 0).all():
        raise ValueError("θ5's window does not bracket the root at every crank angle")
    x0, x1 = np.full(theta2.shape, START[0]), np.full(theta2.shape, START[1])
    f0, last = _closure(x0, ax, ay, bx, by)[3], _closure(x1, ax, ay, bx, by)
    for _ in range(max_iter):
        f1 = last[3]
        with np.errstate(divide="ignore", invalid="ignore"):  # f1 = f0: that instant has converged
            step = np.where(f1 != f0, f1 * (x1 - x0) / (f1 - f0), 0.0)
        x0, f0, x1 = x1, f1, x1 - step
        last = _closure(x1, ax, ay, bx, by)
        if np.abs(step).max() < tol:
            break
    else:
        raise ValueError(f"the secant method did not settle in {max_iter} steps")
    if not ((WINDOW[0] < x1) & (x1 < WINDOW[1])).all():
        raise ValueError("the secant method left θ5's window (another root) at some crank angle")
    theta5, ((cx, cy), (c5, s5), (ex, ey), _) = x1, last
    theta3 = np.arctan2(cy - ay, cx - ax)
    theta4 = np.arctan2(cy + P * s5 - by, cx + P * c5 - bx)
    theta6 = np.arctan2(ey, ex)
    return theta3, theta4, theta5, theta6


def by_hand(theta2, omega2, alpha2):
    """Positions, velocities and accelerations (each stacked θ3, θ4, θ5, θ6) by hand.  With n(θ) = (−sin θ,
    cos θ), the velocity loops read l3 ω3 n3 + p ω5 n5 − l4 ω4 n4 = v_B − v_A and
    l3 ω3 n3 + q ω5 n(θ5 + δ) − l6 ω6 n6 = −v_A; dotted with e4 and e6 they lose ω4 and ω6."""
    theta2 = np.asarray(theta2, dtype=float)
    theta3, theta4, theta5, theta6 = positions(theta2)
    c2, s2, c2b, s2b = np.cos(theta2), np.sin(theta2), np.cos(theta2 + BETA), np.sin(theta2 + BETA)
    c3, s3, c4, s4 = np.cos(theta3), np.sin(theta3), np.cos(theta4), np.sin(theta4)
    c5, s5, c5d, s5d = np.cos(theta5), np.sin(theta5), np.cos(theta5 + DELTA), np.sin(theta5 + DELTA)
    c6, s6 = np.cos(theta6), np.sin(theta6)
    # [l3 sin(θ4 − θ3), p sin(θ4 − θ5); l3 sin(θ6 − θ3), q sin(θ6 − θ5 − δ)] · (ω3, ω5) = (r_a, r_b)
    m11, m12 = L3 * (s4 * c3 - c4 * s3), P * (s4 * c5 - c4 * s5)
    m21, m22 = L3 * (s6 * c3 - c6 * s3), Q * (s6 * c5d - c6 * s5d)
    det = m11 * m22 - m12 * m21

    def solved(gx_a, gy_a, gx_b, gy_b):
        """(ω3, ω4, ω5, ω6) or (α3, …) from the right-hand sides g_a (loop a) and g_b (loop b)."""
        ra, rb = gx_a * c4 + gy_a * s4, gx_b * c6 + gy_b * s6
        w3, w5 = (ra * m22 - m12 * rb) / det, (m11 * rb - m21 * ra) / det
        # the n4 and n6 components: −l4 w4 = g_a·n4 − l3 w3 n3·n4 − p w5 n5·n4, alike for w6
        w4 = (L3 * w3 * (c3 * c4 + s3 * s4) + P * w5 * (c5 * c4 + s5 * s4) - (-gx_a * s4 + gy_a * c4)) / L4
        w6 = (L3 * w3 * (c3 * c6 + s3 * s6) + Q * w5 * (c5d * c6 + s5d * s6) - (-gx_b * s6 + gy_b * c6)) / L6
        return w3, w4, w5, w6

    vax, vay = -L2 * s2 * omega2, L2 * c2 * omega2
    vbx, vby = -B2 * s2b * omega2, B2 * c2b * omega2
    w3, w4, w5, w6 = solved(vbx - vax, vby - vay, -vax, -vay)
    # accelerations: l3 α3 n3 + p α5 n5 − l4 α4 n4 = a_B − a_A + l3 ω3² e3 + p ω5² e5 − l4 ω4² e4, alike
    aax, aay = -L2 * (s2 * alpha2 + c2 * omega2**2), L2 * (c2 * alpha2 - s2 * omega2**2)
    abx, aby = -B2 * (s2b * alpha2 + c2b * omega2**2), B2 * (c2b * alpha2 - s2b * omega2**2)
    common_x, common_y = L3 * w3**2 * c3 - aax, L3 * w3**2 * s3 - aay
    a3, a4, a5, a6 = solved(abx + common_x + P * w5**2 * c5 - L4 * w4**2 * c4,
                            aby + common_y + P * w5**2 * s5 - L4 * w4**2 * s4,
                            common_x + Q * w5**2 * c5d - L6 * w6**2 * c6,
                            common_y + Q * w5**2 * s5d - L6 * w6**2 * s6)
    return (np.stack([theta3, theta4, theta5, theta6]), np.stack([w3, w4, w5, w6]),
            np.stack([a3, a4, a5, a6]))


def gaps(motion, hand) -> tuple[float, float, float]:
    """The largest differences of positions (angles modulo a turn), velocities and accelerations."""
    position = max(float(np.abs(np.angle(np.exp(1j * (motion.position[n] - hand[0][k])))).max())
                   for k, n in enumerate(NAMES))
    velocity = max(float(np.abs(motion.velocity[n] - hand[1][k]).max()) for k, n in enumerate(NAMES))
    acceleration = max(float(np.abs(motion.acceleration[n] - hand[2][k]).max()) for k, n in enumerate(NAMES))
    return position, velocity, acceleration


def by_differences(theta2, omega2, alpha2, h=1e-5):
    """Velocities and accelerations of the hand solution by central differences in θ2 (q̇ = q′ω2,
    q̈ = q″ω2² + q′α2, q″ from the differences of q′ taken from the hand velocities)."""
    ahead, behind = by_hand(theta2 + h, omega2, alpha2), by_hand(theta2 - h, omega2, alpha2)
    step = np.stack(positions(theta2 + h)) - np.stack(positions(theta2 - h))
    slope = np.angle(np.exp(1j * step)) / (2 * h)  # angles compared modulo a turn
    return slope * omega2, (ahead[1] - behind[1]) / (2 * h) * omega2 + slope * alpha2


def main(count: int = 100_000, runs: int = 5) -> dict:
    theta2 = np.linspace(0.0, 2 * np.pi, count)
    mechanism = stephenson_ii()
    if mechanism.closed_forms != [None]:
        raise SystemExit(f"expected no closed form for the Stephenson II; got {mechanism.closed_forms}")
    results = {}

    def core():
        results["core"] = mechanism.solve({"theta2": theta2}, {"theta2": OMEGA2}, {"theta2": ALPHA2},
                                          guess=GUESS)

    def hand():
        results["hand"] = by_hand(theta2, OMEGA2, ALPHA2)

    core()  # derive and compile once, outside the timing
    core_s, hand_s = best_of_each(runs, core, hand)
    position, velocity, acceleration = gaps(results["core"], results["hand"])
    sample = slice(None, None, max(1, count // 500))
    velocity_fd, acceleration_fd = by_differences(theta2[sample], OMEGA2, ALPHA2)
    fd = (float(np.abs(velocity_fd - results["hand"][1][:, sample]).max()),
          float(np.abs(acceleration_fd - results["hand"][2][:, sample]).max()))
    print(f"Stephenson II six-bar, {count:,} crank angles, positions, velocities, accelerations")
    print(f"core, Newton's route (4x4 block, continued, batched)  {core_s:8.3f} s")
    print(f"hand closed form (secant in θ5, Cramer)               {hand_s:8.3f} s")
    print(f"ratio {core_s / hand_s:.1f} (goal ≤ 10); largest differences core − hand {position:.1e} rad, "
          f"{velocity:.1e} rad/s, {acceleration:.1e} rad/s²; hand − central differences {fd[0]:.1e} rad/s, "
          f"{fd[1]:.1e} rad/s²")
    if max(position, velocity, acceleration) > 1e-9 or max(fd) > 1e-6:
        raise SystemExit("the core and the hand closed form disagree (see the differences above)")
    return {"n": count, "core_s": round(core_s, 4), "hand_closed_form_s": round(hand_s, 4),
            "core_vs_hand_closed_form": round(core_s / hand_s, 2), "max_position_diff_rad": position,
            "max_velocity_diff_rad_s": velocity, "max_acceleration_diff_rad_s2": acceleration,
            "max_velocity_vs_differences": fd[0], "max_acceleration_vs_differences": fd[1]}


if __name__ == "__main__":
    print(json.dumps(main(*(int(a) for a in sys.argv[1:3]))))
