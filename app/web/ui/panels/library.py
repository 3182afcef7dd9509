"""Library: saved rulebases, past runs (open, rename, delete, watch a run's best player) and recorded
experiments (their summary, a link to the report, each figure)."""

from __future__ import annotations

from typing import Callable

import viser

from soccer_lab.app.experiment.library import ExperimentFolder, FigureFile
from soccer_lab.app.web.access import ScopedRuns, ScopedStore
from soccer_lab.app.runs.manager import RunStateError
from soccer_lab.app.runs.outputs import best_of_text, run_replayed_note
from soccer_lab.app.store import NotFound, RulebaseRecord, RunStatus, StoreError
from soccer_lab.app.web.ui import style
from soccer_lab.app.web.ui.panels.viewer_link import run_viewer_link
from soccer_lab.app.web.ui.panels.experiments import experiment_html, experiment_label, figure_html
from soccer_lab.app.web.ui.panels.svg import escape
from soccer_lab.fuzzy.export import EXPORT_FORMATS, FORMATS
from soccer_lab.fuzzy.parser import RuleSyntaxError, parse_rulebase
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary

NONE = "(none yet)"


def _label(record_id: int, name: str) -> str:
    return f"#{record_id} {name}"


def _id_of(label: str) -> int | None:
    if not label.startswith("#"):
        return None
    return int(label[1:].split(" ", 1)[0])


