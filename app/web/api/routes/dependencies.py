"""What routes need from the running app: the store and the run manager as the request's visitor may use
them (app/web/access.py; outside classroom mode the one local user may do everything), and the id type of paths."""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends, Path, Request

from soccer_lab.app.web.access import LOCAL, ScopedRuns, ScopedStore, Visitor

SQLITE_MAX_INTEGER = 2**63 - 1
VISITOR_STATE = "visitor"  # where RequestGuard leaves the admitted visitor (the ASGI scope's state)


def visitor_of(request: Request) -> Visitor:
    return getattr(request.state, VISITOR_STATE, LOCAL)


def _store(request: Request) -> ScopedStore:
    return ScopedStore(request.app.state.store, visitor_of(request))


def _runs(request: Request) -> ScopedRuns:
    return ScopedRuns(request.app.state.runs, visitor_of(request))


VisitorDependency = Annotated[Visitor, Depends(visitor_of)]
StoreDependency = Annotated[ScopedStore, Depends(_store)]
RunsDependency = Annotated[ScopedRuns, Depends(_runs)]
# Larger ids cannot exist in SQLite: refuse them as input rather than fail converting them.
RecordId = Annotated[int, Path(ge=1, le=SQLITE_MAX_INTEGER)]
