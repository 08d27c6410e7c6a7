"""The CLI's conventions (docs/errors.md): the command line and every output path are checked before
JAX loads; one output rule, one quiet flag, one manifest name; resource guards and the top-level
catch give one line, never a traceback; progress in a log is plain lines with totals and ETA."""

from __future__ import annotations

import io
import json
import subprocess
import sys
from pathlib import Path

import pytest

import lugre_jax.cli as cli
from malformed_inputs import SWEEP_SPEC, UNWRITABLE, files_under

ROOT = Path(__file__).resolve().parents[1]

# Runs the entry point's early phase the way the console script does, then reports what was imported.
_PROBE = """
import sys, lugre_jax_cli
sys.argv = ["lugre-jax", *sys.argv[1:]]
try:
    code = lugre_jax_cli._early_check(sys.argv[1:])
except SystemExit as e:
    code = e.code
print("IMPORTED", "jax" in sys.modules, "lugre_jax" in sys.modules, "numpy" in sys.modules, code, file=sys.stderr)
"""


def _early(*argv: str, cwd: Path = ROOT) -> tuple[int | None, list[str], tuple[bool, bool, bool]]:
    r = subprocess.run([sys.executable, "-c", _PROBE, *argv], capture_output=True, text=True, cwd=cwd, timeout=120)
    lines = r.stderr.strip().splitlines()
    tag = lines[-1].split()
    assert tag[0] == "IMPORTED", r.stderr
    code = None if tag[4] == "None" else int(tag[4])
    return code, lines[:-1], (tag[1] == "True", tag[2] == "True", tag[3] == "True")


@pytest.mark.parametrize("argv", [["--help"], ["sweep", "--help"], ["emps", "--help"], ["diagnose", "--help"]])
def test_help_needs_neither_jax_nor_the_package(argv):
    code, _, (jax, pkg, numpy) = _early(*argv)
    assert code == 0
    assert not jax and not pkg and not numpy


def test_argument_error_before_jax():
    code, lines, (jax, pkg, _) = _early("identify", "--out", "r.json")  # DATA missing
    assert code == 2 and not jax and not pkg
    assert "required" in lines[-1]


@pytest.mark.parametrize("make, flag", [
    (lambda d: ["emps", "--out", str(d / "taken.txt")], "--out"),  # an existing file for a folder output
    (lambda d: ["emps", "--out", f"{UNWRITABLE}/emps_out"], "--out"),  # nothing can be written there
    (lambda d: ["sweep", str(d / "spec.json"), "--out", str(d / "taken.txt")], "--out"),
    (lambda d: ["sweep", str(d / "spec.json"), "--out", f"{UNWRITABLE}/sw"], "--out"),
    (lambda d: ["simulate", str(d / "s.json"), "--out", str(d / "folder")], "--out"),  # a folder for a file
    (lambda d: ["simulate", str(d / "s.json"), "--out", str(d / "t.csv"), "--plot", str(d / "t.csv")], "--plot"),
    (lambda d: ["identify", str(d / "x.csv"), "--out", str(d / "taken.txt" / "r.json")], "--out"),  # parent: a file
    (lambda d: ["bench", "--out", f"{UNWRITABLE}/b.json"], "--out"),
    (lambda d: ["reproduce", "--out", str(d / "folder")], "--out"),  # a folder the user filled
    (lambda d: ["reproduce", "--out", str(d / "emps_result")], "--out"),  # another command's result
    (lambda d: ["reproduce", "--out", str(d / "r"), "--setup-cache", str(d / "r" / "s.json")], "--setup-cache"),
])
def test_outputs_refused_before_jax_with_one_line_naming_the_flag(tmp_path, make, flag):
    (tmp_path / "taken.txt").write_text("x")
    for name in ("spec.json", "s.json", "x.csv"):  # inputs (checked for existence only, before outputs)
        (tmp_path / name).write_text("{}")
    (tmp_path / "folder").mkdir()
    (tmp_path / "folder" / "notes.txt").write_text("keep me")
    (tmp_path / "emps_result").mkdir()
    (tmp_path / "emps_result" / "MANIFEST.json").write_text(json.dumps({"meta": {"command": "emps"}}))
    before = files_under(tmp_path)
    argv = make(tmp_path)
    code, lines, (jax, pkg, _) = _early(*argv)
    assert code == 2 and len(lines) == 1, lines
    assert lines[0].startswith(f"lugre-jax {argv[0]}: error: {flag} "), lines[0]
    assert not jax and not pkg  # refused before any work: the package was not even imported
    assert files_under(tmp_path) == before


