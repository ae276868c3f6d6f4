"""The Ray example (issue 16): examples/scale/ray_suite.py fans the shipped
scenarios out as Ray tasks on a one-node local cluster, and its merged
result equals a plain `softplc test` run of the same files."""
import json
import subprocess
import sys

import pytest

from conftest import BINARY, ROOT

pytest.importorskip("ray")

# The shipped scenarios (the 24 h soak is for release builds).
FILES = sorted(
    str(p.relative_to(ROOT))
    for d in ("examples/sim", "examples/process", "examples/aplc")
    for p in (ROOT / d).glob("*.toml")
)


def comparable(line):
    """A result line without its wall time (the only part that differs)."""
    d = json.loads(line)
    del d["duration_s"]
    return d


def test_ray_suite_equals_a_plain_run(tmp_path):
    assert len(FILES) >= 10
    plain = subprocess.run([BINARY, "test", "--jsonl", *FILES], cwd=ROOT,
                           capture_output=True, text=True, timeout=600)
    plain_text = subprocess.run([BINARY, "test", *FILES], cwd=ROOT,
                                capture_output=True, text=True, timeout=600)
    out = tmp_path / "results.jsonl"
    ray = subprocess.run(
        [sys.executable, str(ROOT / "examples/scale/ray_suite.py"), "--workers", "2",
         "--softplc", BINARY, "--out", str(out), *FILES],
        cwd=ROOT, capture_output=True, text=True, timeout=600,
    )
    assert ray.returncode == plain.returncode == plain_text.returncode, ray.stderr
    # The same lines, whatever shard ran them.
    merged = sorted((comparable(l) for l in out.read_text().splitlines()), key=lambda d: d["file"])
    single = sorted((comparable(l) for l in plain.stdout.splitlines()), key=lambda d: d["file"])
    assert [d["file"] for d in merged] == FILES
    assert merged == single
    # The same totals as the plain text report.
    totals = plain_text.stdout.strip().splitlines()[-1]
    assert totals.endswith(" failed")
    assert ray.stdout.strip().splitlines()[-1] == totals
    assert f"{len(FILES)} scenario files in {len(FILES)} shards on Ray" in ray.stderr
