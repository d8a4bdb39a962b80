"""Traces: record any object's signals and the command events, export them (CSV, NPZ), and
draw them: the scope figure, the rail plot of CA groups, the planar plot."""

from openmotion.trace.export import (
    read_csv,
    read_npz,
    read_trace,
    write_csv,
    write_npz,
    write_trace,
)
from openmotion.trace.plot import (
    default_figure,
    figure_signals,
    image_format,
    plot_trace,
    save_plot,
)
from openmotion.trace.record import Event, Trace, TraceRecorder
from openmotion.trace.signals import AXIS_SIGNALS, SignalSource, register_source

__all__ = ["AXIS_SIGNALS", "Event", "SignalSource", "Trace", "TraceRecorder", "default_figure",
           "figure_signals", "image_format", "plot_trace", "read_csv", "read_npz", "read_trace",
           "register_source", "save_plot", "write_csv", "write_npz", "write_trace"]
