"""bench/jitter/run.py end to end, briefly: one 10 ms run idle and one under
the protocol clients' load, its Markdown table and its JSON figures."""
import json
import subprocess
import sys

from conftest import BINARY, ROOT


def test_jitter_bench_runs_end_to_end(tmp_path):
    out = tmp_path / "jitter.json"
    r = subprocess.run(
        [sys.executable, str(ROOT / "bench" / "jitter" / "run.py"), "--softplc", BINARY,
         "--seconds", "3", "--warmup", "0.5", "--periods", "10ms", "--loads", "idle,clients",
         "--variants", "normal", "--json", str(out)],
        capture_output=True, text=True, timeout=240)
    assert r.returncode == 0, r.stderr
    lines = r.stdout.strip().splitlines()
    assert lines[0].startswith("| period | load | variant (got) | scans | overruns | lateness p50")
    rows = [line for line in lines[2:] if line.startswith("| 10ms |")]
    assert len(rows) == 2, r.stdout
    assert "| idle | normal (normal, spin 200) |" in rows[0], rows[0]
    results = json.loads(out.read_text())
    assert [(x["load"], x["variant"], x["options"]) for x in results] == [
        ("idle", "normal", "--no-realtime"), ("clients", "normal", "--no-realtime")]
    for x in results:
        t = x["timing"]
        assert t["period_us"] == 10_000
        # 3 s at 10 ms: at most 301 scans (none starts early); a loaded
        # machine may skip some, never most.
        assert 75 <= t["count"] <= 302, t
        late = t["lateness_us"]
        assert late["p50"] <= late["p99"] <= late["p999"] <= late["max"], late
        assert t["realtime"]["sched_fifo"] is False
        assert x["errors"] == [], x["errors"]
    # Under load every client made progress (the server answered them all).
    rates = results[1]["load_rates"]
    assert set(rates) == {"MC", "Modbus", "SSE events", "OPC UA notifications"}, rates
    assert all(v > 0 for v in rates.values()), rates
