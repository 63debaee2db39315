"""The hypothesis-level recursion: H-FISST, R-FISST and HOMHT as one engine.

Document 000 (Sec. II) and document 001 show that FISST and Reid's HOMHT are the same recursion on a
discrete hypothesis space and differ only in how a child hypothesis is weighted; R-FISST makes
the recursion tractable by searching children with MCMC instead of enumerating them. The engine
(:class:`HypothesisFilter`) therefore has two plug-in points:

* a **weight model** — :class:`HFISSTWeights`, :class:`FISSTPoissonWeights`, :class:`ReidWeights`,
  :class:`GLMBWeights`;
* a **child generator** — :class:`ExhaustiveGenerator`, :class:`MurtyGenerator`,
  :class:`MCMCGenerator`, :class:`GibbsGenerator`;

(plus the population model: :class:`SingleEventPopulation`, :class:`BinomialPopulation`,
:class:`LabeledMultiBernoulliPopulation`), and the trackers are presets: :func:`hfisst`,
:func:`rfisst`, :func:`homht`, :func:`homht_kbest`, and the δ-GLMB filter :func:`glmb`,
:func:`glmb_murty`; the PMBM and PMB filters (:mod:`.pmbm`: :func:`pmbm_murty`, :func:`pmbm_gibbs`,
:func:`pmb_lbp`) reuse the association problem and the generators with a state of their own.

The engine's state is a :class:`FilterState` apart from its configuration:
:meth:`HypothesisFilter.advance` maps a state and a scan to the next (:mod:`.state`).

:class:`FactoredFilter` (:mod:`.factored`, options :class:`FactoredOptions`) runs the same engine on a posterior kept as a product
of independent groups of objects (merged when a return falls in two groups' gates, split when
their objects no longer interact), so that cost grows with the largest group, not the scene.
"""

from .association_problem import CLUTTER, SEEDED_BIRTH, AssociationProblem
from .factored import FactoredFilter, FactoredOptions, FactoredPosterior, cardinality_total_variation
from .filter import HypothesisFilter
from .generators import ChildGenerator, ExhaustiveGenerator, MCMCGenerator, MurtyGenerator
from .gibbs import GibbsGenerator
from .hypothesis import ChildSet, Hypothesis
from .population_events import BinomialPopulation, SingleEventPopulation
from .population_lmb import GaussianBirthTerm, LabeledMultiBernoulliPopulation, UnconfirmedDecay
from .pmbm import GlobalHypothesis, PMBMFilter, PMBMPosterior
from .pmbm_poisson import PoissonIntensity
from .posterior import HypothesisEstimate, Posterior
from .presets import fisst_kbest, glmb, glmb_murty, hfisst, homht, homht_kbest, pmb_lbp, pmbm_gibbs, pmbm_murty, rfisst
from .scan_context import ScanContext
from .state import FilterState, StepResult
from .tracks import TrackStore
from .weights import FISSTPoissonWeights, HFISSTWeights, ReidWeights, WeightModel, make_weight_model
from .weights_glmb import GLMBWeights

__all__ = [
    "AssociationProblem",
    "CLUTTER",
    "SEEDED_BIRTH",
    "HypothesisFilter",
    "FilterState",
    "StepResult",
    "FactoredFilter",
    "FactoredOptions",
    "FactoredPosterior",
    "cardinality_total_variation",
    "ChildGenerator",
    "ExhaustiveGenerator",
    "MurtyGenerator",
    "MCMCGenerator",
    "GibbsGenerator",
    "ChildSet",
    "Hypothesis",
    "SingleEventPopulation",
    "BinomialPopulation",
    "LabeledMultiBernoulliPopulation",
    "UnconfirmedDecay",
    "GaussianBirthTerm",
    "HypothesisEstimate",
    "Posterior",
    "ScanContext",
    "TrackStore",
    "WeightModel",
    "HFISSTWeights",
    "FISSTPoissonWeights",
    "ReidWeights",
    "GLMBWeights",
    "make_weight_model",
    "hfisst",
    "rfisst",
    "homht",
    "homht_kbest",
    "fisst_kbest",
    "glmb",
    "glmb_murty",
    "PMBMFilter",
    "PMBMPosterior",
    "GlobalHypothesis",
    "PoissonIntensity",
    "pmbm_murty",
    "pmbm_gibbs",
    "pmb_lbp",
]
