"""FMU plant models (issue 16): builds the test FMU with pythonfmu3
(tests/fmu/build.py), runs the heated-tank scenario with the FMU and with the
built-in heater model through `softplc test`, and checks that the
trajectories agree within the tolerance stated in docs/scenarios.md; an FMU
whose step raises stops the scenario with the Python error."""
import csv
import subprocess
import sys

import pytest

from conftest import BINARY, ROOT

pytest.importorskip("pythonfmu3")
sys.path.insert(0, str(ROOT / "tests" / "fmu"))
import build  # noqa: E402  (tests/fmu/build.py)

FMU_DIR = ROOT / "tests" / "fmu"


@pytest.fixture(scope="module")
def heater_fmu():
    return build.build()


def run_trace(scenario, csv_path):
    out = subprocess.run(
        [BINARY, "test", str(scenario), "--trace-file", str(csv_path)],
        capture_output=True, text=True, timeout=300,
    )
    assert out.returncode == 0, out.stdout + out.stderr
    with open(csv_path, newline="") as f:
        return out.stdout, list(csv.DictReader(f))


def test_fmu_trajectory_matches_the_built_in_heater(heater_fmu, tmp_path):
    assert heater_fmu.is_file()
    text, fmu = run_trace(FMU_DIR / "heated_tank_fmu.toml", tmp_path / "fmu.csv")
    assert "4 passed, 0 failed" in text
    _, builtin = run_trace(FMU_DIR / "heated_tank_builtin.toml", tmp_path / "builtin.csv")
    assert len(fmu) == len(builtin) == 6000
    # Stated tolerance: 1e-3 °C on the open-loop temperature, ±1 count on
    # the closed loop's A/D (D800) and D/A (D820) words.
    for col, tol in (("D900:f32", 1e-3), ("D800", 1), ("D820", 1)):
        worst = max(abs(float(a[col]) - float(b[col])) for a, b in zip(fmu, builtin))
        assert worst <= tol, (col, worst)
    # 5 min: 140 - 120 e^(-290/240) °C, worked out by hand.
    row = next(r for r in fmu if r["time_s"] == "300.000")
    assert abs(float(row["D900:f32"]) - 104.1566) < 1e-3


FAILING = '''
from pythonfmu3 import Fmi3Causality, Fmi3Slave, Float64


class Breaks(Fmi3Slave):
    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.time = 0.0
        self.y = 0.0
        self.register_variable(Float64("time", causality=Fmi3Causality.independent))
        self.register_variable(Float64("y", causality=Fmi3Causality.output))

    def do_step(self, current_time, step_size):
        if current_time >= 0.5:
            raise RuntimeError("the plant broke at half a second")
        self.y = current_time + step_size
        return True
'''


def test_an_fmu_that_raises_stops_the_scenario_with_its_error(tmp_path):
    (tmp_path / "breaks.py").write_text(FAILING)
    subprocess.run(
        [sys.executable, "-m", "pythonfmu3", "build", "-f", str(tmp_path / "breaks.py"),
         "-d", str(tmp_path)],
        check=True, stdout=subprocess.DEVNULL,
    )
    (tmp_path / "p.il").write_text("LD X0\nOUT Y0\nEND\n")
    (tmp_path / "s.toml").write_text(
        'program = "p.il"\nscan_time = "100ms"\nduration = "2s"\n\n'
        '[[model]]\nname = "plant"\ntype = "fmu"\nparams = { file = "Breaks.fmu" }\n'
        'outputs.y = "D0:f32"\n\n'
        '[[expect]]\ndevice = "D0:f32"\nequals = 0.5\ntolerance = 1e-6\nat = "0.5s"\n'
    )
    out = subprocess.run([BINARY, "test", str(tmp_path / "s.toml")],
                         capture_output=True, text=True, timeout=120)
    text = out.stdout
    assert out.returncode == 1, text
    # Five steps of 0.1 s ran (y = 0.5 at 0.5 s), the sixth raised.
    assert "PASS D0:f32 = 0.5" in text, text
    assert "FAIL the plant models keep running (model `plant` failed before scan 6, at 500 ms)" in text, text
    # pythonfmu3 reports a Python exception as fmi3Fatal, with its message.
    assert ("model `plant`: at t = 0.5 s (step 0.1 s): fmi3DoStep returned fmi3Fatal: "
            in text), text
    assert "RuntimeError('the plant broke at half a second')" in text, text


def test_parallel_scenarios_start_python_fmus_one_at_a_time(heater_fmu, tmp_path):
    """Each scenario unpacks its own copy of the FMU; started in parallel,
    the copies must not start Python twice at once (which aborts)."""
    text = (FMU_DIR / "heated_tank_fmu.toml").read_text()
    text = text.replace('program = "../../examples', f'program = "{ROOT}/examples')
    text = text.replace('file = "build/Heater.fmu"', f'file = "{heater_fmu}"')
    files = []
    for i in range(3):
        f = tmp_path / f"copy{i}.toml"
        f.write_text(text)
        files.append(str(f))
    out = subprocess.run([BINARY, "test", "-j", "3", "-q", *files],
                         capture_output=True, text=True, timeout=300)
    assert out.returncode == 0, out.stdout + out.stderr
    assert out.stdout.strip().splitlines()[-1] == "12 passed, 0 failed"
