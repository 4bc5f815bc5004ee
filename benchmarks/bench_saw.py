"""The power saw over the motor's start-up: 1000 instants, position + velocity + acceleration.

Solvers compared, all in this one process:

* batched     - course_lib.saw.sweep(method="batched"): the saw's loop declared on the core and solved
                by Mechanism.consecutive for every instant at once (newton_batch, Cramer's rule; the
                linear velocity and acceleration stages by Newton too, or, in the "direct" row, by one
                batched linear solve);
* scipy loop  - one scipy.optimize.root (MINPACK "lm", analytic Jacobian) per stage per instant, each
                seeded with the previous instant's solution ("hybr" stalls on the all-zero rates at rest:
                its first step is bounded by a multiple of the seed's size);
* symbolic    - what the course's MATLAB code does: the symbolic 3x3 Jacobians are inverted once, then
                at every Newton iteration numbers are substituted into them with sympy (subs) and the
                result converted to floats.  Far too slow for 1000 instants: a few instants are timed
                and the time is scaled to 1000 (said so in the table);
* analytic    - course_lib.saw.sweep(method="analytic"): the closed form, vectorized;
* core        - the saw's loop r1 = r2 + r3 and slider line declared on course_lib.mechanism.Mechanism
                (derived and lambdified once, outside the timing): Mechanism.solve sweeps every instant
                with continuation from the printed seed, then the rates by linear solves.

The table is followed by the cost of batched and analytic for n = 10^3 ... 10^6 instants, to show
the cost grows linearly.  The last line is JSON with the ratios.

Run: .venv/bin/python benchmarks/bench_saw.py
"""

from __future__ import annotations

import json
import time

import numpy as np
import scipy.optimize
import sympy as sp
from timing import best_of, best_of_each

from course_lib import saw
from course_lib.mechanism import Mechanism
from course_lib.profile import first_turn_time, motor_profile

N = 1000
SYMBOLIC_INSTANTS = 4
TOL = 1e-6
METHOD = "lm"  # MINPACK Levenberg–Marquardt; "hybr" stalls on the all-zero seeds of the rates at rest



def profile_points(n):
    return motor_profile(np.linspace(0.0, 2 * first_turn_time(), n))


# ------------------------------------------------------------------ the generic core

R1, TH1, TH2, TH3 = sp.symbols("r1 theta1 theta2 theta3")
R1Y, R2, R3 = sp.symbols("r1y r2 r3", positive=True)
CORE = Mechanism(
    loops=[sp.Matrix([-R1 * sp.cos(TH1) + R2 * sp.cos(TH2) + R3 * sp.cos(TH3),
                      R1 * sp.sin(TH1) - R2 * sp.sin(TH2) - R3 * sp.sin(TH3)]),
           R1 * sp.sin(TH1) - R1Y],
    unknowns=[R1, TH1, TH3], inputs=[TH2], parameters={R1Y: 0.045, R2: 0.075, R3: 0.170})


def core_sweep(n=N):
    theta2, omega2, alpha2 = profile_points(n)
    motion = CORE.solve({TH2: theta2}, {TH2: omega2}, {TH2: alpha2},
                        guess=dict(zip((R1, TH1, TH3), saw.SEED_PRINTED[:3], strict=True)), tol=TOL)
    return np.stack([getattr(motion, kind)[name] for kind in ("position", "velocity", "acceleration")
                     for name in ("r1", "theta1", "theta3")], axis=-1)


# ------------------------------------------------------------------ scipy.optimize.root, point by point


def scipy_loop(n=N):
    theta2s, omega2s, alpha2s = profile_points(n)
    x = saw.SEED_PRINTED.copy()
    out = np.empty((n, 9))
    for k, (theta2, omega2, alpha2) in enumerate(zip(theta2s, omega2s, alpha2s, strict=True)):
        position = scipy.optimize.root(
            lambda q, th=theta2: (saw.position_residual(q, th), saw.position_jacobian(q)),
            x[0:3], jac=True, method=METHOD, options={"xtol": 1e-12},
        ).x
        jac = saw.velocity_residual_jacobian(position)
        velocity = scipy.optimize.root(
            lambda qd, q=position, th=theta2, w=omega2, J=jac: (saw.velocity_residual(qd, q, th, w), J),
            x[3:6], jac=True, method=METHOD, options={"xtol": 1e-12},
        ).x
        acceleration = scipy.optimize.root(
            lambda qdd, q=position, qd=velocity, th=theta2, w=omega2, a=alpha2, J=jac: (
                saw.acceleration_residual(qdd, qd, q, th, w, a), J),
            x[6:9], jac=True, method=METHOD, options={"xtol": 1e-12},
        ).x
        x = out[k] = np.concatenate([position, velocity, acceleration])
    return out


# ------------------------------------------------------------------ the MATLAB way: sympy subs per iteration


