"""What routes need from the running app: the store and the run manager, and the id type of paths."""

from __future__ import annotations

from typing import Annotated

from fastapi import Depends, Path, Request

from app.runs import RunManager
from app.store import Store

SQLITE_MAX_INTEGER = 2**63 - 1


def _store(request: Request) -> Store:
    return request.app.state.store


def _runs(request: Request) -> RunManager:
    return request.app.state.runs


StoreDependency = Annotated[Store, Depends(_store)]
RunsDependency = Annotated[RunManager, Depends(_runs)]
# Larger ids cannot exist in SQLite: refuse them as input rather than fail converting them.
RecordId = Annotated[int, Path(ge=1, le=SQLITE_MAX_INTEGER)]
