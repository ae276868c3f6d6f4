#!/usr/bin/env python3
"""Runs an AWL program in awlsim for N OB1 cycles, then exits.

awlsim-test runs until interrupted; measure.py needs a fixed number of
cycles so that two runs (N low and N high) differ only by the cycles run.
Set AWLSIM_CYTHON=2 to require awlsim's Cython core (aborts if it is absent),
0 for the pure-Python core.

Usage: python awlsim_run.py PROGRAM.awl CYCLES [DEVICE ...]
  DEVICE: a MELSEC name as gen.py translates it; after the cycles, print
  "DEVICE = value": Dn of DB1.DBW 2n, Mn of M n/8.n%8 (0 or 1), CNn the
  value of counter Z n. The pure-Python core only (the Cython core keeps
  its memories from Python).
"""
import sys

from awlsim_loader.common import Project
from awlsim_loader.core import AwlSim
from awlsim_loader.awlcompiler import AwlParser


def main(path, cycles, show):
    project = Project.fromProjectOrRawAwlFile(path)
    sim = AwlSim()
    sim.reset()
    cpu = sim.getCPU()
    specs = cpu.getSpecs()
    # The workloads use E0.0-E511.7, M0.0-M1000.7 and T0/Z0-T999/Z999;
    # awlsim's defaults (128 input bytes, 256 timers/counters) are smaller.
    specs.setNrInputs(1024)
    specs.setNrFlags(2048)
    specs.setNrTimers(1024)
    specs.setNrCounters(1024)
    conf = cpu.getConf()
    conf.setCycleTimeLimitUs(600_000_000)
    for src in project.getAwlSources():
        parser = AwlParser()
        parser.parseSource(src)
        sim.load(parser.getParseTree())
    sim.build()
    sim.startup()
    for _ in range(cycles):
        sim.runCycle()
    for device in show:
        print(f"{device} = {value(cpu, device)}")


def value(cpu, device):
    if device.startswith("CN"):
        return cpu.getCounter(int(device[2:])).getValueBin()
    n = int(device[1:])
    if device[0] == "D":
        data = cpu.getDB(1).structInstance.memory.getDataBytes()
        return int.from_bytes(data[2 * n:2 * n + 2], "big", signed=True)
    if device[0] == "M":
        return cpu.flags.getDataBytes()[n // 8] >> (n % 8) & 1
    sys.exit(f"awlsim_run.py: no translation of device {device}")


if __name__ == "__main__":
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    main(sys.argv[1], int(sys.argv[2]), sys.argv[3:])
