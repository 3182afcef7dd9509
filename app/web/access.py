"""Who may see and change what: the store and the run manager as one visitor sees them.

Outside classroom mode there is one user, `LOCAL`, who may do everything. In classroom mode
(docs/teaching/classroom.md) every request and every UI session has a `Visitor`: a student, or the teacher.
A rulebase or run a student saves or starts is theirs (`owner`, their id); the teacher's are shared
(`owner` None). A student sees their own and the shared ones, and changes only their own; the teacher sees
and changes everything. The API's routes and the UI's panels are given a `ScopedStore` and `ScopedRuns`
for their visitor, so one set of rules holds for both: what a student may not see does not exist for them
(NotFound, the API's 404), what they may see but not change is `Forbidden` (403).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Callable

from soccer_lab.app.runs.manager import RunStateError
from soccer_lab.app.store import NotFound, StoreError

if TYPE_CHECKING:
    from soccer_lab.app.runs.manager import RunManager, RunEvent
    from soccer_lab.app.store import BestIndividual, RulebaseRecord, RunRecord, Store


class Forbidden(StoreError, RunStateError):
    """The visitor may see this but not do that (HTTP 403); caught wherever a refused change is shown."""


@dataclass(frozen=True)
class Visitor:
    """`student_id` None: the teacher (classroom mode) or the machine's only user (LOCAL)."""

    student_id: int | None
    name: str
    teacher: bool

    @property
    def is_student(self) -> bool:
        return self.student_id is not None

    def sees(self, owner: int | None) -> bool:
        return self.teacher or owner is None or owner == self.student_id

    def changes(self, owner: int | None) -> bool:
        return self.teacher or (owner is not None and owner == self.student_id)

    def require_teacher(self, doing: str) -> None:
        if not self.teacher:
            raise Forbidden(f"only the teacher can {doing}")


LOCAL = Visitor(None, "", teacher=True)


class ScopedStore:
    """The store's rulebases and runs as `visitor` may see and change them; experiments are everyone's."""

    def __init__(self, store: Store, visitor: Visitor):
        self.store = store
        self.visitor = visitor

    # ---- rulebases ----
    def list_rulebases(self) -> list[RulebaseRecord]:
        return [r for r in self.store.list_rulebases() if self.visitor.sees(r.owner)]

    def get_rulebase(self, rulebase_id: int) -> RulebaseRecord:
        record = self.store.get_rulebase(rulebase_id)
        if not self.visitor.sees(record.owner):
            raise NotFound("rulebase", rulebase_id)
        return record

    def create_rulebase(self, name: str, text: str, best_of: dict | None = None) -> RulebaseRecord:
        return self.store.create_rulebase(name, text, owner=self.visitor.student_id, best_of=best_of)

    def update_rulebase(self, rulebase_id: int, *, name: str | None = None, text: str | None = None) -> RulebaseRecord:
        self._changeable(self.get_rulebase(rulebase_id).owner, "change the shared library's rulebases")
        return self.store.update_rulebase(rulebase_id, name=name, text=text)

    def delete_rulebase(self, rulebase_id: int) -> None:
        self._changeable(self.get_rulebase(rulebase_id).owner, "delete from the shared library")
        self.store.delete_rulebase(rulebase_id)

    # ---- runs ----
    def list_runs(self) -> list[RunRecord]:
        return [r for r in self.store.list_runs() if self.visitor.sees(r.owner)]

    def get_run(self, run_id: int) -> RunRecord:
        record = self.store.get_run(run_id)
        if not self.visitor.sees(record.owner):
            raise NotFound("run", run_id)
        return record

    def rename_run(self, run_id: int, name: str) -> RunRecord:
        self._changeable(self.get_run(run_id).owner, "rename the teacher's runs")
        return self.store.rename_run(run_id, name)

    def statistics(self, run_id: int) -> list[dict[str, Any]]:
        self.get_run(run_id)
        return self.store.statistics(run_id)

    def best_individual(self, run_id: int) -> BestIndividual:
        self.get_run(run_id)
        return self.store.best_individual(run_id)

    def lineage_record(self, run_id: int, generation: int) -> dict[str, Any]:
        self.get_run(run_id)
        return self.store.lineage_record(run_id, generation)

    def lineage_text(self, run_id: int, generation: int) -> str:
        self.get_run(run_id)
        return self.store.lineage_text(run_id, generation)

    def best_individuals(self, run_id: int) -> list[BestIndividual]:
        self.get_run(run_id)
        return self.store.best_individuals(run_id)

    # ---- experiments: read by everyone ----
    def list_experiments(self):
        return self.store.list_experiments()

    def get_experiment(self, experiment_id: int):
        return self.store.get_experiment(experiment_id)

    def _changeable(self, owner: int | None, doing: str) -> None:
        if not self.visitor.changes(owner):
            raise Forbidden(f"only the teacher can {doing}")


class ScopedRuns:
    """The run manager as `visitor` may use it: a student's runs are theirs (and bounded by the class's
    settings, RunManager.start's `owner`), another's run cannot be stopped, resumed or deleted."""

    def __init__(self, runs: RunManager, visitor: Visitor):
        self.runs = runs
        self.visitor = visitor
        self._scoped = ScopedStore(runs.store, visitor)

    def start(self, name: str | None = None, ga: Any = None, game: Any = None, **options: Any) -> RunRecord:
        return self.runs.start(name, ga, game, owner=self.visitor.student_id, **options)

    def stop(self, run_id: int, **options: Any) -> RunRecord:
        self._changeable(run_id, "stop another's run")
        return self.runs.stop(run_id, **options)

    def resume(self, run_id: int) -> RunRecord:
        self._changeable(run_id, "resume another's run")
        return self.runs.resume(run_id)

    def delete(self, run_id: int) -> None:
        self._changeable(run_id, "delete another's run")
        self.runs.delete(run_id)

    def best_rulebase(self, run_id: int):
        self._scoped.get_run(run_id)
        return self.runs.best_rulebase(run_id)

    def pitch_game(self, run_id: int):
        self._scoped.get_run(run_id)
        return self.runs.pitch_game(run_id)

    def progress(self, run_id: int):
        return self.runs.progress(run_id)

    def is_active(self, run_id: int) -> bool:
        return self.runs.is_active(run_id)

    def is_pending(self, run_id: int) -> bool:
        return self.runs.is_pending(run_id)

    def queue_place(self, run_id: int):
        return self.runs.queue_place(run_id)

    def add_listener(self, listener: Callable[[RunEvent], None]) -> Callable[[], None]:
        """Events of the runs this visitor sees only."""
        def seen(event: RunEvent) -> None:
            try:
                self._scoped.get_run(event.run_id)
            except NotFound:
                return
            listener(event)

        return self.runs.add_listener(seen if self.visitor.is_student else listener)

    def _changeable(self, run_id: int, doing: str) -> None:
        if not self.visitor.changes(self._scoped.get_run(run_id).owner):
            raise Forbidden(f"only the teacher can {doing}")

