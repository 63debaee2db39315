"""Readable output of pipeline jobs: every line a job prints carries the job's name.

Snakemake runs several jobs at once and interleaves their output on one terminal; a line such as
``run 3/25 done`` is useless without knowing whose it is. A script calls
:func:`prefix_output` first thing::

    from hypotrack.reporting.joblog import prefix_output
    prefix_output(snakemake)

and from then on every line written to stdout or stderr by the script, by the library's progress
callbacks and by warnings reads ``[closely_spaced_shard shard=3] ...``.
:func:`claims_line` gives the one-line account of a claims table that a job prints instead of the
table itself (the ledger holds the table). :func:`progress_log` gives a long job's progress callback
that prints each line and keeps it in the job's log file.
"""

from __future__ import annotations

import contextlib
import io
import sys

__all__ = ["job_tag", "prefix_output", "claims_line", "progress_log"]


@contextlib.contextmanager
def progress_log(path):
    """A progress callback ``progress(line)`` that prints ``line`` (so it carries the job's prefix)
    and appends it to the log file ``path`` (opened, truncated, for the ``with`` block)."""
    with open(path, "w") as log:

        def progress(line):
            print(line, flush=True)
            print(line, file=log, flush=True)

        yield progress


def job_tag(smk) -> str:
    """``[rule wildcard=value ...]`` for a Snakemake job object."""
    wildcards = " ".join(f"{k}={v}" for k, v in dict(smk.wildcards.items()).items())
    return f"[{smk.rule}{' ' + wildcards if wildcards else ''}]"


class _PrefixedStream(io.TextIOBase):
    """A text stream that writes ``prefix`` at the start of every line to ``stream``."""

    def __init__(self, stream, prefix: str):
        self._stream = stream
        self._prefix = prefix
        self._line_start = True

    def write(self, text: str) -> int:
        pieces = []
        for piece in text.splitlines(keepends=True):
            if self._line_start:
                pieces.append(self._prefix)
            pieces.append(piece)
            self._line_start = piece.endswith(("\n", "\r"))
        self._stream.write("".join(pieces))
        return len(text)

    def flush(self):
        self._stream.flush()

    def isatty(self) -> bool:
        return self._stream.isatty()

    def fileno(self) -> int:
        return self._stream.fileno()

    @property
    def encoding(self):
        return getattr(self._stream, "encoding", "utf-8")


def prefix_output(smk) -> str:
    """Prefix every later line of this process's stdout and stderr with the job's tag; returns the tag."""
    tag = job_tag(smk)
    if not isinstance(sys.stdout, _PrefixedStream):
        sys.stdout = _PrefixedStream(sys.stdout, tag + " ")
        sys.stderr = _PrefixedStream(sys.stderr, tag + " ")
    return tag


def claims_line(claims, path=None) -> str:
    """``7 claims: 5 reproduced, 2 not reproduced -> results/x/claims.csv`` from a claims table."""
    column = next((c for c in ("status", "verdict") if c in claims), None)
    counts = claims[column].value_counts() if column else {}
    parts = ", ".join(f"{n} {status}" for status, n in sorted(dict(counts).items()))
    return f"{len(claims)} claims: {parts or 'none'}" + (f" -> {path}" if path else "")
