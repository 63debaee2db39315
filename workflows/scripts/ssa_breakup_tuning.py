"""ssa_breakup: the ambiguity output's tuning table (every tuning seed x p_min with the rule's score, and the choice)
from the tuning runs (experiments/ssa_breakup/tuning.py)."""
import pandas as pd

from hypotrack.experiments.ssa_breakup.summary import merged_sweeps
from hypotrack.experiments.ssa_breakup.tuning import chosen_p_min, tuning_table
from hypotrack.reporting.joblog import prefix_output
from hypotrack.scenarios.tables import write_table

prefix_output(snakemake)  # noqa: F821 (every line this job prints names the job)

cfg = snakemake.params.cfg  # noqa: F821 (injected by Snakemake)
amb = cfg["ambiguity"]
cards = pd.concat([pd.read_csv(p) for p in snakemake.input.cards], ignore_index=True)  # noqa: F821
sweep = merged_sweeps([pd.read_csv(p) for p in snakemake.input.sweeps])  # noqa: F821
table = tuning_table(sweep, cards, amb.get("mode", "fresh"), amb["tuning"]["untagged_weight"],
                     cfg["reference_tracker"])
print(f"p_min chosen on tuning seeds {amb['tuning']['seeds']}: {chosen_p_min(table):g}")
write_table(table, snakemake.output.table)  # noqa: F821
