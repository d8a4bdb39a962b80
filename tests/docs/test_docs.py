"""The docs stay true: every error id is documented, links resolve, README code runs."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

import pytest

import openmotion as om

ROOT = Path(__file__).resolve().parents[2]


def test_every_error_id_is_in_the_block_reference():
    text = (ROOT / "docs" / "blocks.md").read_text()
    for error in om.ErrorId:
        assert f"| `{error.name}` | 0x{error.value:04X} ({error.value}) |" in text, error.name


def test_every_plcopen_block_is_in_the_block_reference():
    import openmotion.plcopen as blocks

    text = (ROOT / "docs" / "blocks.md").read_text()
    for name in blocks.__all__:
        if name.startswith("MC_"):
            assert f"| {name} |" in text, name


def test_relative_links_in_markdown_resolve():
    for page in [ROOT / "README.md", *sorted((ROOT / "docs").glob("*.md"))]:
        for target in re.findall(r"\]\(([^)#]+)(?:#[^)]*)?\)", page.read_text()):
            if "://" in target:
                continue
            assert (page.parent / target).exists(), f"{page.name}: broken link {target}"


@pytest.mark.parametrize("page", ["README.md", "docs/tutorial.md"])
def test_python_sessions_print_what_their_comments_say(page: str):
    """Each ``print(...)  # expected`` line of the page's code prints exactly that."""
    text = (ROOT / page).read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert blocks, f"{page} shows a Python session"
    namespace: dict = {}
    expected: list[str] = []
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        for block in blocks:
            expected += re.findall(r"^print\(.*\)\s+# (.*?)(?::.*)?$", block, flags=re.M)
            exec(compile(block, page, "exec"), namespace)  # noqa: S102 - docs must run
    assert out.getvalue().splitlines() == expected
