"""The ```python blocks of docs/python.md run as written, from the repository root."""

import re

import pytest

from conftest import REPO, skip_unless_required


def python_blocks():
    text = (REPO / "docs" / "python.md").read_text()
    return re.findall(r"^```python\n(.*?)^```", text, re.M | re.S)


def test_docs_have_examples():
    assert python_blocks()


@pytest.mark.parametrize("index", range(len(python_blocks())))
def test_docs_example_runs(index, monkeypatch, capsys):
    if not (REPO.parent / "shared" / "data").is_dir():
        skip_unless_required("the examples read ../shared/data")
    monkeypatch.chdir(REPO)
    exec(compile(python_blocks()[index], f"docs/python.md block {index}", "exec"), {})
    assert capsys.readouterr().out
