"""A link that opens a run's rerun recording in rerun's web viewer, served by the app (app/web/rerun_viewer.py)."""

from __future__ import annotations

from soccer_lab.app.web.rerun_viewer import recording_link
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.svg import escape


def run_viewer_link(api_url: str | None, run_id: int, problem: str | None = None) -> str:
    """HTML: "Open run #N in the rerun viewer" (a new browser tab); empty when the app serves no API here;
    why not when the app could not set the viewer up (`problem`, as serve printed it)."""
    if api_url is None:
        return ""
    if problem is not None:
        return (f'<div class="viewer-link" style="{style.FONT}; font-size:{style.FONT_SIZE}px; color:{style.MUTED}">'
                f"rerun's viewer is not available here: {escape(problem)}</div>")
    href = recording_link(api_url, f"{api_url.rstrip('/')}/api/runs/{run_id}/recording.rrd")
    return (f'<div class="viewer-link" style="{style.FONT}; font-size:{style.FONT_SIZE}px">'
            f'<a href="{escape(href)}" target="_blank" rel="noopener">Open run #{run_id} in the rerun viewer</a> '
            f'<span style="color:{style.MUTED}">(its statistics and each generation&#39;s best game, as the '
            "chapter&#39;s figures; reload it there for the newest generations)</span></div>")
