"""scripts/install_python.sh puts the build's package into a fresh virtual environment,
whose interpreter then runs the README's Python quick start without PYTHONPATH."""
import os
import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def readme_block():
    text = (ROOT / "README.md").read_text()
    section = text.split("### Python quick start", 1)[1].split("\n## ", 1)[0]
    blocks = re.findall(r"```python\n(.*?)```", section, re.S)
    assert len(blocks) == 1
    return blocks[0]


def test_install_into_a_venv_and_run_the_readme_quick_start(tmp_path):
    build = Path(os.environ["PYTHONPATH"].split(os.pathsep)[0]).parent
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env.update(GRAPEBENCH_BUILD_DIR=str(build), GRAPEBENCH_NO_BUILD="1")
    venv = tmp_path / "venv"
    subprocess.run([str(ROOT / "scripts" / "install_python.sh"), "--venv", str(venv)], env=env, check=True,
                   capture_output=True, text=True)
    code = "import grapebench as gb; print(gb.__file__)\n" + readme_block()
    p = subprocess.run([str(venv / "bin" / "python"), "-c", code], env=env, capture_output=True, text=True,
                       cwd=ROOT)
    assert p.returncode == 0, p.stderr
    lines = p.stdout.splitlines()
    assert lines[0].startswith(str(venv)), lines[0]  # the venv's copy, not the build's
    assert "berries," in lines[1] and lines[2].endswith("cm3") and "alpha" in p.stdout
    # The unit cube's corners: volume 1 through the installed extension.
    cube = "import grapebench as gb; print(gb.estimate('convex_hull', " \
           "[[x,y,z] for x in (0,1) for y in (0,1) for z in (0,1)])['values']['volume'])"
    v = subprocess.run([str(venv / "bin" / "python"), "-c", cube], env=env, check=True, capture_output=True,
                       text=True, cwd=tmp_path)
    assert abs(float(v.stdout) - 1) < 1e-12
    bad = subprocess.run([str(ROOT / "scripts" / "install_python.sh")], env=env, capture_output=True, text=True)
    assert bad.returncode == 2 and "usage" in bad.stderr
