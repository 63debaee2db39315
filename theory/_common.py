"""Shared plumbing for the theory notebooks: checks, the findings JSON, figure paths, perturbations.

Every notebook builds a :class:`Findings`, records each claim with :meth:`Findings.check`
(which raises ``AssertionError`` on a false claim, so the script exits non-zero and the
pipeline stops), and finally calls :meth:`Findings.write`.

Output directory: the environment variable ``HYPOTRACK_THEORY_OUT`` or the command-line
argument ``--out DIR``; otherwise ``results/theory`` (relative to the working directory).

Perturbation: the formulas a notebook takes from a paper are wrapped in :func:`formula`.
``HYPOTRACK_THEORY_PERTURB="name1,name2"`` makes each named formula return a slightly wrong
value (Python int counts +1, everything else times 1 + 1/1000). The tests use it to show that the
notebooks' checks really fail when an identity is broken. Naming a formula that the
notebook does not define raises ``KeyError`` when :meth:`Findings.write` runs, so a typo
cannot pass for a detected perturbation.
"""

from __future__ import annotations

import functools
import json
import math
import os
import sys
from dataclasses import asdict
from fractions import Fraction
from numbers import Integral
from pathlib import Path

import sympy as sp

from hypotrack.reporting.ledger import Claim
from hypotrack.reporting.verdict import with_control

OUT_ENV = "HYPOTRACK_THEORY_OUT"
PERTURB_ENV = "HYPOTRACK_THEORY_PERTURB"
DEFAULT_OUT = Path("results") / "theory"

_DEFINED_FORMULAS: set[str] = set()


def requested_perturbations() -> set[str]:
    """Names of the formulas that ``HYPOTRACK_THEORY_PERTURB`` asks to break."""
    raw = os.environ.get(PERTURB_ENV, "")
    return {name.strip() for name in raw.split(",") if name.strip()}


def formula(func):
    """Mark ``func`` as a formula taken from a paper; break it if a perturbation names it.

    The perturbation is small on purpose (an integer count off by one, a real value off by
    0.1 %) so that a check that still passes under it is exposed as insensitive.
    """
    _DEFINED_FORMULAS.add(func.__name__)
    if func.__name__ not in requested_perturbations():
        return func

    @functools.wraps(func)
    def perturbed(*args, **kwargs):
        value = func(*args, **kwargs)
        if isinstance(value, int) and not isinstance(value, bool):  # an exact count
            return value + 1
        return value * (1 + sp.Rational(1, 1000))

    return perturbed


def output_dir(argv: list[str] | None = None) -> Path:
    """Directory that receives the findings JSON and the figures (created if missing)."""
    argv = sys.argv[1:] if argv is None else argv
    if "--out" in argv:
        i = argv.index("--out")
        if i + 1 >= len(argv):
            raise ValueError("--out needs a directory argument")
        path = Path(argv[i + 1])
    else:
        path = Path(os.environ.get(OUT_ENV, DEFAULT_OUT))
    path.mkdir(parents=True, exist_ok=True)
    return path


def _jsonable(value):
    """Exact numbers stay exact: big ints and rationals become strings, floats stay floats."""
    if isinstance(value, bool) or value is None or isinstance(value, str):
        return value
    if isinstance(value, Integral):
        # JSON readers other than Python's lose digits beyond 2**53.
        return int(value) if abs(int(value)) < 2**53 else str(int(value))
    if isinstance(value, Fraction):
        return str(value)
    if isinstance(value, sp.Basic):
        if value.is_Integer:
            return _jsonable(int(value))
        if value.is_Rational:
            return str(value)
        if value.is_number and value.is_real:
            return float(value)
        return str(value)
    if isinstance(value, float):
        return value if math.isfinite(value) else str(value)
    if isinstance(value, dict):
        return {str(k): _jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_jsonable(v) for v in value]
    if hasattr(value, "tolist"):  # numpy scalars and arrays
        return _jsonable(value.tolist())
    return str(value)


