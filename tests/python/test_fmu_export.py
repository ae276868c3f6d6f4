"""softplc as an FMU (`softplc fmu`, docs/fmu-export.md): the exported FMU
passes fmpy's validation, and fmpy's co-simulation gives what `softplc run`
gives at every communication point, inputs given as fmpy's `input=` table;
a wrong call sequence is refused with a logged reason, not a crash; the FMU
state goes back in time.

The FMU's library is the libsoftplc_fmu.so that `cargo test` builds next to
target/debug/softplc (in target/debug/deps)."""
import csv
import json
import subprocess

import numpy as np
import pytest

from conftest import BINARY, ROOT

fmpy = pytest.importorskip("fmpy")
from fmpy import fmi3  # noqa: E402
from fmpy.fmi1 import FMICallException  # noqa: E402
from fmpy.model_description import read_model_description  # noqa: E402
from fmpy.validation import validate_fmu  # noqa: E402

H = 0.01  # the scan time and the communication step, s


def export(tmp_path, program, inputs, outputs, name):
    fmu = tmp_path / f"{name}.fmu"
    args = [BINARY, "fmu", str(ROOT / program), "-o", str(fmu)]
    for d in inputs:
        args += ["--input", d]
    for d in outputs:
        args += ["--output", d]
    out = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    return fmu


