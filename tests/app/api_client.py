"""The API app over a data folder, as `soccer-lab serve` assembles it, for the API tests."""

from __future__ import annotations

import time
from contextlib import contextmanager
from pathlib import Path
from typing import Callable, Iterator

from fastapi.testclient import TestClient

from soccer_lab.app.web.api import create_app
from soccer_lab.app.paths import DATABASE_FILE
from soccer_lab.app.runs.manager import RunManager
from soccer_lab.app.store import Store

# A run that takes well under a second a generation: tiny population, short games.
TINY_GA = {"population_size": 4, "max_generations": 2, "max_length": 16, "seed": 7}
SHORT_GAMES = {"max_ticks": 40, "idle_ticks": 20}


@contextmanager
def api_client(data_dir: Path, **manager_options) -> Iterator[TestClient]:
    store = Store(data_dir / DATABASE_FILE)
    runs = RunManager(store, data_dir, **manager_options)
    try:
        # A script of the user's: it says so with the header app/web/api/guard.py asks of body-less POSTs.
        with TestClient(create_app(store, runs), raise_server_exceptions=False,
                        headers={"X-Soccer-Lab": "test"}) as client:
            yield client
    finally:
        runs.shutdown()
        store.close()


def wait_for(condition: Callable[[], object], timeout: float = 120.0, what: str = "condition") -> object:
    """Poll until `condition()` is truthy (background runs report asynchronously)."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = condition()
        if value:
            return value
        time.sleep(0.05)
    raise AssertionError(f"timed out waiting for {what}")
