"""docs/plots.md stays true: its Python session prints what it says, its figures exist and
are made by the commands it shows, from shipped examples."""

from __future__ import annotations

import contextlib
import io
import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
PAGE = ROOT / "docs" / "plots.md"
RUN = re.compile(r"^openmotion run (examples/\S+\.yaml) --trace \S+\.npz --plot (docs/images/\S+)$",
                 flags=re.M)


def test_the_python_session_prints_what_its_comments_say() -> None:
    block = re.findall(r"```python\n(.*?)```", PAGE.read_text(), flags=re.S)[0]
    expected = re.findall(r"^print\(.*\)\s+# (.*)$", block, flags=re.M)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        exec(compile(block, str(PAGE), "exec"), {})  # noqa: S102 - docs must run
    assert expected and out.getvalue().splitlines() == expected


def test_every_figure_shown_is_made_by_a_command_on_the_page() -> None:
    text = PAGE.read_text()
    made = {image: example for example, image in RUN.findall(text)}
    shown = re.findall(r"!\[[^]]*\]\((images/[^)]+)\)", text)
    assert shown and {f"docs/{image}" for image in shown} <= set(made)
    for image, example in made.items():
        assert (ROOT / example).exists(), example
        assert (ROOT / image).read_bytes()[:8] == b"\x89PNG\r\n\x1a\n", image