def run(tmp_path, program, scans, writes, outputs):
    """`softplc run --json` with a trace of the outputs after every scan:
    the rows (one per scan) and the JSON report."""
    trace = tmp_path / "trace.csv"
    args = [BINARY, "run", str(ROOT / program), "--scans", str(scans), "--json",
            "--trace", ",".join(outputs), "--trace-file", str(trace)]
    for n, dev, value in writes:
        args += ["--at", f"{n}:{dev}={value}"]
    for d in outputs:
        args += ["--show", d]
    out = subprocess.run(args, capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stderr
    with open(trace, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows, json.loads(out.stdout)


def input_table(names, types, changes):
    """fmpy's `input=`: one row per change `(time, {dev: value})`, holding
    the other inputs; every input starts at 0."""
    now = {n: 0 for n in names}
    rows = []
    for t, change in changes:
        now.update(change)
        rows.append(tuple([t] + [now[n] for n in names]))
    return np.array(rows, dtype=[("time", np.float64)] + list(zip(names, types)))


def at_scans(changes):
    """The same changes as `run --at`: a value set at time t is written
    before the scan of the step from t, scan round(t / H) + 1."""
    return [(round(t / H) + 1, dev, int(v)) for t, change in changes for dev, v in change.items()]


def compare(tmp_path, program, inputs, types, outputs, changes, stop):
    fmu = export(tmp_path, program, inputs, outputs, program.split("/")[-1].split(".")[0])
    assert validate_fmu(str(fmu)) == []
    md = read_model_description(str(fmu))
    assert md.fmiVersion == "3.0" and md.coSimulation is not None
    kinds = {v.name: (v.type, v.causality) for v in md.modelVariables}
    assert kinds["scan_time"] == ("Float64", "parameter")
    res = fmpy.simulate_fmu(
        str(fmu), start_time=0.0, stop_time=stop, output_interval=H,
        input=input_table(inputs, types, changes), output=outputs,
    )
    scans = round(stop / H)
    rows, report = run(tmp_path, program, scans, at_scans(changes), outputs)
    assert len(rows) == scans
    # fmpy's row k (k ≥ 1) is after the step to k·H: after scan k.
    assert len(res) == scans + 1
    for k in range(1, scans + 1):
        for dev in outputs:
            want = rows[k - 1][dev]
            got = res[dev][k]
            got = str(int(got)) if kinds[dev][0] == "Boolean" else str(got)
            assert got == want, f"{dev} after scan {k}: FMU {got}, run {want}"
    for dev in outputs:
        last = res[dev][-1]
        assert (bool(last) if kinds[dev][0] == "Boolean" else int(last)) == report["devices"][dev]
    return res


def test_blink_fmu_validates_and_matches_run(tmp_path):
    changes = [(0.0, {"X0": 1}), (2.0, {"X0": 0}), (2.5, {"X1": 1}), (2.6, {"X1": 0}),
               (2.7, {"X0": 1})]
    res = compare(tmp_path, "examples/blink.il", ["X0", "X1"], [np.bool_, np.bool_],
                  ["Y0", "CN0", "TN0"], changes, 4.0)
    # Y0 blinks 0.5 s on, 0.5 s off: on for about half of the first 2 s.
    on = sum(res["Y0"][1:201])
    assert 95 <= on <= 105, on


def test_heated_tank_fmu_validates_and_matches_run(tmp_path):
    # The "A/D" word rises 50 counts (5 °C) every half second from 20 °C;
    # PID control starts at 1 s.
    changes = [(0.5 * m, {"D800": 200 + 50 * m}) for m in range(12)]
    changes.insert(2, (1.0, {"X0": 1}))
    changes.sort(key=lambda c: c[0])
    res = compare(tmp_path, "examples/sim/heated_tank.il", ["X0", "D800"],
                  [np.bool_, np.int16], ["Y0", "Y1", "D611", "D820"], changes, 6.0)
    assert res["D611"][-1] == 750
    assert res["Y0"][-1]


def test_a_wrong_call_sequence_is_refused_and_logged(tmp_path):
    program = tmp_path / "count.il"
    program.write_text("LD SM400\nINC D0\nEND\n")
    fmu = export(tmp_path, str(program), ["D10"], ["D0"], "count")
    md = read_model_description(str(fmu))
    unzipped = fmpy.extract(str(fmu))
    slave = fmi3.FMU3Slave(guid=md.guid, unzipDirectory=unzipped,
                           modelIdentifier=md.coSimulation.modelIdentifier, instanceName="plc")
    logged = []

    def log(env, status, category, message):
        logged.append((status, message.decode()))

    slave.instantiate(logMessage=log)
    vr = {v.name: v.valueReference for v in md.modelVariables}
    with pytest.raises(FMICallException):
        slave.doStep(0.0, H)
    assert logged[-1] == (3, "fmi3DoStep is not allowed in Instantiated mode (only in Step)")
    with pytest.raises(FMICallException):
        slave.getInt16([42])
    assert logged[-1][1] == "no variable has value reference 42"
    with pytest.raises(FMICallException):
        slave.setInt16([vr["D0"]], [5])
    assert "is an output and cannot be set" in logged[-1][1]
    # It still runs afterwards: 3 scans in 30 ms.
    slave.setInt16([vr["D10"]], [-7])
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    slave.doStep(0.0, 0.03)
    assert slave.getInt16([vr["D0"], vr["D10"]]) == [3, -7]
    slave.terminate()
    slave.freeInstance()


def test_the_fmu_state_goes_back_in_time(tmp_path):
    program = tmp_path / "count.il"
    program.write_text("LD SM400\nINC D0\nEND\n")
    fmu = export(tmp_path, str(program), [], ["D0"], "count")
    md = read_model_description(str(fmu))
    assert md.coSimulation.canGetAndSetFMUstate and md.coSimulation.canSerializeFMUstate
    slave = fmi3.FMU3Slave(guid=md.guid, unzipDirectory=fmpy.extract(str(fmu)),
                           modelIdentifier=md.coSimulation.modelIdentifier, instanceName="plc")
    slave.instantiate()
    d0 = {v.name: v.valueReference for v in md.modelVariables}["D0"]
    slave.enterInitializationMode()
    slave.exitInitializationMode()
    slave.doStep(0.0, 0.1)
    state = slave.getFMUState()
    slave.doStep(0.1, 0.1)
    assert slave.getInt16([d0]) == [20]
    slave.setFMUState(state)
    assert slave.getInt16([d0]) == [10]
    # Serialized, read back into a new state, and set: 10 scans again.
    copy = slave.deserializeFMUState(slave.serializeFMUState(state))
    slave.doStep(0.1, 0.05)
    assert slave.getInt16([d0]) == [15]
    slave.setFMUState(copy)
    assert slave.getInt16([d0]) == [10]
    slave.freeFMUState(state)
    slave.freeFMUState(copy)
    slave.terminate()
    slave.freeInstance()
