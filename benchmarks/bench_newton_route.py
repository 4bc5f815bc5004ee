"""A long sweep on Newton's route against a closed form: the wiper four-bar of lessons 03–04 declared with
B's coordinates as unknowns (θ3, x_B, y_B: one 3×3 block, no closed form, so ``Mechanism.solve`` follows the
path and solves every instant at once by Newton) against ``FourBar.solve`` (the course's closed form), both
with velocities and accelerations, for N crank angles over a turn, timed in turn in this process.

Prints the two times, their ratio (goal: at most 10) and the largest difference of θ3, then one JSON line.
Usage: python benchmarks/bench_newton_route.py [N]   (default 100000)
"""

from __future__ import annotations

import json
import sys

import numpy as np
import sympy as sp
from timing import best_of_each

from course_lib.fourbar import FourBar
from course_lib.mechanism import Mechanism

LINKAGE = FourBar(crank=0.06, coupler=0.18, rocker=0.12, ground=0.20)
OMEGA2, ALPHA2 = 10.0, 5.0


def newton_route() -> Mechanism:
    theta2, theta3, x_B, y_B = sp.symbols("theta2 theta3 x_B y_B")
    rows = [0.06 * sp.cos(theta2) + 0.18 * sp.cos(theta3) - x_B,
            0.06 * sp.sin(theta2) + 0.18 * sp.sin(theta3) - y_B, (x_B - 0.20) ** 2 + y_B**2 - 0.12**2]
    return Mechanism(rows, [theta3, x_B, y_B], [theta2])


def main(count: int = 100_000) -> dict:
    theta = np.linspace(0.0, 2 * np.pi, count)
    closed = LINKAGE.solve(theta, OMEGA2, ALPHA2)
    start = {"theta3": float(closed.theta3[0]), "x_B": 0.20 + 0.12 * float(np.cos(closed.theta4[0])),
             "y_B": 0.12 * float(np.sin(closed.theta4[0]))}
    mechanism = newton_route()
    results = {}

    def by_newton():
        results["newton"] = mechanism.solve({"theta2": theta}, {"theta2": OMEGA2}, {"theta2": ALPHA2},
                                            guess=start)

    def by_closed_form():
        results["closed"] = LINKAGE.solve(theta, OMEGA2, ALPHA2)

    by_newton()  # derive and compile once, outside the timing
    newton_s, closed_s = best_of_each(3, by_newton, by_closed_form)
    gap = float(np.abs(np.angle(np.exp(1j * (results["newton"].position["theta3"] - closed.theta3)))).max())
    print(f"{count:,} crank angles, positions, velocities, accelerations")
    print(f"Newton's route (3x3 block, continued, batched)  {newton_s:8.3f} s")
    print(f"closed form (FourBar.solve)                     {closed_s:8.3f} s")
    print(f"ratio {newton_s / closed_s:.1f} (goal ≤ 10); largest θ3 difference {gap:.1e} rad")
    return {"n": count, "newton_route_s": round(newton_s, 4), "closed_form_s": round(closed_s, 4),
            "newton_route_vs_closed_form": round(newton_s / closed_s, 2), "max_theta3_diff_rad": gap}


if __name__ == "__main__":
    print(json.dumps(main(*(int(a) for a in sys.argv[1:2]))))
