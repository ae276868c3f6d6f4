#!/usr/bin/env python3
"""Writes the peer-benchmark workloads in each peer's language.

Five workloads, each defined once as a list of rungs and emitted as
  NAME.il          MELSEC instruction list for softplc,
  NAME.awl         S7 AWL (German mnemonics) for awlsim,
  NAME.st          IEC 61131-3 ST PROGRAM for IronPLC (freewheeling),
  NAME_matiec.st   the same PROGRAM with the CONFIGURATION OpenPLC adds, for matiec,
  NAME.c           the same logic as plain C (bool and int16_t arrays), for gcc.

The unit every peer is divided by is one MELSEC instruction of NAME.il (END
not counted): `instructions(NAME)` below. A peer that needs several of its own
instructions for one MELSEC instruction (AWL's L/T for MOV) still counts one.

  bits  10,000 rungs LD X / AND M / OR M / ANI X / OUT M: 50,000 instructions
        (the contact benchmark of crates/core/benches/scan.rs).
  mov   LD SM400 and 20,000 MOVs, half constant to word, half word to word:
        20,001 instructions (the MOV benchmark of crates/core/benches/scan.rs).
  mix   1,000 groups of a 100 ms timer, a counter, an add, a compare with a
        conditional MOV and a contact rung on the timer, after a toggling
        M0: 13,002 instructions.
  chain LD SM400 / + D0 K1 D0, then 20,000 MOVs each reading the word the
        one before it wrote, round a ring of D0-D9999 twice: 20,002
        instructions.
  tcc   a toggling M0 and a scan count in D0, then 1,000 groups of a 100 ms
        timer LDI X / OUT T K10, a counter LD M0 / OUT C K100 and a compare
        LD> D0 K / OUT M: 6,004 instructions.

CHECKS holds, per workload, the devices every peer reports after
CHECK_CYCLES cycles and their values worked out by hand.

Usage: gen.py OUTDIR   (writes the 25 files; prints their names)
"""
import pathlib
import sys

# Rung kinds (one tuple per rung; the MELSEC text is the reference):
#   ("bits", a, b, c, d, o)     LD X a / AND M b / OR M c / ANI X d / OUT M o
#   ("on",)                     LD SM400 (the always-ON contact)
#   ("movk", k, d) / ("movd", s, d)   MOV K k D d / MOV D s D d (on the open rung)
#   ("toggle", m)               LDI M m / OUT M m
#   ("timer", x, t, k)          LDI X x / OUT T t K k          (100 ms timer)
#   ("counter", m, c, k)        LD M m / OUT C c K k
#   ("inc", d)                  LD SM400 / + D d K1 D d
#   ("cmpmov", d, k, m, e)      LD> D d K k / AND M m / MOV D d D e
#   ("timerbits", a, t, c, o)   LD X a / OR T t / ANI X c / OUT M o
#   ("cmpout", d, k, m)         LD> D d K k / OUT M m


def bits():
    return [
        ("bits", i % 4096, (i * 7) % 8000, (i * 13) % 8000, (i % 4096 + 1) % 4096, i % 8000)
        for i in range(10_000)
    ]


def mov():
    rungs = [("on",)]
    for i in range(20_000):
        if i % 2 == 0:
            rungs.append(("movk", i % 30000, i % 12000))
        else:
            rungs.append(("movd", (i * 7) % 12000, i % 12000))
    return rungs


def mix():
    rungs = [("toggle", 0)]
    for k in range(1000):
        rungs += [
            ("timer", k, k, 50),
            ("counter", 0, k, 100),
            ("inc", 2 * k),
            ("cmpmov", 2 * k, 100 + k % 50, 0, 2 * k + 1),
            ("timerbits", k + 1, k, k + 2, k + 1),
        ]
    return rungs


# The chain's ring: 20,000 MOVs round D0-D9999 twice, MOV D9999 D0 closing it.
CHAIN_WORDS = 10_000


def chain():
    rungs = [("inc", 0)]
    for i in range(20_000):
        rungs.append(("movd", i % CHAIN_WORDS, (i + 1) % CHAIN_WORDS))
    return rungs


