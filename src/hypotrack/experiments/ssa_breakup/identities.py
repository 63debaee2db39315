"""An output policy that does not tag an ambiguous correlation: :class:`OutputIdentities`, :func:`output_identities`.

A catalogue operator does not tag a return whose correlation is ambiguous: it becomes an uncorrelated track, to be
resolved later. A multi-hypothesis tracker knows when its MAP is ambiguous — the marginal probability of the MAP's
track of a label (:func:`hypotrack.hypotheses.factored.marginals.map_label_marginals`) — and GNN does not. The
policy maps each filter label to an **output identity**, the label itself until the label's MAP track is
ambiguous: at a scan where the label is in view and its track's marginal is below ``p_min``, the label gets a
fresh output identity from that scan on. Once per ambiguous episode: while the label stays below ``p_min`` scan
after scan it keeps the identity it got; the policy re-arms once the label's marginal has been ``≥ p_min``
(at any scan). The filter is not changed — only the names under which its MAP is reported.

When two neighbours' labels swap in the MAP at a near tie (0.51 against 0.47), both labels take fresh identities:
the returns before the swap stay with the old identities, owned by the objects that made them, and the swap is
charged as a lost track (an identity switch, a newborn identity) rather than as a label carried onto another
object (a cross-tag).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["OUTPUT_ID_BASE", "OutputIdentities", "output_identities", "relabel"]

#: Fresh output identities count from here: above any filter label (NORAD numbers, newborn labels), so that an output
#: identity is never mistaken for a label.
OUTPUT_ID_BASE = 1 << 40


class OutputIdentities:
    """The online policy (module docstring). :meth:`update` takes one scan's MAP labels, their marginals and whether
    each is in view, and returns their output identities."""

    def __init__(self, p_min: float, base: int = OUTPUT_ID_BASE):
        p_min = float(p_min)
        if not 0.0 <= p_min <= 1.0:
            raise ValueError(f"p_min must be in [0, 1], got {p_min}")
        self.p_min, self._next = p_min, int(base)
        self._id: dict = {}       # label -> its output identity (absent: the label itself)
        self._armed: dict = {}    # label -> False while in an ambiguous episode
        self.n_breaks = 0

    def update(self, labels, p, in_view) -> np.ndarray:
        """The output identities of ``labels`` (int, distinct) at this scan, given each one's MAP marginal ``p`` and
        ``in_view`` (bool)."""
        labels = np.asarray(labels, dtype=np.int64)
        p, in_view = np.asarray(p, dtype=float), np.asarray(in_view, dtype=bool)
        if not (labels.shape == p.shape == in_view.shape) or labels.ndim != 1:
            raise ValueError(f"labels, p and in_view must be 1-D of one length, got {labels.shape}, {p.shape}, "
                             f"{in_view.shape}")
        if np.any(~np.isfinite(p)) or np.any((p < 0) | (p > 1)):
            raise ValueError("p must hold probabilities in [0, 1]")
        if len(np.unique(labels)) != len(labels):
            raise ValueError("labels must be distinct within a scan")
        out = np.empty(len(labels), dtype=np.int64)
        for j, (a, q, v) in enumerate(zip(labels.tolist(), p.tolist(), in_view.tolist())):
            if q >= self.p_min:
                self._armed[a] = True
            elif v and self._armed.get(a, True):
                self._id[a], self._armed[a] = self._next, False
                self._next += 1
                self.n_breaks += 1
            out[j] = self._id.get(a, a)
        return out

    def identity(self, label: int) -> int:
        """The current output identity of ``label``."""
        return self._id.get(int(label), int(label))


def output_identities(marginals: pd.DataFrame, p_min: float, base: int = OUTPUT_ID_BASE) -> pd.DataFrame:
    """The policy run over a recorded sequence: ``marginals`` holds one row per (scan, MAP label) with ``p`` and
    ``in_view``; returns it with column ``identity`` (scans in increasing order)."""
    pol = OutputIdentities(p_min, base)
    m = marginals.sort_values(["scan"], kind="stable")
    ident = np.empty(len(m), dtype=np.int64)
    scans = m["scan"].to_numpy(np.int64)
    cuts = np.flatnonzero(np.diff(scans)) + 1
    for a, b in zip(np.r_[0, cuts], np.r_[cuts, len(m)]):
        if b > a:
            ident[a:b] = pol.update(m["label"].to_numpy()[a:b], m["p"].to_numpy()[a:b], m["in_view"].to_numpy()[a:b])
    return m.assign(identity=ident)


def relabel(scan, label, table: pd.DataFrame) -> np.ndarray:
    """Each ``(scan, label)`` (label −1: none) as its output identity in ``table`` (:func:`output_identities`); a
    label the table does not hold at that scan keeps its value."""
    scan, label = np.asarray(scan, dtype=np.int64), np.asarray(label, dtype=np.int64)
    key = dict(zip(zip(table["scan"].to_numpy(np.int64).tolist(), table["label"].to_numpy(np.int64).tolist()),
                   table["identity"].to_numpy(np.int64).tolist()))
    return np.array([key.get((s, a), a) if a >= 0 else a for s, a in zip(scan.tolist(), label.tolist())],
                    dtype=np.int64)
