"""R-FISST's generator asked for the filter's cap (``keep``): the filter's hypotheses are bit for bit those of a
generator that searches without ``keep`` (every event held and returned) and keeps the cap's heaviest afterwards.

Six objects (one out of view, one dying), Eq. 59's binomial births in two halves of the view and deaths, H-FISST
weights, clutter, eight scans of seeded returns with misses; a cap of 4 hypotheses, so that every parent's search
finds far more children than are kept (checked) and the completion's last round is cut. The search's chain draws
the same numbers on both sides, so any difference is the ``keep``'s."""

import numpy as np

from hypotrack.association.samplers import top_k_first
from hypotrack.hypotheses import BinomialPopulation, HFISSTWeights, HypothesisFilter, MCMCGenerator
from hypotrack.models import ConstantVelocity
from hypotrack.models.population import UniformBirthDensity
from hypotrack.models.sensors import Box
from scenes import position_sensor

VIEW = Box([-50.0, -50.0], [50.0, 50.0])
HALVES = [Box([-50.0, -50.0], [0.0, 50.0]), Box([0.0, -50.0], [50.0, 50.0])]
MOTION = ConstantVelocity(0.05)
X0 = np.array([[0.0, 0.0, 1.0, 0.0], [3.0, 1.0, 0.0, 1.0], [2.0, -2.0, 0.5, 0.5], [-20.0, 10.0, 0.0, -1.0],
               [60.0, 0.0, 0.0, 0.0], [-1.0, 2.0, 0.8, -0.3]])  # object 4 out of view (x = 60)
P0 = np.repeat(np.diag([1.0, 1.0, 0.2, 0.2])[None], len(X0), axis=0)


class SearchAllThenCap(MCMCGenerator):
    """The reference: the search without ``keep`` (every event), then the ``keep`` heaviest (first found on ties)."""

    found: list

    def generate(self, problem, rng=None, keep=None):
        events, lw = super().generate(problem, rng, keep=None)
        self.found.append((len(lw), keep))
        sel = top_k_first(lw, keep)
        return events[sel], lw[sel]


def _scans(n_scans=8, seed=4):
    """Returns near objects 0-3 (object 5 stops returning: it dies) with misses, plus two clutter returns."""
    rng = np.random.default_rng(seed)
    x = X0.copy()
    F = MOTION.F(1.0)
    scans = []
    for _ in range(n_scans):
        x = x @ F.T
        near = [x[j, :2] + rng.normal(scale=0.7, size=2) for j in range(4) if rng.random() < 0.85]
        clutter = rng.uniform(-50.0, 50.0, size=(2, 2))
        scans.append(np.vstack(near + [clutter]))
    return scans


def _filter(generator):
    pop = BinomialPopulation([UniformBirthDensity(h, np.eye(2) * 4.0) for h in HALVES], alpha=0.2, p_survive=0.97)
    return HypothesisFilter(MOTION, position_sensor(0.5, 0.9, VIEW, 2.0), HFISSTWeights(), generator, population=pop,
                            max_hypotheses=4, means=X0, covs=P0, seed=3)


def test_the_generators_keep_gives_the_search_all_then_cap_filter_bit_for_bit():
    kw = dict(n_steps=300, completion_rounds=2, completion_threshold=1e-6)
    ref_gen = SearchAllThenCap(**kw)
    object.__setattr__(ref_gen, "found", [])
    new, ref = _filter(MCMCGenerator(**kw)), _filter(ref_gen)
    sizes = set()
    for Z in _scans():
        new.step(Z)
        ref.step(Z)
        assert new.state.same_as(ref.state)
        assert np.array_equal(new.state.log_w, ref.state.log_w)
        sizes |= {len(t) for t in new.state.tracks}
    found = np.array([n for n, _ in ref_gen.found])
    assert all(k == 4 for _, k in ref_gen.found)  # the filter asked for its cap
    assert (found > 4).all() and np.median(found) > 20  # the search found far more than were kept (24-85)
    assert new.state.next_label > len(X0) and min(sizes) < len(X0) < max(sizes)  # births and deaths were kept
