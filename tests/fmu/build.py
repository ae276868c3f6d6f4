"""Builds tests/fmu/build/Heater.fmu from heater.py with pythonfmu3
(tests/fmu/requirements.txt). .ci/run calls it; the Rust test that compares
the FMU with the built-in model is skipped, saying so, until it has run."""
import pathlib
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent


def build() -> pathlib.Path:
    dest = HERE / "build"
    dest.mkdir(exist_ok=True)
    subprocess.run(
        [sys.executable, "-m", "pythonfmu3", "build", "-f", str(HERE / "heater.py"), "-d", str(dest)],
        check=True,
        stdout=subprocess.DEVNULL,
    )
    return dest / "Heater.fmu"


if __name__ == "__main__":
    print(build())
