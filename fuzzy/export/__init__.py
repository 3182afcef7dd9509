"""Export a rulebase with its vocabulary: our versioned JSON, FCL (IEC 61131-7), fuzzylite's FLL and
MATLAB's .fis. Each format's file suffix and media type are here too, for the CLI, API and UI."""

from __future__ import annotations

import re
from dataclasses import dataclass
from typing import Callable

from soccer_lab.fuzzy.export.fcl import to_fcl
from soccer_lab.fuzzy.export.fis import to_fis
from soccer_lab.fuzzy.export.fll import to_fll
from soccer_lab.fuzzy.export.rulebase_json import (RulebaseFormatError, rulebase_from_dict, rulebase_from_json,
                                                   rulebase_to_dict, to_json)
from soccer_lab.fuzzy.rule import Rulebase
from soccer_lab.fuzzy.vocabulary import Vocabulary


@dataclass(frozen=True)
class ExportFormat:
    name: str
    suffix: str
    media_type: str
    write: Callable[[Rulebase, Vocabulary], str]

    def filename(self, name: str) -> str:
        """A file name for a rulebase called `name`, safe anywhere: `../best "run" #3` -> `best_run_3.fcl`."""
        stem = re.sub(r"[^A-Za-z0-9.-]+", "_", name).strip("._-") or "rulebase"
        return stem + self.suffix


EXPORT_FORMATS = {
    f.name: f
    for f in (
        ExportFormat("json", ".json", "application/json", to_json),
        ExportFormat("fcl", ".fcl", "text/plain", to_fcl),
        ExportFormat("fll", ".fll", "text/plain", to_fll),
        ExportFormat("fis", ".fis", "text/plain", to_fis),
    )
}
FORMATS = tuple(EXPORT_FORMATS)


def export_rulebase(rulebase: Rulebase, fmt: str, vocabulary: Vocabulary) -> str:
    """The rulebase as text in `fmt` (one of FORMATS)."""
    if fmt not in EXPORT_FORMATS:
        raise ValueError(f"unknown export format {fmt!r}; expected one of {', '.join(FORMATS)}")
    return EXPORT_FORMATS[fmt].write(rulebase, vocabulary)


__all__ = [
    "EXPORT_FORMATS", "ExportFormat", "FORMATS", "RulebaseFormatError", "export_rulebase", "rulebase_from_dict",
    "rulebase_from_json", "rulebase_to_dict", "to_fcl", "to_fis", "to_fll", "to_json",
]
