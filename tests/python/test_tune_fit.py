"""Validates `softplc tune`'s FOPDT identification against independent
computations: the step responses are simulated with python-control (the lag
discretised exactly by zero-order hold, the dead time as an exact delay of
whole samples), fitted by `softplc tune --fit-csv`, and the fitted K, tau,
theta are compared with the plant's and with scipy's own least-squares fit
of the same data (issue 12 item 5)."""
import json
import subprocess

import control
import numpy as np
import pytest
from scipy.optimize import curve_fit

from conftest import BINARY


def simulate(gain, tau, dead_time, dt, t_end, t_step, u0, u1, noise=0.0, seed=0):
    """Samples of K·e^(−θs)/(1 + τs) after an input step at t_step."""
    delay = round(dead_time / dt)
    assert abs(delay * dt - dead_time) < 1e-9, "theta must be a multiple of dt"
    lag = control.sample_system(control.tf([gain], [tau, 1.0]), dt, method="zoh")
    shift = control.tf([1.0], [1.0] + [0.0] * delay, dt)  # z^-delay
    plant = control.series(shift, lag)
    t = np.arange(0.0, t_end, dt)
    u = np.where(t >= t_step - 1e-9, u1, u0)
    # Start from the steady state of u0: simulate the deviation from it.
    resp = control.forced_response(plant, T=t, U=u - u0)
    y = gain * u0 + np.asarray(resp.outputs).ravel()
    if noise:
        y = y + np.random.default_rng(seed).normal(0.0, noise, size=y.shape)
    return t, u, y


def fit_with_softplc(tmp_path, t, u, y):
    csv = tmp_path / "step.csv"
    with open(csv, "w") as f:
        f.write("t,u,y\n")
        for row in zip(t, u, y):
            f.write("%.6f,%.9g,%.12g\n" % row)
    out = subprocess.run(
        [BINARY, "tune", "--json", "--fit-csv", str(csv)],
        capture_output=True,
        text=True,
        check=True,
    )
    return json.loads(out.stdout)


def fit_with_scipy(t, u, y, t_step):
    """An independent least-squares fit of the same model (scipy)."""
    before = y[(t < t_step - 1e-9) & (t >= t_step / 2)]
    y0 = before.mean()
    du = u[-1] - u[0]
    s = t[t >= t_step - 1e-9] - t_step
    ys = y[t >= t_step - 1e-9]

    def model(x, k, tau, theta):
        return y0 + np.where(x > theta, k * du * (1 - np.exp(-(x - theta) / max(tau, 1e-9))), 0.0)

    p, _ = curve_fit(model, s, ys, p0=[(ys[-1] - y0) / du, s[-1] / 5, s[-1] / 20])
    return p


@pytest.mark.parametrize(
    "gain,tau,dead_time,dt",
    [
        (1.5, 40.0, 7.3, 0.1),
        (-0.8, 12.0, 2.0, 0.05),
        (0.4, 90.0, 15.0, 0.5),
    ],
)
def test_fit_matches_the_python_control_plant(tmp_path, gain, tau, dead_time, dt):
    t_step = 20.0
    t, u, y = simulate(gain, tau, dead_time, dt, t_step + dead_time + 8 * tau, t_step, 10.0, 30.0)
    fit = fit_with_softplc(tmp_path, t, u, y)["fit"]
    assert fit["gain"] == pytest.approx(gain, rel=1e-3)
    assert fit["tau"] == pytest.approx(tau, rel=1e-3)
    assert fit["dead_time"] == pytest.approx(dead_time, rel=1e-3, abs=1e-3)
    assert fit["r2"] > 0.99999


def test_fit_with_noise_agrees_with_scipy(tmp_path):
    gain, tau, dead_time, dt, t_step = 2.0, 30.0, 6.0, 0.2, 30.0
    t, u, y = simulate(gain, tau, dead_time, dt, 330.0, t_step, 0.0, 5.0, noise=0.1, seed=3)
    fit = fit_with_softplc(tmp_path, t, u, y)["fit"]
    k, tau_s, theta_s = fit_with_scipy(t, u, y, t_step)
    # Both recover the plant within a few percent ...
    assert fit["gain"] == pytest.approx(gain, rel=0.02)
    assert fit["tau"] == pytest.approx(tau, rel=0.03)
    assert fit["dead_time"] == pytest.approx(dead_time, rel=0.05)
    # ... and minimise the same sum of squares: they agree much more closely.
    assert fit["gain"] == pytest.approx(k, rel=2e-3)
    assert fit["tau"] == pytest.approx(tau_s, rel=5e-3)
    assert fit["dead_time"] == pytest.approx(theta_s, rel=5e-3, abs=0.02)
    # The RMS error is the noise.
    assert fit["rms"] == pytest.approx(0.1, rel=0.1)
