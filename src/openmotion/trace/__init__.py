"""Traces: record any object's signals and the command events, export them (CSV with a JSON
sidecar, NPZ; a long run's NPZ chunks streamed to a directory), and draw them: the scope
figure, the rail plot of CA groups, the path plot of axes groups, the planar plot."""

from openmotion.trace.export import (
    TraceWarning,
    read_csv,
    read_npz,
    read_sidecar,
    read_trace,
    sidecar_path,
    trace_format,
    write_csv,
    write_npz,
    write_sidecar,
    write_trace,
)
from openmotion.trace.plot import (
    default_figure,
    distinct_colors,
    figure_signals,
    image_format,
    plot_trace,
    save_plot,
)
from openmotion.trace.record import Event, Trace, TraceRecorder
from openmotion.trace.signals import AXIS_SIGNALS, SignalSource, register_source
from openmotion.trace.stream import StreamedTrace, read_stream

__all__ = ["AXIS_SIGNALS", "Event", "SignalSource", "StreamedTrace", "Trace", "TraceRecorder",
           "TraceWarning", "default_figure", "distinct_colors", "figure_signals", "image_format",
           "plot_trace", "read_csv", "read_npz", "read_sidecar", "read_stream", "read_trace",
           "register_source", "save_plot", "sidecar_path", "trace_format", "write_csv",
           "write_npz", "write_sidecar", "write_trace"]
