"""The README's library example runs and prints what it says (so the README stays true)."""

import contextlib
import io
import re
from pathlib import Path

README = Path(__file__).resolve().parents[2] / "README.md"


def test_readme_example_runs_and_tracks_both_targets():
    code = re.search(r"```python\n(.*?)```", README.read_text(), re.S).group(1)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(code, str(README), "exec"), {})
    lines = out.getvalue().splitlines()
    assert lines[0] == "63591"
    assert lines[1].startswith("2.0 ")  # expected number of objects after five scans
    nums = [float(x) for x in re.findall(r"-?\d+\.\d", " ".join(lines[1:])[4:])]
    # two tracks near the truths (-15, 0) and (15, 0) after five scans, within a few sigma of R = I
    assert abs(nums[0] + 15) < 3 and abs(nums[2] - 15) < 3


def test_readme_quick_start_matches_ci():
    text = README.read_text()
    ci = (README.parent / ".ci" / "run").read_text()
    test_cmd = re.findall(r"```bash\n(python -m pip install -r envs/requirements-test.txt[^\n]*)\n```", text)
    assert len(test_cmd) == 1 and test_cmd[0] in ci
    assert "python -m pip install -r envs/requirements.txt -e . && snakemake -c2\n" in text
