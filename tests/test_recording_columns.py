"""Recordings with only some kinematic columns: a position-only (encoder) or velocity-only
recording loads, derives the missing signal and says it was derived; a file with neither is
refused with one line naming the file and the columns."""

from __future__ import annotations

import numpy as np
import pytest

from lugre_jax.io import load_recording, recording_from_arrays, write_recording


def _signals(n=400, fs=100.0):
    t = np.arange(n) / fs
    v = 2.0 * np.sin(2 * np.pi * 0.5 * t)  # deg/s
    th = (2.0 / (2 * np.pi * 0.5)) * (1 - np.cos(2 * np.pi * 0.5 * t))  # its integral from 0
    tau = 1.2 * np.tanh(v / 0.05) + 0.5 * v
    return t, th, v, tau


def _write(path, cols):
    names = list(cols)
    rows = np.column_stack([cols[k] for k in names])
    path.write_text(",".join(names) + "\n" + "\n".join(",".join(f"{x:.12g}" for x in r) for r in rows) + "\n")


def test_position_only_csv_derives_velocity(tmp_path):
    t, th, v, tau = _signals()
    p = tmp_path / "enc.csv"
    _write(p, {"time_s": t, "position_deg": th, "torque_nm": tau})
    rec = load_recording(p)
    assert rec.meta["velocity_measured"] is False and rec.meta["position_measured"] is True
    # central difference of a 0.5-Hz sine at 100 Hz: error <= (2*pi*0.5*dt)^2/6 of the amplitude
    tol = 2.0 * (2 * np.pi * 0.5 / 100.0) ** 2 / 6 * 1.01
    np.testing.assert_allclose(rec.velocity[1:-1], v[1:-1], atol=tol)


def test_velocity_only_csv_integrates_position(tmp_path):
    t, th, v, tau = _signals()
    p = tmp_path / "tacho.csv"
    _write(p, {"time_s": t, "velocity_deg_s": v, "torque_nm": tau})
    rec = load_recording(p)
    assert rec.meta["position_measured"] is False and rec.meta["velocity_measured"] is True
    # trapezoidal integral: error <= dt^2/12 * max|v'| * duration
    tol = (0.01 ** 2 / 12) * (2.0 * 2 * np.pi * 0.5) * t[-1] * 1.01
    np.testing.assert_allclose(rec.position, th, atol=tol)


def test_neither_kinematic_column_is_one_clear_line(tmp_path):
    t, th, v, tau = _signals()
    p = tmp_path / "bad.csv"
    _write(p, {"time_s": t, "torque_nm": tau})
    with pytest.raises(ValueError) as e:
        load_recording(p)
    msg = str(e.value)
    assert "\n" not in msg and str(p) in msg and "position_deg or velocity_deg_s" in msg


def test_derived_column_is_not_written_back(tmp_path):
    """write -> load keeps what was measured: a derived velocity read back would pass for a sensor."""
    t, th, v, tau = _signals()
    rec = recording_from_arrays(t, th, None, tau)
    p = tmp_path / "rt.csv"
    write_recording(p, rec)
    assert p.read_text().splitlines()[0] == "time_s,position_deg,torque_nm"
    back = load_recording(p)
    assert back.meta["velocity_measured"] is False
    np.testing.assert_allclose(back.velocity, rec.velocity, rtol=1e-9, atol=1e-9)


def test_both_columns_measured_by_default():
    t, th, v, tau = _signals()
    rec = recording_from_arrays(t, th, v, tau)
    assert rec.meta["velocity_measured"] and rec.meta["position_measured"]
    with pytest.raises(ValueError, match="neither position nor velocity"):
        recording_from_arrays(t, None, None, tau)
