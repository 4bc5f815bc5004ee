"""What the checker tests share: a message must not give the reference value away.

>>> from course_lib.checks import Feedback
>>> hides(Feedback(False, "Not yet: about 0.25 m"), 0.2500001), hides(Feedback(False, "Not yet"), 0.25)
(False, True)
"""

import numpy as np


def hides(feedback, *values) -> bool:
    """True when no rounding (2–8 significant digits) of any value appears in the message."""
    for value in np.ravel(values):
        for digits in range(2, 9):
            for text in (f"{value:.{digits}g}", f"{value:.{digits}f}", f"{abs(value):.{digits}g}"):
                if len(text.strip("-0.")) >= 2 and text in feedback.message:
                    return False
    return True


def course_newton_count():
    """(root, last iterate, updates) of x³ − 2x − 5 = 0 from x0 = 2 by the course's rule, written out: update
    until a step is shorter than 1e-6; the root by bracketing (scipy's brentq), an independent route."""
    import scipy.optimize

    root = scipy.optimize.brentq(lambda v: v**3 - 2 * v - 5, 2.0, 3.0, xtol=1e-15)
    value, count = 2.0, 0
    while True:
        step = -(value**3 - 2 * value - 5) / (3 * value**2 - 2)
        value, count = value + step, count + 1
        if abs(step) < 1e-6:
            return root, value, count