@pytest.mark.parametrize("argv, named", [
    (["simulate", "{d}/nope.json", "--out", "{d}/t.csv"], "{d}/nope.json: no such file"),
    (["identify", "{d}/nope.csv", "--out", "{d}/r.json"], "{d}/nope.csv: no such file or folder"),
    (["sweep", "{d}", "--out", "{d}/out"], "{d}: is a folder"),
    (["reproduce", "--data", "{d}/nope.csv", "--out", "{d}/out"], "--data {d}/nope.csv: no such file"),
])
def test_missing_inputs_answered_before_jax(tmp_path, argv, named):
    argv = [a.format(d=tmp_path) for a in argv]
    code, lines, (jax, pkg, _) = _early(*argv)
    assert code == 2 and len(lines) == 1 and not jax and not pkg, lines
    assert lines[0].startswith(f"lugre-jax {argv[0]}: error: {named.format(d=tmp_path)}"), lines[0]


def test_early_phase_passes_good_commands_on(tmp_path):
    """A usable command is not decided early (None: the full CLI runs it)."""
    code, lines, (jax, _, _) = _early("emps", "--out", str(tmp_path / "new"), "--quiet")
    assert code is None and lines == [] and not jax


def test_same_job_folder_accepted_other_refused(tmp_path):
    from lugre_jax._cli._outputs import check_output_folder

    d = tmp_path / "res"
    d.mkdir()
    (d / "RESULT.json").write_text("{}")
    with pytest.raises(ValueError, match="holds no MANIFEST.json"):
        check_output_folder(d, "--out", "emps")
    (d / "MANIFEST.json").write_text(json.dumps({"meta": {"command": "emps"}}))
    assert check_output_folder(d, "--out", "emps") == d
    with pytest.raises(ValueError, match="holds a result of 'emps', not of 'reproduce'"):
        check_output_folder(d, "--out", "reproduce")


def test_one_manifest_name_and_one_quiet_flag():
    from lugre_jax._cli import _outputs
    from lugre_jax.io import MANIFEST

    assert _outputs.MANIFEST == MANIFEST
    parser, _ = cli.build_parser()
    minimal = {"simulate": ["s.json", "--out", "t.csv"], "bench": ["--out", "b.json"],
               "identify": ["d.csv", "--out", "r.json"], "reproduce": ["--out", "d"],
               "diagnose": ["r.csv", "--out", "r.json"], "emps": ["--out", "d"], "sweep": ["s.json", "--out", "d"]}
    assert set(minimal) == set(cli.SUBCOMMANDS)
    for cmd, argv in minimal.items():
        assert parser.parse_args([cmd, *argv, "--quiet"]).quiet is True, cmd
        assert parser.parse_args([cmd, *argv]).quiet is False, cmd
    # the former name still works where it was used, and is not shown
    import argparse

    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    for cmd in ("reproduce", "sweep"):
        assert parser.parse_args([cmd, *minimal[cmd], "--no-progress"]).quiet is True
        assert "--no-progress" not in sub.choices[cmd].format_help()


def _sweep_spec(tmp_path, n):
    p = tmp_path / "spec.json"
    p.write_text(json.dumps(dict(SWEEP_SPEC, n=n)))
    return p


