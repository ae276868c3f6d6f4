"""bench/peers/gen.py: the peer-benchmark workloads load in softplc and run
as worked out by hand (bench/peers/README.md)."""
import re
import subprocess
import sys

import pytest

from conftest import BINARY, ROOT

sys.path.insert(0, str(ROOT / "bench" / "peers"))
import gen  # noqa: E402


@pytest.fixture(scope="module")
def programs(tmp_path_factory):
    out = tmp_path_factory.mktemp("peers")
    gen.write_all(out)
    return out


def test_instruction_counts():
    # bits: 10,000 rungs of 5; mov: LD SM400 + 20,000 MOV;
    # mix: LDI/OUT M0 + 1,000 groups of 2 + 2 + 2 + 3 + 4.
    assert {n: gen.instructions(n) for n in gen.WORKLOADS} == {"bits": 50_000, "mov": 20_001, "mix": 13_002}


@pytest.mark.parametrize("name", list(gen.WORKLOADS))
def test_il_loads(programs, name):
    done = subprocess.run([BINARY, "check", programs / f"{name}.il"], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr


def test_il_matches_bench_rungs(programs):
    # The first rung of crates/core/benches/scan.rs's contact program (i = 0)
    # and the last MOV (i = 19,999: D(19,999*7 % 12,000) -> D(19,999 % 12,000)).
    bits = (programs / "bits.il").read_text().splitlines()
    assert bits[1:6] == ["LD X0", "AND M0", "OR M0", "ANI X1", "OUT M0"]
    mov = (programs / "mov.il").read_text().splitlines()
    assert mov[-2:] == ["MOV D7993 D7999", "END"]


def show(program, scans, *devices):
    cmd = [BINARY, "run", program, "--scans", str(scans)]
    for d in devices:
        cmd += ["--show", d]
    out = subprocess.run(cmd, capture_output=True, text=True, check=True).stdout
    return dict(re.findall(r"^(\S+) = (\S+)$", out, re.M))


def test_mix_runs_as_worked_out(programs):
    # 150 scans of 10 ms. M0 toggles, ON in odd scans, so C0 counts 75 rising
    # edges; D0 counts scans (150); D1 takes D0 in the last odd scan with
    # D0 > 100: 149. Group 999 compares with 149: D1998 = 150 only in scan 150,
    # when M0 is OFF, so D1999 stays 0. T0 (X0 OFF, coil ON) has measured
    # 149 scans * 10 ms = 1.49 s: TN0 = 14 (100 ms units), contact still OFF,
    # so M1 = X1 OR T0 is OFF.
    v = show(programs / "mix.il", 150, "CN0", "D0", "D1", "D1999", "TN0", "M1")
    assert v == {"CN0": "75", "D0": "150", "D1": "149", "D1999": "0", "TN0": "14", "M1": "false"}
    # By scan 510 T0 has timed out (K50 = 5 s) and M1 follows it; C0 stops at K100.
    v = show(programs / "mix.il", 510, "T0", "M1", "CN0")
    assert v == {"T0": "true", "M1": "true", "CN0": "100"}


def test_peer_programs_have_one_statement_per_melsec_rung(programs):
    st = (programs / "bits.st").read_text()
    assert st.count(":= ((X") == 10_000
    assert "M0 := ((X0 AND M0) OR M0) AND NOT X1;" in st
    assert (programs / "bits_matiec.st").read_text().startswith(st)
    awl = (programs / "mix.awl").read_text()
    labels = re.findall(r"^\s*(J\d{3}): NOP 0$", awl, re.M)
    assert len(labels) == len(set(labels)) == 1000
    assert "\tSE T 999\n" in awl and "\tZV Z 999\n" in awl
