"""Build step that pyproject.toml cannot declare: the shipped examples go into the wheel.

The scenarios live in the checkout's top-level ``examples/`` folder (where users of a clone
look for them); a wheel carries a copy inside the package, beside ``openmotion/examples``'s
module, so that ``openmotion run`` and ``openmotion run NAME`` work after any install.
"""

from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

EXAMPLES = Path(__file__).resolve().parent / "examples"
SHIPPED = ("*.yaml", "*.out")  #: a scenario and its golden summary


class BuildWithExamples(build_py):
    def run(self) -> None:
        super().run()
        target = Path(self.build_lib, "openmotion", "examples")
        target.mkdir(parents=True, exist_ok=True)
        for pattern in SHIPPED:
            for source in sorted(EXAMPLES.glob(pattern)):
                self.copy_file(str(source), str(target / source.name))


setup(cmdclass={"build_py": BuildWithExamples})
