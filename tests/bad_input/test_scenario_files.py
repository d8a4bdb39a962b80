"""Hostile scenario files are refused quickly and clearly: alias bombs, deep nesting, files
over the size bound, bytes that are not UTF-8 text. Each case names the file (and the line
when there is one), ends ``openmotion check`` with exit 2 and no traceback, and a valid file
loads right after it. The inputs are sized so that a loader without the bounds would run for
hours or crash; with them every case takes milliseconds."""

from __future__ import annotations

import gc
import os
from collections.abc import Callable
from pathlib import Path

import pytest
from typer.testing import CliRunner

from openmotion.bench.startup import large_scenario
from openmotion.cli import app
from openmotion.scenario import ScenarioError, load_scenario, parse_scenario, reading
from openmotion.scenario.reading import (
    DEFAULT_MAX_BYTES,
    MAX_ALIAS_NODES,
    MAX_BYTES_VARIABLE,
    MAX_DEPTH,
)

runner = CliRunner()
HEAD = "name: hostile\naxes: [{name: x}]\n"  # a valid start: line 3 is the first hostile one
VALID = """\
name: valid
axes:
  - name: x
    parameters: &dynamics {max_velocity: 500.0, acceleration: 2000.0}
  - name: y
    parameters: {<<: *dynamics, max_velocity: 300.0}
timeline:
  - {id: on, at: 0.0, axis: x, command: power}
  - {when: on.done, axis: x, command: move_absolute, position: 10.0, velocity: 100.0}
"""
LOADERS = [reading.PythonScenarioLoader] + [
    loader for loader in [getattr(reading, "LibyamlScenarioLoader", None)] if loader]


# -- generators ----------------------------------------------------------------------------

def alias_bomb(levels: int = 9, width: int = 9) -> str:
    """Each anchor holds ``width`` aliases of the one before: width**levels leaves in 500
    bytes (the old duplicate-key walk visited all 3.5e9 of them)."""
    lines = [HEAD.rstrip("\n"), "bomb0: &a0 [" + ", ".join(["lol"] * width) + "]"]
    lines += [f"bomb{i}: &a{i} [" + ", ".join([f"*a{i - 1}"] * width) + "]"
              for i in range(1, levels + 1)]
    return "\n".join(lines) + "\n"


def merge_bomb(levels: int = 40) -> str:
    """Merge keys of merge keys: the constructor's flattened key lists double every level."""
    lines = [HEAD.rstrip("\n"), "m0: &m0 {k: 1}"]
    lines += [f"m{i}: &m{i} {{<<: [*m{i - 1}, *m{i - 1}], k{i}: 1}}"
              for i in range(1, levels + 1)]
    return "\n".join(lines) + "\n"


def deep_flow(depth: int) -> str:
    """``x:`` holds ``depth`` nested flow sequences on line 3 (the file itself is level 1)."""
    return HEAD + "x: " + "[" * depth + "]" * depth + "\n"


def deep_block(depth: int) -> str:
    """``x:`` holds ``depth`` nested block sequences in compact form (``- - - 1``), line 4."""
    return HEAD + "x:\n  " + "- " * depth + "1\n"


def deep_block_mappings(depth: int) -> str:
    """``depth`` block mappings, one more indented per line: level 101 is on line 102."""
    lines = [HEAD.rstrip("\n"), "x:"] + [
        "  " * level + f"k{level}:" for level in range(1, depth + 1)]
    return "\n".join(lines) + " 1\n"


# -- helpers -------------------------------------------------------------------------------

@pytest.fixture(params=LOADERS, ids=lambda loader: loader.__name__)
def loader(request: pytest.FixtureRequest, monkeypatch: pytest.MonkeyPatch) -> type:
    """Both parsers: libyaml (when PyYAML has it) and the pure-Python fallback."""
    monkeypatch.setattr(reading, "ScenarioLoader", request.param)
    return request.param


def refused(path: Path, **kwargs: int) -> list[str]:
    with pytest.raises(ScenarioError) as caught:
        load_scenario(path, **kwargs)
    return [str(problem) for problem in caught.value.problems]


def assert_still_usable(tmp_path: Path) -> None:
    """A valid file loads right after the refusal (and garbage collection is back on)."""
    assert gc.isenabled()
    path = tmp_path / "valid.yaml"
    path.write_text(VALID)
    scenario = load_scenario(path)
    assert [axis.parameters.max_velocity for axis in scenario.axes] == [500.0, 300.0]


