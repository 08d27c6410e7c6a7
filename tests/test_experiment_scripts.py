"""The experiment folders' plot.py scripts share one argument handler (experiments/_common.py, an
application beside the library): ``--results`` (alias ``--out``) and a one-line message naming the
run.py to run when results are missing."""

import subprocess
import sys
from pathlib import Path

import pytest

REPO = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(REPO / "experiments"))
from _common import results_for_plot  # noqa: E402


def test_missing_results_name_the_run_script(tmp_path):
    default = tmp_path / "fig99_example" / "results"
    with pytest.raises(SystemExit) as e:
        results_for_plot("doc", default, ("fig99.json",), argv=[])
    msg = str(e.value)
    assert str(default / "fig99.json") in msg and "experiments/fig99_example/run.py" in msg


def test_results_and_out_are_one_option(tmp_path):
    (tmp_path / "fig99.json").write_text("{}")
    default = tmp_path / "elsewhere" / "results"
    for flag in ("--results", "--out"):
        assert results_for_plot("doc", default, ("fig99.json",), argv=[flag, str(tmp_path)]) == tmp_path


@pytest.mark.parametrize("folder", ["fig13_creep", "table1", "fig09_pid"])
def test_plot_script_without_results_exits_with_one_line(tmp_path, folder):
    # a standalone plot.py and one that goes through plot_main; nothing may be written
    out = subprocess.run([sys.executable, str(REPO / "experiments" / folder / "plot.py"), "--results",
                          str(tmp_path)], capture_output=True, text=True)
    assert out.returncode == 1
    assert out.stderr.strip().count("\n") == 0 and "Traceback" not in out.stderr, out.stderr
    assert f"run experiments/{folder}/run.py first" in out.stderr
    assert list(tmp_path.iterdir()) == []
