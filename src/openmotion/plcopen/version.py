"""F_GetVersionTcMC: the library version, one element at a time (TcMC §5.1)."""

from __future__ import annotations

import re

import openmotion

_LEADING_DIGITS = re.compile(r"\d+")


def F_GetVersionTcMC(version_element: int) -> int:
    """Major (1), minor (2) or revision (3) number of *openmotion*'s own version.

    In TwinCAT the function reports the version of the TcMC library it belongs to; here the
    library is openmotion, so the numbers are those of ``openmotion.__version__`` (``"0.1.0"``
    gives 0, 1, 0). A suffix such as ``rc1`` or ``.dev2`` is ignored; a missing part reads 0.
    Any other ``version_element`` returns 0 (the manual leaves it unspecified).
    """
    if isinstance(version_element, bool) or version_element not in (1, 2, 3):
        return 0
    parts = openmotion.__version__.split(".")
    if version_element > len(parts):
        return 0
    match = _LEADING_DIGITS.match(parts[version_element - 1])
    return int(match.group()) if match else 0
