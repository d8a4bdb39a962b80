"""Traces: record axis signals each cycle, export them as CSV, draw a scope figure."""

from openmotion.trace.export import read_csv, write_csv
from openmotion.trace.plot import plot_trace, save_plot
from openmotion.trace.record import AXIS_SIGNALS, Trace, TraceRecorder

__all__ = ["AXIS_SIGNALS", "Trace", "TraceRecorder", "plot_trace", "read_csv", "save_plot",
           "write_csv"]