def tcc():
    # X is OFF in every peer (no I/O), so LDI X keeps each timer's coil ON:
    # the timers time rather than sit reset.
    rungs = [("toggle", 0), ("inc", 0)]
    for k in range(1000):
        rungs += [
            ("timer", k, k, 10),
            ("counter", 0, k, 100),
            ("cmpout", 0, k, k + 1),
        ]
    return rungs


WORKLOADS = {"bits": bits, "mov": mov, "mix": mix, "chain": chain, "tcc": tcc}

# The values every peer must hold after CHECK_CYCLES cycles, in MELSEC names
# (D word, M bit as 0/1, CN counter value), worked out by hand in
# tests/python/test_bench_peers.py. bits and mov have none: constants and
# inputs that stay OFF.
CHECK_CYCLES = 150
CHECKS = {
    # D0 counts cycles; D1 took D0 in the last odd cycle with D0 > 100;
    # group 999's move never ran.
    "mix": {"D0": 150, "D1": 149, "D1999": 0},
    # The ring carries the incremented D0 round: every word holds the count.
    "chain": {"D0": 150, "D1": 150, "D5000": 150, "D9999": 150},
    # M0 rises in the 75 odd cycles; M(k+1) is D0 > k, so ON up to M150.
    "tcc": {"D0": 150, "CN0": 75, "CN999": 75, "M150": 1, "M151": 0},
}


# --- MELSEC (softplc) -------------------------------------------------------


def melsec(rung):
    kind, *a = rung
    if kind == "bits":
        return [f"LD X{a[0]:X}", f"AND M{a[1]}", f"OR M{a[2]}", f"ANI X{a[3]:X}", f"OUT M{a[4]}"]
    if kind == "on":
        return ["LD SM400"]
    if kind == "movk":
        return [f"MOV K{a[0]} D{a[1]}"]
    if kind == "movd":
        return [f"MOV D{a[0]} D{a[1]}"]
    if kind == "toggle":
        return [f"LDI M{a[0]}", f"OUT M{a[0]}"]
    if kind == "timer":
        return [f"LDI X{a[0]:X}", f"OUT T{a[1]} K{a[2]}"]
    if kind == "counter":
        return [f"LD M{a[0]}", f"OUT C{a[1]} K{a[2]}"]
    if kind == "inc":
        return ["LD SM400", f"+ D{a[0]} K1 D{a[0]}"]
    if kind == "cmpmov":
        return [f"LD> D{a[0]} K{a[1]}", f"AND M{a[2]}", f"MOV D{a[0]} D{a[3]}"]
    if kind == "timerbits":
        return [f"LD X{a[0]:X}", f"OR T{a[1]}", f"ANI X{a[2]:X}", f"OUT M{a[3]}"]
    if kind == "cmpout":
        return [f"LD> D{a[0]} K{a[1]}", f"OUT M{a[2]}"]
    raise ValueError(kind)


def instructions(name):
    """MELSEC instructions of workload `name`, END not counted."""
    return sum(len(melsec(r)) for r in WORKLOADS[name]())


def il(name):
    lines = [f"; bench/peers workload {name}: {instructions(name)} instructions (gen.py)"]
    for r in WORKLOADS[name]():
        lines += melsec(r)
    return "\n".join(lines + ["END", ""])


# --- S7 AWL (awlsim) --------------------------------------------------------
# X n -> E n/8.n%8, M n -> M n/8.n%8, D n -> DB1.DBW 2n (DB1 opened once),
# T -> T, C -> Z (count up). STL ANDs before it ORs, so "U a / U b / O c /
# UN d" is (a AND b) OR (c AND NOT d): the same instructions as the MELSEC
# rung, with STL's own precedence.


def bit(n):
    return f"{n // 8}.{n % 8}"


