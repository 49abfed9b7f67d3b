"""Every Python example of README.md runs as written (so the README cannot drift): each
```python block is executed as a user in the repository's root would run it, in a
temporary folder that shows the repository's samples/ (so its outputs land there)."""
import re
import subprocess
import sys

import pytest

from conftest import SOURCE

BLOCKS = re.findall(r"```python\n(.*?)```", (SOURCE / "README.md").read_text(), re.S)


def test_readme_has_a_five_line_example():
    assert BLOCKS, "README.md has no ```python example"
    assert len(BLOCKS[0].strip().splitlines()) == 5


@pytest.mark.parametrize("code", BLOCKS, ids=["example%d" % i for i in range(len(BLOCKS))])
def test_readme_example(code, tmp_path):
    (tmp_path / "samples").symlink_to(SOURCE / "samples")
    r = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, capture_output=True,
                       text=True)
    assert r.returncode == 0, r.stderr
