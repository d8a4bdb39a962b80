"""The shipped example scenarios, found by name wherever openmotion is installed.

A wheel carries them beside this module (setup.py copies the checkout's top-level
``examples/`` folder here when it builds); a source checkout or an editable install reads
that folder directly. Nothing here depends on the working directory.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

DEFAULT_EXAMPLE = "single_move"  #: what ``openmotion run`` runs without an argument
SUFFIX = ".yaml"


def examples_dir() -> Path:
    """The folder of the shipped examples: the installed copy, else the checkout's."""
    here = Path(__file__).resolve().parent
    if any(here.glob(f"*{SUFFIX}")):
        return here
    return here.parents[2] / "examples"


def default_scenario() -> Path:
    """The scenario ``openmotion run`` runs without an argument."""
    return examples_dir() / f"{DEFAULT_EXAMPLE}{SUFFIX}"


@dataclass(frozen=True)
class Example:
    """One shipped scenario: its name (the file stem), file and one-line summary."""

    name: str
    path: Path
    summary: str


def list_examples() -> list[Example]:
    """Every shipped scenario, by name; the summary is the file's ``description``."""
    return [Example(path.stem, path, _summary(path))
            for path in sorted(examples_dir().glob(f"*{SUFFIX}"))]


def find_example(name: str) -> Path | None:
    """The shipped scenario called ``name`` (``single_move`` or ``single_move.yaml``)."""
    stem = name.removesuffix(SUFFIX)
    if not stem or "/" in stem or "\\" in stem or stem.startswith("."):
        return None
    path = examples_dir() / f"{stem}{SUFFIX}"
    return path if path.is_file() else None


def resolve_scenario(argument: str | Path | None) -> Path:
    """The file a CLI argument means: an existing path as given, else a shipped example of
    that name, else the path as given (so that reading it reports what is wrong)."""
    if argument is None:
        return default_scenario()
    path = Path(argument)
    if path.exists():
        return path
    return find_example(str(argument)) or path


def _summary(path: Path) -> str:
    """The ``description`` of a scenario file, folded to one line; cheap, no validation."""
    import yaml

    try:
        data = yaml.safe_load(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, yaml.YAMLError):
        return ""
    text = data.get("description", "") if isinstance(data, dict) else ""
    return " ".join(str(text).split())
