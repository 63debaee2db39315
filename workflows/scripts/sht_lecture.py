"""Lecture 004 worked example: validation matrix, every association hypothesis, counts, clusters."""
import numpy as np
import pandas as pd

from hypotrack.scenarios.tables import write_table
from hypotrack.experiments.sht.run import lecture_hypotheses, lecture_summary
from hypotrack.reporting.joblog import prefix_output

prefix_output(snakemake)  # every line this job prints names the job

valid = np.asarray(snakemake.params.cfg["lecture_validation"], dtype=bool)  # noqa: F821 (injected by Snakemake)
m, n = valid.shape
table = pd.DataFrame(valid.astype(int), columns=[f"T{j + 1}" for j in range(n)])
table.insert(0, "return", [f"y{i + 1}" for i in range(m)])
write_table(table, snakemake.output.validation)  # noqa: F821
write_table(lecture_hypotheses(valid), snakemake.output.hypotheses)  # noqa: F821
summary, clusters = lecture_summary(valid)
write_table(summary, snakemake.output.summary)  # noqa: F821
write_table(clusters, snakemake.output.clusters)  # noqa: F821
print(summary.to_string(index=False), flush=True)
