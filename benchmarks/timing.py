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
