"""An output policy that does not tag an ambiguous correlation: :class:`OutputIdentities`, :func:`output_identities`.

A catalogue operator does not tag a return whose correlation is ambiguous: it becomes an uncorrelated track, to be
resolved later. A multi-hypothesis tracker knows when its MAP is ambiguous — the marginal probability of the MAP's
track of a label (:func:`hypotrack.hypotheses.factored.marginals.map_label_marginals`) — and GNN does not. The
policy maps each filter label to an **output identity**, the label itself until the label's MAP track is
ambiguous: at a scan where the label is in view and its track's marginal is below ``p_min``, the label gets a
fresh output identity from that scan on. Once per ambiguous episode: while the label stays below ``p_min`` scan
after scan it keeps the identity it got; the policy re-arms once the label's marginal has been ``≥ p_min``
(at any scan). The filter is not changed — only the names under which its MAP is reported.

Two modes (:data:`MODES`). ``fresh`` (above): one fresh identity for the whole episode. But the MAP may move the
label between the two neighbours *within* an episode — at a near tie it flips scan after scan, and an episode can
last across the gap between passes (the hypotheses do not change out of view) — and the episode's identity is then
carried across the swap as the plain MAP carries the label. ``withhold`` is the operator's practice: while the
episode lasts the label's returns are not tagged at all (identity :data:`WITHHELD`, an uncorrelated track to be
resolved), and once the label's marginal is back at ``≥ p_min`` the track that comes out is reported under a fresh
identity (one identity switch per object and episode; the withheld returns count as uncorrelated).

When two neighbours' labels swap in the MAP at a near tie (0.51 against 0.47), both labels take fresh identities:
the returns before the swap stay with the old identities, owned by the objects that made them, and the swap is
charged as a lost track (an identity switch, a newborn identity) rather than as a label carried onto another
object (a cross-tag).
"""

from __future__ import annotations

import numpy as np
import pandas as pd

__all__ = ["OUTPUT_ID_BASE", "MODES", "WITHHELD", "OutputIdentities", "output_identities", "relabel"]

#: Fresh output identities count from here: above any filter label (NORAD numbers, newborn labels), so that an output
#: identity is never mistaken for a label.
OUTPUT_ID_BASE = 1 << 40
#: ``fresh``: a fresh identity from the episode's first ambiguous scan on; ``withhold``: no identity (untagged, the
#: scorecard's *uncorrelated*) while the episode lasts, then a fresh one once the label's marginal is ``≥ p_min``.
MODES = ("fresh", "withhold")
#: The identity of a label withheld while ambiguous (as the scorecard's "no label").
WITHHELD = -1


class OutputIdentities:
    """The online policy (module docstring). :meth:`update` takes one scan's MAP labels, their marginals and whether
    each is in view, and returns their output identities."""

    def __init__(self, p_min: float, base: int = OUTPUT_ID_BASE, *, mode: str = "fresh"):
        p_min = float(p_min)
        if not 0.0 <= p_min <= 1.0:
            raise ValueError(f"p_min must be in [0, 1], got {p_min}")
        if mode not in MODES:
            raise ValueError(f"mode must be one of {MODES}, got {mode!r}")
        self.p_min, self._next, self.mode = p_min, int(base), mode
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
                if self.mode == "withhold" and not self._armed.get(a, True):  # resolved: reported as a new track
                    self._fresh(a)
                self._armed[a] = True
            elif v and self._armed.get(a, True):
                if self.mode == "fresh":
                    self._fresh(a)
                self._armed[a] = False
            withheld = self.mode == "withhold" and not self._armed.get(a, True)
            out[j] = WITHHELD if withheld else self._id.get(a, a)
        return out

    def _fresh(self, a: int):
        self._id[a] = self._next
        self._next += 1
        self.n_breaks += 1

    def identity(self, label: int) -> int:
        """The current output identity of ``label`` (:data:`WITHHELD` while withheld)."""
        if self.mode == "withhold" and not self._armed.get(int(label), True):
            return WITHHELD
        return self._id.get(int(label), int(label))


def output_identities(marginals: pd.DataFrame, p_min: float, base: int = OUTPUT_ID_BASE, *,
                      mode: str = "fresh") -> pd.DataFrame:
    """The policy run over a recorded sequence: ``marginals`` holds one row per (scan, MAP label) with ``p`` and
    ``in_view``; returns it with column ``identity`` (scans in increasing order)."""
    pol = OutputIdentities(p_min, base, mode=mode)
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
    moved = table[table["identity"].to_numpy(np.int64) != table["label"].to_numpy(np.int64)]  # the only changes
    key = dict(zip(zip(moved["scan"].to_numpy(np.int64).tolist(), moved["label"].to_numpy(np.int64).tolist()),
                   moved["identity"].to_numpy(np.int64).tolist()))
    out = label.copy()
    for j in np.flatnonzero(np.isin(label, moved["label"].to_numpy(np.int64))):
        out[j] = key.get((int(scan[j]), int(label[j])), int(label[j]))
    return out
