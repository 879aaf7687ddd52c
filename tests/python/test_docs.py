"""docs/python.md's code blocks, in order, in one namespace, from the repository's root:
the quick start runs as written."""
import os
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_python_md_runs(capsys):
    blocks = re.findall(r"```python\n(.*?)```", (ROOT / "docs" / "python.md").read_text(), re.S)
    assert len(blocks) >= 5
    cwd = os.getcwd()
    os.chdir(ROOT)
    try:
        ns = {}
        for i, code in enumerate(blocks):
            exec(compile(code, f"docs/python.md block {i + 1}", "exec"), ns)
    finally:
        os.chdir(cwd)
    out = capsys.readouterr().out
    assert "Scene('two_bunches_hull'" in out and "mine.yaml:5" in out
