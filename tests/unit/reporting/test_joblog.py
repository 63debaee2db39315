"""Job-prefixed output of pipeline scripts and the one-line claims account."""

import io
import sys
from types import SimpleNamespace

import pandas as pd

from hypotrack.reporting import joblog


class _Wildcards(dict):
    pass


def _job(rule, **wildcards):
    return SimpleNamespace(rule=rule, wildcards=_Wildcards(wildcards))


def test_tag_names_rule_and_wildcards():
    assert joblog.job_tag(_job("closely_spaced_shard", shard="3")) == "[closely_spaced_shard shard=3]"
    assert joblog.job_tag(_job("sht_lecture")) == "[sht_lecture]"


def test_every_line_is_prefixed_even_when_written_in_pieces(monkeypatch):
    out, err = io.StringIO(), io.StringIO()
    monkeypatch.setattr(sys, "stdout", out)
    monkeypatch.setattr(sys, "stderr", err)
    joblog.prefix_output(_job("swaps_shard", shard="0"))
    joblog.prefix_output(_job("swaps_shard", shard="0"))  # a second call does not prefix twice
    print("run 1 done\nrun 2 done")
    sys.stdout.write("partial ")
    sys.stdout.write("line\n")
    print("warning", file=sys.stderr)
    assert out.getvalue() == ("[swaps_shard shard=0] run 1 done\n[swaps_shard shard=0] run 2 done\n"
                              "[swaps_shard shard=0] partial line\n")
    assert err.getvalue() == "[swaps_shard shard=0] warning\n"


def test_claims_line_counts_statuses():
    claims = pd.DataFrame({"status": ["reproduced", "not reproduced", "reproduced"], "item": ["a", "b", "c"]})
    assert joblog.claims_line(claims, "r/x/claims.csv") == "3 claims: 1 not reproduced, 2 reproduced -> r/x/claims.csv"
    assert joblog.claims_line(claims.iloc[:0]) == "0 claims: none"


def test_progress_log_prints_and_keeps_each_line(tmp_path, capsys):
    path = tmp_path / "job.log"
    path.write_text("stale\n")
    with joblog.progress_log(path) as progress:
        progress("scan 1/2")
        progress("scan 2/2")
    assert path.read_text() == "scan 1/2\nscan 2/2\n"  # truncated first: a rerun's log is its own
    assert capsys.readouterr().out == "scan 1/2\nscan 2/2\n"
