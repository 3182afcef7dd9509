"""Export a rulebase with its vocabulary (spec 2.4): our versioned JSON, FCL (IEC 61131-7), fuzzylite's FLL."""

from __future__ import annotations

from fuzzy.export.fcl import to_fcl
from fuzzy.export.fll import to_fll
from fuzzy.export.rulebase_json import (
    RulebaseFormatError,
    rulebase_from_dict,
    rulebase_from_json,
    rulebase_to_dict,
    to_json,
)
from fuzzy.rule import Rulebase
from fuzzy.vocabulary import Vocabulary

EXPORTERS = {"json": to_json, "fcl": to_fcl, "fll": to_fll}
FORMATS = tuple(EXPORTERS)


def export_rulebase(rulebase: Rulebase, fmt: str, vocabulary: Vocabulary) -> str:
    """The rulebase as text in `fmt` (one of FORMATS)."""
    if fmt not in EXPORTERS:
        raise ValueError(f"unknown export format {fmt!r}; expected one of {', '.join(FORMATS)}")
    return EXPORTERS[fmt](rulebase, vocabulary)


__all__ = [
    "EXPORTERS", "FORMATS", "RulebaseFormatError", "export_rulebase", "rulebase_from_dict", "rulebase_from_json",
    "rulebase_to_dict", "to_fcl", "to_fll", "to_json",
]
