"""Ctrl-C and SIGTERM during ``lugre-jax reproduce``: exit 130 / 143, one line on stderr, no crash, and
no unmarked partial output (issue 18). The run is interrupted once its temporary folder holds a file,
i.e. genuinely mid-run, and it is a rerun into a folder that already holds a previous result, which
must survive unchanged."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from lugre_jax.io import MANIFEST

ROOT = Path(__file__).resolve().parents[1]


def _cli_module() -> list[str]:
    """The installed ``lugre-jax`` entry point's module when present (it sets process options before
    the package is imported), else the package's CLI module."""
    root = Path(__file__).resolve().parents[1]
    return ["-m", "lugre_jax_cli"] if (root / "lugre_jax_cli.py").exists() else ["-m", "lugre_jax.cli"]


def default_sigint() -> None:
    """In the child before exec: SIGINT back to its default. A shell starts background jobs with SIGINT
    ignored and the CLI keeps an inherited SIG_IGN (as ``nohup`` asks), so a test run from such a job
    would otherwise send a SIGINT that the CLI rightly ignores, and the run completes."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)


def _previous_result(out: Path) -> dict:
    """A stand-in for an earlier complete result: a file and the manifest that marks it complete."""
    out.mkdir()
    (out / "REPORT.md").write_text("previous run\n")
    (out / MANIFEST).write_text(json.dumps({"complete": True, "files": {"REPORT.md": {}}}))
    return {p.name: p.read_bytes() for p in out.iterdir()}


def _interrupt_reproduce(tmp_path: Path, sig: int, extra: list[str], wait_for_file: bool
                         ) -> tuple[subprocess.CompletedProcess, Path]:
    out = tmp_path / "out"
    before = _previous_result(out)
    cmd = [sys.executable, *_cli_module(), "reproduce", "--quick", "--quiet", "--out", str(out), *extra]
    p = subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                         preexec_fn=default_sigint)
    # Wait until the run has written its first file into its temporary folder (mid-run, partial
    # output exists), or, quicker, until that folder exists (the run is compiling and running).
    deadline = time.monotonic() + 600
    while p.poll() is None and time.monotonic() < deadline:
        staging = list(tmp_path.glob(".out.incomplete-*"))
        if staging and (not wait_for_file or any(f for d in staging for f in d.iterdir())):
            break
        time.sleep(0.2)
    if not wait_for_file:
        time.sleep(2.0)
    assert p.poll() is None, f"reproduce ended before it could be interrupted: {p.communicate()}"
    p.send_signal(sig)
    stdout, stderr = p.communicate(timeout=300)
    res = subprocess.CompletedProcess(cmd, p.returncode, stdout, stderr)
    # The previous result is untouched, and nothing else was left beside it.
    assert {q.name: q.read_bytes() for q in out.iterdir()} == before
    assert sorted(q.name for q in tmp_path.iterdir()) == ["out"], list(tmp_path.iterdir())
    return res, out


@pytest.mark.parametrize("sig,code,word,wait_for_file", [(signal.SIGINT, 130, "Ctrl-C", True),
                                                         (signal.SIGTERM, 143, "SIGTERM", False)])
def test_interrupt_reproduce(tmp_path, sig, code, word, wait_for_file):
    res, _ = _interrupt_reproduce(tmp_path, sig, ["--only", "fig08"], wait_for_file)
    assert res.returncode == code, (res.returncode, res.stderr[-2000:])
    lines = res.stderr.strip().splitlines()
    assert lines == [f"lugre-jax reproduce: interrupted ({word})"], res.stderr[-2000:]
    assert "Traceback" not in res.stderr


@pytest.mark.slow
def test_reproduce_rerun_replaces_a_previous_result(tmp_path):
    """A complete quick run into a folder holding a previous result replaces it, manifest last."""
    out = tmp_path / "out"
    _previous_result(out)
    cmd = [sys.executable, *_cli_module(), "reproduce", "--quick", "--quiet", "--out", str(out),
           "--only", "fig08,table2"]
    r = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, timeout=1200)
    assert r.returncode == 0, r.stderr[-2000:]
    man = json.loads((out / MANIFEST).read_text())
    assert man["complete"] and "REPORT.md" in man["files"] and "fig08.png" in man["files"]
    assert (out / "REPORT.md").read_text() != "previous run\n"
    assert set(man["files"]) == {p.name for p in out.iterdir()} - {MANIFEST}
    assert sorted(q.name for q in tmp_path.iterdir()) == ["out"]


def test_refuses_a_foreign_folder(tmp_path):
    """A non-empty folder without a manifest is not replaced, and the refusal comes before any work."""
    out = tmp_path / "mine"
    out.mkdir()
    (out / "notes.txt").write_text("keep me")
    env = dict(os.environ)
    r = subprocess.run([sys.executable, *_cli_module(), "reproduce", "--out", str(out)], cwd=ROOT,
                       capture_output=True, text=True, timeout=300, env=env)
    assert r.returncode == 2
    assert len(r.stderr.strip().splitlines()) == 1 and str(out) in r.stderr and MANIFEST in r.stderr
    assert (out / "notes.txt").read_text() == "keep me" and len(list(out.iterdir())) == 1
