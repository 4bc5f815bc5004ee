"""Time per slider event of the explorers: compute + redraw + PNG, Agg backend, one process.

Each explorer gets 200 events of its main input (θ2 for the four-bar, t for the saw, θ1 forward and
X3 inverse for the five-bar), moved as a user drags the slider, plus 50 events of a geometry input
(a length, the branch or the working mode), which re-render the whole figure.  Printed: a table of
medians, then the last line a JSON object; "median_update_ms" is the worst explorer's median over its
200 main-input events (the goal is ≤ 50 ms); "median_update_cpu_ms" the same in process CPU time,
which a busy machine inflates less.
"""

from __future__ import annotations

import json
import statistics
import time

import matplotlib

matplotlib.use("Agg")

from course_lib.widgets import fivebar_explorer, fourbar_explorer, saw_explorer  # noqa: E402

EVENTS = 200
GEOMETRY_EVENTS = 50


CPU = {}  # id(list of wall times) → list of CPU times of the same events


def timed(explorer, states) -> list[float]:
    """Wall-clock milliseconds per event (each state set on the widgets as a slider would);
    the process CPU milliseconds of the same events are kept in ``CPU`` (robust on a busy machine)."""
    times, cpu = [], []
    for state in states:
        start, start_cpu = time.perf_counter(), time.process_time()
        for key, value in state.items():
            explorer.controls[key].value = value
        times.append(1e3 * (time.perf_counter() - start))
        cpu.append(1e3 * (time.process_time() - start_cpu))
    CPU[id(times)] = cpu
    return times


def main() -> None:
    rows = []
    fourbar = fourbar_explorer()
    main_fourbar = timed(fourbar, [{"theta2_deg": -180.0 + (k * 7) % 360} for k in range(EVENTS)])
    geometry_fourbar = timed(fourbar, [{"coupler": 0.16 + 0.001 * (k % 40)} for k in range(GEOMETRY_EVENTS)])
    rows.append(("four-bar", "θ2 slider", main_fourbar, "coupler length", geometry_fourbar))

    saw = saw_explorer()
    step = saw.controls["t"].step
    main_saw = timed(saw, [{"t": step * (k % 121)} for k in range(EVENTS)])
    play_saw = timed(saw, [{"t": step * ((k + 3) % 121)} for k in range(GEOMETRY_EVENTS)])
    rows.append(("power saw", "time slider", main_saw, "(no geometry input)", play_saw))

    robot = fivebar_explorer()
    main_forward = timed(robot, [{"theta1_deg": 40.0 + (k % 60)} for k in range(EVENTS)])
    geometry_robot = timed(robot, [{"mode": ("inverse", "forward")[k % 2]} for k in range(GEOMETRY_EVENTS)])
    robot.update(mode="inverse", x3=0.0, y3=0.18)
    main_inverse = timed(robot, [{"x3": -0.06 + 0.005 * (k % 25)} for k in range(EVENTS)])
    rows.append(("five-bar forward", "θ1 slider", main_forward, "mode toggle", geometry_robot))
    rows.append(("five-bar inverse", "X3 slider", main_inverse, "mode toggle", geometry_robot))

    print(f"{'explorer':18s} {'main input':12s} {'median ms':>9s} {'p90 ms':>7s} {'CPU ms':>7s}   "
          f"{'geometry input':20s} {'median ms':>9s}")
    for name, main_name, main_times, geometry_name, geometry_times in rows:
        p90 = statistics.quantiles(main_times, n=10)[-1]
        cpu = statistics.median(CPU[id(main_times)])
        print(f"{name:18s} {main_name:12s} {statistics.median(main_times):9.1f} {p90:7.1f} {cpu:7.1f}   "
              f"{geometry_name:20s} {statistics.median(geometry_times):9.1f}")
    medians = {name: round(statistics.median(times), 2) for name, _, times, _, _ in rows}
    geometry = {name: round(statistics.median(times), 2) for name, _, _, _, times in rows}
    cpu = {name: round(statistics.median(CPU[id(times)]), 2) for name, _, times, _, _ in rows}
    print(json.dumps({
        "median_update_ms": max(medians.values()),
        "median_update_cpu_ms": max(cpu.values()),
        "median_update_ms_by_explorer": medians,
        "median_geometry_update_ms_by_explorer": geometry,
        "events_per_explorer": EVENTS,
    }))


if __name__ == "__main__":
    main()
