"""The test FMU (issue 16): the built-in `heater` plant of softplc-sim,
C·T' = P·u/100 − (T − Ta)/R, as an FMI 3.0 co-simulation FMU written with
pythonfmu3. It integrates with classic Runge-Kutta (RK4), in substeps of at
most τ/50, so it is an independent implementation of the same plant: the
built-in model steps the exact exponential solution.

Build: python3 tests/fmu/build.py (writes tests/fmu/build/Heater.fmu).
"""
import math

from pythonfmu3 import Fmi3Causality, Fmi3Slave, Fmi3Variability, Float64


class Heater(Fmi3Slave):
    author = "softplc"
    description = "Heater with loss to ambient (the softplc-sim `heater` model)"

    def __init__(self, **kwargs):
        super().__init__(**kwargs)
        self.time = 0.0
        self.capacity = 1000.0  # J/K
        self.power = 100.0  # W at 100 %
        self.resistance = 0.5  # K/W
        self.ambient = 20.0  # °C, also the initial temperature
        self.u = 0.0  # heating, 0..100 %
        self.temperature = self.ambient
        self.register_variable(Float64("time", causality=Fmi3Causality.independent,
                                       variability=Fmi3Variability.continuous))
        for name in ("capacity", "power", "resistance", "ambient"):
            self.register_variable(Float64(name, causality=Fmi3Causality.parameter,
                                           variability=Fmi3Variability.fixed))
        self.register_variable(Float64("u", causality=Fmi3Causality.input))
        self.register_variable(Float64("temperature", causality=Fmi3Causality.output))

    def exit_initialization_mode(self):
        self.temperature = self.ambient

    def derivative(self, t, u):
        return (self.power * u / 100.0 - (t - self.ambient) / self.resistance) / self.capacity

    def do_step(self, current_time, step_size):
        u = min(max(self.u, 0.0), 100.0)
        tau = self.resistance * self.capacity
        n = max(1, math.ceil(step_size / (tau / 50.0)))
        h = step_size / n
        t = self.temperature
        for _ in range(n):
            k1 = self.derivative(t, u)
            k2 = self.derivative(t + h / 2 * k1, u)
            k3 = self.derivative(t + h / 2 * k2, u)
            k4 = self.derivative(t + h * k3, u)
            t += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        self.temperature = t
        self.time = current_time + step_size
        return True
