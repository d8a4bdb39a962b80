"""Build steps that pyproject.toml cannot declare: the shipped examples go into the wheel, and
the loops they use are compiled into it.

The scenarios live in the checkout's top-level ``examples/`` folder (where users of a clone
look for them); a wheel carries a copy inside the package, beside ``openmotion/examples``'s
module, so that ``openmotion run`` and ``openmotion run NAME`` work after any install.

A first run compiles the numba loops it uses (11-15 s for a planar track example) and
numba caches them next to their modules. The build runs ``python -m openmotion.warm`` on the
examples (about 40 s), so the wheel, or the checkout of an editable install, carries that
cache and a fresh install's first run only loads it (D-158). The cache is valid for the
machine, Python and numba of the build; elsewhere numba ignores it and compiles as before.
``OPENMOTION_PRECOMPILE=0`` skips the step.
"""

import os
import subprocess
import sys
from pathlib import Path

from setuptools import setup
from setuptools.command.build_py import build_py

ROOT = Path(__file__).resolve().parent
EXAMPLES = ROOT / "examples"
SHIPPED = ("*.yaml", "*.out")  #: a scenario and its golden summary
SKIP_VARIABLE = "OPENMOTION_PRECOMPILE"  #: "0" skips compiling the loops into the build


class BuildWithExamples(build_py):
    def run(self) -> None:
        super().run()
        target = Path(self.build_lib, "openmotion", "examples")
        target.mkdir(parents=True, exist_ok=True)
        for pattern in SHIPPED:
            for source in sorted(EXAMPLES.glob(pattern)):
                self.copy_file(str(source), str(target / source.name))
        if os.environ.get(SKIP_VARIABLE, "1") != "0":
            # an editable install runs the checkout's sources: its cache goes there
            self.precompile(ROOT / "src" if self.editable_mode else Path(self.build_lib))

    def precompile(self, package_root: Path) -> None:
        """Compile the examples' loops into numba's cache beside the modules under
        ``package_root``; a failure costs only the speed of the first runs."""
        # pip's isolated build environment reaches the interpreter through the environment
        # (PYTHONPATH): keep it, and put the package first on the path
        env = {name: value for name, value in os.environ.items() if name != "NUMBA_CACHE_DIR"}
        env["PYTHONDONTWRITEBYTECODE"] = "1"
        code = ("import sys; sys.path.insert(0, sys.argv[1]); from openmotion.warm import main; "
                "sys.exit(main(sys.argv[2:]))")
        self.announce("compiling the loops of the shipped examples (openmotion.warm)", level=2)
        done = subprocess.run([sys.executable, "-c", code, str(package_root), str(EXAMPLES)],
                              env=env, capture_output=True, text=True, check=False)
        if done.returncode != 0:
            why = (done.stderr.strip() or done.stdout.strip())[-300:]
            self.warn(f"the compiled loops are not cached ({why}); first runs compile them")


setup(cmdclass={"build_py": BuildWithExamples})
