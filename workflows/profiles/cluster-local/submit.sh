#!/usr/bin/env bash
# Local stand-in for `sbatch`, used by the cluster-generic executor: run the job script as a
# separate background process in a fresh scratch directory that holds only a copy of the workflow
# source (Snakefile, workflows/, theory/, paper/), and print a job id. The job's outputs count only
# if they land in the shared results folder; the scheduler's job-finished markers stay in the
# submitting directory's .snakemake/ (the one thing a cluster shares besides the results).
set -euo pipefail
jobscript="$1"
workdir=$(sed -n 's/^cd \([^ ]*\) && .*/\1/p' "$jobscript")
[ -n "$workdir" ] || { echo "submit.sh: no 'cd <workdir> &&' line in $jobscript" >&2; exit 1; }
scratch=$(mktemp -d "${TMPDIR:-/tmp}/hypotrack-job.XXXXXX")
# -p keeps the modification times, as a shared filesystem would: a script copied with a new mtime
# looks newer than the outputs it made, and Snakemake's code trigger would then rerun finished
# upstream rules inside a downstream job (seen once: paper_pdf re-running paper_generated).
for src in Snakefile workflows theory paper; do
    cp -rp "$workdir/$src" "$scratch/"
done
rm -rf "$scratch/paper/generated"
logs="$workdir/.snakemake/cluster-logs"
mkdir -p "$logs"
# Every path into the workflow moves to the scratch copy; the .snakemake markers do not.
sed -e "s#$workdir/\.snakemake#@MARKERS@#g" -e "s#$workdir#$scratch#g" -e "s#@MARKERS@#$workdir/.snakemake#g" \
    "$jobscript" > "$scratch/job.sh"
name=$(basename "$jobscript" .sh)
# Detach from this script's stdout: the executor reads it to the end to get the job id.
(bash "$scratch/job.sh" > "$logs/$name.log" 2>&1; rm -rf "$scratch") < /dev/null > /dev/null 2>&1 &
echo "$!"
