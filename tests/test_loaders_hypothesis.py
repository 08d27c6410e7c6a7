"""Property tests of every loader in lugre_jax.io that reads user files (recording CSV, Stribeck CSV,
EPOS export, --params JSON): random valid files round-trip (also with a UTF-8 byte-order mark and
CRLF line ends), and random corruptions either still give a valid file or raise one ``ValueError``
of one line naming the file -- never another exception. Corruptions that can never give a valid file
(semicolons, a duplicated or renamed column, NaN/inf, a foreign encoding) must raise.

Bounded (``max_examples``, no deadline) so the suite stays within the CI budget."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from lugre_jax.io import load_epos_file, load_recording, load_stribeck_csv, write_recording
from lugre_jax.io import recording_from_arrays
from lugre_jax.io._validate import load_params_json

SETTINGS = settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])


# ----------------------------------------------------------------------------------- helpers


def _variant(text: str, bom: bool, crlf: bool) -> bytes:
    if crlf:
        text = text.replace("\n", "\r\n")
    return (b"\xef\xbb\xbf" if bom else b"") + text.encode()


def _check_refusal(load, path, must_fail: bool):
    """Load ``path``: a valid result, or a one-line ValueError that names the file."""
    try:
        load(path)
    except ValueError as e:
        msg = str(e)
        assert "\n" not in msg and str(path) in msg, msg
        return
    assert not must_fail, f"{path} was accepted"


def _flip(data: bytes, i: int, b: int) -> bytes:
    i %= max(len(data), 1)
    return data[:i] + bytes([b]) + data[i + 1:]


# Corruptions of a comma-separated text file with a header line: (name, function(text, draw) -> bytes, always invalid)
def _corruptions(header_col: str):
    def dup(text, k):
        lines = text.splitlines()
        cells = lines[0].split(",")
        j = k % len(cells)
        body = [lines[0] + "," + cells[j]] + [ln + "," + ln.split(",")[j] for ln in lines[1:]]
        return ("\n".join(body) + "\n").encode()

    def rename(text, k):
        return text.replace(header_col, header_col.upper(), 1).encode()

    def nonfinite(text, k):
        lines = text.splitlines()
        i = 1 + k % (len(lines) - 1)
        cells = lines[i].split(",")
        cells[k % 2] = ["nan", "inf", "-inf", "NaN"][k % 4]
        lines[i] = ",".join(cells)
        return ("\n".join(lines) + "\n").encode()

    def semicolons(text, k):
        return text.replace(",", ";").encode()

    def utf16(text, k):
        return text.encode("utf-16")

    def latin1(text, k):
        return text.replace(header_col, header_col + "\xb0", 1).encode("latin-1")

    def cut(text, k):
        data = text.encode()
        return data[: k % len(data)]

    def flip(text, k):
        return _flip(text.encode(), k, (k * 7919) % 256)

    def drop_cell(text, k):
        lines = text.splitlines()
        i = 1 + k % (len(lines) - 1)
        lines[i] = ",".join(lines[i].split(",")[:-1])
        return ("\n".join(lines) + "\n").encode()

    return [("duplicate column", dup, True), ("renamed column", rename, True), ("NaN/inf", nonfinite, True),
            ("semicolons", semicolons, True), ("UTF-16", utf16, True), ("Latin-1", latin1, True),
            ("row cut", drop_cell, True), ("truncated file", cut, False), ("byte flipped", flip, False)]


# --------------------------------------------------------------------------------- recordings


@st.composite
def recordings(draw):
    n = draw(st.integers(100, 400))
    dt = draw(st.sampled_from([1e-3, 2e-3, 0.01, 0.02]))
    amp = draw(st.floats(0.5, 100.0))
    w = draw(st.floats(0.2, 5.0))
    seed = draw(st.integers(0, 2**31 - 1))
    rng = np.random.default_rng(seed)
    t = np.round(np.arange(n) * dt, 9)
    pos = amp * np.sin(w * t) + 0.01 * rng.standard_normal(n)
    vel = amp * w * np.cos(w * t)
    tor = np.tanh(vel) + 0.05 * rng.standard_normal(n)
    return recording_from_arrays(t, pos, vel, tor)


@SETTINGS
@given(rec=recordings(), bom=st.booleans(), crlf=st.booleans())
def test_recording_round_trip(tmp_path, rec, bom, crlf):
    p = tmp_path / "r.csv"
    write_recording(p, rec)
    p.write_bytes(_variant(p.read_text(), bom, crlf))
    back = load_recording(p)
    for a, b in ((back.time, rec.time), (back.position, rec.position), (back.velocity, rec.velocity),
                 (back.torque, rec.torque)):
        np.testing.assert_allclose(a, b, rtol=1e-10, atol=1e-12)  # written with 12 significant digits


@SETTINGS
@given(rec=recordings(), which=st.integers(0, 8), k=st.integers(0, 10**6))
def test_recording_corruptions_raise_one_line(tmp_path, rec, which, k):
    p = tmp_path / "r.csv"
    write_recording(p, rec)
    name, corrupt, always = _corruptions("torque_nm")[which]
    p.write_bytes(corrupt(p.read_text(), k))
    _check_refusal(load_recording, p, always)


# ------------------------------------------------------------------------------- Stribeck CSV


@st.composite
def stribeck_files(draw):
    n_v = draw(st.integers(2, 12))
    vels = sorted(draw(st.sets(st.floats(0.001, 5.0).map(lambda x: round(x, 6)), min_size=n_v, max_size=n_v)))
    reps = draw(st.integers(1, 4))
    signs = draw(st.sampled_from([1, -1]))
    rows = []
    for v in vels:
        for _ in range(reps):
            f = round(draw(st.floats(-10.0, 10.0)), 6)
            rows.append((signs * v, f, draw(st.sampled_from(["accel", "decel", None]))))
    # a branch that occurs needs two distinct velocities: put the branch-less rows in "accel"
    by = {}
    for v, _, b in rows:
        by.setdefault(b or "accel", set()).add(v)
    rows = [(v, f, b if b is None or len(by[b or "accel"]) >= 2 else None) for v, f, b in rows]
    by = {}
    for v, _, b in rows:
        by.setdefault(b or "accel", set()).add(v)
    if any(len(s) < 2 for s in by.values()):
        rows = [(v, f, None) for v, f, _ in rows]
    return rows


def _stribeck_text(rows) -> str:
    return "velocity_deg_s,torque_nm,branch\n" + "".join(f"{v!r},{f!r},{b or 'accel'}\n" for v, f, b in rows)


@SETTINGS
@given(rows=stribeck_files(), bom=st.booleans(), crlf=st.booleans(), comment=st.booleans())
def test_stribeck_round_trip(tmp_path, rows, bom, crlf, comment):
    p = tmp_path / "s.csv"
    text = ("# a comment line\n" if comment else "") + _stribeck_text(rows)
    p.write_bytes(_variant(text, bom, crlf))
    d = load_stribeck_csv(p)
    # Reference: the mean torque per (branch, velocity), computed independently.
    ref: dict = {}
    for v, f, b in rows:
        ref.setdefault((b or "accel", v), []).append(f)
    got = {(str(b), float(v)): (float(m), int(c)) for b, v, m, c in zip(d.branch, d.velocity, d.torque, d.count)}
    assert set(got) == set(ref)
    for key, fs in ref.items():
        assert got[key][1] == len(fs)
        assert math.isclose(got[key][0], float(np.mean(fs)), rel_tol=1e-12, abs_tol=1e-12)


@SETTINGS
@given(rows=stribeck_files(), which=st.integers(0, 8), k=st.integers(0, 10**6))
def test_stribeck_corruptions_raise_one_line(tmp_path, rows, which, k):
    p = tmp_path / "s.csv"
    name, corrupt, always = _corruptions("velocity_deg_s")[which]
    p.write_bytes(corrupt(_stribeck_text(rows), k))
    _check_refusal(load_stribeck_csv, p, always)


# ------------------------------------------------------------------------------------- EPOS


_EPOS_HEAD = ("Date:;2020-07-08 21:24:28\nMax. samples:;{n}\nRecorded samples:;{n}\nSampling period:;51.200\n"
              ";Velocity actual value averaged;Torque actual value averaged\nms;rpm;%\n")


@st.composite
def epos_rows(draw):
    n = draw(st.integers(1, 30))
    rpm = draw(st.lists(st.integers(-3000, 3000), min_size=n, max_size=n))
    pct = draw(st.lists(st.floats(-300, 300).map(lambda x: round(x, 3)), min_size=n, max_size=n))
    return rpm, pct


def _epos_text(rpm, pct, trailing: str = "") -> str:
    return _EPOS_HEAD.format(n=len(rpm)).replace("\n", trailing + "\n") + "".join(
        f"{51.2 * i:.1f};{r};{q}{trailing}\n" for i, (r, q) in enumerate(zip(rpm, pct)))


@SETTINGS
@given(rows=epos_rows(), bom=st.booleans(), crlf=st.booleans(), trailing=st.sampled_from(["", ",", ",,"]))
def test_epos_round_trip(tmp_path, rows, bom, crlf, trailing):
    rpm, pct = rows
    p = tmp_path / "e.csv"
    p.write_bytes(_variant(_epos_text(rpm, pct, trailing), bom, crlf))
    r = load_epos_file(p, nominal_torque_nm=9.84e-3)
    np.testing.assert_allclose(r.velocity, -np.asarray(rpm, float) * 6.0, rtol=0, atol=0)
    np.testing.assert_allclose(r.torque, -np.asarray(pct) * 9.84e-3 / 100, rtol=1e-15, atol=0)
    np.testing.assert_allclose(r.time, np.arange(len(rpm)) * 51.2e-3, rtol=1e-12)


@SETTINGS
@given(rows=epos_rows(), which=st.sampled_from(["nan", "text", "utf16", "latin1", "cells", "flip", "cut"]),
       k=st.integers(0, 10**6))
def test_epos_corruptions_raise_one_line(tmp_path, rows, which, k):
    rpm, pct = rows
    text = _epos_text(rpm, pct)
    lines = text.splitlines()
    i = 6 + k % len(rpm)
    if which == "nan":
        lines[i] = lines[i].rsplit(";", 1)[0] + ";nan"
        data, always = ("\n".join(lines) + "\n").encode(), True
    elif which == "text":
        lines[i] = lines[i].rsplit(";", 1)[0] + ";12,5%"
        data, always = ("\n".join(lines) + "\n").encode(), True
    elif which == "utf16":
        data, always = text.encode("utf-16"), True
    elif which == "latin1":
        data, always = text.replace("Date:", "Dat\xe9:").encode("latin-1"), True
    elif which == "cells":
        lines[i] += ";1"
        data, always = ("\n".join(lines) + "\n").encode(), True
    elif which == "flip":
        data, always = _flip(text.encode(), k, (k * 31) % 256), False
    else:
        data, always = text.encode()[: k % len(text)], False
    p = tmp_path / "e.csv"
    p.write_bytes(data)
    _check_refusal(load_epos_file, p, always)


# ------------------------------------------------------------------------------ --params JSON


@st.composite
def params(draw):
    fc = draw(st.floats(0.0, 100.0))
    return {"J": draw(st.floats(1e-4, 1e3)), "Fc": fc, "Fs": fc + draw(st.floats(0.0, 100.0)),
            "vs": draw(st.floats(1e-4, 10.0)), "sigma2": draw(st.floats(0.0, 100.0)),
            "sigma0": draw(st.floats(1e-2, 1e8)), "sigma1": draw(st.floats(0.0, 1e3)),
            "friction_model": "LuGre"}


@SETTINGS
@given(p=params(), bom=st.booleans(), report=st.booleans())
def test_params_round_trip(tmp_path, p, bom, report):
    f = tmp_path / "p.json"
    obj = {"baseline": {"params": p}} if report else p
    f.write_bytes(_variant(json.dumps(obj, indent=1), bom, False))
    assert load_params_json(f) == p


@SETTINGS
@given(p=params(), key=st.sampled_from(["J", "Fc", "Fs", "vs", "sigma2", "sigma0", "sigma1"]),
       bad=st.sampled_from([float("nan"), float("inf"), -1.0, 1e300, "1", None, True, [1.0], {}]))
def test_params_bad_values_raise_one_line(tmp_path, p, key, bad):
    if bad == -1.0 and key in ("Fs",) and p["Fc"] == 0:
        bad = float("nan")  # Fs = -1 is caught too, but keep every example a certain refusal
    f = tmp_path / "p.json"
    p = dict(p, **{key: bad})
    f.write_text(json.dumps(p))
    _check_refusal(load_params_json, f, True)


@SETTINGS
@given(p=params(), k=st.integers(0, 10**6), how=st.sampled_from(["flip", "cut", "utf16"]))
def test_params_corrupted_bytes(tmp_path, p, k, how):
    text = json.dumps(p)
    data = {"flip": _flip(text.encode(), k, (k * 13) % 256), "cut": text.encode()[: k % len(text)],
            "utf16": text.encode("utf-16")}[how]
    f = tmp_path / "p.json"
    f.write_bytes(data)
    _check_refusal(load_params_json, f, how == "utf16")


def test_strategies_are_exercised():
    """The corruption list covers the classes the issue names (a guard against silently dropping one)."""
    names = {n for n, _, _ in _corruptions("x")}
    assert {"duplicate column", "renamed column", "NaN/inf", "semicolons", "UTF-16", "Latin-1", "row cut",
            "truncated file", "byte flipped"} <= names
    with pytest.raises(ValueError):
        load_params_json("/nonexistent/p.json")


# ------------------------------------------------------------------- the same, through the CLI


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(rec=recordings(), rows=stribeck_files(), which=st.integers(0, 6), k=st.integers(0, 10**6),
       cmd=st.sampled_from(["diagnose", "identify"]))
def test_cli_refuses_corrupt_files_with_exit_2_and_no_output(tmp_path_factory, monkeypatch, capsys, rec, rows, which,
                                                             k, cmd):
    import lugre_jax.cli as cli

    monkeypatch.setattr(cli, "_configure_process", lambda no_cache: None)
    d = tmp_path_factory.mktemp("cli")
    src = d / "in.csv"
    if cmd == "diagnose":
        write_recording(src, rec)
        name, corrupt, always = _corruptions("torque_nm")[which]
        src.write_bytes(corrupt(src.read_text(), k))
    else:
        name, corrupt, always = _corruptions("velocity_deg_s")[which]
        src.write_bytes(corrupt(_stribeck_text(rows), k))
    assert always  # classes 0-6 can never give a valid file
    out = d / "out" / "r.json"
    code = cli.main([cmd, str(src), "--out", str(out), "--quiet"])
    err = capsys.readouterr().err.strip().splitlines()
    assert code == 2 and len(err) == 1 and str(src) in err[0], (name, err)
    assert sorted(p.name for p in d.iterdir()) == ["in.csv"]
