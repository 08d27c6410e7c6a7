"""The documentation runs: every ```python block of README.md and docs/*.md is executed, and every
``lugre-jax ...`` command they show is parsed by the real argument parser.

Conventions for doc authors (picked up automatically, whatever blocks exist):
- A ```python block that imports something is a program: it runs in a fresh process, from a scratch
  folder in which ``data/`` and ``experiments/`` point to the repository's (so relative paths in the
  docs resolve and nothing is written into the repository), after ``lugre_jax.configure()`` unless
  the block calls it. Blocks of one file run in order in one process (a later block may use an
  earlier block's names). A block without any import is an excerpt (a signature, a class outline)
  and is not run.
- ``<!-- no-run -->`` on the line before a fence excludes that block; ``<!-- slow -->`` runs it only
  with the slow tests.
- Commands: every line of a ```bash / ```sh / ```console block that starts with ``lugre-jax`` (also
  after ``&&``) is parsed in full and run to completion in a scratch folder; an inline
  `lugre-jax ...` (usage lines with [optional] parts and ``...``) is checked at the option level: the
  subcommand exists and knows every --option named.

In the default (CI) suite: every python block of README.md and docs/*.md not marked ``<!-- slow -->``
(today README's API example, docs/identification.md's two, docs/sweeps.md's one), and every fenced
command except those in :data:`SLOW_COMMANDS` (today an identify and a grid sweep): the whole file took
47 s on 2 cores (``pytest tests/test_docs_run.py --durations=6``, 2026-11-24). Slow only (``-m
slow``), because each runs for minutes: ``lugre-jax reproduce --out results`` (README.md, the full
reproduction) and ``lugre-jax sweep experiments/scenarios/sweep_wide_lhs.json --out runs/wide``
(docs/sweeps.md, 2,048 lanes with stiff re-solves). A guard test keeps that list in step with the docs.
"""

from __future__ import annotations

import os
import re
import shlex
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
# Fenced commands that run for minutes: parsed in CI, run only with the slow tests (exact text).
SLOW_COMMANDS = {
    "lugre-jax reproduce --out results",
    "lugre-jax sweep experiments/scenarios/sweep_wide_lhs.json --out runs/wide",
}
DOCS = [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]
FENCE = re.compile(r"^```([\w+-]*)\s*$")


def _cli_module() -> list[str]:
    """The installed ``lugre-jax`` entry point's module when present (it sets process options before
    the package is imported), else the package's CLI module."""
    root = Path(__file__).resolve().parents[1]
    return ["-m", "lugre_jax_cli"] if (root / "lugre_jax_cli.py").exists() else ["-m", "lugre_jax.cli"]


def blocks(path: Path) -> list[dict]:
    """Fenced blocks of a Markdown file: language, text, first line number, and the marker comment
    on the line before the fence (if any)."""
    out, cur, lines = [], None, path.read_text().splitlines()
    for i, line in enumerate(lines):
        s = line.strip()
        if cur is None:
            m = FENCE.match(s)
            if m:
                prev = lines[i - 1].strip() if i else ""
                cur = dict(lang=m.group(1).lower(), start=i + 2, text=[],
                           mark="no-run" if "<!-- no-run" in prev else ("slow" if "<!-- slow" in prev else ""))
        elif s == "```":
            cur["text"] = "\n".join(cur["text"])
            out.append(cur)
            cur = None
        else:
            cur["text"].append(line)
    return out


def python_programs(path: Path) -> list[dict]:
    return [b for b in blocks(path) if b["lang"] in ("python", "py") and b["mark"] != "no-run"
            and re.search(r"^\s*(import|from)\s", b["text"], re.M)]


def fenced_commands(path: Path) -> list[tuple[int, str]]:
    cmds = []
    for b in blocks(path):
        if b["lang"] not in ("bash", "sh", "shell", "console") or b["mark"] == "no-run":
            continue
        for k, line in enumerate(b["text"].splitlines()):
            line = re.sub(r"^\$\s*", "", line.strip())
            line = re.sub(r"\s+#.*$", "", line)
            for part in re.split(r"\s*(?:&&|;|\|\|)\s*", line):
                if part.startswith("lugre-jax"):
                    cmds.append((b["start"] + k, part))
    return cmds


def inline_commands(path: Path) -> list[tuple[int, str]]:
    out = []
    for i, line in enumerate(path.read_text().splitlines(), 1):
        if line.strip().startswith("```"):
            continue
        out += [(i, m) for m in re.findall(r"`(lugre-jax[^`]*)`", line)]
    return out


def _parser():
    from lugre_jax.cli import build_parser

    return build_parser()[0]


def _subparsers(parser):
    import argparse

    act = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    return act.choices


def _scratch(tmp_path: Path) -> Path:
    for name in ("data", "experiments"):
        if (ROOT / name).exists():
            (tmp_path / name).symlink_to(ROOT / name)
    return tmp_path


# ------------------------------------------------------------------------------ python blocks


