"""``python -m openmotion``: the same command as ``openmotion``."""

from openmotion.cli import main

main()
