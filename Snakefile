# hypotrack: regenerate every figure and table of the reproduced papers.
#
#   snakemake -c2                                              # paper fidelity (default.yaml)
#   snakemake -c2 --configfile workflows/config/quick.yaml     # every rule at toy size
#   snakemake -c2 <experiment>                                 # one experiment, e.g. generation_time
#
# Each experiment lives in workflows/rules/<experiment>.smk, defines a rule named after the
# experiment that collects its final outputs, and appends those outputs to ALL_TARGETS.
import glob

from hypotrack.config import validate_config


configfile: "workflows/config/default.yaml"


validate_config(config, "workflows/config/schema")

RESULTS = config["results"]
ALL_TARGETS = []


for _rules in sorted(glob.glob("workflows/rules/*.smk")):

    include: _rules


rule all:
    default_target: True
    input:
        ALL_TARGETS,