def _program(path: Path, bs: list[dict]) -> str:
    body = []
    for b in bs:
        body.append(f"# --- {path.name}:{b['start']}\n{textwrap.dedent(b['text'])}\n")
    src = "\n".join(body)
    if "configure(" not in src:
        src = "import lugre_jax\nlugre_jax.configure()\n" + src
    return src


def _run_python(path: Path, bs: list[dict], tmp_path: Path) -> None:
    src = _program(path, bs)
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    r = subprocess.run([sys.executable, "-c", src], cwd=_scratch(tmp_path), capture_output=True, text=True, env=env,
                       timeout=3600)
    where = ", ".join(f"{path.name}:{b['start']}" for b in bs)
    assert r.returncode == 0, f"python blocks at {where} failed:\n{r.stderr[-3000:]}"


def _doc_params(slow: bool):
    """One case per file: its unmarked blocks (fast), or, for the slow tests, all its blocks when any
    is marked slow (a slow block may use names of the blocks before it)."""
    out = []
    for p in DOCS:
        bs = python_programs(p)
        fast = [b for b in bs if b["mark"] != "slow"]
        if not slow and fast:
            out.append(pytest.param(p, fast, id=p.name))
        if slow and len(fast) < len(bs):
            out.append(pytest.param(p, bs, id=p.name + "-with-slow-blocks"))
    return out


@pytest.mark.parametrize("path,bs", _doc_params(slow=False))
def test_python_blocks_run(path, bs, tmp_path):
    _run_python(path, bs, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("path,bs", _doc_params(slow=True))
def test_slow_python_blocks_run(path, bs, tmp_path):
    _run_python(path, bs, tmp_path)


def test_harness_finds_the_readme_example():
    """Guard: the harness sees the README's python example (a harness that finds nothing passes)."""
    assert python_programs(ROOT / "README.md"), "no runnable ```python block found in README.md"
    assert any(fenced_commands(p) for p in DOCS) and any(inline_commands(p) for p in DOCS)
    assert _doc_params(slow=False) and _fenced(slow=False), "nothing of the docs runs in the default suite"


def test_slow_commands_are_in_the_docs():
    """Guard: every command kept out of the default suite is still shown in the docs (a stale entry
    would hide nothing, but a renamed heavy command would then run in CI: keep the list exact)."""
    shown = {c for p in DOCS for _, c in fenced_commands(p)}
    assert SLOW_COMMANDS <= shown, sorted(SLOW_COMMANDS - shown)


# ---------------------------------------------------------------------------------- commands


def _all_fenced():
    return [pytest.param(c, id=f"{p.name}:{ln}") for p in DOCS for ln, c in fenced_commands(p)]


def _fenced(slow: bool):
    return [pytest.param(c, id=f"{p.name}:{ln}") for p in DOCS for ln, c in fenced_commands(p)
            if (c in SLOW_COMMANDS) == slow]


def _all_inline():
    return [pytest.param(c, id=f"{p.name}:{ln}") for p in DOCS for ln, c in inline_commands(p)]


@pytest.mark.parametrize("cmd", _all_fenced())
def test_fenced_commands_parse(cmd):
    argv = shlex.split(cmd)[1:]
    try:
        _parser().parse_args(argv)
    except SystemExit as e:
        pytest.fail(f"{cmd!r} does not parse (exit {e.code})")


@pytest.mark.parametrize("cmd", _all_inline())
def test_inline_commands_name_real_options(cmd):
    """Usage lines: the subcommand exists and every --option shown is one of its options."""
    parser = _parser()
    words = cmd.replace("\\|", "|").split()[1:]
    top = {s for a in parser._actions for s in a.option_strings}
    words = [w for w in words if w.strip("[]") not in top]  # global options before the subcommand
    if not words or words[0].startswith(("[", ".")):
        return  # "lugre-jax --no-cache ...": only global options, checked above
    subs = _subparsers(parser)
    assert words[0] in subs, f"{cmd!r}: no subcommand {words[0]!r}; the CLI has {sorted(subs)}"
    known = {s for a in subs[words[0]]._actions for s in a.option_strings}
    for w in words[1:]:
        flag = w.strip("[]").split("=")[0]
        if flag.startswith("--"):
            assert flag in known, f"{cmd!r}: {words[0]} has no option {flag}; it has {sorted(known)}"


@pytest.mark.parametrize("cmd", _fenced(slow=False))
def test_fenced_commands_run(cmd, tmp_path):
    _run_command(cmd, tmp_path)


@pytest.mark.slow
@pytest.mark.parametrize("cmd", _fenced(slow=True))
def test_slow_fenced_commands_run(cmd, tmp_path):
    _run_command(cmd, tmp_path)


def _run_command(cmd: str, tmp_path: Path) -> None:
    env = dict(os.environ, MPLBACKEND="Agg", PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))
    argv = shlex.split(cmd)[1:]
    r = subprocess.run([sys.executable, *_cli_module(), *argv], cwd=_scratch(tmp_path), capture_output=True,
                       text=True, env=env, timeout=7200)
    assert r.returncode == 0, f"{cmd!r} failed:\n{r.stderr[-3000:]}"
