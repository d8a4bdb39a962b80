"""Gymnasium and PettingZoo environments on a planar field (issue 25).

``PlanarFieldEnv`` (Gymnasium) drives every mover with one agent; ``PlanarFieldParallelEnv``
(PettingZoo's parallel API) gives each mover its own agent. Both step a real TF5430 planar
group: actions become MoveToPosition commands the group admits or refuses (docs/envs.md).
Needs the ``envs`` extra (gymnasium, pettingzoo); nothing else in openmotion imports this.
"""

import gymnasium

from openmotion.envs.episode import EpisodeConfig
from openmotion.envs.field import PlanarField
from openmotion.envs.parallel import PlanarFieldParallelEnv
from openmotion.envs.registry import LAYOUTS, make_layout
from openmotion.envs.single import PlanarFieldEnv

#: ``gymnasium.make(GYMNASIUM_ID, layout="B3")`` makes a ``PlanarFieldEnv``
GYMNASIUM_ID = "openmotion/PlanarField-v0"
if GYMNASIUM_ID not in gymnasium.registry:
    gymnasium.register(GYMNASIUM_ID, entry_point="openmotion.envs.single:PlanarFieldEnv")

__all__ = [
    "GYMNASIUM_ID",
    "LAYOUTS",
    "EpisodeConfig",
    "PlanarField",
    "PlanarFieldEnv",
    "PlanarFieldParallelEnv",
    "make_layout",
]
