"""GET /api/vocabulary: the terms and their membership parameters, actions, world and GA defaults."""

from __future__ import annotations

from typing import Any

from fastapi import APIRouter

from soccer_lab.fuzzy.vocabulary import Vocabulary
from soccer_lab.ga.config import GAConfig
from soccer_lab.soccer.config import GameConfig

router = APIRouter(tags=["vocabulary"])


@router.get("/vocabulary", summary="The vocabulary, world constants and defaults")
def vocabulary() -> dict[str, Any]:
    return {
        **Vocabulary.default().to_dict(),
        "game_defaults": GameConfig().model_dump(),
        "ga_defaults": GAConfig().model_dump(),
    }
