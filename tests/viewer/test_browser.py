"""End to end: the viewer in headless Chromium, Debian's /usr/bin/chromium driven by Playwright
(which never downloads a browser here). Without Chromium the test skips, unless CI=true.

Run as a script, the same set-up makes the screenshot of docs/viewer.md:

    python tests/viewer/test_browser.py docs/images/viewer.png
"""

from __future__ import annotations

import contextlib
import os
import sys
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest

from openmotion.scenario import examples_dir
from openmotion.viewer import Layer, Row, Session, registered_layers, serving

CHROMIUM = Path("/usr/bin/chromium")
FLAGS = ["--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
         "--disable-background-networking", "--disable-component-update", "--disable-sync"]
VIEWPORT = {"width": 1400, "height": 900}
SCENARIO = examples_dir() / "planar_choreography.yaml"
SCREENSHOT_STEPS = 57  #: frames stepped for the docs' picture: 57 x 40 ms = 2.28 s


def sync_playwright() -> Any:
    """Playwright's entry point; skips (fails where CI=true) naming what is missing."""
    missing = ""
    if not CHROMIUM.is_file():
        missing = f"Debian's chromium is not installed ({CHROMIUM}): apt-get install -y chromium"
    try:
        from playwright.sync_api import sync_playwright as entry
    except ImportError:
        missing = missing or "the playwright package is missing: pip install -e '.[test]'"
    if missing:
        if os.environ.get("CI") == "true":
            pytest.fail(f"{missing} (.ci/run installs both)")
        pytest.skip(missing)
    return entry


@contextlib.contextmanager
def browser_page(entry: Any, viewport: dict[str, int] = VIEWPORT
                 ) -> Iterator[tuple[Any, list[str]]]:
    """A page in a fresh Chromium with an empty profile, and the errors it reports."""
    errors: list[str] = []
    with entry() as playwright, tempfile.TemporaryDirectory() as profile:
        context = playwright.chromium.launch_persistent_context(
            profile, executable_path=str(CHROMIUM), args=FLAGS, headless=True,
            viewport=viewport)
        try:
            page = context.new_page()
            page.on("pageerror", lambda error: errors.append(str(error)))
            page.on("console", lambda message: message.type == "error"
                    and errors.append(message.text))
            yield page, errors
        finally:
            context.close()


def shown_time(page: Any) -> float:
    return float(page.inner_text("#time"))


def wait_for_time(page: Any, seconds: float) -> None:
    """Until the page shows ``seconds`` (it shows milliseconds: 0.812 + 0.04 is 0.852)."""
    page.wait_for_function("Number(document.getElementById('time').textContent) >= "
                           f"{seconds - 5e-4}", timeout=15_000)


def canvas(page: Any) -> str:
    return page.evaluate("() => document.getElementById('machine').toDataURL()")


def positions(page: Any) -> list[str]:
    return page.eval_on_selector_all("#objects td.position",
                                     "cells => cells.map(cell => cell.textContent)")


def test_the_viewer_plays_draws_pauses_and_steps_in_chromium(tmp_path: Path) -> None:
    entry = sync_playwright()
    session = Session.for_scenario(SCENARIO, paused=True)
    with serving(session) as url, browser_page(entry) as (page, errors):
        page.goto(url)
        page.wait_for_selector("#status.paused")  # the first frame is drawn
        assert shown_time(page) == 0.0 and page.inner_text("#name") == "planar choreography"
        page.click("#toggle")  # play
        page.wait_for_selector("#status.running")
        wait_for_time(page, 0.2)
        before = canvas(page), positions(page), shown_time(page)
        wait_for_time(page, before[2] + 0.25)
        after = canvas(page), positions(page), shown_time(page)
        assert after[0] != before[0], "the canvas did not change: nothing moved"
        assert after[1] != before[1], "the table's positions did not advance"
        assert len(after[1]) == 10  # the environment, the group and 8 movers
        page.click("#toggle")  # pause
        page.wait_for_selector("#status.paused")
        paused_at = shown_time(page)
        page.wait_for_timeout(400)
        assert shown_time(page) == paused_at, "time went on while paused"
        assert session.machine.runtime.now == pytest.approx(paused_at, abs=5e-4)
        page.click("#step")
        wait_for_time(page, paused_at + 0.04)
        assert shown_time(page) == pytest.approx(paused_at + 0.04, abs=1e-6)
        picture = tmp_path / "viewer.png"
        page.screenshot(path=str(picture))
        assert errors == []
    assert picture.read_bytes().startswith(b"\x89PNG\r\n\x1a\n")
    assert picture.stat().st_size > 20_000


