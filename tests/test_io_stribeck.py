"""Loaders for steady-state friction data: Stribeck CSV and EPOS Studio exports (units deg/s, N*m)."""

from pathlib import Path

import numpy as np
import pytest

from lugre_jax.io._epos import load_epos_file, load_epos_steady_state, load_friction_data
from lugre_jax.io._stribeck_data import load_stribeck_csv

ROOT = Path(__file__).resolve().parents[1]
TRO = ROOT.parent / "shared" / "data" / "tro2021"


def _write(tmp_path, name, text):
    p = tmp_path / name
    p.write_text(text)
    return p


# ------------------------------------------------------------------ Stribeck CSV


def test_csv_averages_repeats_and_uses_spread_as_weight(tmp_path):
    p = _write(
        tmp_path, "ok.csv",
        "# comment\nvelocity_deg_s,torque_nm,branch\n"
        "0.1,1.0,accel\n0.1,1.2,accel\n0.1,1.4,accel\n"
        "0.2,2.0,accel\n0.2,2.2,accel\n"
        "0.05,3.0,decel\n0.05,3.1,decel\n0.08,2.5,decel\n0.08,2.7,decel\n",
    )
    d = load_stribeck_csv(p)
    assert len(d) == 4
    a = d.select(d.branch == "accel")
    np.testing.assert_allclose(a.velocity, [0.1, 0.2])
    np.testing.assert_allclose(a.torque, [1.2, 2.1], rtol=1e-12)
    np.testing.assert_allclose(a.torque_sd[0], 0.2, rtol=1e-12)
    np.testing.assert_allclose(a.torque_se[0], 0.2 / np.sqrt(3), rtol=1e-12)
    np.testing.assert_array_equal(a.count, [3, 2])
    assert list(d.branch).count("decel") == 2


def test_csv_without_branch_or_repeats(tmp_path):
    p = _write(tmp_path, "plain.csv", "torque_nm,velocity_deg_s\n1.0,0.1\n2.0,0.2\n3.0,0.3\n")
    d = load_stribeck_csv(p)
    np.testing.assert_allclose(d.torque, [1.0, 2.0, 3.0])
    assert set(d.branch) == {"accel"}
    assert not d.has_weights  # no repeats: no spread to weight by


@pytest.mark.parametrize(
    "name,text,line,fragment",
    [
        ("empty.csv", "", 1, "empty"),
        ("comments_only.csv", "# nothing here\n\n", 1, "empty"),
        ("header_only.csv", "velocity_deg_s,torque_nm\n", 1, "no data rows"),
        ("unknown.csv", "velocity_deg_s,torque_nm,temperature\n0.1,1,20\n", 1, "unknown column"),
        ("missing.csv", "velocity_deg_s\n0.1\n", 1, "missing column"),
        ("cells.csv", "velocity_deg_s,torque_nm\n0.1,1.0\n0.2\n", 3, "expected 2 cells"),
        ("text.csv", "velocity_deg_s,torque_nm\n0.1,1.0\n0.2,abc\n", 3, "torque_nm"),
        ("nan.csv", "velocity_deg_s,torque_nm\n0.1,1.0\nnan,2.0\n", 3, "finite"),
        ("inf.csv", "velocity_deg_s,torque_nm\n0.1,1.0\n0.2,inf\n", 3, "finite"),
        ("branch.csv", "velocity_deg_s,torque_nm,branch\n0.1,1.0,accel\n0.2,2.0,up\n", 3, "branch"),
        ("single.csv", "velocity_deg_s,torque_nm\n0.1,1.0\n0.1,1.1\n", 2, "single velocity"),
        ("blankcell.csv", "velocity_deg_s,torque_nm\n0.1,1.0\n,2.0\n", 3, "velocity_deg_s"),
    ],
)
def test_csv_malformed_names_file_and_line(tmp_path, name, text, line, fragment):
    p = _write(tmp_path, name, text)
    with pytest.raises(ValueError) as e:
        load_stribeck_csv(p)
    msg = str(e.value)
    assert f"{name}:{line}" in msg, msg
    assert fragment in msg, msg


def test_missing_path_is_a_clear_error(tmp_path):
    with pytest.raises(ValueError, match="no such file"):
        load_friction_data(tmp_path / "nope.csv")


# ------------------------------------------------------------------ EPOS exports

_EPOS_HEAD = (
    "Date:;2020-07-08 21:24:28{c}\r\nMax. samples:;4{c}\r\nRecorded samples:;4{c}\r\nSampling period:;51.200{c}\r\n"
    ";Velocity actual value averaged;Torque actual value averaged{c}\r\nms;rpm;%{c}\r\n"
)


