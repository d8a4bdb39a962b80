"""The live viewer: a paced session of a machine, served as a page on localhost.

``openmotion view SCENARIO`` does ``serve(Session.for_scenario(SCENARIO))``; from Python,
``with serving(Session(rt)) as url: ...`` shows a runtime of your own while you work
(docs/viewer.md).
"""

from openmotion.scenario.live import Machine, scenario_machine
from openmotion.viewer.axes import AxesLayer, axes_layers
from openmotion.viewer.layers import Layer, LayerFactory, Row, register_layer, registered_layers
from openmotion.viewer.planar import PlanarLayer, planar_layers
from openmotion.viewer.rails import RailLayer, rail_layers
from openmotion.viewer.server import create_app, serve, serving
from openmotion.viewer.session import Frame, Session

for _factory in (axes_layers, rail_layers, planar_layers):  # the shipped ones, drawing order
    register_layer(_factory)

__all__ = [
    "AxesLayer",
    "Frame",
    "Layer",
    "LayerFactory",
    "Machine",
    "PlanarLayer",
    "RailLayer",
    "Row",
    "Session",
    "create_app",
    "register_layer",
    "registered_layers",
    "scenario_machine",
    "serve",
    "serving",
]
