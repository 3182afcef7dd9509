"""The library's experiments: what a recorded experiment says (presets, trials, verdicts, links to its
report) and one of its figures, as HTML for viser. The figure is inlined (a data: URL) so the UI works
without the API server; the report is linked through the API when its address is known."""

from __future__ import annotations

import base64

from soccer_lab.app.experiment.library import ExperimentFolder, FigureFile
from soccer_lab.app.store import ExperimentRecord
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.svg import escape


def experiment_label(record: ExperimentRecord) -> str:
    return f"#{record.id} {record.preset} ({record.created[:10]})"


def experiment_html(record: ExperimentRecord, folder: ExperimentFolder, api_url: str | None) -> str:
    summary = record.summary
    verdicts = ", ".join(f"{n} {v}" for v, n in (summary.get("verdicts") or {}).items() if n) or "none"
    figures = folder.figures()
    lines = [
        f"<b>{escape(', '.join(summary.get('presets', [record.preset])))}</b> · {escape(summary.get('trials', '?'))} "
        f"trials · recorded {escape(record.created[:16].replace('T', ' '))}",
        f"Verdicts: {escape(verdicts)}",
    ]
    if not folder.exists:
        lines.append(f'<span style="color:{style.ERROR}">Its folder {escape(record.folder)} is gone.</span>')
    else:
        lines.append(f'{len(figures)} figures, {len(folder.recordings())} trial recordings in '
                     f'<code style="font-size:{style.SMALL_FONT_SIZE}px; overflow-wrap:anywhere">'
                     f'{escape(record.folder)}</code>')
        if api_url and folder.report_html is not None:
            base = f"{api_url.rstrip('/')}/api/experiments/{record.id}"
            lines.append(f'<a class="experiment-report" href="{escape(base)}/report.html" target="_blank">'
                         f"Open the report</a> (findings, verdicts, every figure) · "
                         f'<a href="{escape(base)}/statistics.csv" target="_blank">statistics.csv</a>')
    body = "".join(f"<div>{line}</div>" for line in lines)
    return (f'<div class="experiment" data-id="{record.id}" data-figures="{len(figures)}" '
            f'style="{style.FONT}; font-size:{style.FONT_SIZE}px; color:{style.INK}; overflow-wrap:anywhere">{body}</div>')


def figure_html(figure: FigureFile) -> str:
    """The figure inlined as PNG, with its caption; a note instead when the file cannot be read."""
    try:
        data = base64.b64encode(figure.path.read_bytes()).decode("ascii")
    except OSError as exc:
        return f'<div style="color:{style.ERROR}">Cannot read {escape(figure.name)}: {escape(exc.strerror or exc)}</div>'
    return (f'<figure class="experiment-figure" data-name="{escape(figure.name)}" style="margin:0">'
            f'<img alt="{escape(figure.caption)}" src="data:image/png;base64,{data}" style="max-width:100%">'
            f'<figcaption style="{style.FONT}; font-size:{style.SMALL_FONT_SIZE}px; color:{style.MUTED}">'
            f"{escape(figure.caption)}</figcaption></figure>")