def test_sweep_memory_guard_one_line_with_figure_and_split(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(cli, "_configure_process", lambda no_cache: None)
    spec = _sweep_spec(tmp_path, 2 ** 30)
    code = cli.main(["sweep", str(spec), "--out", str(tmp_path / "out"), "--quiet"])
    err = capsys.readouterr().err.strip()
    assert code == 2 and len(err.splitlines()) == 1, err
    assert "4,294,967,296 points" in err and "GiB" in err and '"n" at most' in err and '"seed"' in err, err
    assert not (tmp_path / "out").exists()


def test_sweep_memory_estimate_bounds_the_samples(tmp_path):
    """The estimate covers at least the sample array the runner builds (an independent count), and
    the largest "n" it suggests fits under the limit while twice that does not."""
    from lugre_jax._cli import sweep as cmd
    from lugre_jax.sweep import load_spec

    spec = load_spec(_sweep_spec(tmp_path, 64))
    X = spec.sampler.sample(spec.problem, spec.n, spec.seed)
    points, need = cmd.memory_estimate(spec)
    assert points == X.shape[0] and need >= 3 * X.nbytes
    limit = 10 * 1024 ** 2
    with pytest.raises(ValueError, match='"n" at most') as e:
        cmd.check_memory(load_spec(_sweep_spec(tmp_path, 2 ** 16)), "spec", limit)
    n_max = int(str(e.value).split('"n" at most ')[1].split(" ")[0].replace(",", ""))
    assert cmd.memory_estimate(spec, n_max)[1] <= limit < cmd.memory_estimate(spec, 2 * n_max)[1]


@pytest.mark.parametrize("exc, code, words", [
    (MemoryError("Unable to allocate 32.0 GiB"), 2, "out of memory"),
    (RuntimeError("RESOURCE_EXHAUSTED: Out of memory allocating 34359738368 bytes."), 2, "out of memory"),
    (RuntimeError("boom"), 1, "internal error (RuntimeError)")])
def test_no_traceback_reaches_the_user(tmp_path, capsys, monkeypatch, exc, code, words):
    from lugre_jax._cli import bench

    monkeypatch.setattr(cli, "_configure_process", lambda no_cache: None)
    monkeypatch.delenv("LUGRE_JAX_TRACEBACK", raising=False)

    def fail(args):
        raise exc

    monkeypatch.setattr(bench, "run", fail)
    assert cli.main(["bench", "--out", str(tmp_path / "b.json")]) == code
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1 and err.startswith("lugre-jax bench: error: ") and words in err, err
    assert str(exc) in err


def test_progress_in_a_log_is_plain_lines_with_total_and_eta():
    buf = io.StringIO()
    LogLines = cli._log_lines_class(interval_s=0.0)
    with LogLines(total=4, desc="experiments", file=buf) as bar:
        for _ in range(4):
            bar.update(1)
    text = buf.getvalue()
    assert "\r" not in text and "\x1b" not in text
    lines = text.splitlines()
    assert lines[0].startswith("experiments: 0/4 (0 %)") and "ETA" in lines[0]
    assert lines[-1].startswith("experiments: 4/4 (100 %)") and lines[-1].endswith("ETA 0:00")
    assert any(ln.startswith("experiments: 2/4 (50 %)") for ln in lines)
    # at most one line per interval: a long interval gives the first and the last line only
    buf = io.StringIO()
    with cli._log_lines_class(interval_s=3600.0)(total=100, desc="sweep", file=buf) as bar:
        for _ in range(100):
            bar.update(1)
    assert [ln.split(",")[0] for ln in buf.getvalue().splitlines()] == ["sweep: 0/100 (0 %)", "sweep: 100/100 (100 %)"]


def test_log_progress_replaces_tqdm_auto_only_inside_the_command(monkeypatch):
    import tqdm.auto

    original = tqdm.auto.tqdm
    monkeypatch.setattr(sys, "stderr", io.StringIO())  # not a terminal
    with cli._progress_for_logs(True):
        assert tqdm.auto.tqdm is not original and tqdm.auto.tqdm.__name__ == "LogLines"
    assert tqdm.auto.tqdm is original
    with cli._progress_for_logs(False):  # --quiet: the command's own disable= decides
        assert tqdm.auto.tqdm is original


@pytest.mark.parametrize("quiet", [False, True])
def test_a_commands_bars_become_lines_in_a_log(tmp_path, capsys, monkeypatch, quiet):
    """Through ``main``: a subcommand's ``tqdm.auto`` bar (as the library's are made) prints plain
    lines when stderr is not a terminal, and nothing with --quiet (the command passes disable=)."""
    from lugre_jax._cli import bench

    monkeypatch.setattr(cli, "_configure_process", lambda no_cache: None)

    def run(args):
        from tqdm.auto import tqdm

        for _ in tqdm(range(3), desc="work", disable=args.quiet):
            pass
        return 0

    monkeypatch.setattr(bench, "run", run)
    assert cli.main(["bench", "--out", str(tmp_path / "b.json"), *(["--quiet"] if quiet else [])]) == 0
    err = capsys.readouterr().err
    if quiet:
        assert err == ""
    else:
        assert "\r" not in err and err.splitlines()[-1].startswith("work: 3/3 (100 %), elapsed "), err


def test_log_line_without_a_total_gives_no_eta():
    buf = io.StringIO()
    with cli._log_lines_class(interval_s=0.0)(desc="fit", unit=" evals", file=buf) as bar:
        bar.update(5)
    last = buf.getvalue().splitlines()[-1]
    assert last.startswith("fit: 5 evals, elapsed ") and "ETA" not in last, last
