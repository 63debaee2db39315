"""The ``k`` heaviest of a search's events (:mod:`hypotrack.association.samplers.selection`): hand-computed ties (the
first kept, at the ``k``-th weight too), the same events from any subset holding every event at least as heavy as the
``k``-th, bad ``k`` refused by name; the min-heap of the heaviest is an ascending array of them."""

import numpy as np
import pytest

from hypotrack.association.samplers import heaviest_heap, top_k_first


def test_top_k_first_hand_computed():
    lw = np.array([1.0, 3.0, 3.0, 2.0, 3.0])
    assert top_k_first(lw, 2).tolist() == [1, 2]  # three tied at 3: the first two
    assert top_k_first(lw, 4).tolist() == [1, 2, 4, 3]
    assert top_k_first(lw, 0).tolist() == []
    assert top_k_first(lw, None).tolist() == [1, 2, 4, 3, 0]
    assert top_k_first(lw, 9).tolist() == [1, 2, 4, 3, 0]
    # the same events from any subset holding every event at least as heavy as the k-th
    sub = np.array([1, 2, 3, 4])
    assert sub[top_k_first(lw[sub], 2)].tolist() == top_k_first(lw, 2).tolist()
    with pytest.raises(ValueError, match="k"):
        top_k_first(lw, -1)


def test_heaviest_heap_holds_the_k_heaviest_ascending():
    heap, n = heaviest_heap(np.array([0.5, -1.0, 3.0, 2.0, 3.0]), 3)
    assert n == 3 and heap.tolist() == [2.0, 3.0, 3.0]
    heap, n = heaviest_heap(np.array([0.5, -1.0]), 4)
    assert n == 2 and len(heap) == 4 and heap[:2].tolist() == [-1.0, 0.5]