def symbolic_solver():
    """Symbolic stage systems and their inverted Jacobians, built once (not timed), as in the course."""
    r1, th1, th3, th2 = sp.symbols("r1 theta1 theta3 theta2")
    v_r, w1, w3, w2 = sp.symbols("v_r omega1 omega3 omega2")
    a_r, al1, al3, al2 = sp.symbols("a_r alpha1 alpha3 alpha2")
    r1y, r2, r3 = 0.045, 0.075, 0.170
    position = sp.Matrix([-r1 * sp.cos(th1) + r2 * sp.cos(th2) + r3 * sp.cos(th3),
                          r1 * sp.sin(th1) - r2 * sp.sin(th2) - r3 * sp.sin(th3),
                          r1 * sp.sin(th1) - r1y])
    q, qd, qdd = [r1, th1, th3], [v_r, w1, w3], [a_r, al1, al3]
    velocity = position.jacobian(q) * sp.Matrix(qd) + position.diff(th2) * w2
    acceleration = (velocity.jacobian(q) * sp.Matrix(qd) + velocity.jacobian(qd) * sp.Matrix(qdd)
                    + velocity.diff(th2) * w2 + velocity.diff(w2) * al2)
    stages = []
    for F, unknowns in ((position, q), (velocity, qd), (acceleration, qdd)):
        stages.append((F, F.jacobian(unknowns).inv(), unknowns))
    known = {"theta2": th2, "omega2": w2, "alpha2": al2}

    def solve(theta2, omega2, alpha2, seed):
        values = {known["theta2"]: theta2, known["omega2"]: omega2, known["alpha2"]: alpha2}
        result = []
        for stage, (F, J_inv, unknowns) in enumerate(stages):
            F_here, J_here = F.subs(values), J_inv.subs(values)   # like MATLAB's subs(fP, theta_2, ...)
            x = np.array(seed[3 * stage: 3 * stage + 3], dtype=float)
            for _ in range(50):
                point = dict(zip(unknowns, x, strict=True))
                step = np.array((J_here.subs(point) * F_here.subs(point)).evalf(), dtype=float).ravel()
                x = x - step
                if np.linalg.norm(step) < TOL:
                    break
            values.update(zip(unknowns, x, strict=True))
            result.extend(x)
        return np.array(result)

    return solve


def main():
    exact = saw.sweep(N, method="analytic").x
    batched = saw.sweep(N, method="batched", tol=TOL)
    direct = saw.sweep(N, method="batched", tol=TOL, linear_stages="direct")
    # in turn, as many calls each: a slow spell of the machine falls on all three alike
    t_batched, t_direct, t_analytic = best_of_each(
        20, lambda: saw.sweep(N, method="batched", tol=TOL),
        lambda: saw.sweep(N, method="batched", tol=TOL, linear_stages="direct"),
        lambda: saw.sweep(N, method="analytic"))
    core_sweep(10)  # derive and lambdify once, outside the timing
    t_core, core_x = best_of(5, core_sweep)
    t_scipy, scipy_x = best_of(1, scipy_loop)
    t_consecutive, consecutive = best_of(1, lambda: saw.sweep(N, method="consecutive", tol=TOL))
    t_simultaneous, simultaneous = best_of(1, lambda: saw.sweep(N, method="simultaneous", tol=TOL))

    solve = symbolic_solver()
    instants = np.linspace(0, N - 1, SYMBOLIC_INSTANTS).astype(int)
    theta2s, omega2s, alpha2s = profile_points(N)
    # each timed instant is seeded with the previous instant's solution, as in a 1000-instant run
    start = time.perf_counter()
    symbolic_x = np.array([solve(theta2s[k], omega2s[k], alpha2s[k], exact[max(k - 1, 0)]) for k in instants])
    t_symbolic = (time.perf_counter() - start) * N / SYMBOLIC_INSTANTS

    def error(x, rows_=slice(None)):
        return float(np.abs(x - exact[rows_]).max())

    rows = [
        ("batched Newton (newton_batch, all stages)", t_batched, error(batched.x)),
        ("batched, linear stages solved directly", t_direct, error(direct.x)),
        ("Mechanism core (declared loop, continuation, linear rate solves)", t_core, error(core_x)),
        ("consecutive Newton, point by point", t_consecutive, error(consecutive.x)),
        ("simultaneous Newton 9x9, point by point", t_simultaneous, error(simultaneous.x)),
        ("scipy.optimize.root loop, point by point", t_scipy, error(scipy_x)),
        (f"sympy subs per iteration (MATLAB style; {SYMBOLIC_INSTANTS} instants timed, scaled to {N})",
         t_symbolic, error(symbolic_x, instants)),
        ("analytic, vectorized", t_analytic, 0.0),
    ]
    print(f"The power saw, {N} instants over 2T = {2 * first_turn_time():.3f} s, "
          f"position + velocity + acceleration (tol {TOL:g})\n")
    print(f"{'solver':<78} {'time (s)':>10} {'/ batched':>10} {'max |x - exact|':>16}")
    for name, seconds, err in rows:
        print(f"{name:<78} {seconds:>10.4f} {seconds / t_batched:>10.1f} {err:>16.1e}")

    print("\nCost against the number of instants (batched Newton; analytic):")
    print(f"{'n':>9} {'batched (s)':>12} {'us / instant':>13} {'analytic (s)':>13} {'us / instant':>13}")
    for n in (10**3, 10**4, 10**5, 10**6):
        repeats = 3 if n <= 10**4 else 1
        t_b, result = best_of(repeats, lambda n=n: saw.sweep(n, method="batched", tol=TOL))
        t_a, _ = best_of(repeats, lambda n=n: saw.sweep(n, method="analytic"))
        assert bool(np.all(result.iterations > 0))
        print(f"{n:>9} {t_b:>12.4f} {t_b / n * 1e6:>13.2f} {t_a:>13.4f} {t_a / n * 1e6:>13.2f}")

    print(f"\nbatched with the linear stages solved directly / analytic: {t_direct / t_analytic:.1f}")
    print(json.dumps({
        "vs_scipy_loop": round(t_scipy / t_batched, 1),
        "vs_symbolic": round(t_symbolic / t_batched, 1),
        "vs_analytic": round(t_batched / t_analytic, 2),
        "vs_analytic_one_step_linear_stages": round(t_direct / t_analytic, 2),
        "core_vs_analytic": round(t_core / t_analytic, 2),
        "core_vs_batched": round(t_core / t_batched, 2),
    }))


if __name__ == "__main__":
    main()
