"""Planar routing: collision-free routes for a group's movers, driven as TF5430 commands
(docs/planar-routing.md)."""

from openmotion.planar.routing.router import RouteCommand, Router, RouterStats

__all__ = ["RouteCommand", "Router", "RouterStats"]