def awl_rung(rung, label):
    kind, *a = rung
    if kind == "bits":
        return [f"U E {bit(a[0])}", f"U M {bit(a[1])}", f"O M {bit(a[2])}", f"UN E {bit(a[3])}", f"= M {bit(a[4])}"]
    if kind == "on":
        return []
    if kind == "movk":
        return [f"L {a[0]}", f"T DBW {2 * a[1]}"]
    if kind == "movd":
        return [f"L DBW {2 * a[0]}", f"T DBW {2 * a[1]}"]
    if kind == "toggle":
        return [f"UN M {bit(a[0])}", f"= M {bit(a[0])}"]
    if kind == "timer":
        return [f"UN E {bit(a[0])}", f"L S5T#{a[2] // 10}S", f"SE T {a[1]}"]
    if kind == "counter":
        return [f"U M {bit(a[0])}", f"ZV Z {a[1]}"]
    if kind == "inc":
        return [f"L DBW {2 * a[0]}", "L 1", "+I", f"T DBW {2 * a[0]}"]
    if kind == "cmpmov":
        return [
            f"L DBW {2 * a[0]}", f"L {a[1]}", ">I", f"U M {bit(a[2])}", f"SPBN {label}",
            f"L DBW {2 * a[0]}", f"T DBW {2 * a[3]}", f"{label}: NOP 0",
        ]
    if kind == "timerbits":
        return [f"U E {bit(a[0])}", f"O T {a[1]}", f"UN E {bit(a[2])}", f"= M {bit(a[3])}"]
    if kind == "cmpout":
        return [f"L DBW {2 * a[0]}", f"L {a[1]}", ">I", f"= M {bit(a[2])}"]
    raise ValueError(kind)


def awl(name):
    body = ["AUF DB 1"]
    labels = 0
    for r in WORKLOADS[name]():
        body += awl_rung(r, f"J{labels:03d}")
        labels += r[0] == "cmpmov"
    return "\n".join(
        [
            f"// bench/peers workload {name}: {instructions(name)} MELSEC instructions (gen.py)",
            "DATA_BLOCK DB 1",
            "STRUCT",
            "\tD : ARRAY [0 .. 11999] OF INT;",
            "END_STRUCT;",
            "BEGIN",
            "END_DATA_BLOCK",
            "",
            "ORGANIZATION_BLOCK OB 1",
            "BEGIN",
        ]
        + ["\t" + line for line in body]
        + ["END_ORGANIZATION_BLOCK", ""]
    )


# --- IEC 61131-3 ST (IronPLC, matiec) ---------------------------------------
# X n, M n -> BOOL X<n>, M<n>; D n -> INT D<n>; T t -> TON T<t> (K50 of a
# 100 ms timer = T#5S); C c -> CTU C<c>. Operators keep MELSEC's left-to-right
# evaluation of the rung.


def st_rung(rung):
    kind, *a = rung
    if kind == "bits":
        return [f"M{a[4]} := ((X{a[0]} AND M{a[1]}) OR M{a[2]}) AND NOT X{a[3]};"]
    if kind == "on":
        return []
    if kind == "movk":
        return [f"D{a[1]} := {a[0]};"]
    if kind == "movd":
        return [f"D{a[1]} := D{a[0]};"]
    if kind == "toggle":
        return [f"M{a[0]} := NOT M{a[0]};"]
    if kind == "timer":
        return [f"T{a[1]}(IN := NOT X{a[0]}, PT := T#{a[2] // 10}S);"]
    if kind == "counter":
        return [f"C{a[1]}(CU := M{a[0]}, PV := {a[2]});"]
    if kind == "inc":
        return [f"D{a[0]} := D{a[0]} + 1;"]
    if kind == "cmpmov":
        return [f"IF D{a[0]} > {a[1]} AND M{a[2]} THEN D{a[3]} := D{a[0]}; END_IF;"]
    if kind == "timerbits":
        return [f"M{a[3]} := (X{a[0]} OR T{a[1]}.Q) AND NOT X{a[2]};"]
    if kind == "cmpout":
        return [f"M{a[2]} := D{a[0]} > {a[1]};"]
    raise ValueError(kind)


