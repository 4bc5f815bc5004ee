"""The one timing rule of every benchmark: the smallest wall time of a few calls, in this process."""

import time


def best_of(repeats, function, *args):
    """Smallest wall time (s) of ``repeats`` calls ``function(*args)``, and the last result."""
    best, result = float("inf"), None
    for _ in range(repeats):
        start = time.perf_counter()
        result = function(*args)
        best = min(best, time.perf_counter() - start)
    return best, result


def best_of_each(repeats, *functions):
    """The same rule for several functions called in turn, ``repeats`` rounds: a slow spell of the
    machine falls on all of them alike, so ratios of their times stay fair.  Returns the smallest
    wall time (s) of each, in order."""
    best = [float("inf")] * len(functions)
    for _ in range(repeats):
        for k, function in enumerate(functions):
            start = time.perf_counter()
            function()
            best[k] = min(best[k], time.perf_counter() - start)
    return best
