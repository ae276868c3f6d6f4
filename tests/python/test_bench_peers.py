"""bench/peers/gen.py: the peer-benchmark workloads load in softplc and run
as worked out by hand (bench/peers/README.md)."""
import re
import shutil
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
    # mix: LDI/OUT M0 + 1,000 groups of 2 + 2 + 2 + 3 + 4;
    # chain: LD SM400 / + D0 K1 D0 + 20,000 MOV;
    # tcc: LDI/OUT M0, LD SM400 / + D0 K1 D0 + 1,000 groups of 2 + 2 + 2.
    assert {n: gen.instructions(n) for n in gen.WORKLOADS} == {
        "bits": 50_000,
        "mov": 20_001,
        "mix": 13_002,
        "chain": 20_002,
        "tcc": 6_004,
    }


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


def test_chain_is_one_dependent_ring(programs):
    # Each MOV reads the word the one before it wrote: D0 -> D1 -> ... ->
    # D9999 -> D0 -> ... twice round, the increment of D0 first.
    lines = (programs / "chain.il").read_text().splitlines()
    assert lines[1:5] == ["LD SM400", "+ D0 K1 D0", "MOV D0 D1", "MOV D1 D2"]
    movs = lines[3:-1]
    assert len(movs) == 20_000 and movs[9_999] == "MOV D9999 D0" and movs[-1] == "MOV D9999 D0"
    for before, after in zip(movs, movs[1:]):
        assert after.split()[1] == before.split()[2]


def test_chain_runs_as_worked_out(programs):
    # Every scan D0 counts up and the ring carries it to every word, back to
    # D0 itself: after n scans D0 = D1 = ... = D9999 = n, D10000 untouched.
    v = show(programs / "chain.il", 3, "D0", "D1", "D5000", "D9999", "D10000")
    assert v == {"D0": "3", "D1": "3", "D5000": "3", "D9999": "3", "D10000": "0"}


def test_tcc_runs_as_worked_out(programs):
    # Scans of 10 ms; X0-X999 OFF keep every timer coil ON from scan 1, so
    # at OUT T of scan s a timer has measured (s - 1) * 10 ms: TN = 9 in
    # scan 100, and K10 (1 s) reached in scan 101. M0 is ON in odd scans:
    # 50 rising edges in 100 scans. M(k+1) = D0 > k with D0 = s.
    v = show(programs / "tcc.il", 100, "D0", "TN0", "T0", "TN999", "CN0", "M100", "M101")
    assert v == {"D0": "100", "TN0": "9", "T0": "false", "TN999": "9", "CN0": "50", "M100": "true", "M101": "false"}
    v = show(programs / "tcc.il", 101, "TN0", "T0", "T999", "CN999")
    assert v == {"TN0": "10", "T0": "true", "T999": "true", "CN999": "51"}
    # By scan 300 C0 has counted 100 edges (its K100) and stays there;
    # the timer holds its set value.
    v = show(programs / "tcc.il", 300, "TN0", "CN0", "C0", "M300", "M301")
    assert v == {"TN0": "10", "CN0": "100", "C0": "true", "M300": "true", "M301": "false"}


@pytest.mark.parametrize("name", sorted(gen.CHECKS))
def test_checked_values_are_softplcs(programs, name):
    # measure.py's "values" column holds every peer to these.
    v = show(programs / f"{name}.il", gen.CHECK_CYCLES, *gen.CHECKS[name])
    bits = {"true": 1, "false": 0}
    assert {d: bits[x] if x in bits else int(x) for d, x in v.items()} == gen.CHECKS[name]


@pytest.mark.parametrize("name", sorted(gen.CHECKS))
def test_plain_c_computes_the_checked_values(programs, tmp_path, name):
    # The plain-C peer is the same logic: it holds the checked values, and a
    # timer and a counter agree with softplc's at the boundary scan of tcc
    # (TN0 = 10, CN0 = 51). Compiled without optimisation: gcc -O2 takes
    # minutes on these 5,000-20,000-statement functions (measure.py's own
    # check covers its -O2 build).
    cc = shutil.which("gcc")
    if cc is None:
        pytest.skip("no gcc")
    binary = tmp_path / name
    subprocess.run([cc, "-O0", "-o", binary, programs / f"{name}.c"], check=True)
    out = subprocess.run([binary, str(gen.CHECK_CYCLES), *gen.CHECKS[name]], capture_output=True, text=True,
                         check=True).stdout
    assert {d: int(x) for d, x in re.findall(r"^(\S+) = (-?\d+)$", out, re.M)} == gen.CHECKS[name]
    if name == "tcc":
        out = subprocess.run([binary, "101", "TN0", "T0", "CN0"], capture_output=True, text=True, check=True).stdout
        assert out.splitlines()[1:] == ["TN0 = 10", "T0 = 1", "CN0 = 51"]


def test_peer_translations_of_the_new_rungs(programs):
    tcc_st = (programs / "tcc.st").read_text()
    assert "  T999(IN := NOT X999, PT := T#1S);" in tcc_st
    assert "  C999(CU := M0, PV := 100);" in tcc_st
    assert "  M1000 := D0 > 999;" in tcc_st
    tcc_awl = (programs / "tcc.awl").read_text()
    # M1000 is M 125.0; the compare is L / L / >I / =.
    assert "\tL DBW 0\n\tL 999\n\t>I\n\t= M 125.0\n" in tcc_awl
    assert "\tL S5T#1S\n\tSE T 999\n" in tcc_awl
    chain_st = (programs / "chain.st").read_text()
    assert chain_st.count("  D0 := D9999;") == 2 and "  D1 := D0;" in chain_st
    chain_c = (programs / "chain.c").read_text()
    assert chain_c.count("    d[0] = d[9999];") == 2