def test_epos_file_sign_convention_and_units(tmp_path):
    p = _write(tmp_path, "10.csv", _EPOS_HEAD.format(c="") + "0.000;-10;-30.0\r\n51.2;-10;-32.0\r\n102.4;-11;-31.0\r\n153.6;-9;-31.0\r\n")
    r = load_epos_file(p)
    # omega = -rpm*pi/30 rad/s -> -rpm*6 deg/s; tau = -% * 9.84e-3/100 N*m
    np.testing.assert_allclose(r.velocity, [60.0, 60.0, 66.0, 54.0])
    np.testing.assert_allclose(r.torque, np.array([30.0, 32.0, 31.0, 31.0]) * 9.84e-5)
    np.testing.assert_allclose(r.time, [0.0, 0.0512, 0.1024, 0.1536])


def test_epos_trailing_commas_and_annotation(tmp_path):
    p = _write(tmp_path, "2.csv", _EPOS_HEAD.format(c=",,") + "0.000;-1;-800,,was -11.1\r\n128.0;-5;-10.6,,\r\n256.0;-1;-11.0,,\r\n384;-1;-11.6,,\r\n")
    r = load_epos_file(p)
    assert r.torque.size == 3  # the hand-corrected row is dropped
    np.testing.assert_allclose(r.torque, np.array([10.6, 11.0, 11.6]) * 9.84e-5)
    assert any("2.csv:7" in n and "was -11.1" in n for n in r.notes)


@pytest.mark.parametrize(
    "body,line,fragment",
    [
        ("0.000;-10;-30.0\r\n51.2;-10;abc\r\n", 8, "column 3"),
        ("0.000;-10;-30.0\r\n51.2;-10\r\n", 8, "expected 3"),
        ("0.000;-10;-30.0\r\n51.2;x;-30\r\n", 8, "column 2"),
        ("", 7, "no data rows"),
    ],
)
def test_epos_malformed_rows(tmp_path, body, line, fragment):
    p = _write(tmp_path, "bad.csv", _EPOS_HEAD.format(c="") + body)
    with pytest.raises(ValueError) as e:
        load_epos_file(p)
    assert f"bad.csv:{line}" in str(e.value) and fragment in str(e.value), str(e.value)


def test_epos_bad_units_and_missing_channel_line(tmp_path):
    p = _write(tmp_path, "units.csv", _EPOS_HEAD.format(c="").replace("ms;rpm;%", "ms;rad/s;%") + "0;1;1\r\n")
    with pytest.raises(ValueError, match=r"units\.csv:6.*rpm"):
        load_epos_file(p)
    p = _write(tmp_path, "nochan.csv", "Date:;2020\r\nms;rpm;%\r\n0;1;1\r\n")
    with pytest.raises(ValueError, match=r"nochan\.csv:\d+.*channel line"):
        load_epos_file(p)


def test_epos_folder_one_point_per_file(tmp_path):
    for name, rpm, pct in (("10.csv", -10, -30.0), ("20.csv", -20, -32.0), ("n10.csv", 10, 35.0)):
        _write(tmp_path, name, _EPOS_HEAD.format(c="") + "".join(f"{i * 51.2};{rpm};{pct + 0.1 * (i % 2)}\r\n" for i in range(4)))
    d = load_epos_steady_state(tmp_path)
    np.testing.assert_allclose(d.velocity, [-60.0, 60.0, 120.0])
    np.testing.assert_allclose(d.torque, np.array([-35.05, 29.95, 31.95]) * 9.84e-5)
    pos = d.direction(+1)
    np.testing.assert_allclose(pos.velocity, [60.0, 120.0])
    neg = d.direction(-1)
    np.testing.assert_allclose(neg.torque, [35.05 * 9.84e-5])


@pytest.mark.skipif(not TRO.is_dir(), reason="TRO2021 data not present at ../shared/data/tro2021")
def test_real_tro2021_folders():
    d1 = load_epos_steady_state(TRO / "driveNo1" / "steady_state" / "0.096kg")
    assert len(d1) == 32
    pos = d1.direction(+1)
    assert len(pos) == 16
    # Slowest positive run: 2 rpm ~ 12 deg/s, ~2.77 mN*m (mean of 500 samples of ~28 %).
    assert abs(pos.velocity[0] - 12.4) < 0.5 and abs(pos.torque[0] - 2.77e-3) < 0.02e-3
    assert np.all(pos.torque > 0)
    d3 = load_epos_steady_state(TRO / "driveNo3" / "steady_state" / "0.096kg")
    assert len(d3) == 46
    assert sum("was" in n for n in d3.notes) == 3
    assert np.all(np.isfinite(d3.torque)) and np.max(np.abs(d3.torque)) < 3e-3  # no -800 % spike
