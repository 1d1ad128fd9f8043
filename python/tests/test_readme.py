"""The README's Python example runs as written (from the repository root; it
uses the repository's own examples/data)."""

import os
import re

from conftest import REPO


def test_readme_example_runs(capsys):
    text = (REPO / "README.md").read_text()
    section = text.split("\n## Python\n", 1)[1]
    code = re.search(r"```python\n(.*?)```", section, re.S).group(1)
    assert len(code.strip().splitlines()) == 10
    cwd = os.getcwd()
    os.chdir(REPO)
    try:
        exec(compile(code, "README.md", "exec"), {})
    finally:
        os.chdir(cwd)
    out = capsys.readouterr().out
    m = re.fullmatch(r"\((\d+), (\d+)\) (\S+) \((\d+), (\d+)\)\n", out)
    assert m, out
    frames, dofs, energy = int(m.group(1)), int(m.group(2)), float(m.group(3))
    assert frames > 30 and dofs > 30 and energy > 0
    assert (int(m.group(4)), int(m.group(5))) == (frames, dofs)
