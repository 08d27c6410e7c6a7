"""``lugre-jax simulate``: output format, and one clear error (no traceback, nothing written) per bad input."""

import json
import subprocess
import sys

import numpy as np
import pytest

from lugre_jax.cli import main

GOOD = {
    "friction": {"model": "lugre", "Fc": 0.915, "Fs": 6.4808, "vs": 0.0315, "sigma0": 111.316,
                 "sigma1": 2.3042, "sigma2": 2.9804},
    "joint": {"J": 0.128},
    "controller": {"type": "velocity_pid", "kp": 8.0, "ki": 60.0},
    "reference": {"type": "velocity_steps", "levels": [0.01, 0.02], "dwell_s": 1.0},
    "duration_s": 2.0,
    "sample_hz": 50,
}


def _write(tmp_path, obj, name="s.json"):
    p = tmp_path / name
    p.write_text(obj if isinstance(obj, str) else json.dumps(obj))
    return p


def test_simulate_writes_csv_and_png(tmp_path):
    out, png = tmp_path / "t.csv", tmp_path / "t.png"
    assert main(["simulate", str(_write(tmp_path, GOOD)), "--out", str(out), "--plot", str(png)]) == 0
    header = out.read_text().splitlines()[0].split(",")
    assert header == ["time_s", "position_deg", "velocity_deg_s", "torque_nm", "z_deg",
                      "position_ref_deg", "velocity_ref_deg_s"]
    data = np.loadtxt(out, delimiter=",", skiprows=1)
    np.testing.assert_allclose(data[:, 0], np.arange(101) / 50)
    assert np.all(data[0, 1:3] == 0)  # starts at rest
    np.testing.assert_allclose(data[-1, 6], 0.02)  # the staircase reached its second level
    np.testing.assert_allclose(data[-1, 5], 0.01 + 0.02, rtol=1e-12)  # integral of the staircase
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    "mutate, expect",
    [
        (lambda d: d["joint"].update(J="heavy"), "joint.J: expected a finite number"),
        (lambda d: d["joint"].update(J=-1), "joint.J: expected a number > 0"),
        (lambda d: d.pop("controller"), "missing required key 'controller'"),
        (lambda d: d["controller"].update(type="bang_bang"), "controller.type: expected one of"),
        (lambda d: d.update(colour="red"), "unknown key 'colour'"),
        (lambda d: d["friction"].pop("sigma0"), "friction: missing required key 'sigma0'"),
        (lambda d: d["reference"].update(levels=[]), "reference.levels"),
        (lambda d: d.update(duration_s=1.005), "whole number of samples"),
        (lambda d: d.update(friction={"model": "segmented", "segments": [GOOD["friction"]] * 2, "edges": []}),
         "friction.edges: expected 1 ascending"),
    ],
)
def test_bad_scenarios_give_one_clear_error(tmp_path, capsys, mutate, expect):
    d = json.loads(json.dumps(GOOD))
    mutate(d)
    out = tmp_path / "t.csv"
    rc = main(["simulate", str(_write(tmp_path, d)), "--out", str(out)])
    err = capsys.readouterr().err
    assert rc == 2
    assert expect in err and "s.json" in err
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert not out.exists() and not list(tmp_path.glob(".t.csv*"))


def test_json_syntax_error_names_line_and_column(tmp_path, capsys):
    p = _write(tmp_path, '{"friction": "paper",\n  "joint": {"J": 0.1,}\n}')
    assert main(["simulate", str(p), "--out", str(tmp_path / "t.csv")]) == 2
    assert f"{p}:2:" in capsys.readouterr().err


def test_console_script_exit_code_and_single_line(tmp_path):
    r = subprocess.run([sys.executable, "-m", "lugre_jax_cli", "simulate", str(tmp_path / "missing.json"),
                        "--out", str(tmp_path / "t.csv")], capture_output=True, text=True)
    assert r.returncode == 2
    assert "missing.json: no such file; expected a scenario JSON file" in r.stderr
    assert len(r.stderr.strip().splitlines()) == 1


def test_a_non_passive_scenario_is_noted_by_name():
    """The paper's segment 1 is not passive (sigma2 2.98 against the 14.0 it needs): simulate builds it
    and says so on its progress channel in one line naming sigma2; a passive set gives no note."""
    import lugre_jax as lj
    from lugre_jax._cli.simulate import passivity_notes

    notes = passivity_notes(lj.paper_segment(1))
    assert len(notes) == 1 and "\n" not in notes[0] and notes[0].startswith("LuGre(sigma2=") and "not passive" in notes[0]
    passive = lj.LuGre(Fc=1.0, Fs=1.2, vs=0.1, sigma2=5.0, sigma0=100.0, sigma1=2.0)
    assert passivity_notes(passive) == []