class LibraryPanel:
    """`on_load(rulebase, name, run_id)` puts a saved rulebase (run_id None) or a run's best player on the
    pitch. `api_url`: where the JSON API answers, for links to the files it serves (None: no links)."""

    def __init__(
        self,
        gui: viser.GuiApi,
        store: ScopedStore,
        runs: ScopedRuns,
        vocabulary: Vocabulary,
        api_url: str | None,
        *,
        on_load: Callable[[Rulebase, str, int | None], None],
        viewer_problem: str | None = None,
    ):
        self.store = store
        self.run_manager = runs
        self.vocabulary = vocabulary
        self.api_url = api_url
        self.viewer_problem = viewer_problem  # why there is no rerun viewer to link to (None: there is)
        self.on_load = on_load
        gui.add_markdown("**Saved rulebases**")
        self.rulebases = gui.add_dropdown("Rulebase", (NONE,))
        self.rulebase_figures = gui.add_html("")  # a run's best: the fitness the GA saw and its true quality
        rulebase_actions = gui.add_button_group("Rulebase actions", ("Open", "Rename", "Delete"))
        self.export_format = gui.add_dropdown("Export as", FORMATS, initial_value="fcl")
        download = gui.add_button("Download", color="gray")
        gui.add_markdown("**Past runs**")
        self.runs = gui.add_dropdown("Run", (NONE,))
        # Stop: a running run stops, a queued one leaves the queue (the teacher's way to any pupil's run)
        run_actions = gui.add_button_group("Run actions", ("Watch best", "Stop", "Rename", "Delete"))
        self.new_name = gui.add_text("New name", "")
        refresh = gui.add_button("Refresh", color="gray")
        self.message = gui.add_html("")
        gui.add_markdown("**Experiments** (`soccer-lab experiment`)")
        self.experiments = gui.add_dropdown("Experiment", (NONE,))
        self.experiment_view = gui.add_html("")
        self.figures = gui.add_dropdown("Figure", (NONE,))
        self.figure_view = gui.add_html("")
        self._figure_files: dict[str, FigureFile] = {}

        @self.rulebases.on_update
        def _(_: viser.GuiEvent) -> None:
            self.show_rulebase_figures()

        @self.experiments.on_update
        def _(_: viser.GuiEvent) -> None:
            self.show_experiment()

        @self.figures.on_update
        def _(_: viser.GuiEvent) -> None:
            self.show_figure()

        @rulebase_actions.on_click
        def _(event: viser.GuiEvent) -> None:
            {"Open": self.open_rulebase, "Rename": self.rename_rulebase, "Delete": self.delete_rulebase}[
                event.target.value
            ]()

        @download.on_click
        def _(event: viser.GuiEvent) -> None:
            if event.client is not None:
                self.download_rulebase(event.client)

        @run_actions.on_click
        def _(event: viser.GuiEvent) -> None:
            {"Watch best": self.watch_run, "Stop": self.stop_run, "Rename": self.rename_run,
             "Delete": self.delete_run}[event.target.value]()

        @refresh.on_click
        def _(_: viser.GuiEvent) -> None:
            self.refresh()

        self.refresh()

    def refresh(self) -> None:
        # Newest first (the highest id); a record just made is selected.
        rulebases = [_label(r.id, r.name) for r in self.store.list_rulebases()]
        runs = [_label(r.id, f"{r.name} ({r.status})") for r in self.store.list_runs()]
        self._set_options(self.rulebases, rulebases)
        self.show_rulebase_figures()
        self._set_options(self.runs, runs)
        experiments = [experiment_label(e) for e in self.store.list_experiments()]
        self._set_options(self.experiments, experiments)
        self.show_experiment()

    @staticmethod
    def _set_options(dropdown: viser.GuiDropdownHandle, labels: list[str]) -> None:
        current = _id_of(dropdown.value)
        known = {_id_of(label) for label in dropdown.options}
        options = tuple(labels) or (NONE,)
        if tuple(dropdown.options) != options:
            dropdown.options = options
        if _id_of(options[0]) not in known:  # a new record (or the first look): select it
            dropdown.value = options[0]
            return
        for label in options:  # keep the selection on the same record across a rename
            if current is not None and _id_of(label) == current:
                dropdown.value = label

    def _say(self, text: str, *, error: bool = False) -> None:
        self.message.content = (
            f'<div class="library-message" data-error="{str(error).lower()}" style="{style.FONT}; '
            f'font-size:{style.FONT_SIZE}px; color:{style.ERROR if error else style.FIRED}">{escape(text)}</div>'
        )

    def _selected(self, dropdown: viser.GuiDropdownHandle, what: str) -> int | None:
        record_id = _id_of(dropdown.value)
        if record_id is None:
            self._say(f"No {what} selected.", error=True)
        return record_id

    def _new_name(self) -> str | None:
        name = self.new_name.value.strip()
        if not name:
            self._say("Type the new name first.", error=True)
            return None
        return name

    # ---- rulebases ----------------------------------------------------------------------------
    def _selected_rulebase(self, doing: str) -> tuple[RulebaseRecord, Rulebase] | None:
        """(record, parsed rulebase) of the selected rulebase, or None after saying why not."""
        record_id = self._selected(self.rulebases, "rulebase")
        if record_id is None:
            return None
        try:
            record = self.store.get_rulebase(record_id)
            return record, parse_rulebase(record.text, self.vocabulary)
        except (NotFound, RuleSyntaxError) as exc:
            self._say(f"Cannot {doing}: {exc}", error=True)
            return None

    def show_rulebase_figures(self) -> None:
        """Under the selected rulebase, when it was saved from a run's best: both its figures."""
        record_id = _id_of(self.rulebases.value)
        try:
            figures = best_of_text(self.store.get_rulebase(record_id).best_of) if record_id is not None else ""
        except NotFound:
            figures = ""
        self.rulebase_figures.content = "" if not figures else (
            f'<div class="rulebase-figures" style="{style.FONT}; font-size:{style.SMALL_FONT_SIZE}px; '
            f'color:{style.INK}">Saved from {escape(figures)}</div>')

    def open_rulebase(self) -> None:
        selected = self._selected_rulebase("open")
        if selected is None:
            return
        record, rulebase = selected
        figures = best_of_text(record.best_of)  # the name says both figures, e.g. in a class entry's source
        self.on_load(rulebase, f"{record.name} ({figures})" if figures else record.name, None)
        self._say(f"“{record.name}” is on the pitch.")

    def rename_rulebase(self) -> None:
        record_id, name = self._selected(self.rulebases, "rulebase"), self._new_name()
        if record_id is None or name is None:
            return
        try:
            self.store.update_rulebase(record_id, name=name)
        except (NotFound, StoreError) as exc:
            self._say(f"Not renamed: {exc}", error=True)
            return
        self.refresh()
        self._say(f"Renamed to “{name}”.")

    def delete_rulebase(self) -> None:
        record_id = self._selected(self.rulebases, "rulebase")
        if record_id is None:
            return
        try:
            self.store.delete_rulebase(record_id)
        except (NotFound, StoreError) as exc:  # StoreError: a student deleting from the shared library
            self._say(str(exc), error=True)
            return
        self.refresh()
        self._say(f"Deleted rulebase #{record_id}.")

    def download_rulebase(self, client: viser.ClientHandle) -> None:
        """Send the selected rulebase to the tab that asked, as a file in the chosen export format."""
        selected = self._selected_rulebase("export")
        if selected is None:
            return
        record, rulebase = selected
        chosen = EXPORT_FORMATS[self.export_format.value]
        filename = chosen.filename(record.name)
        client.send_file_download(filename, chosen.write(rulebase, self.vocabulary).encode(), save_immediately=True)
        self._say(f"Downloading {filename}.")

    # ---- runs ---------------------------------------------------------------------------------
    def watch_run(self) -> None:
        record_id = self._selected(self.runs, "run")
        if record_id is None:
            return
        try:
            rulebase = self.run_manager.best_rulebase(record_id)
            best = self.store.best_individual(record_id)
        except (NotFound, RuleSyntaxError) as exc:
            self._say(f"No best player yet: {exc}", error=True)
            return
        quality = run_replayed_note(self.store, record_id, best.fitness)
        name = f"run #{record_id} best (gen {best.generation}, fitness {best.fitness:.3f}{quality})"
        self.on_load(rulebase, name, record_id)
        self._say(f"Watching {name}.")
        self.message.content += run_viewer_link(self.api_url, record_id, self.viewer_problem)

    def stop_run(self) -> None:
        record_id = self._selected(self.runs, "run")
        if record_id is None:
            return
        try:
            queued = self.store.get_run(record_id).status is RunStatus.QUEUED
            self.run_manager.stop(record_id, wait=0.0)
        except (NotFound, RunStateError) as exc:
            self._say(str(exc), error=True)
            return
        self.refresh()
        self._say(f"Run #{record_id} taken out of the queue." if queued else f"Run #{record_id} is stopping.")

    def rename_run(self) -> None:
        record_id, name = self._selected(self.runs, "run"), self._new_name()
        if record_id is None or name is None:
            return
        try:
            self.store.rename_run(record_id, name)
        except (NotFound, StoreError) as exc:
            self._say(f"Not renamed: {exc}", error=True)
            return
        self.refresh()
        self._say(f"Renamed to “{name}”.")

    def delete_run(self) -> None:
        record_id = self._selected(self.runs, "run")
        if record_id is None:
            return
        try:
            self.run_manager.delete(record_id)
        except (NotFound, RunStateError) as exc:
            self._say(str(exc), error=True)
            return
        self.refresh()
        self._say(f"Deleted run #{record_id}.")

    # ---- experiments --------------------------------------------------------------------------
    def show_experiment(self) -> None:
        """The selected experiment's summary and its figures in the figure dropdown."""
        record_id = _id_of(self.experiments.value)
        figures = []
        if record_id is None:
            self.experiment_view.content = ""
        else:
            try:
                record = self.store.get_experiment(record_id)
            except NotFound as exc:
                self.experiment_view.content = ""
                self._say(str(exc), error=True)
            else:
                folder = ExperimentFolder(record.folder, record.summary)
                figures = folder.figures()
                self.experiment_view.content = experiment_html(record, folder, self.api_url)
        self._figure_files = {figure.caption: figure for figure in figures}
        options = tuple(self._figure_files) or (NONE,)
        if tuple(self.figures.options) != options:
            self.figures.options = options  # viser selects the first option: its update shows it
        self.show_figure()

    def show_figure(self) -> None:
        figure = self._figure_files.get(self.figures.value)
        self.figure_view.content = figure_html(figure) if figure is not None else ""