def st_vars(rungs):
    """Declarations of every variable the ST rungs use, in a fixed order."""
    used = {"X": set(), "M": set(), "D": set(), "T": set(), "C": set()}
    for kind, *a in rungs:
        if kind == "bits":
            used["X"] |= {a[0], a[3]}
            used["M"] |= {a[1], a[2], a[4]}
        elif kind in ("movk",):
            used["D"].add(a[1])
        elif kind == "movd":
            used["D"] |= {a[0], a[1]}
        elif kind == "toggle":
            used["M"].add(a[0])
        elif kind == "timer":
            used["X"].add(a[0])
            used["T"].add(a[1])
        elif kind == "counter":
            used["M"].add(a[0])
            used["C"].add(a[1])
        elif kind == "inc":
            used["D"].add(a[0])
        elif kind == "cmpmov":
            used["D"] |= {a[0], a[3]}
            used["M"].add(a[2])
        elif kind == "timerbits":
            used["X"] |= {a[0], a[2]}
            used["T"].add(a[1])
            used["M"].add(a[3])
        elif kind == "cmpout":
            used["D"].add(a[0])
            used["M"].add(a[2])
    types = {"X": "BOOL", "M": "BOOL", "D": "INT", "T": "TON", "C": "CTU"}
    return [f"{p}{n} : {types[p]};" for p in types for n in sorted(used[p])]


def st(name):
    rungs = WORKLOADS[name]()
    lines = [f"(* bench/peers workload {name}: {instructions(name)} MELSEC instructions (gen.py) *)"]
    lines += [f"PROGRAM {name}_prog", "VAR"]
    lines += ["  " + v for v in st_vars(rungs)]
    lines += ["END_VAR"]
    for r in rungs:
        lines += ["  " + s for s in st_rung(r)]
    lines += ["END_PROGRAM", ""]
    return "\n".join(lines)


def st_matiec(name):
    """The PROGRAM plus the configuration OpenPLC's editor writes: one
    resource, one cyclic task, one program instance."""
    return st(name) + "\n".join(
        [
            "CONFIGURATION Config0",
            "  RESOURCE Res0 ON PLC",
            "    TASK task0(INTERVAL := T#10ms, PRIORITY := 0);",
            f"    PROGRAM instance0 WITH task0 : {name}_prog;",
            "  END_RESOURCE",
            "END_CONFIGURATION",
            "",
        ]
    )


def st_name(device):
    """The ST variable holding MELSEC `device` of CHECKS (CN n: C n's CV)."""
    if device.startswith("CN"):
        return f"C{device[2:]}.CV"
    return device


# --- plain C (gcc) ----------------------------------------------------------
# The same logic as a C programmer would write it without a PLC: X, M as bool
# arrays, D as int16_t, a 100 ms timer as its current value in 100 ms plus
# the milliseconds not yet a unit (it counts scan time: `dt_ms` is the time
# since the scan before, 0 in the first scan), a counter as its count and the
# input's last state (it counts rising edges up to its set value). Every
# array is global with external linkage and `scan` is not inlined nor
# analysed across calls (noipa), so gcc must do each scan's reads and writes;
# main prints a checksum of the memory at the end.

C_PRELUDE = r"""#include <stdbool.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

bool x[8192], m[8192];
int16_t d[12288];
bool ts[2048];     /* timer contacts */
int16_t tn[2048];  /* timer current values, 100 ms units */
int16_t tms[2048]; /* milliseconds towards the next 100 ms */
bool cs[1024];     /* counter contacts */
int16_t cn[1024];  /* counter current values */
bool cin[1024];    /* counter inputs in the last execution */
int16_t dt_ms;     /* time since the scan before */

static inline void out_t(int t, bool coil, int16_t k) {
    if (!coil) {
        tn[t] = 0;
        tms[t] = 0;
        ts[t] = false;
        return;
    }
    if (ts[t])
        return;
    tms[t] += dt_ms;
    while (tms[t] >= 100) {
        tms[t] -= 100;
        tn[t]++;
    }
    if (tn[t] >= k) {
        tn[t] = k;
        ts[t] = true;
    }
}

static inline void out_c(int c, bool in, int16_t k) {
    if (in && !cin[c] && cn[c] < k) {
        cn[c]++;
        if (cn[c] >= k)
            cs[c] = true;
    }
    cin[c] = in;
}
"""

