"""`softplc test --junit`: the report is read by junitparser (a JUnit XML
parser from the Python registry, as CI systems read it) and counts what the
text report counts — passes, failed assertions, a scenario that does not load
and one whose CPU stops — also for shards merged with `--merge`."""
import re
import shlex
import shutil
import subprocess

import junitparser
import pytest
import yaml

from conftest import BINARY, ROOT

EXAMPLE = ROOT / "examples" / "sim" / "conveyor.toml"


def softplc(*args, cwd=None):
    return subprocess.run(
        [BINARY, *map(str, args)], capture_output=True, text=True, timeout=300, cwd=cwd
    )


def text_counts(stdout):
    m = re.search(r"^(\d+) passed, (\d+) failed$", stdout, re.M)
    assert m, stdout
    return int(m.group(1)), int(m.group(2))


@pytest.fixture
def suite(tmp_path):
    """The shipped conveyor scenario, a copy with one wrong expectation, one
    that does not load and one whose CPU stops with an operation error."""
    shutil.copy(EXAMPLE.with_name("conveyor.il"), tmp_path / "conveyor.il")
    good = tmp_path / "good.toml"
    shutil.copy(EXAMPLE, good)
    wrong = tmp_path / "wrong.toml"
    wrong.write_text(
        EXAMPLE.read_text()
        + '\n[[expect]]\nat = "4s"\ndevice = "D20"\nequals = 99\n'
    )
    broken = tmp_path / "broken.toml"
    broken.write_text('name = "broken"\nprogram = "missing.il"\nduration = "1s"\n')
    (tmp_path / "stops.il").write_text("LD SM400\nMOV K1000 Z0\nMOV K1 D12000Z0\nEND\n")
    stops = tmp_path / "stops.toml"
    stops.write_text(
        'name = "stops"\nprogram = "stops.il"\nscan_time = "10ms"\nduration = "1s"\n'
        '[[expect]]\nat = "0.5s"\ndevice = "D0"\nequals = 0\n'
    )
    return [good, wrong, broken, stops]


def check_report(xml_file, stdout):
    passed, failed = text_counts(stdout)
    xml = junitparser.JUnitXml.fromfile(str(xml_file))
    suites = {s.name: s for s in xml}
    cases = [c for s in xml for c in s]
    failures = [c for c in cases if any(isinstance(r, junitparser.Failure) for r in c.result)]
    errors = [c for c in cases if any(isinstance(r, junitparser.Error) for r in c.result)]
    assert len(cases) == passed + failed
    assert len(failures) + len(errors) == failed
    assert sum(s.tests for s in xml) == passed + failed
    assert sum(s.failures for s in xml) == len(failures)
    assert sum(s.errors for s in xml) == len(errors)
    return suites, failures, errors


def test_a_run_and_merged_shards_write_reports_that_count_as_the_text(suite, tmp_path):
    report = tmp_path / "report.xml"
    r = softplc("test", "--junit", report, *suite, cwd=tmp_path)
    assert r.returncode == 1, r.stderr
    suites, failures, errors = check_report(report, r.stdout)
    assert set(suites) == {str(f) for f in suite}
    good = suites[str(suite[0])]
    assert good.tests > 0 and good.failures == 0 and good.errors == 0
    # The wrong expectation: its message gives the expected and the actual value.
    (msg,) = [res.message for c in suites[str(suite[1])] for res in c.result]
    assert msg.startswith("expected D20 = 99 at 4 s: got 100"), msg
    # The file that does not load and the CPU that stops are errors.
    assert suites[str(suite[2])].errors == 1
    assert suites[str(suite[3])].errors == 1
    assert any("error 4101 OPERATION ERROR" in res.message for c in errors for res in c.result)

    # Two shards, merged: the same counts in one report.
    jsonl = []
    for i in range(2):
        out = tmp_path / f"shard{i}.jsonl"
        s = softplc("test", "--jsonl", "--shard", f"{i}/2", *suite, cwd=tmp_path)
        out.write_text(s.stdout)
        jsonl.append(out)
    merged = tmp_path / "merged.xml"
    m = softplc("test", "--merge", *jsonl, "--junit", merged, cwd=tmp_path)
    assert m.returncode == 1, m.stderr
    check_report(merged, m.stdout)
    assert text_counts(m.stdout) == text_counts(r.stdout)


def test_a_report_that_cannot_be_written_is_an_error(suite, tmp_path):
    r = softplc("test", "--junit", tmp_path / "no" / "dir" / "r.xml", suite[0], cwd=tmp_path)
    assert r.returncode == 2
    assert "cannot write" in r.stderr and "r.xml" in r.stderr


def test_the_ci_example_runs_its_suite_and_writes_its_report(tmp_path):
    """examples/ci/scenarios.yml is a GitHub Actions workflow; its `softplc
    test` line runs here as the runner would run it (from the checkout)."""
    workflow = yaml.safe_load((ROOT / "examples" / "ci" / "scenarios.yml").read_text())
    steps = workflow["jobs"]["scenarios"]["steps"]
    (line,) = [s["run"] for s in steps if "softplc test" in s.get("run", "")]
    args = shlex.split(line)
    assert args[0] == "target/release/softplc" and args[1] == "test"
    report = tmp_path / "scenarios.xml"
    files = []
    for a in args[2:]:
        if a == "scenarios.xml":
            files.append(str(report))
        elif "*" in a:
            files.extend(sorted(str(p) for p in ROOT.glob(a)))
        else:
            files.append(a)
    r = subprocess.run([BINARY, "test", *files], capture_output=True, text=True, timeout=600, cwd=ROOT)
    assert r.returncode == 0, r.stdout + r.stderr
    check_report(report, r.stdout)
    xml = junitparser.JUnitXml.fromfile(str(report))
    assert len(list(xml)) == len([a for a in files if a.endswith(".toml")])
