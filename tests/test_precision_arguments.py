"""``Precision`` refuses nonsense by name: digits a whole number from 1 to 17, decimals a bool, numbers
that are numbers (text never agrees), and a bounded count of numbers to read the typed digits of."""

from __future__ import annotations

import time

import numpy as np
import pytest

from course_lib.checks import DECIMALS, FIGURES, Precision
from course_lib.checks.engine import MOST_TYPED, diagnose
from course_lib.errors import InvalidArgumentError


@pytest.mark.parametrize("digits", [-1, 0, 18, 10**6, True, False, 4.5, 4.0, "4", None, [4], np.float64(4.0)])
def test_digits_that_are_not_a_whole_number_from_1_to_17_are_refused_by_name(digits):
    with pytest.raises(InvalidArgumentError) as caught:
        Precision(digits)
    assert str(caught.value) == f"digits must be a whole number (an int) from 1 to 17; got {digits!r}"


@pytest.mark.parametrize("decimals", ["yes", "False", 1, 0, None, 1.0])
def test_decimals_that_are_not_a_bool_are_refused_by_name(decimals):
    with pytest.raises(InvalidArgumentError, match=r"^decimals must be True .* or False .*; got ") as caught:
        Precision(4, decimals=decimals)
    assert repr(decimals) in str(caught.value)


def test_sane_digits_and_decimals_are_kept_as_plain_int_and_bool():
    precisions = [Precision(1), Precision(17), Precision(np.int64(6), np.bool_(True))]
    assert [(type(p.digits), type(p.decimals)) for p in precisions] == [(int, bool)] * 3
    assert precisions[2] == Precision(6, decimals=True) and str(precisions[2]) == "6 decimals"
    with pytest.raises(InvalidArgumentError, match="scale must be None or one number"):
        Precision(4, scale="big")


@pytest.mark.parametrize("answer", ["1", "1.0", b"1", ["1"], ("1", "2"), True, [True], 1 + 0j, {1.0},
                                    {"x": 1.0}, [1.0, [2.0]]])
def test_only_numbers_agree_never_text(answer):
    reference = (1.0, 2.0) if isinstance(answer, tuple) else [1.0] if isinstance(answer, list) else 1.0
    assert FIGURES.agrees(answer, reference) is False
    assert DECIMALS.agrees(answer, reference) is False
    assert FIGURES.agrees(1.0, 1.0) and FIGURES.agrees(np.float32(1.0), 1.0)
    assert FIGURES.agrees([1.00004], [1])
    assert not diagnose(answer, FIGURES, [(reference, "Correct.")], "no").ok  # a checker never passes it


def test_an_answer_of_another_shape_does_not_agree():
    assert not FIGURES.agrees([0.5975, 1.0, 2.0, 3.0], (0.59746, None, 2.0))  # the old code said True
    assert FIGURES.agrees([0.5975, 9.0, 2.0], (0.59746, None, 2.0))


@pytest.mark.parametrize(("call", "shown"), [
    (lambda: FIGURES.typed("abc"), "value must be a number or numbers; got 'abc'"),
    (lambda: FIGURES.typed(None), "value must be a number or numbers; got None"),
    (lambda: FIGURES.typed(["0.5", 1.0]), "value must be a number or numbers; got ['0.5', 1.0]"),
    (lambda: FIGURES.of_size([]), "vector must hold at least one number (its size counts the digits); "
                                  "got []"),
    (lambda: FIGURES.of_size("ab"), "vector must be a number or numbers; got 'ab'"),
    (lambda: FIGURES.of_size(None), "vector must be a number or numbers; got None"),
    (lambda: FIGURES.unit("a"), "reference must be a number or numbers; got 'a'"),
    (lambda: FIGURES.agrees(1.0, "1"), "reference must be a number or numbers; got '1'"),
    (lambda: FIGURES.agrees(1.0, 1.0, angles="yes"), "angles must be True/False, or one True/False per "
                                                     "entry; got 'yes'"),
    (lambda: FIGURES.agrees([1.0, 2.0], [1.0, 2.0], angles=[True, False, True]), "angles must be one "
                                                                                  "True/False, or one per"),
    (lambda: FIGURES.agrees(1.0, 1.0, digits="3"), "digits must be a whole number (an int) from -17 to 17; "
                                                   "got '3'"),
    (lambda: FIGURES.more_digits("0.6", 0.59746), "value must be a number or numbers; got '0.6'"),
])
def test_wrong_arguments_to_the_methods_are_refused_by_name_with_their_value(call, shown):
    with pytest.raises(InvalidArgumentError) as caught:
        call()
    assert str(caught.value).startswith(shown), str(caught.value)


def test_typed_refuses_a_million_numbers_by_name_quickly():
    start = time.perf_counter()
    numbers = np.linspace(0.0, 1.0, 10**6)
    for million in (numbers, numbers.tolist(), numbers.reshape(1000, 1000)):
        with pytest.raises(InvalidArgumentError) as caught:
            FIGURES.typed(million)
        assert str(caught.value).startswith(f"value must hold at most {MOST_TYPED} numbers to count their "
                                            "digits; got 1000000")
    assert time.perf_counter() - start < 3
    assert MOST_TYPED == 10_000
    assert FIGURES.typed(np.full(MOST_TYPED, 0.25)) == 2  # as many as allowed: read
    with pytest.raises(InvalidArgumentError, match="got 10001"):
        FIGURES.typed(np.full(MOST_TYPED + 1, 0.25))
