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
