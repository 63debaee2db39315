"""Compile the report: paper/ sources, generated inputs and build directory under results (hypotrack.reporting.paper)."""

from hypotrack.reporting.paper import build_pdf

overfull = build_pdf("paper", snakemake.params.inputs, snakemake.params.build, snakemake.output[0],
                     snakemake.log[0])
print(f"paper: {snakemake.output[0]} ({len(overfull)} overfull boxes, none over 1 pt)")
