"""Planar motion (TF5430): maglev movers on a stator surface, planar groups, parts, feedback."""
