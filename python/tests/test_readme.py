"""The README's "Use from Python" example runs as written (it reads Debian's
AAL atlas, so it is skipped without mricron-data)."""
import os
import re

import pytest

README = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "README.md")


@pytest.mark.skipif(not os.path.exists("/usr/share/mricron/templates/aal.nii.gz"),
                    reason="mricron-data not installed")
def test_readme_python_example(tmp_path, monkeypatch):
    text = open(README).read()
    section = text[text.index("## Use from Python"):text.index("## Use from C")]
    code = re.findall(r"```python\n(.*?)```", section, flags=re.S)
    assert code, "no python example in the README"
    monkeypatch.chdir(tmp_path)
    scope = {}
    exec(compile(code[0], "README.md", "exec"), scope)
    assert scope["m"]["count"] == scope["same"].count() > 0
    assert (tmp_path / "hippocampus.nii.gz").exists()
