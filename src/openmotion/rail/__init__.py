"""The 1-D multi-mover engine CA rails (transport) and planar tracks share: brake envelopes
(braking.py), the gap filter (gap_control.py), gear synchronisation (gear.py) and their
compiled loops (kernels.py). It imports only the maths; both systems use it through these
modules' public functions."""