C_MAIN = r"""
/* plc CYCLES [DEVICE...]: runs CYCLES scans of 10 ms, prints a checksum and
   "DEVICE = value" for each D, M, CN, TN or T named. */
int main(int argc, char **argv) {
    if (argc < 2) {
        fprintf(stderr, "usage: %s CYCLES [DEVICE...]\n", argv[0]);
        return 2;
    }
    long cycles = strtol(argv[1], NULL, 10);
    for (long i = 0; i < cycles; i++) {
        scan();
        dt_ms = 10;
    }
    long sum = 0;
    for (int i = 0; i < 12288; i++)
        sum += d[i];
    for (int i = 0; i < 8192; i++)
        sum += m[i];
    printf("checksum %ld\n", sum);
    for (int a = 2; a < argc; a++) {
        const char *name = argv[a];
        int n = atoi(name + strspn(name, "ABCDEFGHIJKLMNOPQRSTUVWXYZ"));
        long v;
        if (strncmp(name, "CN", 2) == 0)
            v = cn[n];
        else if (strncmp(name, "TN", 2) == 0)
            v = tn[n];
        else if (name[0] == 'D')
            v = d[n];
        else if (name[0] == 'M')
            v = m[n];
        else if (name[0] == 'T')
            v = ts[n];
        else {
            fprintf(stderr, "unknown device %s\n", name);
            return 2;
        }
        printf("%s = %ld\n", name, v);
    }
    return 0;
}
"""


def c_rung(rung):
    kind, *a = rung
    if kind == "bits":
        return [f"m[{a[4]}] = ((x[{a[0]}] && m[{a[1]}]) || m[{a[2]}]) && !x[{a[3]}];"]
    if kind == "on":
        return []
    if kind == "movk":
        return [f"d[{a[1]}] = {a[0]};"]
    if kind == "movd":
        return [f"d[{a[1]}] = d[{a[0]}];"]
    if kind == "toggle":
        return [f"m[{a[0]}] = !m[{a[0]}];"]
    if kind == "timer":
        return [f"out_t({a[1]}, !x[{a[0]}], {a[2]});"]
    if kind == "counter":
        return [f"out_c({a[1]}, m[{a[0]}], {a[2]});"]
    if kind == "inc":
        return [f"d[{a[0]}] = (int16_t)(d[{a[0]}] + 1);"]
    if kind == "cmpmov":
        return [f"if (d[{a[0]}] > {a[1]} && m[{a[2]}]) d[{a[3]}] = d[{a[0]}];"]
    if kind == "timerbits":
        return [f"m[{a[3]}] = (x[{a[0]}] || ts[{a[1]}]) && !x[{a[2]}];"]
    if kind == "cmpout":
        return [f"m[{a[2]}] = d[{a[0]}] > {a[1]};"]
    raise ValueError(kind)


def c(name):
    lines = [f"/* bench/peers workload {name}: {instructions(name)} MELSEC instructions (gen.py) */", C_PRELUDE]
    lines += ["__attribute__((noipa)) void scan(void) {"]
    for r in WORKLOADS[name]():
        lines += ["    " + s for s in c_rung(r)]
    lines += ["}", C_MAIN]
    return "\n".join(lines)


def write_all(outdir):
    outdir = pathlib.Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    written = []
    for name in WORKLOADS:
        for suffix, text in [
            (".il", il(name)),
            (".awl", awl(name)),
            (".st", st(name)),
            ("_matiec.st", st_matiec(name)),
            (".c", c(name)),
        ]:
            path = outdir / f"{name}{suffix}"
            # Unchanged files keep their time, so measure.py --keep can reuse builds.
            if not path.is_file() or path.read_text() != text:
                path.write_text(text)
            written.append(path)
    return written


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    for p in write_all(sys.argv[1]):
        print(p)