def assert_cli_refuses(path: Path, message: str) -> None:
    """``check`` and ``run`` end with exit 2 and the message on stderr, no traceback."""
    for arguments in (["check", str(path)], ["run", str(path), "--quiet"]):
        result = runner.invoke(app, arguments)
        assert result.exit_code == 2, result.output
        assert result.stderr.startswith(f"ConfigError: {path}"), result.stderr
        assert message in result.stderr and "Traceback" not in result.output
        assert not isinstance(result.exception, RecursionError | UnicodeError | MemoryError)


def assert_cli_usable(tmp_path: Path) -> None:
    """A valid file checks fine right after a refusal."""
    valid = tmp_path / "valid.yaml"
    valid.write_text(VALID)
    result = runner.invoke(app, ["check", str(valid)])
    assert result.exit_code == 0 and result.stdout.startswith(f"{valid}: ok (2 axes")


@pytest.fixture(autouse=True)
def in_tmp(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> Path:
    monkeypatch.chdir(tmp_path)  # `run` would write its trace here
    monkeypatch.delenv(MAX_BYTES_VARIABLE, raising=False)
    return tmp_path


def write(tmp_path: Path, text: str | bytes, name: str = "hostile.yaml") -> Path:
    path = tmp_path / name
    if isinstance(text, str):
        path.write_text(text, encoding="utf-8")
    else:
        path.write_bytes(text)
    return path


# -- aliases -------------------------------------------------------------------------------

@pytest.mark.parametrize("make, line", [(alias_bomb, 8), (merge_bomb, 16)],
                         ids=["nested-aliases", "merge-keys"])
def test_alias_bomb_is_refused_at_the_alias_that_crosses_the_bound(
        tmp_path: Path, loader: type, make: Callable[[], str], line: int) -> None:
    path = write(tmp_path, make())
    assert path.stat().st_size < 1500
    assert refused(path) == [f"{path}:{line}: aliases repeat more than {MAX_ALIAS_NODES} "
                             "nodes (aliases of aliases multiply)"]
    assert_still_usable(tmp_path)


def test_alias_bomb_through_the_cli(tmp_path: Path) -> None:
    assert_cli_refuses(write(tmp_path, alias_bomb()), f"aliases repeat more than "
                                                      f"{MAX_ALIAS_NODES} nodes")
    assert_cli_usable(tmp_path)


def test_aliases_may_repeat_up_to_the_bound(tmp_path: Path, loader: type) -> None:
    """An anchor of 1000 nodes (a list of 999) aliased exactly as often as the bound allows
    is no bomb: the file gets past the composer to the schema (the key is unknown)."""
    times = MAX_ALIAS_NODES // 1000
    anchor = "a: &a [" + ", ".join(["0"] * 999) + "]\n"
    at_bound = HEAD + anchor + "b: [" + ", ".join(["*a"] * times) + "]\n"
    found = refused(write(tmp_path, at_bound))
    assert [problem.split(": ", 2)[1:] for problem in found] == [
        ["a", found[0].split(": ", 2)[2]], ["b", found[1].split(": ", 2)[2]]]
    assert all(": unknown field '" in problem for problem in found)
    over = HEAD + anchor + "b: [" + ", ".join(["*a"] * times) + ", *a]\n"
    assert refused(write(tmp_path, over))[0].endswith(
        f":4: aliases repeat more than {MAX_ALIAS_NODES} nodes (aliases of aliases multiply)")


@pytest.mark.parametrize("text, line", [
    ("x: &a [1, *a]\n", 3),
    ("x: &a\n  k: *a\n", 4),
], ids=["sequence", "mapping"])
def test_alias_inside_its_own_anchor_is_refused(tmp_path: Path, loader: type, text: str,
                                                line: int) -> None:
    path = write(tmp_path, HEAD + text)
    assert refused(path) == [f"{path}:{line}: alias *a is inside the node it refers to"]
    assert_still_usable(tmp_path)


def test_duplicate_key_inside_an_anchor_is_reported_once(tmp_path: Path) -> None:
    """The duplicate-key walk visits each node once, however many aliases lead to it."""
    text = HEAD + "d: &d {k: 1, k: 2}\nmany: [" + ", ".join(["*d"] * 5000) + "]\n"
    found = [p for p in refused(write(tmp_path, text)) if "duplicate key" in p]
    assert found == [f"{tmp_path / 'hostile.yaml'}:3: d.k: duplicate key (the last one "
                     "would win)"]


def test_merge_key_then_an_override_is_no_duplicate(tmp_path: Path) -> None:
    assert_still_usable(tmp_path)  # VALID overrides max_velocity after ``<<: *dynamics``


# -- nesting -------------------------------------------------------------------------------

@pytest.mark.parametrize("make, line", [(deep_flow, 3), (deep_block, 4)],
                         ids=["flow", "block"])
@pytest.mark.parametrize("depth", [MAX_DEPTH, 100_000])
def test_nesting_beyond_the_bound_is_refused(tmp_path: Path, loader: type,
                                             make: Callable[[int], str], line: int,
                                             depth: int) -> None:
    """With the file's own mapping, ``depth`` nested collections under ``x`` are one level
    more than the bound allows. 100 000 levels overflowed the recursive composer."""
    path = write(tmp_path, make(depth))
    assert refused(path) == [f"{path}:{line}: nested deeper than {MAX_DEPTH} levels of "
                             "mappings and sequences"]
    assert_still_usable(tmp_path)


@pytest.mark.parametrize("make", [deep_flow, deep_block], ids=["flow", "block"])
def test_nesting_at_the_bound_is_composed(tmp_path: Path, loader: type,
                                          make: Callable[[int], str]) -> None:
    found = refused(write(tmp_path, make(MAX_DEPTH - 1)))
    assert len(found) == 1 and ":3: x: unknown field 'x'" in found[0]


def test_deep_block_mappings_are_refused_at_the_line_of_the_level_beyond(
        tmp_path: Path, loader: type) -> None:
    path = write(tmp_path, deep_block_mappings(MAX_DEPTH + 20))
    assert refused(path) == [f"{path}:{MAX_DEPTH + 3}: nested deeper than {MAX_DEPTH} levels "
                             "of mappings and sequences"]


def test_deep_nesting_through_the_cli(tmp_path: Path) -> None:
    assert_cli_refuses(write(tmp_path, deep_flow(100_000)), f"{tmp_path / 'hostile.yaml'}:3: "
                       f"nested deeper than {MAX_DEPTH} levels")
    assert_cli_usable(tmp_path)


# -- size ----------------------------------------------------------------------------------

def test_file_over_the_default_bound_is_refused_before_it_is_read(tmp_path: Path) -> None:
    """A sparse 10 GiB file: reading it would exhaust memory, its size alone refuses it."""
    path = tmp_path / "huge.yaml"
    with path.open("wb") as stream:
        stream.truncate(10 * 2**30)
    assert refused(path) == [f"{path}: too large: {10 * 2**30} bytes, more than the limit of "
                             f"{DEFAULT_MAX_BYTES} bytes (set {MAX_BYTES_VARIABLE} to change "
                             "it)"]
    assert_still_usable(tmp_path)
    assert_cli_refuses(path, f"too large: {10 * 2**30} bytes")
    assert_cli_usable(tmp_path)


def test_size_bound_per_call_and_from_the_environment(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    path = write(tmp_path, VALID)
    size = path.stat().st_size
    assert load_scenario(path, max_bytes=size).name == "valid"  # the bound itself is allowed
    assert refused(path, max_bytes=size - 1) == [
        f"{path}: too large: {size} bytes, more than the limit of {size - 1} bytes (set "
        f"{MAX_BYTES_VARIABLE} to change it)"]
    monkeypatch.setenv(MAX_BYTES_VARIABLE, str(size - 1))
    assert "too large" in refused(path)[0]
    assert load_scenario(path, max_bytes=size).name == "valid"  # the argument wins
    assert_cli_refuses(path, f"more than the limit of {size - 1} bytes")
    monkeypatch.setenv(MAX_BYTES_VARIABLE, str(size))
    assert load_scenario(path).name == "valid"
    assert_cli_usable(tmp_path)


def test_size_bound_counts_utf8_bytes_of_parsed_text() -> None:
    text = VALID.replace("name: valid", "name: välid")  # one character, two bytes
    size = len(text.encode())
    assert parse_scenario(text, max_bytes=size).name == "välid"
    with pytest.raises(ScenarioError, match=f"^<string>: too large: more than the limit of "
                                            f"{size - 1} bytes"):
        parse_scenario(text, max_bytes=size - 1)


@pytest.mark.parametrize("value", ["lots", "0", "-5", "1.5e6"])
def test_a_bad_size_bound_in_the_environment_is_a_config_error(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch, value: str) -> None:
    path = write(tmp_path, VALID)
    monkeypatch.setenv(MAX_BYTES_VARIABLE, value)
    assert refused(path) == [f"{path}: {MAX_BYTES_VARIABLE} must be a whole number of bytes "
                             f"> 0, got {value!r}"]
    assert_cli_refuses(path, f"{MAX_BYTES_VARIABLE} must be a whole number")
    monkeypatch.delenv(MAX_BYTES_VARIABLE)
    assert_cli_usable(tmp_path)


@pytest.mark.parametrize("value", [0, -1, 1.5, True, "100"])
def test_a_bad_max_bytes_argument_is_a_value_error(tmp_path: Path, value: object) -> None:
    with pytest.raises(ValueError, match="max_bytes must be a whole number of bytes > 0"):
        load_scenario(write(tmp_path, VALID), max_bytes=value)  # type: ignore[arg-type]
    assert_still_usable(tmp_path)


@pytest.mark.skipif(not os.path.exists("/dev/zero"), reason="needs /dev/zero")
def test_endless_stream_stops_at_the_bound(tmp_path: Path) -> None:
    """A device reports size 0: reading stops one byte past the bound."""
    assert refused(Path("/dev/zero"), max_bytes=1000) == [
        "/dev/zero: too large: more than the limit of 1000 bytes (set "
        f"{MAX_BYTES_VARIABLE} to change it)"]
    assert_still_usable(tmp_path)


# -- encoding ------------------------------------------------------------------------------

@pytest.mark.parametrize("data, line, message", [
    ("name: café\naxes: [{name: x}]\n".encode("latin-1"), 1,
     "invalid UTF-8 at byte offset 9: 0xe9"),
    (HEAD.encode() + b"x: 1\x00\x01\x02\n", 3, "non-printable character U+0000 at byte "
                                               "offset 36"),
    (HEAD.encode() + b"description: ring \x07\n", 3, "non-printable character U+0007 at "
                                                     "byte offset 50"),
    (HEAD.encode("utf-16"), 1, "invalid UTF-8 at byte offset 0: 0xff"),
    (bytes(range(256)) * 4, 1, "non-printable character U+0000 at byte offset 0"),
    (b"\x89PNG\r\n\x1a\n" + bytes(100), 1, "invalid UTF-8 at byte offset 0: 0x89"),
], ids=["latin-1", "nul", "bell", "utf-16", "binary", "png"])
def test_bytes_that_are_not_utf8_text_are_refused(tmp_path: Path, data: bytes, line: int,
                                                  message: str) -> None:
    path = write(tmp_path, data)
    assert refused(path) == [f"{path}:{line}: not a UTF-8 text file ({message})"]
    assert_still_usable(tmp_path)


def test_not_utf8_through_the_cli(tmp_path: Path) -> None:
    path = write(tmp_path, "name: café\naxes: [{name: x}]\n".encode("latin-1"))
    assert_cli_refuses(path, f"{path}:1: not a UTF-8 text file (invalid UTF-8 at byte offset 9")
    assert_cli_usable(tmp_path)


def test_text_with_a_lone_surrogate_is_refused_by_parse_scenario() -> None:
    with pytest.raises(ScenarioError, match=r"^<string>:1: not a UTF-8 text file "
                                            r"\(non-printable character U\+D800"):
        parse_scenario("name: a\ud800\naxes: [{name: x}]\n")


def test_utf8_with_a_byte_order_mark_loads(tmp_path: Path, loader: type) -> None:
    path = write(tmp_path, b"\xef\xbb\xbf" + VALID.replace("valid", "bom").encode())
    assert load_scenario(path).name == "bom"
    result = runner.invoke(app, ["check", str(path)])
    assert result.exit_code == 0 and result.stdout.startswith(f"{path}: ok (2 axes")


# -- big legitimate files ------------------------------------------------------------------

def test_a_one_megabyte_scenario_loads(tmp_path: Path) -> None:
    path = write(tmp_path, large_scenario(1_000_000))
    assert 1_000_000 <= path.stat().st_size < DEFAULT_MAX_BYTES
    scenario = load_scenario(path)
    assert len(scenario.axes) == 100 and len(scenario.timeline) > 7000
    assert str(scenario.timeline[-1].when) == f"m{len(scenario.timeline) - 201}.done"
    assert gc.isenabled()


def test_errors_of_a_big_file_are_all_listed(tmp_path: Path) -> None:
    """Every misspelt field of a long timeline is reported at its line."""
    text = large_scenario(200_000).replace("    velocity: 250.0", "    velocty: 250.0")
    path = write(tmp_path, text)
    found = refused(path)
    moves = path.read_text().count("velocty")
    assert len(found) == 2 * moves  # the unknown field and the missing one of each entry
    assert found[1].endswith("timeline[100].velocty: unknown field 'velocty' (did you mean "
                             "'velocity'?)")
