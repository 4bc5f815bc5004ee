"""Index arrays are np.intp, the one integer type numpy indexes with on every platform.

On a 32-bit build (np.intp is int32) ``np.take`` refuses uint32 indices, since uint32 does not cast
safely to int32; on 64-bit it casts them silently, so the mistake only shows elsewhere.  These tests
record the dtype of every index array the PNG quantizer hands to ``np.take`` and pin it to np.intp.
"""

import numpy as np
import pytest

from course_lib import plotting


@pytest.fixture
def take_dtypes(monkeypatch):
    seen, take = [], np.take

    def recording_take(array, indices, *args, **kwargs):
        seen.append(np.asarray(indices).dtype)
        return take(array, indices, *args, **kwargs)

    monkeypatch.setattr(plotting.np, "take", recording_take)
    return seen


def _picture(rows=24, columns=32):
    rng = np.random.default_rng(7)
    picture = np.full((rows, columns, 4), 255, np.uint8)
    picture[..., :3] = rng.integers(0, 256, (rows, columns, 3), dtype=np.uint8)
    return picture


def test_the_quantizer_takes_from_its_table_with_intp_indices(take_dtypes):
    picture = _picture()
    quantizer = plotting._Quantizer(picture)
    png = quantizer.png(picture)
    assert png.startswith(b"\x89PNG")
    assert take_dtypes and all(dtype == np.dtype(np.intp) for dtype in take_dtypes), take_dtypes


def test_intp_indices_give_the_same_picture_as_a_32_bit_platform_would(take_dtypes):
    """What a 32-bit numpy does with the indices: a safe cast to int32 (uint32 would refuse)."""
    picture = _picture(8, 8)
    quantizer = plotting._Quantizer(picture)
    word = plotting._pack(picture, little_endian=True)
    cells = ((word >> 1) & 0x7F) | ((word >> 2) & 0x3F80) | ((word >> 3) & 0x1FC000)
    assert not np.can_cast(cells.dtype, np.int32, "safe")  # the uint32 the packing makes
    assert int(cells.max()) < 1 << 21 and np.can_cast(np.int32, np.intp, "safe")
    first = quantizer.png(picture)
    assert quantizer.png(picture) == first  # the table filled on the first call gives the same PNG
    assert all(dtype == np.dtype(np.intp) for dtype in take_dtypes)