class Findings:
    """The checks and values one notebook establishes, written as ``<name>.json``.

    Parameters
    ----------
    name : str
        Notebook name; the JSON is ``<out>/<name>.json`` and figures ``<out>/<name>_*.{png,pdf}``.
    source : str
        The paper and equations the notebook checks, copied into the JSON.
    """

    def __init__(self, name: str, source: str):
        self.name = name
        self.source = source
        self.out = output_dir()
        self.checks: list[dict] = []
        self.claims: list[dict] = []
        self.values: dict = {}

    def check(self, label: str, ok: bool, **details) -> None:
        """Record the claim ``label``; raise ``AssertionError`` (exit non-zero) if it is false."""
        ok = bool(ok)
        self.checks.append({"check": label, "passed": ok, **_jsonable(details)})
        print(f"[{'PASS' if ok else 'FAIL'}] {label}" + (f"  {details}" if details and not ok else ""))
        if not ok:
            raise AssertionError(f"check failed: {label}: {details}")

    def claim(self, item: str, source: str, published, reproduced, status: str, *, key: str = "",
              evidence: str = "independent oracle", tolerance: str = "exact", note: str = "",
              control: tuple | None = None, cause: str = "") -> None:
        """A row of the reproduction ledger (:mod:`hypotrack.reporting.ledger`): a published statement and
        what this notebook found. ``status`` is one of :data:`hypotrack.reporting.ledger.STATUSES`; ``key``
        names the row's paper macros stably; ``evidence`` defaults to the symbolic computation here
        (an oracle that shares no code with the engine).

        ``control = (what, value, passes)``: the same check run on a formula with a known defect (a
        negative control, :func:`hypotrack.reporting.verdict.with_control`); a *reproduced* or
        *qualitative* row whose control also passes is written as *uninformative*. ``cause`` (a key of
        :data:`hypotrack.reporting.ledger.CAUSES`) says why a *not reproduced* row failed."""
        row = Claim("theory", item, source, str(published), str(reproduced), tolerance, status, note, evidence,
                    key=key, cause=cause if status == "not reproduced" else "")
        if control is not None:
            what, value, passes = control
            row = with_control(row, what, str(value), bool(passes))
        self.claims.append(asdict(row))
        print(f"[claim: {status}] {item}: published {published}, found {reproduced}")

    def record(self, key: str, value) -> None:
        """Store a finding (a number, a table as a list of rows, an expression as text)."""
        self.values[key] = _jsonable(value)

    def figure(self, fig, stem: str, width: float = 1.0) -> list[Path]:
        """Save ``fig`` as PDF (paper) and PNG (report); return both paths.

        The figure is first held to the report's legibility rules at ``width`` × the line width
        (:func:`hypotrack.reporting.figure_style.legibility_problems`: no text under 7 pt, no clipped
        title, no legend over data, series told apart): ``ValueError`` lists what fails, nothing is written.
        """
        from hypotrack.reporting import figure_style

        figure_style.enlarge_scripts(fig, width)
        problems = figure_style.legibility_problems(fig, width)
        if problems:
            raise ValueError(f"figure {self.name}_{stem} is not legible at width {width} × \\linewidth: "
                             + "; ".join(problems))
        paths = [self.out / f"{self.name}_{stem}.{ext}" for ext in ("pdf", "png")]
        for path in paths:
            fig.savefig(path, dpi=150, bbox_inches="tight")
        self.values.setdefault("figures", []).extend(p.name for p in paths)
        return paths

    def write(self) -> Path:
        """Write the findings JSON after confirming every requested perturbation was applied."""
        unknown = requested_perturbations() - _DEFINED_FORMULAS
        if unknown:
            raise KeyError(f"{PERTURB_ENV} names formulas this notebook does not define: {sorted(unknown)}")
        path = self.out / f"{self.name}.json"
        doc = {
            "notebook": self.name,
            "source": self.source,
            "n_checks": len(self.checks),
            "all_passed": all(c["passed"] for c in self.checks),
            "checks": self.checks,
            "claims": self.claims,
            "values": self.values,
        }
        path.write_text(json.dumps(doc, indent=1, sort_keys=False) + "\n")
        print(f"{len(self.checks)} checks passed; findings written to {path}")
        return path


_DUMMY = sp.Symbol("_t", real=True)


@functools.lru_cache(maxsize=None)
def _integrate_factor(factor, lower, upper):
    return sp.integrate(factor, (_DUMMY, lower, upper))


def integrate_sum_of_products(expr, variables, lower=-sp.oo, upper=sp.oo) -> sp.Expr:
    """Exact integral of ``expr`` over ``[lower, upper]`` in each of ``variables``.

    ``expr`` must expand into a sum of terms each of which is a product of one-variable
    factors (the form of every multi-target likelihood and RFS density here). Fubini then
    makes each term's integral the product of one-dimensional integrals, which Sympy does
    exactly and which are cached (with the variable renamed, so ``N(x1)`` and ``N(x2)`` share
    one integral): a direct multiple ``sympy.integrate`` of the same sum is correct but some
    twenty times slower.
    """
    total = sp.Integer(0)
    # Distributing products over sums only (not expanding the exponents) keeps each Gaussian
    # a single factor, which both speeds Sympy up and lets the cache hit.
    for term in sp.Add.make_args(sp.expand_mul(expr)):
        value = term
        for var in variables:
            const, factor = value.as_independent(var, as_Add=False)
            value = const * _integrate_factor(factor.subs(var, _DUMMY), lower, upper)
        total += value
    return sp.expand(total)


def association_events(n_objects: int, n_returns: int):
    """Brute-force enumeration of the association events of document 000 Eq. 4.

    Each return goes to one of the objects or to clutter (``-1``), and no object receives two
    returns. Independent of any closed form: every map returns -> objects ∪ {clutter} is
    generated and the infeasible ones are discarded.

    Yields
    ------
    tuple of int
        ``event[i]`` is the object of return ``i`` or ``-1`` for clutter.
    """
    from itertools import product

    for event in product(range(-1, n_objects), repeat=n_returns):
        used = [j for j in event if j >= 0]
        if len(used) == len(set(used)):
            yield event
