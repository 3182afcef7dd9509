"""The library's experiments view as a pure renderer: summary, report links and inlined figures."""

from __future__ import annotations

import base64
import re
import shutil

from soccer_lab.app.experiment.library import ExperimentFolder
from soccer_lab.app.store import Store
from soccer_lab.app.web.ui.panels.experiments import experiment_html, experiment_label, figure_html

PNG = b"\x89PNG\r\n\x1a\nfake image data"
SUMMARY = {
    "presets": ["selection"], "trials": 30, "verdicts": {"agrees": 3, "disagrees": 1, "inconclusive": 0},
    "figures": ["figures/selection-best_fitness.png", "figures/selection-mean_fitness.png"],
    "figure_captions": ["Selection: best fitness (chapter Fig. 21)", "Selection: mean fitness (chapter Fig. 20)"],
}


def recorded(tmp_path):
    folder = tmp_path / "selection-seed0"
    (folder / "figures").mkdir(parents=True)
    (folder / "trials").mkdir()
    (folder / "report.html").write_text("<html></html>")
    (folder / "statistics.csv").write_text("preset\n")
    for name in ("selection-mean_fitness.png", "selection-best_fitness.png", "extra.png"):
        (folder / "figures" / name).write_bytes(PNG)
    (folder / "trials" / "abc-0.rrd").write_bytes(b"RRF2")
    store = Store(tmp_path / "db.sqlite3")
    record = store.record_experiment("selection", folder, SUMMARY)
    store.close()
    return record, folder


def test_summary_links_the_report_through_the_api_and_counts_the_files(tmp_path):
    record, folder = recorded(tmp_path)
    experiment = ExperimentFolder(folder, record.summary)
    html = experiment_html(record, experiment, "http://127.0.0.1:8000/")
    assert experiment_label(record) == f"#{record.id} selection ({record.created[:10]})"
    assert "3 agrees, 1 disagrees" in html and "inconclusive" not in html and "30 trials" in html
    assert f'href="http://127.0.0.1:8000/api/experiments/{record.id}/report.html"' in html
    assert "3 figures, 1 trial recordings" in html
    assert "report.html" not in experiment_html(record, experiment, None)  # no API: no link
    # The report's order and captions first, then any other figure on disk.
    assert [f.caption for f in experiment.figures()] == [*SUMMARY["figure_captions"], "extra"]


def test_figure_is_inlined_with_its_caption(tmp_path):
    record, folder = recorded(tmp_path)
    first = ExperimentFolder(folder, record.summary).figures()[0]
    html = figure_html(first)
    data = re.search(r'src="data:image/png;base64,([^"]+)"', html).group(1)
    assert base64.b64decode(data) == PNG
    assert "Selection: best fitness (chapter Fig. 21)" in html and 'data-name="selection-best_fitness.png"' in html


def test_a_vanished_folder_says_so(tmp_path):
    record, folder = recorded(tmp_path)
    experiment = ExperimentFolder(folder, record.summary)
    figure = experiment.figures()[0]
    shutil.rmtree(folder)
    html = experiment_html(record, experiment, "http://127.0.0.1:8000")
    assert "is gone" in html and "report.html" not in html and 'data-figures="0"' in html
    assert "Cannot read selection-best_fitness.png" in figure_html(figure)
