"""The summary figure of a sweep: each metric (a row of panels) against each varied parameter
(a column), one dot per finished point; failed points are left out and counted in the title.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

from openmotion.trace.plot import new_figure

if TYPE_CHECKING:
    import pandas
    from matplotlib.figure import Figure

PANEL_WIDTH, PANEL_HEIGHT = 3.2, 2.2  #: inches per panel
MAX_PANELS = 64  #: metrics x parameters beyond this: the first ones only
DOT_SIZE = 12.0


def plot_sweep(table: pandas.DataFrame, parameters: list[str], metrics: list[str],
               title: str = "") -> Figure:
    """The figure: metrics down, varied parameters across (a parameter with one value, or
    none varied: the point index across)."""
    varied = [name for name in parameters if table[name].nunique(dropna=False) > 1] \
        or ["index"]
    shown = [name for name in metrics if _numeric(table[name])]
    while len(shown) * len(varied) > MAX_PANELS and len(shown) > 1:
        shown.pop()
    rows = max(1, len(shown))
    done = table[table["status"] == "done"]
    failed = len(table) - len(done)
    heading = f"{title}: " if title else ""
    figure = new_figure(PANEL_WIDTH * len(varied), PANEL_HEIGHT * rows,
                        f"{heading}{len(done)} points" + (f", {failed} failed" if failed else ""))
    axes = figure.subplots(rows, len(varied), squeeze=False)
    for row, metric in enumerate(shown):
        for column, parameter in enumerate(varied):
            panel = axes[row][column]
            positions, labels = _positions(table[parameter], done[parameter])
            panel.scatter(positions, done[metric].astype("float64"), s=DOT_SIZE)
            if labels is not None:
                panel.set_xticks(range(len(labels)), labels, rotation=30, fontsize="small")
            if row == rows - 1:
                panel.set_xlabel(parameter)
            if column == 0:
                panel.set_ylabel(metric)
    if not shown:
        axes[0][0].text(0.5, 0.5, "no numeric metric", ha="center", va="center")
    return figure


def save_sweep_figure(table: pandas.DataFrame, parameters: list[str], metrics: list[str],
                      path: str | Path, title: str = "") -> None:
    plot_sweep(table, parameters, metrics, title).savefig(path, dpi=100)


def _numeric(column: Any) -> bool:
    import pandas

    return pandas.api.types.is_numeric_dtype(column) or pandas.api.types.is_bool_dtype(column)


def _positions(every: Any, shown: Any) -> tuple[Any, list[str] | None]:
    """x values of the shown points: the values when numeric, else category positions."""
    if _numeric(every):
        return shown.astype("float64"), None
    labels = sorted({str(value) for value in every})
    where = {label: number for number, label in enumerate(labels)}
    return [where[str(value)] for value in shown], labels