class _Crowded(Layer):
    """Table rows as long as they come: a long name, state, command and detail, and an
    error message longer than the table is wide."""

    kind = "crowded"

    def __init__(self, runtime: Any) -> None:
        self.name = "crowded"

    def panel(self) -> dict[str, Any]:
        return {}

    def rows(self) -> list[Row]:
        return [Row("planar mover", "conveyor_mover_12", "synchronized_motion",
                    "1234.5, -2345.6", "-1000.000", "move_absolute_ca",
                    "gap 100.0, track 21, z 4.0, c 90.0°",
                    "PLANAR_TARGET_BLOCKED: the target position is reserved by mover m7 in "
                    "group field, which waits for its own way to clear")]


@pytest.mark.parametrize("width", [1280, 1920])
def test_the_objects_table_fits_its_panel_from_1280_px_on(width: int) -> None:
    entry = sync_playwright()
    session = Session.for_scenario(SCENARIO, paused=True,
                                   layers=[*registered_layers(), lambda rt: [_Crowded(rt)]])
    with serving(session) as url, browser_page(entry, {"width": width, "height": 800}) as (
            page, errors):
        page.goto(url)
        page.wait_for_selector("#objects td.error")  # the crowded row's error line is drawn
        boxes = page.evaluate("""() => {
            const right = (element) => element.getBoundingClientRect().right;
            return {panel: right(document.getElementById('table-box')),
                    table: right(document.getElementById('objects')),
                    cells: Math.max(...[...document.querySelectorAll('#objects th, #objects td')]
                                    .map(right)),
                    page: document.documentElement.scrollWidth};
        }""")
        assert boxes["page"] <= width  # no horizontal scrolling of the page
        assert boxes["table"] <= boxes["panel"] <= width  # the table inside its panel ...
        assert boxes["cells"] <= boxes["panel"]  # ... and every column in it
        names = page.eval_on_selector_all("#objects td.name",
                                          "cells => cells.map(cell => cell.textContent)")
        assert "conveyor_mover_12" in names and len(names) == 11  # wrapped, not cut
        assert errors == []


@pytest.mark.parametrize(("ci", "outcome"), [("true", pytest.fail.Exception),
                                             ("", pytest.skip.Exception)])
def test_without_chromium_the_browser_test_skips_but_fails_in_ci(
        monkeypatch: pytest.MonkeyPatch, ci: str, outcome: type[BaseException]) -> None:
    monkeypatch.setitem(globals(), "CHROMIUM", Path("/nonexistent/chromium"))
    monkeypatch.setenv("CI", ci)
    with pytest.raises(outcome, match="chromium is not installed"):
        sync_playwright()


def make_screenshot(target: Path) -> None:
    """The docs' picture: the planar example stepped to 2.28 s, deterministically."""
    from playwright.sync_api import sync_playwright as entry

    session = Session.for_scenario(SCENARIO, paused=True)
    with serving(session) as url, browser_page(entry) as (page, errors):
        page.goto(url)
        page.wait_for_selector("#status.paused")
        for _ in range(SCREENSHOT_STEPS):
            page.click("#step")
        wait_for_time(page, SCREENSHOT_STEPS * 0.04)
        page.wait_for_timeout(300)  # the last frame drawn
        target.parent.mkdir(parents=True, exist_ok=True)
        page.screenshot(path=str(target))
        if errors:
            raise RuntimeError(f"the page reported errors: {errors}")
    print(f"screenshot: written to {target}")


if __name__ == "__main__":
    make_screenshot(Path(sys.argv[1] if len(sys.argv) > 1 else "docs/images/viewer.png"))
