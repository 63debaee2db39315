# hypotrack: regenerate every figure and table of the reproduced papers.
#
#   snakemake -c2                                              # paper fidelity (default.yaml)
#   snakemake -c2 --configfile workflows/config/quick.yaml     # every rule at toy size
#   snakemake -c2 <experiment>                                 # one experiment, e.g. generation_time
#   snakemake --report results/report.html                     # browse the results with captions
#
# Each experiment lives in workflows/rules/<experiment>.smk, defines a rule named after the
# experiment that collects its final outputs, and appends those outputs to ALL_TARGETS.
# Figures and main tables are marked for the report with report_figure / report_table below
# (captions in workflows/report/<experiment>/, see workflows/report/README.md).
import glob
import os
from pathlib import Path

# One BLAS thread per job (a job may set its own): the jobs already fill the cores Snakemake is given, and on a
# busy machine OpenBLAS's extra threads only spin (a (10^6, 3) @ (3, 3) product measured at ~250 ms of CPU with
# the default threads against ~3 ms with one). Set before any import that loads NumPy; the jobs inherit it.
for _blas in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_blas, "1")

from hypotrack.config import validate_config
from hypotrack.registry import TrackerSpec


configfile: "workflows/config/default.yaml"


validate_config(config, "workflows/config/schema", tracker_specs=TrackerSpec.from_config)

RESULTS = config["results"]
ALL_TARGETS = []


report: "workflows/report/workflow.rst"


def report_figure(path, experiment, caption, kind="Figures"):
    """Mark an output for `snakemake --report`, captioned by workflows/report/<experiment>/<caption>.rst
    and shown under the experiment's category. Only for rules in workflows/rules/ or workflows/report/
    (the caption path is resolved relative to the including rule file)."""
    return report(path, caption=f"../report/{experiment}/{caption}.rst", category=experiment, subcategory=kind)


def report_table(path, experiment, caption):
    """A main table (CSV, a download link in the report) with its caption; see report_figure."""
    return report_figure(path, experiment, caption, kind="Tables")


for _rules in sorted(glob.glob("workflows/rules/*.smk")):

    include: _rules


include: "workflows/report/ledger.smk"


# Every job writes a Snakemake benchmark (wall, CPU, peak memory) to {RESULTS}/benchmarks/<rule>/, one
# file per wildcard combination; at the end of a run they become {RESULTS}/paper/pipeline_timing.csv
# (hypotrack.reporting.pipeline_time), the run-time record the README quotes.
# HYPOTRACK_GROUP_JOBS=experiment (the test suite's local cluster run): each experiment's connected jobs form one
# group job, i.e. one cluster job instead of one per rule, saving each job's Snakemake start-up (~2.5 s of CPU). Not for
# a real cluster: an experiment's shards would then share one node.
_GROUP_JOBS = os.environ.get("HYPOTRACK_GROUP_JOBS", "")
if _GROUP_JOBS not in ("", "experiment"):
    raise ValueError(f"HYPOTRACK_GROUP_JOBS must be 'experiment' or unset, got {_GROUP_JOBS!r}")
for _rule in workflow.rules:
    if _GROUP_JOBS == "experiment":
        _rule.group = Path(_rule.snakefile).stem
    if _rule.output and _rule.benchmark is None:
        _wc = sorted(_rule.wildcard_names)
        _rule.benchmark_modifier = workflow.modifier.path_modifier  # what a `benchmark:` directive sets
        _rule.benchmark = f"{RESULTS}/benchmarks/{_rule.name}/" + ("_".join(f"{{{w}}}" for w in _wc) or "job") + ".tsv"


rule all:
    default_target: True
    input:
        ALL_TARGETS,


def _run_summary():
    """The end of a successful run in a few lines: the ledger's verdicts and where to read the results."""
    import pandas as pd

    from hypotrack.reporting.joblog import claims_line

    ledger, pdf = Path(rules.paper_generated.output.ledger), Path(rules.paper_pdf.output[0])
    lines = [f"hypotrack: done; results in {RESULTS}"]
    if ledger.exists():
        lines.append("  ledger: " + claims_line(pd.read_csv(ledger, dtype=str, keep_default_na=False), ledger))
    lines.append(f"  report PDF: {pdf}" if pdf.exists() else "  report PDF: not built yet (rule paper_pdf, needs latexmk)")
    lines.append(f"  browse figures with captions: snakemake --report {RESULTS}/report.html (same --configfile/--config)")
    print("\n".join(lines))


_RUN_STARTED = []


onstart:
    import time

    _RUN_STARTED.append(time.time())


onsuccess:
    import time

    from hypotrack.reporting.pipeline_time import write_run_record

    from snakemake.exceptions import WorkflowError

    try:
        _cores = workflow.cores
    except WorkflowError:  # an executor run (cluster profile) sets a number of jobs, not of cores
        _cores = None
    if _RUN_STARTED:
        _record = write_run_record(RESULTS, _RUN_STARTED[0], time.time(), _cores)
        if _record:
            print(f"hypotrack: run time per rule -> {_record}")
    _run_summary()
