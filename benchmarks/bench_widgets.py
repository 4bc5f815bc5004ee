"""Time per event of the explorers: compute + redraw + PNG, Agg backend, one process.

Each explorer gets 200 events of its main input (θ2 for the four-bar, t for the saw, θ1 forward and
X3 inverse for the five-bar), moved as a user drags the slider, and 40 events of each other control a
student changes (the four-bar's lengths and branch, the five-bar's mode and assembly toggles), each
followed by one main-input event, as a student changes a control and then moves the slider again.
Printed: a table of medians, then the last line a JSON object:

- ``median_update_ms``: the worst explorer's median over its main-input events (goal ≤ 50 ms);
  ``median_update_cpu_ms`` the same in process CPU time, which a busy machine inflates less;
- ``median_change_ms``: the worst explorer's median over its length, branch and mode changes
  (goal < 30 ms; ``median_change_cpu_ms`` the same in CPU time), and ``change_vs_update``, the worst
  explorer's ratio of its median change to its median main-input event, both in CPU time (goal ≤ 2);
  ``worst_control_vs_update`` the same ratio for the single costliest control.
"""

from __future__ import annotations

import json
import statistics
import time

import matplotlib

matplotlib.use("Agg")

from course_lib.widgets import fivebar_explorer, fourbar_explorer, saw_explorer  # noqa: E402

EVENTS = 200
CHANGE_EVENTS = 40


def timed(explorer, states) -> tuple[list[float], list[float]]:
    """Wall-clock and process-CPU milliseconds per event, each state set on the widgets as a user would."""
    wall, cpu = [], []
    for state in states:
        start, start_cpu = time.perf_counter(), time.process_time()
        for key, value in state.items():
            explorer.controls[key].value = value
        wall.append(1e3 * (time.perf_counter() - start))
        cpu.append(1e3 * (time.process_time() - start_cpu))
    return wall, cpu


def changes(explorer, key: str, values, main_key: str, main_values) -> tuple[list[float], list[float]]:
    """Wall and CPU milliseconds of ``CHANGE_EVENTS`` changes of ``key`` (cycling ``values``), each
    followed by one (untimed) main-input event, so every change starts from a slider-moved state."""
    wall, cpu = [], []
    for k in range(CHANGE_EVENTS):
        one_wall, one_cpu = timed(explorer, [{key: values[k % len(values)]}])
        wall += one_wall
        cpu += one_cpu
        timed(explorer, [{main_key: main_values[k % len(main_values)]}])
    return wall, cpu


def main() -> None:
    rows = []  # (explorer, main input, main wall, main cpu, {change name: (wall times, cpu times)})

    fourbar = fourbar_explorer()
    theta2 = [-180.0 + (k * 7) % 360 for k in range(EVENTS)]
    wall, cpu = timed(fourbar, [{"theta2_deg": value} for value in theta2])
    couplers, cranks = [0.16 + 0.001 * k for k in range(40)], [0.05 + 0.001 * k for k in range(20)]
    fourbar_changes = {
        "coupler length": changes(fourbar, "coupler", couplers, "theta2_deg", theta2),
        "crank length": changes(fourbar, "crank", cranks, "theta2_deg", theta2),
        "branch": changes(fourbar, "branch", ["crossed", "open"], "theta2_deg", theta2),
    }
    rows.append(("four-bar", "θ2 slider", wall, cpu, fourbar_changes))

    saw = saw_explorer()
    step = saw.controls["t"].step
    wall, cpu = timed(saw, [{"t": step * (k % 121)} for k in range(EVENTS)])
    rows.append(("power saw", "time slider", wall, cpu, {}))

    robot = fivebar_explorer()
    theta1 = [40.0 + (k % 60) for k in range(EVENTS)]
    wall, cpu = timed(robot, [{"theta1_deg": value} for value in theta1])
    forward_changes = {"σ toggle": changes(robot, "sigma", [-1, 1], "theta1_deg", theta1)}
    rows.append(("five-bar forward", "θ1 slider", wall, cpu, forward_changes))

    robot.update(mode="inverse", x3=0.0, y3=0.18)
    x3 = [-0.06 + 0.005 * (k % 25) for k in range(EVENTS)]
    wall, cpu = timed(robot, [{"x3": value} for value in x3])
    inverse_changes = {
        "mode toggle": changes(robot, "mode", ["forward", "inverse"], "x3", x3),
        "σ1 toggle": changes(robot, "sigma1", [-1, 1], "x3", x3),
        "σ2 toggle": changes(robot, "sigma2", [-1, 1], "x3", x3),
    }
    rows.append(("five-bar inverse", "X3 slider", wall, cpu, inverse_changes))

    print(f"{'explorer':18s} {'main input':12s} {'median ms':>9s} {'p90 ms':>7s} {'CPU ms':>7s}   "
          f"{'control change':16s} {'median ms':>9s} {'CPU ms':>7s}")
    for name, main_name, wall, cpu, changed in rows:
        p90 = statistics.quantiles(wall, n=10)[-1]
        print(f"{name:18s} {main_name:12s} {statistics.median(wall):9.1f} {p90:7.1f} "
              f"{statistics.median(cpu):7.1f}   "
              + ("\n" + " " * 62).join(f"{change:16s} {statistics.median(times):9.1f} "
                                       f"{statistics.median(cpu_times):7.1f}"
                                       for change, (times, cpu_times) in changed.items()))
    medians = {name: round(statistics.median(wall), 2) for name, _, wall, _, _ in rows}
    cpu = {name: round(statistics.median(cpu), 2) for name, _, _, cpu, _ in rows}
    # per explorer (the five-bar's two rows are one explorer): its main events and its changes, pooled
    main_cpu: dict[str, list[float]] = {}
    pooled: dict[str, list[float]] = {}
    pooled_cpu: dict[str, list[float]] = {}
    for name, _, _, cpu_times, changed in rows:
        explorer = name.split()[0]
        main_cpu.setdefault(explorer, []).extend(cpu_times)
        for times, change_cpu_times in changed.values():
            pooled.setdefault(explorer, []).extend(times)
            pooled_cpu.setdefault(explorer, []).extend(change_cpu_times)
    change = {name: round(statistics.median(times), 2) for name, times in pooled.items()}
    change_cpu = {name: round(statistics.median(times), 2) for name, times in pooled_cpu.items()}
    ratio = {name: round(statistics.median(pooled_cpu[name]) / statistics.median(main_cpu[name]), 2)
             for name in pooled_cpu}
    per_control = {f"{name.split()[0]}: {control}":
                   round(statistics.median(cpu_times) / statistics.median(main_cpu[name.split()[0]]), 2)
                   for name, _, _, _, changed in rows for control, (_, cpu_times) in changed.items()}
    print(json.dumps({
        "median_update_ms": max(medians.values()),
        "median_update_cpu_ms": max(cpu.values()),
        "median_change_ms": max(change.values()),
        "median_change_cpu_ms": max(change_cpu.values()),
        "change_vs_update": max(ratio.values()),
        "median_update_ms_by_explorer": medians,
        "median_change_ms_by_explorer": change,
        "change_vs_update_by_explorer": ratio,
        "worst_control_vs_update": max(per_control.values()),
        "control_vs_update": per_control,
        "events_per_explorer": EVENTS,
        "changes_per_control": CHANGE_EVENTS,
    }, ensure_ascii=False))


if __name__ == "__main__":
    main()
